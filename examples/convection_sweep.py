#!/usr/bin/python3
"""Nusselt number against Rayleigh number of the spam-ark Rayleigh-Benard cell.

Usage:
    examples/convection_sweep.py --spam-ark build/spam-ark [--workdir DIR]
        [--ratios 0.5,0.8,1.2,1.6,2,3,4,5] [--nx 32 --ny 16] [--t-end T] [--amplitude A]
        [--variant NAME="OPTIONS" ...] [-o OUT.png] [--readings]

Runs -scene convection (options/convection.opts: T_b = 1.25, T_t = 0.75, Pr = 1,
g = 0.1 c_p / H) at Ra = ratio x 1707.76 (the superadiabatic Rayleigh number), each to
t_end (default: the scene's, one thermal diffusion time H^2/chi, times --diffusion-times),
and takes Nu = (mean heat flux through the walls) / (kappa (T_b - T_t) / H) averaged
over the last half of each run (examples/plot_convection.py, nusselt()). The chart has
Nu against Ra / Ra_c with the continuum onset (rigid-rigid walls, Boussinesq: 1707.76)
marked. Each --variant NAME="OPTIONS" (repeatable; default one variant, "default", with no
options) runs every ratio with those options added; each variant has its own colour and
marker, and a run that fails (say exit 3, unstable) is drawn as a cross on Nu = 1 and
listed. Prints one line per run: variant ratio Ra Nu Nu_bottom Nu_top ke_final ms_per_rhs.
With --readings, the runs and a table of Nu (hot, cold wall) per ratio and variant are
written beside the chart (OUT.json, examples/chart_readings.py) for the pages' markers.
"""

import argparse
import os
import re
import shlex
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import plot_convection as pc  # noqa: E402
import convection_linear  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


STYLES = [("C3", "o"), ("C0", "s"), ("C2", "^"), ("C1", "D"), ("C4", "v")]


def run_one(a, ratio, name, extra):
    """(Ra, Nu, Nu_bottom, Nu_top, KE_final, ms per RHS) of one run, or None when it fails."""
    out = os.path.join(a.workdir, name, f"ra{ratio:g}")
    args = [a.spam_ark, "-options_file", os.path.join(HERE, "..", "options", "convection.opts"),
            "-convection_nx", a.nx, "-convection_ny", a.ny, "-convection_g", 0.1 * 2.0 / a.ny,
            "-convection_ra", ratio * pc.RA_CRITICAL, "-convection_amplitude", a.amplitude, "-snapshot_interval", 0,
            "-output_dir", out, "-output_overwrite", "-output_interval", a.t_end / 200 if a.t_end else 20]
    if a.t_end:
        args += ["-ts_max_time", a.t_end]
    args = [str(x) for x in args] + extra
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        print(f"run failed (exit {p.returncode}): {' '.join(args)}: {p.stderr.strip()[-300:]}", file=sys.stderr)
        return None
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
    ap.add_argument("--variant", action="append", default=None, help='NAME="OPTIONS" run at every ratio (repeatable)')
    ap.add_argument("-o", "--out", default=None)
    ap.add_argument("--readings", action="store_true", help="write the runs and the table beside the chart (OUT.json)")
    a = ap.parse_args()
    variants = []
    for v in a.variant or ["default="]:
        name, _, opts = v.partition("=")
        if not name or not re.fullmatch(r"[A-Za-z0-9_.+-]+", name):
            sys.exit(f"convection_sweep: error: --variant {v!r}: NAME=OPTIONS with a plain NAME")
        variants.append((name, shlex.split(opts)))
    if len(variants) > len(STYLES):
        sys.exit(f"convection_sweep: error: at most {len(STYLES)} variants")
    os.makedirs(a.workdir, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ratios = [float(r) for r in a.ratios.split(",")]
    fig, ax = plt.subplots(figsize=(7.5, 5))
    print("variant ratio Ra Nu Nu_bottom Nu_top ke_final ms_per_rhs")
    runs = {}
    for (name, extra), (colour, marker) in zip(variants, STYLES):
        ok, failed = [], []
        for r in ratios:
            got = run_one(a, r, name, extra)
            if got is None:
                failed.append(r)
                print(f"{name} {r:g} failed", flush=True)
                continue
            ra, nu, nub, nut, ke, ms = got
            ok.append((r, nu, nub, nut))
            runs.setdefault(name, {})[f"{r:g}".replace(".", "_")] = {"ratio": r, "Ra": ra, "Nu": nu, "Nu_bottom": nub,
                                                                   "Nu_top": nut, "wall_difference": nut - nub, "ke_final": ke}
            print(f"{name} {r:g} {ra:.6g} {nu:.5f} {nub:.5f} {nut:.5f} {ke:.5g} {ms:.4f}", flush=True)
        label = f"{name}: {' '.join(extra)}" if extra else name
        ax.semilogx([x[0] for x in ok], [x[1] for x in ok], "-", color=colour, marker=marker, label=f"{label} (mean of both walls)")
        ax.plot([x[0] for x in ok] * 2, [x[2] for x in ok] + [x[3] for x in ok], "_", color=colour, ms=9)
        if failed:
            ax.plot(failed, [1.0] * len(failed), "x", color=colour, ms=10, mew=2, label=f"{name}: run failed")
    ax.plot([], [], "_", color="0.3", ms=9, label="bars: hot and cold wall")
    cell = convection_linear.Cell(nx=a.nx, ny=a.ny, g=0.1 * 2.0 / a.ny, t_bottom=a.t_bottom, t_top=a.t_top)
    ra_cell, _ = convection_linear.cell_critical(cell)
    ax.axvline(1.0, color="k", ls="--", lw=1, label="continuum onset, rigid walls, Boussinesq (1707.76)")
    ax.axvline(ra_cell / pc.RA_CRITICAL, color="k", ls=":", lw=1.2, label=f"onset of this compressible cell, linear theory ({ra_cell:.2f})")
    print(f"linear theory of the cell: Ra_c = {ra_cell:.6g} ({ra_cell / pc.RA_CRITICAL:.4f} of 1707.76)")
    ax.axhline(1.0, color="0.5", ls=":", lw=1, label="conduction Nu = 1")
    ax.set_xlabel("Ra / Ra_c (superadiabatic Rayleigh number over 1707.76)")
    ax.set_ylabel("Nusselt number Nu")
    ax.set_title(f"scene convection: Nu against Ra ({a.nx} x {a.ny} lattice, Pr = 1, T_b = {a.t_bottom:g}, T_t = {a.t_top:g}, kick {a.amplitude:g} c_s)", fontsize=9)
    ax.legend(fontsize=8)
    out = a.out or os.path.join(a.workdir, "convection_nu_ra.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"png={out}")
    if a.readings:
        import chart_readings

        def cell(name, r):
            x = runs.get(name, {}).get(f"{r:g}".replace(".", "_"))
            return f"{x['Nu']:.4f} ({x['Nu_bottom']:.4f}, {x['Nu_top']:.4f})" if x else "failed"
        chart_readings.write(out, {"runs": runs, "table": chart_readings.table(
            ["Ra / Ra_c"] + [f"Nu, {name} (hot, cold wall)" for name, _ in variants],
            [[f"{r:g}"] + [cell(name, r) for name, _ in variants] for r in ratios])})


if __name__ == "__main__":
    main()
