#!/usr/bin/python3
"""Block individual steps (-ts_type block_kdk) against the global step on the 2D Sedov blast
(options/sedov.opts: gamma 5/3, E0 = 1e4, n x n periodic lattice, h = 3, Monaghan's
viscosity, the scene's end time: the shock at 0.35 of the box, 4.15 at n = 64): ARKODE's
Dormand-Prince 5(4) (-ts_type arkode, the default) at a
sweep of -ts_rtol, global kick-drift-kick (block_kdk with -block_max_level 0: one bin, the
step the shortest particle wants) and block steps (-block_max_level 16) at a sweep of
-block_cfl (= -block_force): with the pass restricted to the active particles (the default,
-block_restricted) and, at --full-cfls, with the whole right-hand side at each tick
(-block_restricted 0: the same result up to round-off, the cost of the first version),
and at --delay-cfls with the restricted pass and -block_wake_delay (a wake off the needed
bin's grid put off to that grid's next tick).

The error of each run is its time-integration error: against a DP5 run at -ts_rtol 1e-9 of
the same scene, the shock radius (the outer radius where the radially binned summed density
falls to the mean of its peak and 1, tests/shock_exact.half_level_radius, bins 0.5) and
L1(rho) = mean_i |rho_i - rho_i,ref| (particles matched by id) at t_end; and the largest
relative energy drift; and beside it the radius against the exact solution averaged by
the kernel (run_sedov.py's reference), the error every method shares. Cost: CPU time of the process (the machine is shared: wall time
would measure the load), right-hand-side evaluations, and for block steps the particle
steps (the sum over evaluations of the particles whose step ended there) from -ts_view:
'ideal evals' = particle steps / N is what the block steps' work would be if it were
proportional to the particles stepped, in full evaluations (the restricted pass still
reads the whole neighbour list and drifts every particle at each tick).

All runs write outputs every 0.5 (block cycles end there) and one snapshot at t_end.
With --chart PNG: the time error (L1(rho) and |R - R_ref|) against the CPU time of every
run, one colour and marker per method (the readings are then written beside the PNG).

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_block.py [--n 64] [--readings bench/readings/block.json] [--chart docs/gallery/block_sedov64.png]
"""
import argparse
import csv
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
from shock_exact import half_level_radius, sedov_profile, sedov_smoothed_density, sedov_xi0  # noqa: E402

BIN = 0.5
GAMMA, E0, H = 5.0 / 3.0, 1e4, 3.0


def smoothed_exact_radius(t_end):
    """The half-level radius of the exact profile averaged by the kernel (run_sedov.py)."""
    r_exact = sedov_xi0(2, GAMMA) * (E0 * t_end * t_end) ** 0.25
    grid = np.arange(0.0, r_exact + 2 * H, 0.05)
    return half_level_radius(grid, sedov_smoothed_density(grid, r_exact, 2, GAMMA, H, sedov_profile(2, GAMMA)))[0]


def snapshot(path):
    """(id-sorted rho_sum, half-level radius) of a CSV snapshot about the box centre."""
    with open(path) as f:
        f.readline()
        rows = list(csv.DictReader(f))
    ids = np.array([int(r["id"]) for r in rows])
    x = np.array([[float(r["x"]), float(r["y"])] for r in rows])
    rho = np.array([float(r["rho_sum"]) for r in rows])
    return rho[np.argsort(ids)], x, rho


def dp5_cpu_at(dp5, key, err):
    """DP5's CPU time at error err of reading key, interpolated in log-log between the two DP5
    runs whose errors bracket it (None outside their range)."""
    pts = sorted((r[key], r["cpu_s"]) for r in dp5)
    for (e0, c0), (e1, c1) in zip(pts, pts[1:]):
        if e0 <= err <= e1 and e0 > 0:
            f = 0.0 if e1 == e0 else np.log(err / e0) / np.log(e1 / e0)
            return float(np.exp(np.log(c0) + f * np.log(c1 / c0)))
    return None


def radius(x, rho, n):
    r = np.linalg.norm(x - 0.5 * n, axis=1)
    b = np.floor(r / BIN).astype(int)
    cnt, s = np.bincount(b), np.bincount(b, rho)
    ok = cnt > 0
    return half_level_radius(((np.arange(len(cnt)) + 0.5) * BIN)[ok], s[ok] / cnt[ok])[0]


