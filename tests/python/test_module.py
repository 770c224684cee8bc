"""[python] The Python module `retroprism` against the C++ node and the command line.

Run by ctest (entry `python`) with Debian's python3, PYTHONPATH at the built module and
RETROPRISM_CLI naming the built command. Random directions come from fixed seeds.
"""
import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import retroprism

CLI = os.environ["RETROPRISM_CLI"]
LOBES = ["f", "surface", "retro", "diffuse"]


def cli(*args, stdin=None):
    r = subprocess.run([CLI, *args], input=stdin, capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def directions(n, seed, tilt_below=0.0):
    """n random (wi, wo) pairs, mostly above the horizon; `tilt_below` of them below it."""
    rng = np.random.default_rng(seed)
    wi, wo = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    below = rng.random(n) < tilt_below
    wo[below, 2] *= -1
    # near the retro peak: wo a small step from wi
    near = rng.random(n) < 0.3
    wo[near] = wi[near] + 0.02 * rng.normal(size=(near.sum(), 3))
    return wi, wo


def materials():
    """The defaults, every value of every enum and boolean, every float at its lower and at its
    upper range end, a tilted frame: walked from the parameter table, so new inputs are covered
    as they arrive."""
    out = [{}]
    lows, highs = {}, {}
    for p in retroprism.param_table():
        if p["type"] == "string":
            out += [{p["name"]: v} for v in p["values"] if v != p["default"]]
        elif p["type"] == "boolean":
            out.append({p["name"]: not p["default"]})
        elif p["type"] == "float":
            lows[p["name"]], highs[p["name"]] = p["min"], p["max"]
    out += [lows, highs]
    out.append({"normal": [0.2, -0.1, 1.0], "tangent": [1.0, 0.3, 0.0], "era_mode": "oriented",
                "orientation": 40.0})
    out.append({"roughness": 0.3, "ior": 1.586, "prism_reflection": "tir",
                "era_mode": "matched_pair", "retro_lobe": "anisotropic", "reciprocal": True,
                "diffuse_color": [0.9, 0.8, 0.1], "retro_color": [1.0, 0.75, 0.08]})
    return out


def cli_eval(material, wi, wo, backend, tmp_path):
    query = tmp_path / "query.json"
    query.write_text(json.dumps({"material": material, "samples": [
        {"wi": a.tolist(), "wo": b.tolist()} for a, b in zip(wi, wo)]}))
    code, out, err = cli("eval", "--backend", backend, str(query))
    assert code == 0, err
    results = json.loads(out)["results"]
    return {k: np.array([r[k] for r in results], dtype=np.float64) for k in LOBES + ["pdf"]}


@pytest.mark.parametrize("material", materials(), ids=lambda m: json.dumps(m))
def test_eval_bit_identical_to_the_cpp_node(material, tmp_path):
    wi, wo = directions(200, seed=11, tilt_below=0.05)
    node = retroprism.Node(material)
    for backend, dtype in [("cpp-double", np.float64), ("cpp-float", np.float32)]:
        want = cli_eval(material, wi, wo, backend, tmp_path)
        # the command rounds the JSON's doubles to the float node's precision the same way
        got = node.eval(wi.astype(dtype), wo.astype(dtype))
        for key in LOBES + ["pdf"]:
            assert got[key].dtype == dtype
            np.testing.assert_array_equal(got[key].astype(np.float64), want[key],
                                          err_msg=f"{backend} {key}")


def test_f_and_pdf_are_eval_parts():
    wi, wo = directions(5000, seed=12)
    node = retroprism.Node(roughness=0.2, prism_reflection="tir")
    for dtype in [np.float32, np.float64]:
        e = node.eval(wi.astype(dtype), wo.astype(dtype))
        f = node.f(wi.astype(dtype), wo.astype(dtype))
        for key in LOBES:
            np.testing.assert_array_equal(f[key], e[key])
        np.testing.assert_array_equal(node.pdf(wi.astype(dtype), wo.astype(dtype)), e["pdf"])


def test_rows_do_not_depend_on_the_batch():
    # 300 000 rows run on every core; batches of 7 rows on one thread (below the 1024-row grain)
    wi, wo = directions(300_000, seed=13)
    node = retroprism.Node(roughness=0.08)
    whole = node.eval(wi, wo)
    for start in range(0, 300_000, 29_989):
        part = node.eval(wi[start:start + 7], wo[start:start + 7])
        for key in LOBES + ["pdf"]:
            np.testing.assert_array_equal(part[key], whole[key][start:start + 7])


def test_a_forked_child_runs_batches():
    # Batches run on the process's pool of workers (util/parallel.h). A child forked after the
    # pool started (Python's multiprocessing on Linux forks) has the pool's state but none of its
    # threads: its batches must still run (on its own thread) and give the parent's rows, not
    # wait for workers that are not there. The child reports through its exit status; the parent
    # gives it 60 s.
    wi, wo = directions(50_000, seed=17)
    node = retroprism.Node(roughness=0.08)
    whole = node.eval(wi, wo)
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            again = node.eval(wi, wo)
            code = 0 if all(np.array_equal(again[k], whole[k]) for k in LOBES + ["pdf"]) else 2
        finally:
            os._exit(code)
    deadline = time.monotonic() + 60
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, 9)
            os.waitpid(pid, 0)
            pytest.fail("the forked child's batch did not finish in 60 s")
        time.sleep(0.05)
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, f"child status {status}"


