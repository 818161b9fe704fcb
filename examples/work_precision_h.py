#!/usr/bin/python3
"""Work-precision of the kernel range's modes on a small Sedov blast (2D), or on the gas
of the free expansion (--scene expansion: no shock, no viscosity, -h_max 3).

Usage:
    /usr/bin/python3 examples/work_precision_h.py --spam-ark build/spam-ark --workdir DIR
        [--n 48] [--t-end 1] [--rtols 1e-3,...] [--ref-rtol 1e-10] [--png FILE] [--readings FILE]

For -smoothing_length fixed (one h), adaptive (h_i solved in every right-hand side by
Newton's method on rho_i h_i^D = eta^D m_i, to -h_tol 1e-10 of the relation, and once
with -h_tol tied to the run's rtol, h_tol = rtol) and evolved (h_i in the state,
dh_i/dt = -h_i/(D rho_i) drho_i/dt): runs of options/sedov.opts at -sedov_n N to t_end
with its method (ARKODE's default table) at each -ts_rtol (atol = rtol/1000), and one at
the reference tolerance (the tied series takes the adaptive reference: the same equations
solved tightly). The error of a run is the rms over particles of the distance of its
final positions from the reference run's of the same mode, in units of h (each mode is
measured against itself: the three modes solve different equations). The work is the
right-hand-side evaluations and the CPU time of the run (its rhs_s + the rest, summary.json's
wall time on one rank: the same load for all, so the ratios hold; the load is written).
The slope of log(error) against log(rtol) is fitted over all the tolerances and over
rtol <= 1e-5: 1 is an error proportional to the tolerance; a flattening at the tight end
is a plateau (a right-hand side noisier than the tolerance). A failed run is drawn as such.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

import chart_readings  # noqa: E402
from chart_style import UNSTABLE  # noqa: E402

# label: (-smoothing_length, extra options at rtol, the label whose reference run it takes)
SERIES = {
    "fixed": ("fixed", lambda rtol: [], "fixed"),
    "adaptive": ("adaptive", lambda rtol: [], "adaptive"),
    "adaptive, h_tol = rtol": ("adaptive", lambda rtol: ["-h_tol", repr(rtol)], "adaptive"),
    "evolved": ("evolved", lambda rtol: [], "evolved"),
}
STYLE = {"fixed": ("#1f77b4", "o"), "adaptive": ("#d62728", "s"), "adaptive, h_tol = rtol": ("#ff7f0e", "v"),
         "evolved": ("#2ca02c", "D")}


def final_positions(path, dim):
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    head, body = rows[0], rows[1:]
    cols = [head.index(a) for a in "xyz"[:dim]]
    return np.array([[float(r[c]) for c in cols] for r in body])


def one_run(a, label, rtol):
    mode, extra, _ = SERIES[label]
    out = os.path.join(a.workdir, f"{label.replace(' ', '').replace(',', '_').replace('=', '')}_{rtol:g}")
    final = os.path.join(out, "final.csv")
    os.makedirs(out, exist_ok=True)
    if a.scene == "sedov":
        scene = ["-options_file", os.path.join(HERE, "..", "options", "sedov.opts"), "-sedov_n", str(a.n), "-h", repr(a.h)]
    else:  # the gas of the free expansion: smooth, no viscosity (tests/run_expansion_entropy.py)
        scene = ["-scene", "expansion", "-dim", "2", "-expansion_n", str(a.n), "-h", repr(a.h), "-material", "gas",
                 "-gas_gamma", "2", "-gas_e0", "0.5", "-viscosity", "none"] + (["-h_max", "3"] if mode != "fixed" else [])
    cmd = [a.spam_ark] + scene + ["-ts_max_time", repr(a.t_end), "-ts_rtol", repr(rtol), "-ts_atol", repr(rtol * 1e-3),
           "-smoothing_length", mode] + extra(rtol) + ["-output_interval", "0", "-snapshot_interval", "0",
           "-final_csv", final, "-output_dir", out, "-output_overwrite", "-quiet"]
    c0 = os.times()
    p = subprocess.run(cmd, capture_output=True, text=True)
    c1 = os.times()
    cpu = (c1.children_user - c0.children_user) + (c1.children_system - c0.children_system)
    if p.returncode:
        return {"ok": False, "why": (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]}
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return {"ok": True, "x": final_positions(final, 2), "rhs": s["rhs_evals"], "cpu": cpu,
            "steps": s.get("steps"), "energy_drift": s.get("energy_rel_drift_max")}


def Slope(pairs):
    """The slope of log10(error) against log10(rtol), least squares (None below two points)."""
    if len(pairs) < 2:
        return None
    return float(np.polyfit(np.log10([t for t, _ in pairs]), np.log10([r["err"] for _, r in pairs]), 1)[0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spam-ark", required=True)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--scene", choices=("sedov", "expansion"), default="sedov")
    ap.add_argument("--n", type=int, default=48)
    ap.add_argument("--h", type=float, default=3.0)
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--rtols", default="1e-3,3e-4,1e-4,3e-5,1e-5,3e-6,1e-6,3e-7,1e-7")
    ap.add_argument("--ref-rtol", type=float, default=1e-10)
    ap.add_argument("--series", default=";".join(SERIES), help="labels of SERIES, separated by ;")
    ap.add_argument("--png", default=None)
    ap.add_argument("--readings", default=None)
    a = ap.parse_args()
    os.makedirs(a.workdir, exist_ok=True)
    rtols = [float(r) for r in a.rtols.split(",")]
    labels = a.series.split(";")
    res, refs, readings = {}, {}, {"scene": a.scene, "n": a.n, "h": a.h, "t_end": a.t_end, "ref_rtol": a.ref_rtol, "rtols": rtols}
    for mode in labels:
        rl = SERIES[mode][2]
        if rl not in refs:
            refs[rl] = one_run(a, rl, a.ref_rtol)
            print(f"{rl} reference rtol {a.ref_rtol:g}: {'ok' if refs[rl]['ok'] else refs[rl]['why']}", flush=True)
        ref = refs[rl]
        rows = []
        for rtol in rtols:
            r = one_run(a, mode, rtol)
            if r["ok"] and ref["ok"]:
                d = r["x"] - ref["x"]
                r["err"] = float(np.sqrt(np.mean(np.sum(d * d, axis=1)))) / a.h
            rows.append((rtol, r))
            print(f"  {mode} rtol {rtol:g}: " + (f"error {r['err']:.3e} h, {r['rhs']} RHS, {r['cpu']:.2f} CPU-s"
                                                 if "err" in r else f"FAILED {r.get('why', 'no reference')}"), flush=True)
        good = [(t, r) for t, r in rows if "err" in r and r["err"] > 0]
        slope = Slope(good)
        tight = Slope([(t, r) for t, r in good if t <= 1.01e-5])
        runs_ok = [r for _, r in rows if "err" in r]
        res[mode] = (ref, rows, slope)
        readings[mode.replace(", h_tol = rtol", "_tied")] = {
            "slope": slope, "slope_tight": tight,
            "cpu_per_rhs_ms": 1e3 * sum(r["cpu"] for r in runs_ok) / max(1, sum(r["rhs"] for r in runs_ok)),
            "rhs_total": sum(r["rhs"] for r in runs_ok), "cpu_total": sum(r["cpu"] for r in runs_ok),
            "failed": len(rows) - len(runs_ok),
            "ref_rhs": ref.get("rhs"), "ref_cpu": ref.get("cpu"),
            "runs": {f"{t:.0e}": ({"error": r["err"], "rhs": r["rhs"], "cpu": r["cpu"], "steps": r["steps"]}
                                if "err" in r else {"failed": r.get("why", "no reference")}) for t, r in rows},
        }
        print(f"  {mode}: slope of log error against log rtol {slope} (rtol <= 1e-5: {tight}); "
              f"{readings[mode.replace(', h_tol = rtol', '_tied')]['cpu_per_rhs_ms']:.3f} CPU-ms per RHS", flush=True)
    draw(a, res, rtols)
    png = a.png or os.path.join(a.workdir, "work_precision_h.png")
    chart_readings.write(png, readings) if a.readings is None else chart_readings.write_json(a.readings, readings, chart=png)


def draw(a, res, rtols):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    for mode, (ref, rows, slope) in res.items():
        col, mk = STYLE[mode]
        ok = [(t, r) for t, r in rows if "err" in r]
        bad = [(t, r) for t, r in rows if "err" not in r]
        lab = f"{mode} (slope {slope:.2f})" if slope is not None else mode
        ax[0].loglog([t for t, _ in ok], [r["err"] for _, r in ok], color=col, marker=mk, label=lab)
        ax[1].loglog([r["rhs"] for _, r in ok], [r["err"] for _, r in ok], color=col, marker=mk, label=mode)
        ax[2].loglog([r["cpu"] for _, r in ok], [r["err"] for _, r in ok], color=col, marker=mk, label=mode)
        for t, _ in bad:
            ax[0].loglog([t], [1e-1], **UNSTABLE)
    t = np.array(rtols)
    ax[0].loglog(t, t / t[0] * 1e-2, "k:", lw=1, label="proportional to rtol")
    ax[0].set_xlabel("rtol (atol = rtol/1000)")
    ax[1].set_xlabel("right-hand-side evaluations")
    ax[2].set_xlabel("CPU time of the run [s]")
    for x in ax:
        x.set_ylabel("rms final position error / h")
        x.grid(True, which="both", alpha=0.3)
        x.legend(fontsize=8)
    what = f"Sedov 2D {a.n}x{a.n} (E0 1e4, h {a.h:g})" if a.scene == "sedov" else f"free expansion, gas 2D {a.n}x{a.n} (h {a.h:g}, no viscosity)"
    fig.suptitle(f"{what}, t = {a.t_end:g}: kernel range fixed, adaptive (solved), evolved (in the state); "
                 f"error against each mode's rtol {a.ref_rtol:g} run")
    fig.tight_layout()
    png = a.png or os.path.join(a.workdir, "work_precision_h.png")
    fig.savefig(png, dpi=90)
    print("wrote", png)


if __name__ == "__main__":
    main()
