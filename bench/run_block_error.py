#!/usr/bin/python3
"""Error-controlled individual steps (-ts_type block_kdk -block_criterion error): the error
against the tolerance, and the work against global DP5 at equal error.

Scenes: the Sedov blast (options/sedov.opts at -sedov_n N, its end time: 4.15 at N 64 in
2D; --dim 3: the 3D blast on N^3, the scene's end time 3.3 at N 32 unless --t-end) and the
periodic 2D expansion of the isentropic gas (--scene expansion: 24^2 particles,
h 3, gamma 1.7, amplitude 0.1, to t 20, as tests/run_block_ranks.py runs it). Runs:
ARKODE's Dormand-Prince 5(4) (-ts_type arkode) at --dp5-rtols, block steps with bins by
error control at --rtols (-block_cfl --bound as the stability bound), and for comparison
block steps with the CFL and force criteria at --cfls.

The error of each run is its time-integration error against DP5 at -ts_rtol 1e-9 of the
same scene (--ref-rtol: a looser reference for the costly 3D runs, well below the errors
compared): L1(rho) = mean_i |rho_i - rho_i,ref| (summed density, particles matched by id)
and max_i |x_i - x_i,ref| (nearest periodic image) at the end; for the blast also the shock
radius's error |R - R_ref| (R the outer radius where the summed density binned in shells of
0.5 about the centre falls to the mean of its peak and 1, as bench/run_block.py). Conservation: the largest
relative energy drift |dE/E| (summary.json), the largest change of each momentum component
over the outputs relative to the summed |m v| at the end (timeseries.csv), and the mass (the
particles' masses are constants of every method: the sum of the final snapshot's masses
against the initial one's). Cost: CPU time of the process, user + sys (the machine is
shared: the 1-minute load average is recorded at each run's end), right-hand-side evaluations, particle steps from
-ts_view ('ideal evals' = particle steps / N) and the rejected cycles. The observed order
in the tolerance: the least-squares slope of log L1(rho) against log rtol over the
error-controlled runs (the estimate is O(dt^2) and the method second order: dt ~ rtol^(1/2)
and a global error ~ dt^2 ~ rtol, slope 1).

With --readings FILE: the readings as JSON (command, commit, load); with --chart PNG: the
error against rtol and against CPU time (and the shock radius's against CPU time), a run
that failed drawn as a cross at its setting on the top edge of the first panel.

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_block_error.py [--scene sedov|expansion] [--dim 2|3] [--n 64] [--readings F] [--chart PNG]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "examples"))
import chart_readings  # noqa: E402
from spamrun import table  # noqa: E402  (timeseries.csv)
from shock_exact import half_level_radius  # noqa: E402

BIN = 0.5  # the shells of the shock radius's density profile


def scene_args(a, work):
    """(arguments for DP5, arguments for block_kdk, box side) of the scene."""
    if a.scene == "sedov":
        opts = str(ROOT / "options" / "sedov.opts")
        plain = os.path.join(work, "sedov_no_rtol.opts")  # the file's -ts_rtol is DP5's: given per run here
        with open(opts) as f, open(plain, "w") as g:
            g.writelines(ln for ln in f if not ln.startswith("-ts_rtol"))
        common = ["-options_file", plain, "-dim", a.dim, "-sedov_n", a.n, "-output_interval", 0.5, "-snapshot_interval", 100]
        if a.t_end:
            common += ["-ts_max_time", a.t_end]
        return common, common, float(a.n)
    common = ["-scene", "expansion", "-dim", 2, "-expansion_n", a.n, "-h", 3, "-eos_gamma", 1.7, "-expansion_amplitude", 0.1,
              "-ts_max_time", a.t_end or 20, "-output_interval", 1, "-snapshot_interval", 100]
    return common, common, None


def shock_radius(x, rho, box):
    """The half-level radius of the density binned in shells about the box centre."""
    r = np.linalg.norm(x - 0.5 * box, axis=1)
    b = np.floor(r / BIN).astype(int)
    cnt, s = np.bincount(b), np.bincount(b, rho)
    ok = cnt > 0
    return float(half_level_radius(((np.arange(len(cnt)) + 0.5) * BIN)[ok], s[ok] / cnt[ok])[0])


def go(a, work, name, args):
    out = os.path.join(work, name)
    cmd = [a.spam_ark] + [str(x) for x in args] + ["-snapshot_hdf5", "0", "-output_dir", out, "-output_overwrite", "-quiet", "-ts_view"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"{name}: {cpu:.1f} s CPU, load {os.getloadavg()[0]:.1f}", flush=True)
    if p.returncode:
        print(f"{name}: failed: {p.stderr.strip()[-300:]}")
        return None
    s = json.load(open(os.path.join(out, "summary.json")))
    snaps = [e["name"] for e in json.load(open(os.path.join(out, "manifest.json")))["files"] if e.get("kind") == "snapshot_csv"]
    with open(os.path.join(out, snaps[-1])) as fh:  # the snapshot at the end: a "# t=" line, then the columns
        fh.readline()
        f = {k: [float(v) for v in col] for k, col in zip(fh.readline().strip().split(","), zip(*(ln.strip().split(",") for ln in fh if ln.strip())))}
    order = np.argsort(f["id"])
    ts = table(os.path.join(out, "timeseries.csv"))
    dim = 3 if "z" in f else 2
    axes = "xyz"[:dim]
    x = np.array([f[k] for k in axes]).T[order]
    v = np.array([f["v" + k] for k in axes]).T[order]
    m = np.array(f["m"])[order] if "m" in f else np.ones(len(order))
    r = {"name": name, "t_end": s["t_end"], "cpu_s": cpu, "load_1min": os.getloadavg()[0],
         "rhs_evals": s["rhs_evals_total"], "drift": s["energy_rel_drift_max"], "x": x, "rho": np.array(f["rho_sum"])[order], "mass": float(np.sum(m)),
         "momentum": max(max(abs(q - ts[f"p{k}"][0]) for q in ts[f"p{k}"]) for k in axes) / float(np.sum(m * np.linalg.norm(v, axis=1)))}
    for line in p.stdout.splitlines():
        if "block cycles" in line:
            r["particle_steps"] = int(line.split("particle steps")[1].split()[0])
            r["deepest"] = int(line.split("deepest bin")[1].split()[0])
        if "rejected cycles" in line:
            r["rejected"] = int(line.split("rejected cycles")[1].split()[0])
            r["largest_estimate"] = float(line.split("largest")[1].split(",")[0])
            r["above_tolerance"] = int(line.split("above the tolerance")[1].split(",")[0])
    if a.scene == "sedov":
        r["R"] = shock_radius(np.array([f[k] for k in axes]).T, np.array(f["rho_sum"]), float(a.n))
    return r


def dp5_cpu_at(dp5, key, err, what="cpu_s"):
    """DP5's CPU time (or evaluations) at error err, log-log between the bracketing runs."""
    pts = sorted((r[key], r[what]) for r in dp5)
    for (e0, c0), (e1, c1) in zip(pts, pts[1:]):
        if e0 <= err <= e1 and e0 > 0:
            f = 0.0 if e1 == e0 else np.log(err / e0) / np.log(e1 / e0)
            return float(np.exp(np.log(c0) + f * np.log(c1 / c0)))
    return None


