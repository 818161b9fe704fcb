#!/usr/bin/python3
"""-conduction_linear with ghost periodic images equals it with minimum images, to round-off.

The pair conduction's linear correction (-conduction_linear, src/pair/pair_diffusion.h)
gives each side of a pair its own first-order term, G_i . (x_i - x_j) with G_i particle i's
corrected temperature gradient; the two sides do not cancel. With minimum images every
pair joins two of the rank's particles. With -periodic_images ghost a pair across a
periodic face joins a particle and a ghost slot, whose side must be its source's: the slot
takes the source's G (gathered) and its side is folded onto the source. A slot that took
no side (as mirror images do: their side is the wall's) would lose that heat on every pair
across the face.

Run: the convection cell of options/convection.opts (32 x 16, periodic in x, mirror walls
in y, h = 3) with `-gas_scheme flow -conduction_linear -shift_compression`, at 3 Ra_c with
a seed of 0.01, to t = 60, once with each kind of image. Checked: the same output times and
steps, and kinetic energy, internal energy and the flow scheme's book (scheme_energy, which
carries the correction's heat) the same at every output to 1e-9 relative (of the book: of
the internal energy's scale). The two differ only in the order of the pair sums: round-off
(1e-16) grown by the adaptive integrator over the run's steps; 1e-9 leaves that margin and
is far below what a lost side gives.

Measured (30 steps): kinetic energy 7.5e-11 (the seed's kinetic energy is a small
difference of large pair forces), internal energy below the 13 digits of timeseries.csv,
book 7e-16. With the ghost slots' sides left out (a trial build): kinetic energy 1.9,
internal energy 2.9e-3, book 3.9e-3."""
import os

import numpy as np

from spamrun import Checks, arguments, run, table

OPTIONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "convection.opts")
RA = 3 * 1700.79
TOL = 1e-9


def main():
    a = arguments()
    c = Checks()
    series = {}
    for images in ("minimum", "ghost"):
        out = os.path.join(a.workdir, images)
        args = ["-options_file", OPTIONS, "-convection_ra", RA, "-convection_amplitude", 0.01, "-ts_max_time", 60,
                "-output_interval", 6, "-snapshot_interval", 0, "-periodic_images", images,
                "-gas_scheme", "flow", "-conduction_linear", "-shift_compression"]
        code, _, err = run(a.spam_ark, args, out)
        if not c.check(code == 0, f"-periodic_images {images}: run completes (exit {code}) {err.strip()[-300:]}"):
            c.finish()
        series[images] = {k: np.array(v, dtype=float) for k, v in table(os.path.join(out, "timeseries.csv")).items()}
    m, g = series["minimum"], series["ghost"]
    same = len(m["t"]) == len(g["t"]) and np.array_equal(m["t"], g["t"]) and np.array_equal(m["step"], g["step"])
    c.check(same, f"the same output times and steps ({len(m['t'])} outputs, {int(m['step'][-1])} steps)")
    if same:
        scale = np.abs(m["internal"])
        for key, ref in (("kinetic", np.abs(m["kinetic"])), ("internal", scale), ("scheme_energy", scale)):
            diff = float(np.max(np.abs(g[key] - m[key]) / ref))
            c.check(diff < TOL, f"{key}: ghost images = minimum images to {diff:.1e} relative (bound {TOL:g})")
    c.finish()


if __name__ == "__main__":
    main()
