#!/usr/bin/python3
"""Write a particle file for -scene file: two discs of gas flying at each other.

    examples/make_two_drops.py [-o examples/particles/two_drops.csv] [--radius 8] [--speed 2]

Each disc holds the points of the unit square lattice within --radius of its centre, one
unit mass each, at rest but for the velocity +-speed along x. The box is 64 x 32 and
periodic (pass -box_len 64,32 to spam-ark). The file's header names its columns
(x,y,vx,vy,m,id); see docs/outputs.md, "Particle files", for every column spam-ark reads.
This is the script docs/tutorial.md starts from: change it to pose your own problem.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import spamread  # noqa: E402

import numpy as np  # noqa: E402

BOX = (64.0, 32.0)


def disc(cx, cy, radius):
    r = int(np.ceil(radius))
    g = np.arange(-r, r + 1, dtype=float)
    x, y = np.meshgrid(g, g, indexing="ij")
    inside = x * x + y * y <= radius * radius
    return cx + x[inside], cy + y[inside]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                        "particles", "two_drops.csv"))
    ap.add_argument("--radius", type=float, default=8.0)
    ap.add_argument("--speed", type=float, default=2.0)
    a = ap.parse_args()
    if not 0 < a.radius < BOX[1] / 2 - 1:
        ap.error("--radius must lie in (0, %g)" % (BOX[1] / 2 - 1))
    xl, yl = disc(BOX[0] / 4 + 0.5, BOX[1] / 2 + 0.5, a.radius)
    xr, yr = disc(3 * BOX[0] / 4 + 0.5, BOX[1] / 2 + 0.5, a.radius)
    x, y = np.concatenate([xl, xr]), np.concatenate([yl, yr])
    vx = np.concatenate([np.full(len(xl), a.speed), np.full(len(xr), -a.speed)])
    spamread.write_particles(a.out, {"x": x, "y": y, "vx": vx, "vy": np.zeros_like(x),
                                     "m": np.ones_like(x), "id": np.arange(len(x))})
    print("wrote %s: %d particles in a %g x %g box" % (a.out, len(x), BOX[0], BOX[1]))


if __name__ == "__main__":
    main()