STYLE = {"dp5": ("DP5 (-ts_rtol)", "tab:blue", "o"), "err": ("block KDK, -block_criterion error (-ts_rtol)", "tab:red", "v"),
         "cfl": ("block KDK, -block_criterion cfl (-block_cfl)", "tab:green", "^")}


def chart(png, runs, failed, title, ref_rtol):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    radius = all("dR" in r for r in runs)
    fig, axes = plt.subplots(1, 4 if radius else 3, figsize=(21 if radius else 16, 4.6))
    panels = [(axes[1], "cpu_s", "L1"), (axes[2], "ideal", "L1")] + ([(axes[3], "cpu_s", "dR")] if radius else [])
    for m, (label, colour, marker) in STYLE.items():
        rs = [r for r in runs if r["name"].split("_", 1)[0] == m]
        if m != "cfl" and rs:
            axes[0].loglog([r["rtol"] for r in rs], [r["L1"] for r in rs], marker=marker, color=colour, label=label)
        bad = [float(n.split("_", 1)[1].replace("p", ".")) for n in failed if n.split("_", 1)[0] == m]
        if bad:  # a failed run: a cross at its setting on the top edge
            axes[0].plot(bad, [1.0] * len(bad), linestyle="none", marker="x", markersize=9, color=colour, transform=axes[0].get_xaxis_transform(), clip_on=False, label=label.split(" (")[0] + ": failed")
        for ax, key, err in panels:
            if not rs:
                continue
            ys = [max(r[err], 1e-12) for r in rs]  # an error 0 (the same bits as the reference) at the floor
            ax.loglog([r[key] for r in rs], ys, marker=marker, color=colour, label=label)
            for r, y in zip(rs, ys):
                ax.annotate(r["name"].split("_", 1)[1].replace("p", "."), (r[key], y), textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
    axes[0].set_xlabel("-ts_rtol (-ts_atol the same)")
    axes[0].set_ylabel(f"L1(rho) against DP5 rtol {ref_rtol} (mean |rho_i - rho_i,ref|)")
    axes[1].set_xlabel("CPU time of the run (s)")
    axes[1].set_ylabel(f"L1(rho) against DP5 rtol {ref_rtol}")
    axes[2].set_xlabel("particle steps / N (DP5: right-hand-side evaluations)")
    axes[2].set_ylabel(f"L1(rho) against DP5 rtol {ref_rtol}")
    if radius:
        axes[3].set_xlabel("CPU time of the run (s)")
        axes[3].set_ylabel("|R - R_ref| of the shock radius (lattice spacings)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    if failed:
        axes[1].text(0.02, 0.02, "failed: " + ", ".join(failed), transform=axes[1].transAxes, color="red", fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--spam-ark", default=str(ROOT / "build" / "spam-ark"))
    p.add_argument("--scene", default="sedov", choices=("sedov", "expansion"))
    p.add_argument("--dim", type=int, default=2, choices=(2, 3), help="sedov: the dimension")
    p.add_argument("--n", type=int, default=None, help="lattice side (sedov 64, expansion 24)")
    p.add_argument("--t-end", type=float, default=None, help="end time (expansion 20, sedov the scene's)")
    p.add_argument("--ref-rtol", default="1e-9", help="-ts_rtol (and -ts_atol) of the DP5 reference")
    p.add_argument("--rtols", default="1e-2,1e-3,1e-4,1e-5")
    p.add_argument("--dp5-rtols", default="1e-3,1e-4,1e-5,1e-6")
    p.add_argument("--cfls", default="0.2,0.1,0.05")
    p.add_argument("--bound", default="0.5", help="-block_cfl under -block_criterion error (the stability bound)")
    p.add_argument("--readings")
    p.add_argument("--chart")
    a = p.parse_args()
    a.n = a.n or (64 if a.scene == "sedov" else 24)
    work = tempfile.mkdtemp(prefix="block_error_")
    dp5_args, block_args, box = scene_args(a, work)
    if a.scene != "sedov" and a.dim != 2:
        p.error("--dim 3: the sedov scene only")
    N = a.n ** a.dim
    ref = go(a, work, "ref", dp5_args + ["-ts_rtol", a.ref_rtol, "-ts_atol", a.ref_rtol])
    runs, names = [], []
    for r in a.dp5_rtols.split(","):
        names.append(f"dp5_{r}")
        runs.append(go(a, work, names[-1], dp5_args + ["-ts_rtol", r, "-ts_atol", r]))
        if runs[-1]:
            runs[-1]["rtol"] = float(r)
    for r in a.rtols.split(","):
        names.append(f"err_{r}")
        runs.append(go(a, work, names[-1], block_args + ["-ts_type", "block_kdk", "-block_criterion", "error", "-block_cfl", a.bound, "-ts_rtol", r, "-ts_atol", r]))
        if runs[-1]:
            runs[-1]["rtol"] = float(r)
    for c in a.cfls.split(","):
        if c:
            names.append(f"cfl_{c.replace('.', 'p')}")
            runs.append(go(a, work, names[-1], block_args + ["-ts_type", "block_kdk", "-block_cfl", c, "-block_force", c]))
    side = " x ".join([str(a.n)] * a.dim)
    title = f"{'Sedov' if a.scene == 'sedov' else 'expansion'} {a.dim}D, {side} particles, t = {ref['t_end']:.3g}: time-integration error"
    print(title + f"; reference DP5 rtol {a.ref_rtol}: {ref['rhs_evals']} evals, {ref['cpu_s']:.1f} s CPU")
    load = os.getloadavg()[0]
    readings = {"scene": a.scene, "dim": a.dim, "n": a.n, "t_end": ref["t_end"], "bound_cfl": float(a.bound), "load_1min": load, "ref_rtol": float(a.ref_rtol),
                "reference": {"rhs_evals": ref["rhs_evals"], "cpu_s": ref["cpu_s"], "load_1min": ref["load_1min"]} | ({"R": ref["R"]} if "R" in ref else {})}
    print(f"{'run':12s} {'cpu s':>7s} {'load':>5s} {'evals':>7s} {'ideal':>8s} {'bin':>4s} {'rej':>4s} {'L1(rho)':>9s} {'|dR|':>9s} {'max|dx|':>9s} {'|dE/E|':>9s} {'|dP|/P':>9s} {'dM':>8s}")
    ok = [r for r in runs if r is not None]
    for r in ok:
        r["L1"] = float(np.mean(np.abs(r["rho"] - ref["rho"])))
        dx = r["x"] - ref["x"]
        if box:
            dx -= box * np.round(dx / box)
        r["xerr"] = float(np.max(np.abs(dx)))
        r["ideal"] = r["particle_steps"] / N if "particle_steps" in r else float(r["rhs_evals"])
        r["dmass"] = abs(r["mass"] - ref["mass"]) / ref["mass"]
        if "R" in r:
            r["dR"] = abs(r["R"] - ref["R"])
        print(f"{r['name']:12s} {r['cpu_s']:7.2f} {r['load_1min']:5.1f} {r['rhs_evals']:7d} {r['ideal']:8.1f} {r.get('deepest', 0):4d} {r.get('rejected', 0):4d} {r['L1']:9.2e} {r.get('dR', float('nan')):9.2e} {r['xerr']:9.2e} {r['drift']:9.2e} {r['momentum']:9.2e} {r['dmass']:8.1e}")
        readings[r["name"]] = {k: r[k] for k in ("cpu_s", "load_1min", "rhs_evals", "ideal", "L1", "R", "dR", "xerr", "drift", "momentum", "dmass", "rejected", "deepest", "particle_steps", "largest_estimate", "above_tolerance", "rtol") if k in r}
    dp5 = [r for r in ok if r["name"].startswith("dp5_")]
    err = [r for r in ok if r["name"].startswith("err_")]
    for group, rs in (("dp5", dp5), ("err", err)):
        if len(rs) >= 2:
            for key in ("L1", "xerr"):
                slope = float(np.polyfit(np.log([r["rtol"] for r in rs]), np.log([r[key] for r in rs]), 1)[0])
                readings[f"{group}_slope_{key}"] = slope
                print(f"{group}: slope of log {key} against log rtol {slope:.2f}")
    for r in ok:
        if r["name"].startswith("dp5_"):
            continue
        cpu = dp5_cpu_at(dp5, "L1", r["L1"])
        ev = dp5_cpu_at(dp5, "L1", r["L1"], "rhs_evals")
        readings[r["name"]]["dp5_cpu_at_equal_L1"] = cpu
        readings[r["name"]]["cpu_ratio_equal_L1"] = r["cpu_s"] / cpu if cpu else None
        readings[r["name"]]["ideal_ratio_equal_L1"] = r["ideal"] / ev if ev else None
        line = f"{r['name']:12s} CPU / DP5's at equal L1(rho): {r['cpu_s'] / cpu if cpu else float('nan'):.2f}; ideal evaluations / DP5's {r['ideal'] / ev if ev else float('nan'):.2f}"
        if "dR" in r:
            cr = dp5_cpu_at(dp5, "dR", r["dR"])
            readings[r["name"]]["dp5_cpu_at_equal_dR"] = cr
            readings[r["name"]]["cpu_ratio_equal_dR"] = r["cpu_s"] / cr if cr else None
            line += f"; CPU / DP5's at equal |dR|: {r['cpu_s'] / cr if cr else float('nan'):.2f}"
        print(line)
    rows = []
    for r in ok:
        method, knob = r["name"].split("_", 1)
        rows.append([{"dp5": "DP5", "err": "block KDK, error", "cfl": "block KDK, cfl"}[method], ("cfl " if method == "cfl" else "rtol ") + knob.replace("p", "."),
                     f"{r['cpu_s']:.2f}", str(r["rhs_evals"]), f"{r['ideal']:.0f}" if "particle_steps" in r else "–", str(r.get("rejected", "–")),
                     f"{r['L1']:.1e}"] + ([f"{r['dR']:.1e}"] if "dR" in r else []) + [f"{r['xerr']:.1e}", f"{r['drift']:.1e}", f"{r['momentum']:.1e}"])
    readings["table"] = chart_readings.table(["method", "setting", "CPU s", "evaluations", "ideal evaluations", "rejected cycles", "L1(rho) vs ref"] + (["dR vs ref"] if "R" in ref else []) + ["max dx vs ref", "max dE/E", "max dP / sum of m abs(v)"], rows)
    failed = [n for n, r in zip(names, runs) if r is None]
    readings["failed"] = failed
    if a.chart:
        chart(a.chart, ok, failed, title, a.ref_rtol)
    if a.readings:
        chart_readings.write_json(a.readings, readings, chart=os.path.basename(a.chart) if a.chart else None)


main()
