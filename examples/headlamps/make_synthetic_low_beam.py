#!/usr/bin/env python3
"""Writes synthetic_low_beam.ies (IES LM-63-2002, photometric type A) and synthetic_low_beam.ldt
(EULUMDAT, C-gamma) from one analytic model of a low beam. SYNTHETIC: the shape of a low beam,
not a measured or published lamp.

The model, in the lamp's frame of io/luminaire.h (H to the right, V up, degrees):
  - a hot spot below the horizon, right of straight ahead: 15000 cd, a Gaussian centred at
    H = 2, V = -1.5 (sigma 4 across, 1.2 up and down);
  - a wide spread: 4000 cd, a Gaussian centred at H = 0, V = -2 (sigma 18 across, 3 up and down);
  - a cut-off: the two above are multiplied by a logistic step of width 0.15 degrees at the
    cut-off line, horizontal at V = -0.57 on the left (the oncoming side) and rising at 15 degrees
    to the right of H = 0 up to V = +1 (the kinked cut-off of European low beams, which keeps
    light off oncoming drivers and lifts it toward the near-side shoulder);
  - above the cut-off a glare floor: 250 cd, falling with H as a Gaussian of sigma 20 and with V
    as exp(-V / 8), which is what lights overhead signs.
Intensities are those of one lamp; the vehicle has two (`approach --headlamps`).
Run from this folder: python3 make_synthetic_low_beam.py
"""
import math


def cutoff_v(h):
    return -0.57 if h <= 0 else min(1.0, -0.57 + math.tan(math.radians(15)) * h)


def intensity(h, v):
    below = 15000 * math.exp(-0.5 * (((h - 2) / 4) ** 2 + ((v + 1.5) / 1.2) ** 2)) + \
        4000 * math.exp(-0.5 * ((h / 18) ** 2 + ((v + 2) / 3) ** 2))
    step = 1 / (1 + math.exp((v - cutoff_v(h)) / 0.15))
    glare = 250 * math.exp(-0.5 * (h / 20) ** 2) * math.exp(-max(v, 0) / 8)
    return below * step + glare


def type_a_angles(x, y, z):
    """Type A angles (io/luminaire.h) of a direction in the lamp's frame."""
    return math.degrees(math.atan2(x, z)), math.degrees(math.atan2(y, math.hypot(x, z)))


def frange(a, b, step):
    n = int(round((b - a) / step))
    return [round(a + k * step, 6) for k in range(n + 1)]


def fmt(v):
    return "%.1f" % v


def angle(a):
    return "%g" % a


def wrapped(values, per_line=10):
    """LM-63 lines stay under 256 characters: values continue on the next line."""
    return [" ".join(values[k:k + per_line]) for k in range(0, len(values), per_line)]


def write_ies(path):
    hs = frange(-60, -10, 2) + frange(-9, 9, 1)[0:] + frange(10, 60, 2)
    hs = sorted(set(hs))
    vs = sorted(set(frange(-20, -4, 2) + frange(-3, 3, 0.25) + frange(4, 30, 2)))
    lines = ["IESNA:LM-63-2002",
             "[TEST] none: synthetic",
             "[MANUFAC] retroprism examples",
             "[LUMCAT] synthetic_low_beam",
             "[LUMINAIRE] SYNTHETIC low beam (one lamp), not a measured or published lamp",
             "[OTHER] Made by make_synthetic_low_beam.py: a hot spot of 15000 cd at 1.5D 2R, a",
             "[MORE] 4000 cd spread, a cut-off at 0.57D rising 15 degrees on the right, 250 cd",
             "[MORE] above it. Type A: H to the right, V up (io/luminaire.h).",
             "TILT=NONE",
             "1 -1 1 %d %d 3 2 0 0 0" % (len(vs), len(hs)),
             "1 1 0"]
    lines += wrapped([angle(v) for v in vs])
    lines += wrapped([angle(h) for h in hs])
    for h in hs:
        lines += wrapped([fmt(intensity(h, v)) for v in vs])
    open(path, "w").write("\n".join(lines) + "\n")


def write_ldt(path):
    cs = sorted(set(frange(0, 60, 1) + frange(70, 290, 10) + frange(300, 359, 1)))
    gs = sorted(set(frange(0, 70, 10) + frange(72, 86, 2) + frange(87, 93, 0.25) +
                    frange(94, 120, 2) + frange(130, 180, 10)))
    out = ["retroprism examples: SYNTHETIC low beam (make_synthetic_low_beam.py), not a real lamp",
           "1", "0", str(len(cs)), "0", str(len(gs)), "0",
           "none: synthetic", "synthetic_low_beam", "synthetic_low_beam",
           "synthetic_low_beam.ldt", "retroprism examples",
           "100", "150", "100", "90", "140", "0", "0", "0", "0",
           "100", "100", "1", "0",
           "1", "1", "SYNTHETIC low beam", "1000", "4000", "70", "55"]
    out += ["0"] * 10
    out += [angle(c) for c in cs] + [angle(g) for g in gs]
    for c in cs:
        for g in gs:
            # C-gamma (io/luminaire.h): C counter-clockwise from ahead toward the left.
            cr, gr = math.radians(c), math.radians(g)
            d = (-math.sin(gr) * math.sin(cr), -math.cos(gr), math.sin(gr) * math.cos(cr))
            h, v = type_a_angles(*d)
            out.append(fmt(intensity(h, v) if abs(h) <= 90 else 0.0))
    open(path, "w").write("\r\n".join(out) + "\r\n")


if __name__ == "__main__":
    write_ies("synthetic_low_beam.ies")
    write_ldt("synthetic_low_beam.ldt")
