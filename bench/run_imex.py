#!/usr/bin/python3
"""Work at equal max-norm error: -ts_type arkode_imex (ARKStep, diffusion implicit by
Newton-GMRES, unpreconditioned and preconditioned) against the explicit default, ARKODE's Dormand-Prince 5(4) (-ts_type arkode),
on a diffusion-limited case: the temperature mode of the conducting gas at rest
(-scene heat-mode, 2D, L x 12 lattice, h = 3, gamma = 1.4, kappa = 1, e0 = 1e-6, eps = 1e-4:
the sound speed, 7.5e-4, leaves conduction alone to set the steps), run to one e-folding,
T = 1/sigma_v. The explicit step is bounded by the conduction of the lattice's shortest
waves, ~h^2/chi; the mode's own time is (L/2 pi)^2/chi, so the explicit method takes
~(L/h)^2 steps where accuracy would take a few.

Each method runs at a sweep of -ts_rtol (the error weights of e are rtol e0); the error is
the max-norm over the particles of e(T) against the lattice's linear theory of the mode
(tests/lattice_modes.py, pair form), relative to the mode's amplitude eps e0 (that theory
itself stands 3.2e-8 off the runs: tests/run_imex_order.py). Cost: right-hand-side
evaluations (explicit and implicit separately, from the summary's rhs_evals_process and
rhs_evals_diffusion), GMRES iterations (ARKStep's statistics, -sundials_stats), the
preconditioner's Jacobian assemblies (each a pass over the pairs like one evaluation of the
diffusion part, counted with the evaluations in the ratios), wall time (the summary's) and CPU time (the
process's user + system time, its start included; less sensitive to the load). The ratio DP5 /
IMEX at equal error is the DP5 cost interpolated (log-log) at the IMEX run's error. Prints a
table and the ratios; with --chart, a PNG of error against wall time and against evaluations.

--pcs: the IMEX runs' stage preconditioners (-arkode_imex_pc), comma-separated: none
(unpreconditioned GMRES; method "imex"), diffusion (GMRES preconditioned on the right by
the assembled diffusion Jacobian, ILU(1) by default; method "imex_pc"), assembled (the same
with -arkode_imex_jv assembled: GMRES's products from that Jacobian but in each stage's
first linear solve; method "imex_jv"); --pc-options adds options of its KSP (say
"-imex_pc_pc_type lu"). --repeat N runs each method and tolerance N times and keeps the run
of least CPU time (the same steps and evaluations each time; the load varies); a run that
fails is reported and the others kept.

--case couette: plane Couette flow from rest (options/couette.opts) with the viscosity raised
to --nu (default 10: Re = U H / nu = 0.32, c h / nu = 0.42), to t = 1.5 H^2/nu = 150; the
error is the max-norm of vx(t) against a DP5 run at rtol 1e-11, over U. There the sound
(c = 1.41) bounds the explicit part's step, and so IMEX's, at ~h/c.

--case convection: the convection cell (options/convection.opts, 32 x 16, Ra = 5 Ra_c) with the
flow scheme's pair diffusion, -convection_prandtl --prandtl (default 10), to --t-end (default
100); the error is the max-norm of (vx, vy) against a DP5 run at rtol 1e-11, over the
reference's largest speed.

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_imex.py [--L 96] [--table ARK436L2SA] [--chart docs/imex_heat_mode.png]
    /usr/bin/python3 bench/run_imex.py --case couette [--nu 10] [--rtols 1e-5,1e-6,1e-7] [--pcs none,diffusion]
With --readings FILE, the runs, the table and the ratios go to FILE (with the command, the
commit and the load the wall times were taken under) for the pages' markers.
"""
import argparse
import csv
import json
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from lattice_modes import heat_mode  # noqa: E402

LY, H, GAMMA, KAPPA, E0, EPS = 12, 3.0, 1.4, 1.0, 1e-6, 1e-4


def columns(path, names):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return [np.array([float(r[n]) for r in rows]) for n in names]


