#!/usr/bin/env python3
"""Nusselt number against Rayleigh number of the spam-ark Rayleigh-Benard cell.

Usage:
    python3 examples/convection_sweep.py --spam-ark build/spam-ark [--workdir DIR]
        [--ratios 0.5,0.8,1.2,1.6,2,3,4,5] [--nx 32 --ny 16] [--t-end T] [--amplitude A] [-o OUT.png]

Runs -scene convection (options/convection.opts: T_b = 1.25, T_t = 0.75, Pr = 1,
g = 0.1 c_p / H) at Ra = ratio x 1707.76 (the superadiabatic Rayleigh number), each to
t_end (default: the scene's, one thermal diffusion time H^2/chi, times --diffusion-times),
and takes Nu = (mean heat flux through the walls) / (kappa (T_b - T_t) / H) averaged
over the last half of each run (examples/plot_convection.py, nusselt()). The chart has
Nu against Ra / Ra_c with the continuum onset (rigid-rigid walls, Boussinesq: 1707.76)
marked. Prints one line per run: ratio Ra Nu Nu_bottom Nu_top ke_final ms_per_rhs.
"""

import argparse
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_convection as pc  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def run_one(a, ratio):
    out = os.path.join(a.workdir, f"ra{ratio:g}")
    args = [a.spam_ark, "-options_file", os.path.join(HERE, "..", "options", "convection.opts"),
            "-convection_nx", a.nx, "-convection_ny", a.ny, "-convection_g", 0.1 * 2.0 / a.ny,
            "-convection_ra", ratio * pc.RA_CRITICAL, "-convection_amplitude", a.amplitude, "-snapshot_interval", 0,
            "-output_dir", out, "-output_overwrite", "-output_interval", a.t_end / 200 if a.t_end else 20]
    if a.t_end:
        args += ["-ts_max_time", a.t_end]
    args = [str(x) for x in args]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"run failed ({p.returncode}): {' '.join(args)}\n{p.stderr[-2000:]}")
    m = re.search(r"convection: Ra = ([0-9.eE+-]+)", p.stdout)
    summary, series, _ = pc.load(out)
    t_end = series["t"][-1]
    nu, nub, nut, _ = pc.nusselt(summary, series, a.t_bottom, a.t_top, 0.5 * t_end)
    ms = 1e3 * summary["rhs_time_s"] / summary["rhs_evals"]
    return float(m.group(1)), nu, nub, nut, series["kinetic"][-1], ms


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", required=True)
    ap.add_argument("--workdir", default="out/convection_sweep")
    ap.add_argument("--ratios", default="0.5,0.8,1.2,1.6,2,3,4,5")
    ap.add_argument("--nx", type=int, default=32)
    ap.add_argument("--ny", type=int, default=16)
    ap.add_argument("--t-end", type=float, default=0.0, help="end time of every run (0: the options file's)")
    ap.add_argument("--amplitude", type=float, default=0.01, help="-convection_amplitude of every run (the seeded kick)")
    ap.add_argument("--t-bottom", type=float, default=1.25)
    ap.add_argument("--t-top", type=float, default=0.75)
    ap.add_argument("-o", "--out", default=None)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ratios = [float(r) for r in a.ratios.split(",")]
    results = []
    print("ratio Ra Nu Nu_bottom Nu_top ke_final ms_per_rhs")
    for r in ratios:
        ra, nu, nub, nut, ke, ms = run_one(a, r)
        results.append((ra, nu, nub, nut))
        print(f"{r:g} {ra:.6g} {nu:.5f} {nub:.5f} {nut:.5f} {ke:.5g} {ms:.4f}", flush=True)

    fig, ax = plt.subplots(figsize=(7, 4.8))
    x = [ra / pc.RA_CRITICAL for ra, *_ in results]
    ax.semilogx(x, [r[1] for r in results], "C3-o", label="SPAM: mean of both walls")
    ax.plot(x, [r[2] for r in results], "C1v", ms=5, label="SPAM: hot wall")
    ax.plot(x, [r[3] for r in results], "C0^", ms=5, label="SPAM: cold wall")
    ax.axvline(1.0, color="k", ls="--", lw=1, label="continuum onset Ra_c = 1707.76 (rigid walls)")
    ax.axhline(1.0, color="0.5", ls=":", lw=1, label="conduction Nu = 1")
    ax.set_xlabel("Ra / Ra_c (superadiabatic Rayleigh number over 1707.76)")
    ax.set_ylabel("Nusselt number Nu")
    ax.set_title(f"scene convection: Nu against Ra ({a.nx} x {a.ny} lattice, Pr = 1, T_b = {a.t_bottom:g}, T_t = {a.t_top:g}, kick {a.amplitude:g} c_s)", fontsize=9)
    ax.legend(fontsize=8)
    out = a.out or os.path.join(a.workdir, "convection_nu_ra.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"png={out}")


if __name__ == "__main__":
    main()
