#!/usr/bin/python3
"""-conduction_linear on 2 ranks equals it on 1 rank, to round-off.

The pair conduction's linear correction (-conduction_linear, src/pair/pair_diffusion.h)
gives each side of a pair its own first-order term, G_i . (x_i - x_j) with G_i particle i's
corrected temperature gradient; the two sides do not cancel. A pair across two ranks is
computed on both, each rank for its own particle with the same operands (docs/parallel.md):
each side is taken once, on its particle's rank, and the halo carries G to the remote slots
with the other gathered fields. A side lost (or taken twice) across the cut would move the
heat of every such pair.

Run: the convection cell of options/convection.opts (32 x 16, periodic in x, mirror walls
in y, h = 3) with `-gas_scheme flow -conduction_linear -shift_compression`, at 3 Ra_c with
a seed of 0.01, fixed steps (ERKStep's Dormand-Prince 5(4), dt = 1, as tests/run_ranks.py
runs the cell) to t = 60, on 1 and 2 ranks. Checked: kinetic energy, internal energy and
the flow scheme's book (scheme_energy, which carries the correction's heat) the same at
every output row to 1e-11 relative (the book and the internal energy of the internal
energy's scale), the bound of tests/run_ranks.py (a): the ranks sum a particle's pairs in
another order (remote partners are walked newton-off), so one RHS differs by a few ulp
(~1e-15 relative), carried through 360 stage evaluations of a short run that is not
chaotic; 1e-11 leaves a factor 100 of growth. A lost side moves these by one pair's
share of the correction's heat, orders above (measured below).
Not checked bitwise: -reproducible refuses the gas model's tensor-path passes, which are
the flow scheme's at the one smoothing length -conduction_linear needs ("the gas model's
tensor-path passes sum their pairs in list order"): no flow-scheme field is bitwise across
ranks, and -reproducible refuses mirror walls as well (docs/parallel.md).

Measured (fixed steps, 60 steps): kinetic and internal energy the same to the 13 digits of
timeseries.csv, book 2e-17 relative. With the correction left out of the pairs across the
cut (a trial build): kinetic energy 14 relative (the seed's kinetic energy is a small
difference of large pair forces), internal energy 3.2e-4, book 1.1e-3."""
import os
import subprocess

import numpy as np

from spamrun import Checks, arguments, mpiexec_env, brief, rank_command, table

OPTIONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "convection.opts")
RA = 3 * 1700.79
TOL = 1e-11


def main():
    a = arguments()
    c = Checks()
    mpiexec, env0 = mpiexec_env()
    series = {}
    for ranks in (1, 2):
        out = os.path.join(a.workdir, f"np{ranks}")
        args = ["-options_file", OPTIONS, "-convection_ra", RA, "-convection_amplitude", 0.01, "-ts_max_time", 60,
                "-arkode_fixed_step", 1.0, "-output_interval", 6, "-snapshot_interval", 0,
                "-gas_scheme", "flow", "-conduction_linear", "-shift_compression", "-output_dir", out, "-output_overwrite"]
        cmd, env = rank_command(mpiexec, env0, ranks, a.spam_ark, args)
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
        if not c.check(p.returncode == 0, f"{ranks} rank(s): run completes (exit {p.returncode}) {brief(p.stderr)}"):
            c.finish()
        series[ranks] = {k: np.array(v, dtype=float) for k, v in table(os.path.join(out, "timeseries.csv")).items()}
    one, two = series[1], series[2]
    same = len(one["t"]) == len(two["t"]) and np.array_equal(one["t"], two["t"]) and np.array_equal(one["step"], two["step"])
    c.check(same, f"the same output times and steps ({len(one['t'])} outputs, {int(one['step'][-1])} steps)")
    if same:
        scale = np.abs(one["internal"])
        for key, ref in (("kinetic", np.abs(one["kinetic"])), ("internal", scale), ("scheme_energy", scale)):
            diff = float(np.max(np.abs(two[key] - one[key]) / ref))
            c.check(diff < TOL, f"{key}: 2 ranks = 1 rank to {diff:.1e} relative (bound {TOL:g})")
    c.finish()


if __name__ == "__main__":
    main()