def case_args(case, L, nu, prandtl=10.0, t_conv=100.0):
    """The scene's options, the end time and the error function (final CSV paths -> error)."""
    if case == "convection":
        args = ["-options_file", str(ROOT / "options" / "convection.opts"), "-gas_scheme", "flow", "-diffusion_form", "pair",
                "-convection_prandtl", repr(prandtl), "-ts_max_time", repr(t_conv), "-snapshot_interval", "0"]

        def error(first, last):
            vx, vy = columns(last, ["vx", "vy"])
            scale = float(np.max(np.hypot(REFERENCE["vx"], REFERENCE["vy"])))
            return float(max(np.max(np.abs(vx - REFERENCE["vx"])), np.max(np.abs(vy - REFERENCE["vy"]))) / scale)
        return args, error
    if case == "couette":
        t_end = 1.5 * 32 * 32 / nu
        args = ["-options_file", str(ROOT / "options" / "couette.opts"), "-viscosity_shear", repr(nu), "-ts_max_time", repr(t_end),
                "-snapshot_interval", "0"]

        def error(first, last):
            (v,) = columns(last, ["vx"])
            return float(np.max(np.abs(v - REFERENCE["vx"])) / 0.1)
        return args, error
    k = 2 * math.pi / L
    t_end = 1 / ((GAMMA - 1) * KAPPA * k * k)
    args = ["-dim", "2", "-scene", "heat-mode", "-heatmode_n", str(L), "-heatmode_ny", str(LY), "-h", str(H),
            "-gas_gamma", str(GAMMA), "-gas_e0", str(E0), "-heatmode_eps", str(EPS), "-conductivity", str(KAPPA),
            "-ts_max_time", repr(t_end)]

    def error(first, last):
        (x0,) = columns(first, ["x"])
        (e,) = columns(last, ["e"])
        exact = E0 * (1 + EPS * DISCRETE[L](t_end) * np.cos(k * x0))
        return float(np.max(np.abs(e - exact)) / (E0 * EPS))
    return args, error