def test_the_gil_is_released_during_a_batch():
    # albedo of 24 directions at grid 256: about 10 ms of quadrature per direction. The main
    # thread stamps the time every millisecond while the batch runs in a thread; holding the GIL,
    # the batch would keep it from running Python between the call's start and end, so no stamp
    # could fall in the middle half of the call.
    node = retroprism.Node()
    wi = np.tile([0.3, 0.0, 0.95], (24, 1))
    call = []

    def work():
        call.append(time.perf_counter())
        node.albedo(wi, grid=256)
        call.append(time.perf_counter())

    stamps = []
    t = threading.Thread(target=work)
    t.start()
    while t.is_alive():
        stamps.append(time.perf_counter())
        time.sleep(0.001)
    t.join()
    begin, end = call
    quarter = (end - begin) / 4
    inside = [s for s in stamps if begin + quarter < s < end - quarter]
    assert inside, f"no Python ran during the middle half of a {end - begin:.2f} s batch"


def test_sample_agrees_with_eval():
    rng = np.random.default_rng(14)
    wi, _ = directions(20_000, seed=15)
    u = rng.random((20_000, 3))
    node = retroprism.Node(roughness=0.15, prism_reflection="metallized")
    s = node.sample(wi, u)
    assert s["valid"].mean() > 0.9
    v = s["valid"]
    e = node.eval(wi[v], s["wo"][v])
    # The default frame is the identity: the sampled direction reaches eval unchanged, so the
    # values agree to the rounding of the sum of the lobes (1e-12 relative in double, as the
    # adversarial sweep's sample/eval check).
    for key in LOBES:
        np.testing.assert_allclose(s[key][v], e[key], rtol=1e-12, atol=0)
    np.testing.assert_allclose(s["pdf"][v], e["pdf"], rtol=1e-12, atol=0)
    assert set(np.unique(s["lobe"][v])) <= {0, 1, 2}
    assert np.all(s["lobe"][~v] == -1) and np.all(s["pdf"][~v] == 0)
    assert s["wo"].dtype == np.float64
    assert node.sample(wi.astype(np.float32), u.astype(np.float32))["pdf"].dtype == np.float32


def test_albedo_era_and_ra_match_the_command():
    node = retroprism.Node()
    # `retroprism albedo` prints the channel mean at 6 decimals, grid 256
    code, out, err = cli("albedo", "--theta-i", "0", "30", "60")
    assert code == 0, err
    rows = [l.split() for l in out.splitlines()[1:4]]
    t = np.radians([0.0, 30.0, 60.0])
    wi = np.stack([np.sin(t), np.zeros(3), np.cos(t)], axis=1)
    a = node.albedo(wi, grid=256)
    for i, r in enumerate(rows):
        for j, key in enumerate(["surface", "retro", "diffuse", "total"]):
            assert abs(a[key][i].mean() - float(r[1 + j])) <= 5e-7
    # `retroprism era` prints 9 decimals
    for mode in ["averaged", "matched_pair", "oriented"]:
        for cant in [0.0, -12.0]:
            code, out, err = cli("era", "--theta-t", "25", "--phi", "12", "--mode", mode,
                                 "--cant", str(cant))
            assert code == 0, err
            got = retroprism.era(25, 12, mode, cant=cant)
            assert abs(got - float(out.split("ERA")[1])) <= 5e-10
    np.testing.assert_array_equal(retroprism.era(np.array([0.0, 10.0]), [[0.0], [30.0]]).shape,
                                  (2, 2))
    assert abs(retroprism.era(0.0) - 2.0 / 3.0) < 1e-12
    # `retroprism ra --csv --material M` prints 9 significant digits
    material = {"prism_reflection": "tir", "era_mode": "matched_pair", "roughness": 0.05}
    path = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"rp_py_{os.getpid()}.json")
    with open(path, "w") as f:
        json.dump(material, f)
    code, out, err = cli("ra", "--csv", "--material", path, "--rotation", "30")
    os.remove(path)
    assert code == 0, err
    table = retroprism.Node(material).ra_table(rotation=30)
    lines = out.splitlines()[1:]
    assert len(lines) == table["Y"].size
    for line in lines:
        obs, ent, rot, y, r, g, b = map(float, line.split(","))
        i = list(table["observation"]).index(obs)
        j = list(table["entrance"]).index(ent)
        np.testing.assert_allclose([table["Y"][i, j], *table["rgb"][i, j]], [y, r, g, b],
                                   rtol=1e-8)


