#!/usr/bin/env python3
"""Write data/sample-carpaint.csv, the sample measurement of libbrdffit.

The file is SYNTHETIC: no instrument measured it. It imitates a red metallic
car paint in the thesis's grid layout (docs/definitions.md, Geometry): a Lambert base, a
broad Ashikhmin-Shirley lobe standing in for the metallic flakes and a sharp
Ashikhmin-Shirley lobe standing in for the clear coat, with 1.5 %
multiplicative Gaussian noise from a fixed seed. Only the Python standard
library is used, so the file can be regenerated anywhere:

    python3 data/make_sample.py data/sample-carpaint.csv

Without an argument the CSV goes to standard output.
"""
import math
import random
import sys

SEED = 20170
NOISE = 0.015  # relative standard deviation of the multiplicative noise
FLOOR = 1e-4  # floor of the dot products, as in the library (docs/definitions.md, Geometry)

CD = (0.10, 0.012, 0.010)  # Lambert base colour (times 1/pi)
FLAKE_NS, FLAKE_CS = 35.0, (0.30, 0.05, 0.035)  # broad coloured lobe
COAT_NS, COAT_CS = 1200.0, (0.04, 0.04, 0.04)  # sharp white lobe

THETA_I = [5.0 * k for k in range(19)]  # 0 .. 90 deg step 5
THETA_O = [2.5 * k for k in range(37)]  # 0 .. 90 deg step 2.5
PHI_O = [180.0 * k / 35 for k in range(36)]  # 0 .. 180 deg in 36 values


def clamp(x):
    return min(max(x, FLOOR), 1.0)


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))


def lobe(ns, nh, hv, nl, nv):
    """Ashikhmin-Shirley specular term without colour (docs/models.md)."""
    return (ns + 1.0) / (8.0 * math.pi) * nh ** ns / (hv * max(nl, nv))


def brdf(ti, to, po):
    l = direction(ti, 180.0)  # the light sits at azimuth 180 deg
    v = direction(to, po)
    h = [a + b for a, b in zip(l, v)]
    norm = math.sqrt(sum(x * x for x in h))
    h = [x / norm for x in h]
    nl, nv, nh = clamp(l[2]), clamp(v[2]), clamp(h[2])
    hv = clamp(sum(a * b for a, b in zip(h, v)))
    flake = lobe(FLAKE_NS, nh, hv, nl, nv)
    coat = lobe(COAT_NS, nh, hv, nl, nv)
    return [CD[c] / math.pi + FLAKE_CS[c] * flake + COAT_CS[c] * coat for c in range(3)]


HEADER = """\
# SYNTHETIC DATA - NOT A REAL MEASUREMENT.
# A made-up, car-paint-like BRDF for the examples and tests of libbrdffit,
# written by data/make_sample.py (Python standard library only):
#   f_c = cd_c / pi + flake_c * AS(35) + coat_c * AS(1200),
#   AS(ns) = (ns + 1) / (8 pi) (n.h)^ns / ((h.v) max(n.l, n.v)),
#   cd = (0.10, 0.012, 0.010), flake = (0.30, 0.05, 0.035), coat = (0.04, 0.04, 0.04):
#   a Lambert base, a broad metallic-flake-like lobe and a sharp clear-coat-like lobe,
#   each value times (1 + 0.015 g), g standard normal from Python's random.gauss, seed 20170.
# Layout of the thesis: light at azimuth 180 deg, theta_i 0..90 deg step 5,
# theta_o 0..90 deg step 2.5, phi_o 0..180 deg in 36 values; angles in degrees,
# values in 1/sr, 6 significant digits.
# Regenerate: python3 data/make_sample.py data/sample-carpaint.csv
theta_i,theta_o,phi_o,r,g,b
"""


def write(out):
    rng = random.Random(SEED)
    out.write(HEADER)
    for ti in THETA_I:
        for to in THETA_O:
            for po in PHI_O:
                values = [max(f * (1.0 + NOISE * rng.gauss(0.0, 1.0)), 0.0)
                          for f in brdf(ti, to, po)]
                out.write("%g,%g,%r,%s\n" % (ti, to, po,
                                            ",".join("%.6g" % x for x in values)))


def main(argv):
    if len(argv) > 2:
        sys.stderr.write("usage: make_sample.py [OUT.csv]\n")
        return 2
    if len(argv) == 2:
        with open(argv[1], "w", newline="\n") as out:
            write(out)
    else:
        write(sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