def one_run(spam_ark, work, case, method, rtol):
    """Runs one method at one tolerance; returns its error and costs."""
    scene, error = case
    out = Path(work) / f"{method[1]}_{rtol:g}"
    args = [spam_ark] + scene + ["-ts_rtol", repr(rtol), "-ts_atol", "1e-20", "-output_interval", "0",
                                 "-output_dir", str(out), "-output_overwrite", "-initial_csv", str(out) + ".initial.csv",
                                 "-final_csv", str(out) + ".final.csv", "-sundials_stats"] + method[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(args, capture_output=True, text=True, timeout=3600)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    if p.returncode != 0:
        print(f"  {method[1]} rtol {rtol:g}: exit {p.returncode} {p.stderr.strip()[-200:]}")
        return None
    s = json.load(open(out / "summary.json"))
    lin = re.search(r"^LS iters\s*=\s*(\d+)", p.stdout, re.M)
    jac = re.search(r"^Jacobian assemblies\s*=\s*(\d+)", p.stdout, re.M)
    implicit = s["rhs_evals_diffusion"]
    nu = re.search(r"\bnu = ([0-9.eE+-]+)", p.stdout)
    return {"method": method[1], "rtol": rtol, "dt_mean": s["t_final"] / max(s["steps"], 1), "nu": float(nu.group(1)) if nu else None, "error": error(str(out) + ".initial.csv", str(out) + ".final.csv"),
            "steps": s["steps"], "rejected": s["rejected_steps"], "explicit": s["rhs_evals_process"] - implicit,
            "implicit": implicit, "linear": int(lin.group(1)) if lin else 0, "assemblies": int(jac.group(1)) if jac else 0,
            "wall": s["wall_time_s"], "cpu": cpu,
            "drift": s["energy_rel_drift_max"]}


def at_error(runs, key, err):
    """The cost 'key' of a method interpolated in log-log at error err (None outside its runs)."""
    pts = sorted((r["error"], r[key]) for r in runs)
    for (e1, c1), (e2, c2) in zip(pts, pts[1:]):
        if e1 <= err <= e2 and e1 < e2:
            w = math.log(err / e1) / math.log(e2 / e1)
            return math.exp((1 - w) * math.log(c1) + w * math.log(c2))
    return None


def evaluations(r):
    """Every pass over the pairs: both parts' evaluations and the Jacobian's assemblies."""
    return r["explicit"] + r["implicit"] + r.get("assemblies", 0)


def narrow_log_ticks(axis, lim):
    """Over two decades or less matplotlib labels a log axis's minor ticks, and the labels
    run into each other (or labels only one decade): there, labels at 1, 2 and 5 of each
    decade (within one decade also at 1.5, 3 and 7), written as plain numbers, none between."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter
    span = lim[1] / lim[0]
    if span < 100:
        subs = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0) if span < 10 else (1.0, 2.0, 5.0)
        axis.set_major_locator(LogLocator(base=10, subs=subs))
        axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        axis.set_minor_formatter(NullFormatter())


def chart(path, runs, failed, title, table, load):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sys.path.insert(0, str(ROOT / "examples"))
    from chart_style import style, UNSTABLE
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 5.0))
    for method, rs in runs.items():
        if not rs:
            continue
        name = NAMES.get(method, "IMEX {table}, preconditioned, " + method[2:] + " (" + VARIANTS.get(method, "") + ")").format(table=table)
        err = [r["error"] for r in rs]
        st = style(STYLE_KEYS.get(method, "IMEX, " + method[2:]))
        axes[0].loglog([r["wall"] for r in rs], err, "-", label=name, **st)
        axes[1].loglog([evaluations(r) for r in rs], err, "-", **st)
    for method, rtol in failed:
        axes[0].plot([], [], label=f"{method} rtol {rtol:g}: failed", **UNSTABLE)
    axes[0].set_xlabel("wall time (s)")
    axes[1].set_xlabel("pair passes: right-hand-side evaluations + Jacobian assemblies")
    for ax in axes:
        ax.set_ylabel("max-norm error (relative)")
        ax.grid(True, which="both", alpha=0.3)
        narrow_log_ticks(ax.xaxis, ax.get_xlim())
    fig.legend(loc="lower center", ncol=2, fontsize=8, frameon=False)
    fig.suptitle(f"{title}: work at equal error (load {load:.0f} on {os.cpu_count()} cores)")
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=110)
    print(f"chart: {path}")


DISCRETE = {}
REFERENCE = {}
VARIANTS = {}  # --variants: method -> its options
STYLE_KEYS = {"dp5": "DP5", "imex": "IMEX, unpreconditioned", "imex_pc": "IMEX, preconditioned", "imex_jv": "IMEX, assembled J v"}
NAMES = {"dp5": "DP5 (explicit, -ts_type arkode)", "imex": "IMEX {table}, GMRES unpreconditioned",
         "imex_pc": "IMEX {table}, GMRES preconditioned (-arkode_imex_pc diffusion)",
         "imex_jv": "IMEX {table}, preconditioned, assembled J v (-arkode_imex_jv assembled)"}


def chart_title(a):
    if a.case == "convection":
        return f"Convection 32 x 16, Ra = 5 Ra_c, Pr = {a.prandtl:g}, to t = {a.t_end:g}"
    if a.case == "couette":
        return f"Couette from rest, nu = {a.nu:g} (Re = {0.1 * 32 / a.nu:.2g})"
    return f"Heat mode, 2D {a.L} x {LY}, h = 3, to one e-folding"


def redraw(a):
    """The chart again from a readings file's runs (its load, not today's), e.g. after a style change."""
    if not (a.readings and a.chart):
        sys.exit("run_imex.py: --redraw needs --readings (to read) and --chart (to draw)")
    d = json.load(open(a.readings))
    r = d["readings"]
    for v in filter(None, (r.get("variants") or "").split(";")):
        vname, vopts = v.split("=", 1)
        VARIANTS["v:" + vname.strip()] = vopts.strip()
    failed = [(f["method"], f["rtol"]) for f in r["failed"]]
    chart(a.chart, r["runs"], failed, chart_title(a), a.table, d["load_1min"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(ROOT / "build" / "spam-ark"))
    ap.add_argument("--case", choices=("heat-mode", "couette", "convection"), default="heat-mode")
    ap.add_argument("--prandtl", type=float, default=10.0, help="convection: -convection_prandtl")
    ap.add_argument("--t-end", type=float, default=100.0, help="convection: the end time")
    ap.add_argument("--nu", type=float, default=10.0)
    ap.add_argument("--L", type=int, default=96)
    ap.add_argument("--table", default="ARK436L2SA")
    ap.add_argument("--rtols", default="1e-7,1e-8,1e-9,1e-10,1e-11")
    ap.add_argument("--dp5-rtols", default=None, help="DP5's own sweep (default --rtols), to bracket the IMEX runs' errors")
    ap.add_argument("--pcs", default="none", help="IMEX stage preconditioners, comma-separated: none, diffusion")
    ap.add_argument("--pc-options", default="", help="options of the preconditioner's KSP, e.g. '-imex_pc_pc_type lu'")
    ap.add_argument("--variants", default="", help="more preconditioned IMEX runs, 'name=options;name=options' (say 'previous=-arkode_imex_predictor 0')")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each method and tolerance; the one of least CPU time is kept")
    ap.add_argument("--chart", default=None)
    ap.add_argument("--readings", default=None, help="also write the runs, table and ratios the pages quote to this JSON")
    ap.add_argument("--redraw", action="store_true", help="run nothing: draw --chart from the runs in --readings (made with the same case options)")
    a = ap.parse_args()
    if a.redraw:
        redraw(a)
        return
    DISCRETE[a.L] = heat_mode(2, a.L, H, E0, GAMMA, KAPPA, "pair")[0]
    rtols = [float(x) for x in a.rtols.split(",")]
    dp5_rtols = [float(x) for x in a.dp5_rtols.split(",")] if a.dp5_rtols else rtols
    case = case_args(a.case, a.L, a.nu, a.prandtl, a.t_end)
    methods = [(["-ts_type", "arkode"], "dp5")]
    for pc in a.pcs.split(","):
        extra = a.pc_options.split() if pc in ("diffusion", "assembled") else []
        if pc == "assembled":
            extra = ["-arkode_imex_jv", "assembled"] + extra
        name = {"none": "imex", "diffusion": "imex_pc", "assembled": "imex_jv"}[pc]
        methods.append((["-ts_type", "arkode_imex", "-arkode_imex_table", a.table, "-arkode_imex_pc", "none" if pc == "none" else "diffusion"] + extra, name))
    for v in filter(None, a.variants.split(";")):
        vname, vopts = v.split("=", 1)
        methods.append((["-ts_type", "arkode_imex", "-arkode_imex_table", a.table, "-arkode_imex_pc", "diffusion"] + vopts.split(), "v:" + vname.strip()))
        VARIANTS["v:" + vname.strip()] = vopts.strip()
    with tempfile.TemporaryDirectory() as work:
        if a.case in ("couette", "convection"):
            ref = one_run(a.spam_ark, work, (case[0], lambda f, l: 0.0), (["-ts_type", "arkode"], "reference"), 1e-11)
            REFERENCE["vx"], REFERENCE["vy"] = columns(str(Path(work) / "reference_1e-11") + ".final.csv", ["vx", "vy"])
            print(f"reference: DP5 rtol 1e-11, {ref['steps']} steps, {ref['wall']:.1f} s")
        else:
            ref = None
        runs, failed = {}, []
        for m in methods:
            runs[m[1]] = []
            for t in (dp5_rtols if m[1] == "dp5" else rtols):
                tries = [x for x in (one_run(a.spam_ark, work, case, m, t) for _ in range(a.repeat)) if x]
                r = min(tries, key=lambda x: x["cpu"]) if tries else None
                if r:
                    runs[m[1]].append(r)
                else:
                    failed.append((m[1], t))
    if a.case == "convection":
        print(f"convection 32 x 16 at Ra = 5 Ra_c, Pr = {a.prandtl:g}, flow scheme, pair diffusion, to t = {a.t_end:g}; error = max |v - v_ref| / max |v_ref|")
    elif a.case == "couette":
        print(f"Couette from rest, nu = {a.nu:g} (Re = {0.1 * 32 / a.nu:.2f}), to 1.5 H^2/nu; error = max |vx - vx_ref| / U")
    else:
        print(f"heat mode 2D {a.L} x {LY}, to T = 1/sigma_v; error = max |e - exact| / (eps e0)")
    print(f"{'method':12} {'rtol':>7} {'error':>9} {'steps':>6} {'rej':>4} {'mean dt':>8} {'f_E':>7} {'f_I':>7} {'GMRES':>7} {'J':>4} {'wall s':>7} {'cpu s':>7} {'dE/E':>8}")
    for m in runs.values():
        for r in m:
            print(f"{r['method']:12} {r['rtol']:7.0e} {r['error']:9.2e} {r['steps']:6d} {r['rejected']:4d} {r['dt_mean']:8.3g} {r['explicit']:7d} {r['implicit']:7d} {r['linear']:7d} {r['assemblies']:4d} {r['wall']:7.2f} {r['cpu']:7.2f} {r['drift']:8.1e}")
    nu = next((r["nu"] for m in runs.values() for r in m if r.get("nu")), None)
    if nu:
        print(f"nu = {nu:g}: h^2/nu = {H * H / nu:.3g} (DP5's mean steps above)")
    all_ratios = {}
    for method in runs:
        if method == "dp5":
            continue
        print(f"ratio DP5 / {method} at the {method} run's error (DP5 interpolated):")
        ratios = all_ratios.setdefault(method, [])
        for r in runs[method]:
            w = at_error(runs["dp5"], "wall", r["error"])
            cpu = at_error(runs["dp5"], "cpu", r["error"])
            ev = at_error([dict(x, all=evaluations(x)) for x in runs["dp5"]], "all", r["error"])
            if w is None:
                print(f"  error {r['error']:.2e}: outside the DP5 runs' range")
                ratios.append(None)
                continue
            ratios.append({"error": r["error"], "wall": w / r["wall"], "cpu": cpu / r["cpu"], "evaluations": ev / evaluations(r)})
            print(f"  error {r['error']:.2e}: wall time {w / r['wall']:.2f}x, CPU time {cpu / r['cpu']:.2f}x, evaluations {ev / evaluations(r):.2f}x")
    if a.readings:
        sys.path.insert(0, str(ROOT / "examples"))
        import chart_readings
        label = {"dp5": "DP5", "imex": "IMEX", "imex_pc": "IMEX, pc", "imex_jv": "IMEX, pc, J v"}
        rows = [[label.get(r["method"], r["method"][2:]), f"{r['rtol']:.0e}".replace("e-0", "e-"),
                 f"{r['error']:.2e}".replace("e-0", "e-"), f"{r['steps']} ({r['rejected']})", r["explicit"], r["implicit"],
                 r["linear"], r["assemblies"], f"{r['wall']:.1f}", f"{r['cpu']:.1f}"] for m in runs.values() for r in m]
        chart_readings.write_json(a.readings, {
            "runs": runs, "ratios": all_ratios.get("imex", []), "ratios_pc": all_ratios.get("imex_pc", []),
            "ratios_jv": all_ratios.get("imex_jv", []), "repeat": a.repeat,
            "ratios_variants": {m[2:]: v for m, v in all_ratios.items() if m.startswith("v:")}, "variants": a.variants,
            "nu": nu, "h2_over_nu": H * H / nu if nu else None,
            "failed": [{"method": m, "rtol": t} for m, t in failed], "pc_options": a.pc_options,
            "reference_steps": ref["steps"] if ref else None,
            "table": chart_readings.table(["method", "rtol", "error", "steps (rejected)", "f_E", "f_I", "GMRES", "J", "wall s", "CPU s"], rows)},
            chart=a.chart)
    if a.chart:
        chart(a.chart, runs, failed, chart_title(a), a.table, os.getloadavg()[0])


if __name__ == "__main__":
    main()
