#!/usr/bin/env python3
"""Checks that an installed retroprism works alone (issue 17): run by scripts/check-install.sh
with Debian's python3 after the build tree (and, with --fresh-clone, the checkout) is gone.

    verify-install.py PREFIX [--source-path DIR] [--materialx]

- the installed command runs `eval`, `era`, `ra` and `export` (the exported MaterialX library
  and GLSL equal the installed ones byte for byte), and with --materialx `check --backend
  materialx` (real MaterialX from share/retroprism/materialx/tools);
- `view` serves the installed page with the installed web/serve.py: site.json, the baseline's
  GLSL as installed, and POST /fit-baseline answering what `fit --ra --baseline-only --json`
  prints for the same table;
- examples/consumer (installed under share/retroprism/examples/consumer) builds against the
  prefix with CMake (find_package) and with pkg-config, and prints the command's "f"; its
  consumer_ra (retroprism::analysis) prints the command's R_A table; consumer_batch
  (retroprism::batch) the float node's f within the batch kernels' rounding;
- `import retroprism` from the prefix evaluates a batch equal, bit for bit, to the command's
  answer in double and in float;
- with --source-path, that folder (the deleted checkout) is named in no installed binary.
Prints what it checked; exits non-zero with the first difference.
"""
import argparse
import filecmp
import glob
import json
import os
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request

import numpy as np


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"FAILED: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    return r.stdout


def fail(msg):
    sys.exit(f"FAILED: {msg}")


def same_tree(a, b):
    d = filecmp.dircmp(a, b)
    if d.left_only or d.right_only or d.diff_files or d.funny_files:
        fail(f"{a} and {b} differ: {d.left_only} {d.right_only} {d.diff_files}")
    for sub in d.common_dirs:
        same_tree(os.path.join(a, sub), os.path.join(b, sub))
    # dircmp compares shallowly (size and time); compare the contents
    for name in d.common_files:
        if not filecmp.cmp(os.path.join(a, name), os.path.join(b, name), shallow=False):
            fail(f"{a}/{name} and {b}/{name} differ")


def check_commands(prefix, cli, share, work, materialx):
    era = run([cli, "era", "--theta-t", "20", "--phi", "10", "--mode", "oriented"])
    ra = run([cli, "ra"])
    if len([l for l in ra.splitlines() if l.strip()[:1].isdigit()]) != 5:
        fail(f"ra printed no table of 5 rows:\n{ra}")
    out = os.path.join(work, "export")
    run([cli, "export", "--out", out])
    same_tree(os.path.join(out, "rp_pbrlib"), os.path.join(share, "materialx", "rp_pbrlib"))
    same_tree(os.path.join(out, "glsl"), os.path.join(share, "glsl"))
    print("installed command: eval, era, ra, export (library and GLSL equal to the installed)")
    if materialx:
        report = run([cli, "check", "--backend", "materialx"])
        if "pass" not in report:
            fail(f"check --backend materialx did not pass:\n{report}")
        print("installed command: check --backend materialx passes")
    return float(era.split("ERA")[1])