def go(binary, n, work, name, extra, opts):
    out = os.path.join(work, name)
    args = [binary, "-options_file", opts, "-sedov_n", str(n), "-output_interval", "0.5", "-snapshot_interval", "100", "-snapshot_hdf5", "0",
            "-output_dir", out, "-output_overwrite", "-quiet", "-ts_view"] + [str(e) for e in extra]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(args, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        print(f"{name}: failed: {p.stderr.strip()[-300:]}")
        return None
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    s = json.load(open(os.path.join(out, "summary.json")))
    snaps = [e["name"] for e in json.load(open(os.path.join(out, "manifest.json")))["files"] if e.get("kind") == "snapshot_csv"]
    rho_id, x, rho = snapshot(os.path.join(out, snaps[-1]))
    r = {"name": name, "t_end": s["t_end"], "cpu_s": cpu, "wall_s": s["wall_time_s"], "rhs_evals": s["rhs_evals_total"], "drift": s["energy_rel_drift_max"],
         "R": radius(x, rho, n), "rho": rho_id}
    for line in p.stdout.splitlines():
        if "block cycles" in line:
            r["particle_steps"] = int(line.split("particle steps")[1].split()[0])
            r["deepest"] = int(line.split("deepest bin")[1].split()[0])
        if "restricted evaluations" in line:
            r["restricted_evals"] = int(line.split("restricted evaluations")[1].split()[0])
        if "mean active fraction" in line:
            r["active"] = float(line.split("mean active fraction")[1].split()[0])
    return r


STYLE = {"dp5": ("DP5 (-ts_rtol)", "tab:blue", "o"), "kdk": ("global KDK (-block_max_level 0)", "tab:orange", "s"),
         "block": ("block KDK, restricted pass", "tab:green", "^"), "blockfull": ("block KDK, full pass at each tick", "tab:gray", "D"),
         "blockdelay": ("block KDK, restricted, -block_wake_delay", "tab:red", "v")}


def chart(png, runs, failed, n, t_end):
    """L1(rho) and |R - R_ref| against CPU time, one series per method (log-log)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    for ax, key, label in ((axes[0], "L1", "L1(rho) against DP5 rtol 1e-9 (mean |rho_i - rho_i,ref|)"), (axes[1], "dR", "|R - R_ref| of the shock radius (lattice spacings)")):
        for m, (name, colour, marker) in STYLE.items():
            rs = [r for r in runs if r["name"].split("_", 1)[0] == m]  # in the order of their setting
            if rs:
                ax.loglog([r["cpu_s"] for r in rs], [max(r[key], 1e-12) for r in rs], marker=marker, color=colour, label=name)
                for r in rs:  # the setting beside each point: rtol, or cfl
                    ax.annotate(r["name"].split("_", 1)[1].replace("p", "."), (r["cpu_s"], max(r[key], 1e-12)), textcoords="offset points", xytext=(4, 3), fontsize=7, color=colour)
        ax.set_xlabel("CPU time of the run (s)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    if failed:
        axes[1].text(0.02, 0.02, "failed: " + ", ".join(failed), transform=axes[1].transAxes, color="red", fontsize=8)
    fig.suptitle(f"Sedov 2D, {n} x {n} particles, t = {t_end:.3g}: time-integration error against CPU time")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--spam-ark", default=str(ROOT / "build" / "spam-ark"))
    p.add_argument("--n", type=int, default=64)
    p.add_argument("--rtols", default="1e-2,1e-3,1e-4,1e-5,1e-6")
    p.add_argument("--cfls", default="0.4,0.2,0.1,0.05")
    p.add_argument("--full-cfls", default="0.1,0.05", help="block steps with the whole right-hand side at each tick ('' for none)")
    p.add_argument("--delay-cfls", default="", help="block steps with -block_wake_delay ('' for none)")
    p.add_argument("--readings")
    p.add_argument("--chart", help="error against CPU time, PNG (its readings JSON beside it)")
    a = p.parse_args()
    work = tempfile.mkdtemp(prefix="block_sedov_")
    opts = str(ROOT / "options" / "sedov.opts")
    plain = os.path.join(work, "sedov_no_rtol.opts")  # sedov.opts without -ts_rtol, which block_kdk refuses
    with open(opts) as f, open(plain, "w") as g:
        g.writelines(l for l in f if not l.startswith("-ts_rtol"))
    N = a.n * a.n
    ref = go(a.spam_ark, a.n, work, "ref", ["-ts_rtol", "1e-9"], opts)
    # run names are reading keys: no dots (1e-3 stays, 0.1 is written 0p1)
    runs = [go(a.spam_ark, a.n, work, f"dp5_{r}", ["-ts_rtol", r], opts) for r in a.rtols.split(",")]
    runs += [go(a.spam_ark, a.n, work, f"kdk_{c.replace('.', 'p')}", ["-ts_type", "block_kdk", "-block_max_level", 0, "-block_cfl", c, "-block_force", c], plain) for c in a.cfls.split(",")]
    runs += [go(a.spam_ark, a.n, work, f"block_{c.replace('.', 'p')}", ["-ts_type", "block_kdk", "-block_cfl", c, "-block_force", c], plain) for c in a.cfls.split(",")]
    runs += [go(a.spam_ark, a.n, work, f"blockfull_{c.replace('.', 'p')}", ["-ts_type", "block_kdk", "-block_restricted", 0, "-block_cfl", c, "-block_force", c], plain) for c in a.full_cfls.split(",") if c]
    runs += [go(a.spam_ark, a.n, work, f"blockdelay_{c.replace('.', 'p')}", ["-ts_type", "block_kdk", "-block_wake_delay", 1, "-block_cfl", c, "-block_force", c], plain) for c in a.delay_cfls.split(",") if c]
    names = [f"dp5_{r}" for r in a.rtols.split(",")] + [f"{m}_{c.replace('.', 'p')}" for m, cs in (("kdk", a.cfls), ("block", a.cfls), ("blockfull", a.full_cfls), ("blockdelay", a.delay_cfls)) for c in cs.split(",") if c]
    r_sm = smoothed_exact_radius(ref["t_end"])
    print(f"Sedov 2D n = {a.n} (N = {N}), t_end {ref['t_end']:.4g}; reference DP5 rtol 1e-9: R = {ref['R']:.4f} (smoothed exact {r_sm:.4f}), {ref['rhs_evals']} evals, {ref['cpu_s']:.1f} s CPU")
    print(f"{'run':14s} {'cpu s':>7s} {'evals':>7s} {'ideal':>8s} {'active':>7s} {'bin':>4s} {'|dR|':>9s} {'L1(rho)':>9s} {'|dE/E|':>9s} {'R-Rexact':>9s}")
    readings = {"n": a.n, "t_end": ref["t_end"], "reference": {"R": ref["R"], "rhs_evals": ref["rhs_evals"], "cpu_s": ref["cpu_s"]}, "R_smoothed_exact": r_sm}
    rows = []
    for r in runs:
        if r is None:
            continue
        r["dR"] = abs(r["R"] - ref["R"])
        r["L1"] = float(np.mean(np.abs(r["rho"] - ref["rho"])))
        ideal = r["particle_steps"] / N if "particle_steps" in r else float(r["rhs_evals"])
        print(f"{r['name']:14s} {r['cpu_s']:7.2f} {r['rhs_evals']:7d} {ideal:8.1f} {r.get('active', 1.0):7.3f} {r.get('deepest', 0):4d} {r['dR']:9.2e} {r['L1']:9.2e} {r['drift']:9.2e} {r['R'] - r_sm:9.3f}")
        method, knob = r["name"].split("_", 1)
        rows.append([{"dp5": "DP5", "kdk": "global KDK", "block": "block KDK", "blockfull": "block KDK, full pass", "blockdelay": "block KDK, delayed wakes"}[method], ("rtol " if method == "dp5" else "cfl ") + knob.replace("p", "."),
                     f"{r['cpu_s']:.2f}", str(r["rhs_evals"]), f"{ideal:.0f}" if "active" in r else "–", f"{r['active']:.3f}" if "active" in r else "–",
                     f"{r['dR']:.1e}", f"{r['L1']:.1e}", f"{r['drift']:.1e}", f"{r['R'] - r_sm:+.3f}"])
        readings[r["name"]] = {k: r[k] for k in ("cpu_s", "wall_s", "rhs_evals", "restricted_evals", "dR", "L1", "drift") if k in r}
        readings[r["name"]]["ideal_evals"] = ideal
        readings[r["name"]]["R_minus_exact"] = r["R"] - r_sm
        if "active" in r:
            readings[r["name"]]["active"] = r["active"]
            readings[r["name"]]["deepest"] = r["deepest"]
    # CPU time against DP5's at the same error (DP5's interpolated between its runs)
    dp5 = [r for r in runs if r is not None and r["name"].startswith("dp5_")]
    for r in runs:
        if r is None or r["name"].startswith("dp5_"):
            continue
        for key in ("L1", "dR"):
            c = dp5_cpu_at(dp5, key, r[key])
            readings[r["name"]][f"dp5_cpu_at_equal_{key}"] = c
            readings[r["name"]][f"cpu_ratio_equal_{key}"] = r["cpu_s"] / c if c else None
        print(f"{r['name']:14s} CPU / DP5's at equal L1(rho): {readings[r['name']]['cpu_ratio_equal_L1'] or float('nan'):.2f}, at equal |dR|: {readings[r['name']]['cpu_ratio_equal_dR'] or float('nan'):.2f}")
    readings["table"] = chart_readings.table(["method", "setting", "CPU s", "evaluations", "ideal evaluations", "active fraction", "dR vs ref", "L1(rho) vs ref", "max dE/E", "R - R_exact"], rows)
    failed = [n for n, r in zip(names, runs) if r is None]
    readings["failed"] = failed
    if a.chart:
        chart(a.chart, [r for r in runs if r is not None], failed, a.n, ref["t_end"])
        chart_readings.write(a.chart, readings)
    if a.readings:
        chart_readings.write_json(a.readings, readings)


main()