def test_inputs_walk_the_parameter_table():
    table = retroprism.param_table()
    node = retroprism.Node()
    assert [p["name"] for p in table] == list(node.inputs)
    for p in table:
        default = p["default"]
        assert node.inputs[p["name"]] == default
        # each input given alone at its default is accepted, as keyword and in a dict
        assert retroprism.Node(**{p["name"]: default}).inputs == node.inputs
        assert retroprism.Node({p["name"]: default}).inputs == node.inputs
    given = retroprism.Node(roughness=np.float32(0.25), diffuse_color=np.array([0.1, 0.2, 0.3]),
                            reciprocal=np.bool_(True), prism_reflection="tir")
    assert given.inputs["roughness"] == 0.25
    assert given.inputs["diffuse_color"] == (0.1, 0.2, 0.3)
    assert given.inputs["reciprocal"] is True and given.inputs["prism_reflection"] == "tir"
    assert retroprism.Node(**given.inputs).inputs == given.inputs


def json_error(material):
    """The command's error text for a JSON material, after its "where" prefix."""
    code, _, err = cli("eval", "-", stdin=json.dumps({"material": material, "samples": []}))
    assert code != 0
    return err.split("<stdin>: material", 1)[1].strip()


@pytest.mark.parametrize("material", [
    {"roughness": 2.0}, {"diffuse_color": [0.5, 0.5]}, {"diffuse_color": [0.5, 1.5, 0.5]},
    {"prism_reflection": "gold"}, {"reciprocal": 1.0}, {"no_such_input": 1.0},
    {"normal": [0, 0, 0]}, {"weight": "heavy"},
], ids=lambda m: repr(m))
def test_bad_inputs_raise_the_json_readers_errors(material):
    with pytest.raises(ValueError) as e:
        retroprism.Node(**material)
    # the JSON reader's text, with "Node" where the command names the query's material
    assert str(e.value) == "Node" + json_error(material)


@pytest.mark.parametrize("material, message", [
    ({"roughness": float("nan")}, "Node.roughness = nan is outside its range [0, 1]"),
    ({"ior": float("inf")}, "Node.ior = inf is outside its range [1, 3]"),
    ({"diffuse_color": (0.5, float("nan"), 0.5)},
     "Node.diffuse_color[1] = nan is outside its range [0, 1]"),
    ({"normal": [0, -np.inf, 1]}, "Node.normal[1] = -inf is outside its range [-1e+30, 1e+30]"),
], ids=lambda m: repr(m))
def test_non_finite_inputs_raise_value_error_naming_them(material, message):
    # JSON has no NaN or Inf, so these texts are the reader's range errors as Python reaches them
    with pytest.raises(ValueError) as e:
        retroprism.Node(material)
    assert str(e.value) == message


def test_node_arguments():
    with pytest.raises(ValueError, match="as one dict or as keywords"):
        retroprism.Node({"roughness": 0.1}, ior=1.5)
    with pytest.raises(ValueError, match="expected a dict"):
        retroprism.Node([("roughness", 0.1)])
    with pytest.raises(ValueError, match=r"Node\.roughness: expected a number, a string"):
        retroprism.Node(roughness=object())
    assert issubclass(retroprism.InputError, ValueError)