def check_view(cli, share):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    view = subprocess.Popen([cli, "view", "--no-open", "--port", str(port)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        line = view.stdout.readline()
        if "retroprism view: http://" not in line:
            fail(f"view printed no address: {line}{view.stdout.read() if view.poll() is not None else ''}")
        base = f"http://127.0.0.1:{port}"
        for _ in range(100):
            try:
                site = json.load(urllib.request.urlopen(base + "/site.json", timeout=10))
                break
            except (urllib.error.URLError, ConnectionError):
                time.sleep(0.1)
        else:
            fail(f"view does not serve {base}/site.json")
        glsl = urllib.request.urlopen(base + site["baseline"], timeout=10).read().decode()
        with open(os.path.join(share, "glsl", "mrm_ggx.glsl")) as f:
            if glsl != f.read():
                fail(f"{site['baseline']} served by view differs from the installed glsl/mrm_ggx.glsl")
        table = os.path.join(share, "examples", "sheeting", "dg983_white.csv")
        with open(table, "rb") as f:
            request = urllib.request.Request(base + "/fit-baseline", data=f.read(), method="POST")
        served = json.load(urllib.request.urlopen(request, timeout=120))
        printed = json.loads(run([cli, "fit", "--ra", table, "--baseline-only", "--json"]))
        if served["mrm"] != printed["mrm"]:
            fail(f"POST /fit-baseline answered {served['mrm']}, fit --baseline-only printed {printed['mrm']}")
    finally:
        view.terminate()
        view.wait(timeout=30)
    print("installed command: view serves the page, the baseline's GLSL and its fit")


def check_consumer(prefix, cli, share, work):
    src = os.path.join(share, "examples", "consumer")
    answer = json.loads(run([cli, "eval", os.path.join(src, "query.json")]))
    expected = answer["results"][0]["f"]
    build = os.path.join(work, "consumer")
    run(["cmake", "-S", src, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
         f"-DCMAKE_PREFIX_PATH={prefix}"])
    run(["cmake", "--build", build])
    env = dict(os.environ, PKG_CONFIG_PATH=os.path.join(prefix, "lib", "pkgconfig"))
    flags = run(["pkg-config", "--cflags", "--libs", "retroprism"], env=env).split()
    pcBinary = os.path.join(work, "consumer_pkgconfig")
    run(["c++", "-std=c++17", "-O2", os.path.join(src, "main.cpp"), "-o", pcBinary] + flags)
    for how, binary in [("CMake", os.path.join(build, "consumer")), ("pkg-config", pcBinary)]:
        printed = run([binary]).split()
        if printed[0] != "f" or [float(v) for v in printed[1:]] != expected:
            fail(f"consumer built with {how} printed {printed}, retroprism eval {expected}")
    print(f"consumer (CMake and pkg-config) prints the command's f = {expected}")
    # retroprism::batch: the float node's answer within 1e-6 relative (glibc's vector exp and
    # erfc round differently from the scalar ones by a few ulp, 6e-8 relative each)
    answer32 = json.loads(run([cli, "eval", "--backend", "cpp-float", os.path.join(src, "query.json")]))
    expected32 = answer32["results"][0]["f"]
    printed = run([os.path.join(build, "consumer_batch")]).split()
    if printed[0] != "f" or any(abs(float(v) - e) > 1e-6 * abs(e) for v, e in zip(printed[1:], expected32)):
        fail(f"consumer_batch printed {printed}, retroprism eval --backend cpp-float {expected32}")
    print(f"consumer_batch (retroprism::batch) prints the float node's f = {expected32}")
    # retroprism::analysis and ::io, with their own dependencies, through the package
    material = os.path.join(share, "examples", "materials", "white_sign.json")
    table = run([os.path.join(build, "consumer_ra"), material]).split()
    csv = run([cli, "ra", "--csv", "--material", material]).split()[1:]
    if table != [",".join(row.split(",")[:2] + row.split(",")[3:4]) for row in csv]:
        fail(f"consumer_ra printed {table}, retroprism ra --csv {csv}")
    print(f"consumer_ra (retroprism::analysis) prints the command's R_A table of {material}")


def check_python(prefix, cli, work, era):
    site = glob.glob(os.path.join(prefix, "lib*", "python3*", "site-packages"))
    if len(site) != 1:
        fail(f"expected one site-packages under {prefix}, found {site}")
    sys.path.insert(0, site[0])
    import retroprism
    if not os.path.realpath(retroprism.__file__).startswith(os.path.realpath(prefix)):
        fail(f"imported {retroprism.__file__}, not the installed module")
    rng = np.random.default_rng(17)
    wi = rng.normal(size=(256, 3))
    wo = rng.normal(size=(256, 3))
    wi[:, 2] = np.abs(wi[:, 2])
    wo[:, 2] = np.abs(wo[:, 2])
    material = {"roughness": 0.1, "prism_reflection": "tir", "era_mode": "matched_pair"}
    query = os.path.join(work, "batch.json")
    with open(query, "w") as f:
        json.dump({"material": material,
                   "samples": [{"wi": list(a), "wo": list(b)} for a, b in zip(wi, wo)]}, f)
    node = retroprism.Node(material)
    for backend, dtype in [("cpp-double", np.float64), ("cpp-float", np.float32)]:
        results = json.loads(run([cli, "eval", "--backend", backend, query]))["results"]
        got = node.eval(wi.astype(dtype), wo.astype(dtype))
        for key in ["f", "surface", "retro", "diffuse", "pdf"]:
            want = np.array([r[key] for r in results], dtype=np.float64)
            if not np.array_equal(got[key].astype(np.float64), want):
                fail(f"python {dtype.__name__} {key} differs from retroprism eval --backend "
                     f"{backend}")
    if abs(retroprism.era(20, 10, "oriented") - era) > 5e-10:  # era prints 9 decimals
        fail("python era differs from retroprism era")
    print(f"python: import retroprism from {site[0]}; a batch of 256 equals retroprism eval "
          "bit for bit (float64 and float32)")


def check_no_source_path(prefix, source):
    for path in glob.glob(os.path.join(prefix, "**", "*"), recursive=True):
        binary = os.path.isfile(path) and (os.access(path, os.X_OK) or path.endswith(".so"))
        if binary:
            with open(path, "rb") as f:
                if source.encode() in f.read():
                    fail(f"{path} names the source folder {source}")
    print(f"no installed binary names {source}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("prefix")
    ap.add_argument("--source-path")
    ap.add_argument("--materialx", action="store_true")
    args = ap.parse_args()
    prefix = os.path.abspath(args.prefix)
    cli = os.path.join(prefix, "bin", "retroprism")
    share = os.path.join(prefix, "share", "retroprism")
    work = os.path.join(os.path.dirname(prefix), "verify")
    os.makedirs(work, exist_ok=True)
    if "RETROPRISM_DATA_DIR" in os.environ:
        fail("RETROPRISM_DATA_DIR is set: the installed tree must find its data alone")
    era = check_commands(prefix, cli, share, work, args.materialx)
    check_view(cli, share)
    check_consumer(prefix, cli, share, work)
    check_python(prefix, cli, work, era)
    if args.source_path:
        check_no_source_path(prefix, args.source_path)


if __name__ == "__main__":
    main()
