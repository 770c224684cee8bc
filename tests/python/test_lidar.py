"""[python] retroprism.lidar_return and retroprism.aperture_reflectance against `retroprism lidar`
and their own contracts (analysis/lidar.h)."""
import json
import math
import os
import subprocess

import pytest

import retroprism

CLI = os.environ["RETROPRISM_CLI"]
PLATE = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "materials",
                     "microprismatic_160um.json")


def plate():
    with open(PLATE) as f:
        return retroprism.Node(json.load(f))


def test_lidar_return_answers_the_command():
    r = retroprism.lidar_return(plate(), wavelength=1550, range=50, entrance=30)
    out = subprocess.run([CLI, "lidar", "plate=" + PLATE, "--wavelength", "1550", "--range", "50",
                          "--entrance", "30", "--csv"], capture_output=True, text=True, check=True)
    row = [line for line in out.stdout.splitlines() if line.startswith("plate,")][0].split(",")
    # The CSV's 7 significant digits.
    assert float(row[5]) == pytest.approx(r["fraction"], rel=1e-6)
    assert float(row[6]) == pytest.approx(r["reflectance"], rel=1e-6)
    assert float(row[8]) == pytest.approx(r["albedo"], rel=1e-6)


def test_lambertian_reading_and_retroreflection():
    # The plate reads far above its albedo at 20 m; the beam falls whole on a target larger than
    # the footprint; the observation angle is the offset's at the range.
    r = retroprism.lidar_return(plate(), range=20)
    assert r["reflectance"] > 10 * r["albedo"]
    # The footprint's Gauss-Legendre rule integrates the Gaussian beam to 3e-8.
    assert r["intercepted"] == pytest.approx(1.0, abs=1e-6)
    assert r["observation_mrad"] == pytest.approx(1e3 * math.atan(0.03 / 20), rel=1e-9)


def test_aperture_reflectance_is_positive_in_front_and_zero_behind():
    args = dict(wavelength=905, position=(0, 0, 10), tangent=(1, 0, 0), emitter=(0, 0, 0),
                centre=(0.03, 0, 0), axis=(0, 0, 1), diameter=0.025)
    assert retroprism.aperture_reflectance(plate(), normal=(0, 0, -1), **args) > 0
    assert retroprism.aperture_reflectance(plate(), normal=(0, 0, 1), **args) == 0


@pytest.mark.parametrize("kwargs,message", [
    (dict(range=-1), "--range -1: must be in [0.1, 100000] m"),
    (dict(wavelength=3000), "--wavelength 3000: must be in (0, 2000] nm"),
    (dict(divergence=0), "--divergence 0: must be in (0, 100] mrad"),
    (dict(size=(1, 0)), "--size 1,0: width and height must both be in"),
])
def test_bad_inputs_raise_naming_the_input(kwargs, message):
    with pytest.raises(ValueError, match=".*" + message.replace("(", r"\(").replace(")", r"\)")
                       .replace("[", r"\[").replace("]", r"\]")):
        retroprism.lidar_return(plate(), **kwargs)