@pytest.mark.parametrize("wi, wo, pattern", [
    (np.zeros((4, 2)), np.zeros((4, 3)), r"wi: expected shape \(N, 3\), got \(4, 2\)"),
    (np.zeros(3), np.zeros(3), r"wi: expected shape \(N, 3\), got \(3,\)"),
    (np.zeros((4, 3)), np.zeros((2, 4, 3)), r"wo: expected shape \(N, 3\), got \(2, 4, 3\)"),
    (np.zeros((4, 3), dtype=np.int64), np.zeros((4, 3)), "wi: expected float32 or float64 values, got int64"),
    (np.zeros((4, 3)), np.zeros((4, 3), dtype=np.float16), "wo: expected float32 or float64 values, got float16"),
    (np.zeros((4, 3)), np.zeros((4, 3), dtype=np.float32), "wo: dtype float32 differs from wi's float64"),
    (np.zeros((4, 3)), np.zeros((5, 3)), "wo: 5 rows, wi has 4"),
    ([["a", "b", "c"]], np.zeros((1, 3)), "wi: expected float32 or float64 values, got <U1"),
], ids=range(8))
def test_bad_batches_raise_value_error_naming_the_argument(wi, wo, pattern):
    node = retroprism.Node()
    for method in [node.eval, node.f, node.pdf]:
        with pytest.raises(ValueError, match=pattern):
            method(wi, wo)


def test_bad_sample_albedo_era_ra_arguments():
    node = retroprism.Node()
    wi = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match=r"u: values must be finite and in \[0, 1\)"):
        node.sample(wi, np.array([[0.5, 1.0, 0.5]]))
    with pytest.raises(ValueError, match=r"u: values must be finite"):
        node.sample(wi, np.array([[0.5, np.nan, 0.5]]))
    with pytest.raises(ValueError, match=r"grid: must be in \[1, 4096\]"):
        node.albedo(wi, grid=0)
    with pytest.raises(ValueError, match=r"theta_t: must be in \[0, 90\) degrees"):
        retroprism.era(90.0)
    with pytest.raises(ValueError, match="phi: values must be finite"):
        retroprism.era(10.0, float("nan"))
    with pytest.raises(ValueError, match='mode: expected one of "averaged,matched_pair,oriented"'):
        retroprism.era(10.0, mode="sideways")
    with pytest.raises(ValueError, match="rotation: must be finite"):
        node.ra_table(rotation=float("inf"))
    with pytest.raises(ValueError, match="entrance: values must be finite"):
        node.ra_table(entrance=[10.0, float("nan")])


def test_directions_follow_the_nodes_guards():
    # zero, non-finite and below-horizon directions give zeros, as the C++ node does
    node = retroprism.Node()
    wi = np.array([[0, 0, 0], [np.nan, 0, 1], [0, 0, 1], [0.1, 0, 1]], dtype=np.float64)
    wo = np.array([[0, 0, 1], [0, 0, 1], [np.inf, 0, 1], [0.1, 0, -1]], dtype=np.float64)
    e = node.eval(wi, wo)
    for key in LOBES + ["pdf"]:
        assert np.all(e[key] == 0)


def test_wavelength_evaluates_the_diffraction_lobe_there():
    # With a prism pitch the retro lobe's diffraction pattern widens with the wavelength: at 1 deg
    # from the retro direction the node at 1550 nm returns more than at 550 nm, and wavelength=NM
    # is the node whose `wavelength` input is NM, value for value.
    node = retroprism.Node(roughness=0.005, prism_pitch=150.0, prism_reflection="tir")
    wi = np.array([[0.0, 0.0, 1.0]])
    t = np.radians(1.0)
    wo = np.array([[np.sin(t), 0.0, np.cos(t)]])
    green = node.eval(wi, wo, wavelength=550.0)["retro"][0, 0]
    infrared = node.eval(wi, wo, wavelength=1550.0)["retro"][0, 0]
    assert infrared > 2.0 * green
    direct = retroprism.Node(roughness=0.005, prism_pitch=150.0, prism_reflection="tir",
                             wavelength=1550.0)
    assert direct.eval(wi, wo)["retro"][0, 0] == infrared
    ra = node.ra_table(wavelength=905.0)
    assert ra["Y"].shape == (5, 5) and np.all(np.isfinite(ra["Y"]))
    # Photopic R_A: a weighted mean over 410-690 nm, so within the band's least and largest;
    # without a pitch nothing depends on the wavelength, so it is the channels' luminance.
    photopic = node.ra_table(photopic=True)["Y"]
    band = np.array([node.ra_table(wavelength=nm)["Y"] for nm in range(410, 700, 20)])
    assert np.all(photopic >= band.min(axis=0)) and np.all(photopic <= band.max(axis=0))
    plain = retroprism.Node(roughness=0.05)
    assert np.allclose(plain.ra_table(photopic=True)["Y"], plain.ra_table()["Y"],
                       rtol=1e-12, atol=0.0)
    with pytest.raises(ValueError, match="photopic"):
        node.ra_table(wavelength=550.0, photopic=True)
    with pytest.raises(ValueError, match="wavelength"):
        node.eval(wi, wo, wavelength=-5.0)
