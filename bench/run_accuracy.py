#!/usr/bin/python3
"""Time to accuracy: spam-ark against LAMMPS velocity Verlet on the 2D expansion.

Both programs integrate the same dynamics (P = rho^2/2, so SPAM is molecular dynamics with
Lucy's kernel as the pair potential; see run_bench.py) from the same particles (the
expansion lattice, h = 3) to t = 10. Each setting -- a LAMMPS `fix nve` step dt, a
spam-ark method with a tolerance rtol (ARKODE Dormand-Prince 5(4) or Bogacki-Shampine
3(2)) or spam-ark's own velocity Verlet (kdk) with a step dt -- is run as a whole process
(start-up, reading the particles, the run and writing the final particles), one core each,
`--repeats` times, the settings interleaved so that a slow spell of this shared machine hits
every program. Its accuracy is measured against a converged reference (spam-ark
Dormand-Prince at rtol 1e-13, checked against Verner 8(5)6 at the same tolerance):

    KE error       |KE(t) - KE_ref(t)| / KE_ref(t)
    position error max_i |x_i(t) - x_ref,i(t)|  (minimum image; reduced length, lattice spacing 1)

For each accuracy eps (1e-4 ... 1e-8) and each program's curve the time to accuracy is the
shortest median wall time of a setting whose error is at most eps ("runs": settings actually
run) and, between the two settings that bracket eps, the time interpolated linearly in
log(time) against log(error) ("interpolated": the step or tolerance that just reaches eps,
so that neither side pays for the coarseness of its ladder). The ratio spam-ark / LAMMPS uses
spam-ark's cheapest method at that eps. Target: KE within 1e-6 at N = 16384 in at
most 0.2 of LAMMPS's time.

This is a measurement, not a test. Usage (spam-ark built in build/, LAMMPS as lmp):
    /usr/bin/python3 bench/run_accuracy.py                      # N = 16384 and 65536, 3 repeats
    /usr/bin/python3 bench/run_accuracy.py --sizes 16384 --repeats 5
    /usr/bin/python3 bench/run_accuracy.py --quick              # N = 4096, 1 repeat, short ladders
It writes bench/results/accuracy_<date>.json and the chart docs/time_to_accuracy.png.
"""
import argparse
import datetime
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_common as bc  # noqa: E402  (re-executes under /usr/bin/python3 if numpy is missing)
import peer_lammps as pl  # noqa: E402
import spam_driver as sd  # noqa: E402

np = bc.np

T_END = 10.0
H = 3.0
EPS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
TARGET_RATIO = 0.2
TARGET_N = 16384
TARGET_EPS = 1e-6
REF = ("ARKODE_DORMAND_PRINCE_7_4_5", 1e-13)
REF_CHECK = ("ARKODE_VERNER_8_5_6", 1e-13)
# atol = ATOL_OVER_RTOL * rtol, so that rtol is the one knob (the default atol 1e-9 would
# decide the weights below rtol ~ 1e-9).
ATOL_OVER_RTOL = 1e-2
TABLES = {"dp5": "ARKODE_DORMAND_PRINCE_7_4_5", "bs3": "ARKODE_BOGACKI_SHAMPINE_4_2_3"}
# Ladders. Velocity Verlet's error goes as dt^2, so halving dt divides it by 4; the
# tolerances go by sqrt(10) where the cheapest setting for 1e-6 .. 1e-8 is expected.
LADDERS = {
    "lammps": [0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125],
    "kdk": [0.02, 0.01, 0.005, 0.0025],
    "dp5": [1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10],
    "bs3": [1e-6, 1e-7, 1e-8, 1e-9],
}
# Above N = 16384 (four times the cost per run) the ladders keep the settings around
# 1e-5 ... 1e-8 only.
LARGE_LADDERS = {
    "lammps": [0.02, 0.01, 0.005, 0.0025],
    "kdk": [0.01, 0.005],
    "dp5": [1e-6, 1e-7, 1e-8, 1e-9, 3e-10],
    "bs3": [1e-7, 1e-8],
}
QUICK_LADDERS = {"lammps": [0.02, 0.01], "kdk": [0.01], "dp5": [1e-7, 1e-8], "bs3": [1e-7]}
LABELS = {"lammps": "LAMMPS velocity Verlet (fix nve)", "kdk": "spam-ark velocity Verlet (kdk)",
          "dp5": "spam-ark Dormand-Prince 5(4)", "bs3": "spam-ark Bogacki-Shampine 3(2)"}


# --------------------------------------------------------------------------
# One run of a setting
# --------------------------------------------------------------------------

def spam_cmd(a, curve, param, csv, box, outdir, final):
    cmd = [a.spam_ark, "-scene", "file", "-file_path", csv, "-dim", 2, "-box_lo", "0,0",
           "-box_len", "%.17g,%.17g" % box, "-periodic", "1,1", "-h", H]
    if curve == "kdk":
        steps = int(round(T_END / param))
        cmd += ["-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "kdk",
                "-ts_dt", param, "-ts_max_steps", steps,
                "-ts_max_time", "%.17g" % ((steps + 0.5) * param)]
    else:
        table, rtol = (param[0], param[1]) if isinstance(param, tuple) else (TABLES[curve], param)
        cmd += ["-arkode_table", table, "-ts_rtol", "%.3g" % rtol,
                "-ts_atol", "%.3g" % (ATOL_OVER_RTOL * rtol),
                "-ts_max_time", "%.17g" % T_END, "-ts_max_steps", 10 ** 7]
    return cmd + ["-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0,
                  "-final_csv", final, "-output_dir", outdir, "-output_overwrite"]


def run_spam(a, curve, param, csv, box, work, tag, pin):
    outdir, final = work / ("out_" + tag), work / ("final_%s.csv" % tag)
    if final.exists():
        final.unlink()
    cmd = pin + spam_cmd(a, curve, param, csv, box, outdir, final)
    log = work / ("%s.log" % tag)
    rc, wall, _, cpu = bc.run_measured_cpu(cmd, bc.REPO_ROOT, log)
    rec = {"wall_s": wall, "cpu_s": cpu, "rc": rc}
    try:
        s = json.loads((outdir / "summary.json").read_text())
        rec.update({"status": s.get("status"), "steps": s.get("steps"), "rhs_evals": s.get("rhs_evals"),
                    "loop_s": s.get("wall_time_s"), "rhs_s": s.get("rhs_time_s"),
                    "t_final": s.get("t_final")})
    except (OSError, ValueError):
        rec["status"] = "failed"
    if curve == "kdk" and rec.get("status") == "max_steps":
        rec["status"] = "ok"  # kdk stops at its step count (t = steps * dt = T_END) by design
    if rc != 0 or not final.exists():
        rec["status"] = rec.get("status") if rc == 3 else "failed"
        rec["error"] = bc.tail(log, 5)
        return rec, None
    pos, vel, mass, _ = bc.read_particles_csv(final)
    return rec, (pos, vel, mass)


def run_lammps(a, dt, data, table, work, tag, pin):
    steps = int(round(T_END / dt))
    dump = "final_%s.txt" % tag
    inp = work / ("in_%s.lmp" % tag)
    inp.write_text(pl.lammps_input(data.name, table.name, H, a.skin, steps, a.table_points, dt=dt,
                                   after_run="write_dump all custom %s id x y vx vy modify sort id "
                                             "format float %%.17g" % dump))
    log = work / ("lammps_%s.log" % tag)
    rc, wall, _, cpu = bc.run_measured_cpu(pin + [a.lmp, "-in", inp.name, "-log", "none", "-nocite"],
                                           work, log)
    res = pl.parse_lammps_log(log.read_text(errors="replace"))
    rec = {"wall_s": wall, "cpu_s": cpu, "rc": rc, "steps": steps, "loop_s": res.get("loop_time_s"),
           "status": "ok" if rc == 0 and "loop_time_s" in res else "failed"}
    if rec["status"] != "ok":
        rec["error"] = bc.tail(log, 5)
        return rec, None
    d = np.loadtxt(work / dump, skiprows=9)
    return rec, (d[:, 1:3], d[:, 3:5], None)


# --------------------------------------------------------------------------
# Accuracy
# --------------------------------------------------------------------------

def kinetic(vel, mass):
    return 0.5 * float(np.sum(mass[:, None] * vel * vel))


def errors(state, ref, box, mass):
    """(relative KE error, max and RMS position error) of state against ref."""
    pos, vel, _ = state
    d = pos - ref[0]
    d -= box * np.round(d / box)
    r = np.sqrt(np.sum(d * d, axis=1))
    ke, ke_ref = kinetic(vel, mass), kinetic(ref[1], mass)
    return {"ke": kinetic(vel, mass), "ke_err": abs(ke - ke_ref) / ke_ref,
            "pos_err": float(r.max()), "pos_err_rms": float(np.sqrt(np.mean(r * r)))}


def time_to_accuracy(points, eps, measure):
    """(runs, interpolated) wall time to reach eps on one curve; None where it is not reached.

    points: (median wall, error) of the settings that ran. The frontier keeps, in order of
    time, each point more accurate than every cheaper one; "interpolated" is the time on the
    segment of that frontier which crosses eps (log-log), or the cheapest point if already
    the cheapest one meets eps.
    """
    pts = sorted((w, e[measure]) for w, e in points if e is not None and w is not None)
    front = []
    for w, e in pts:
        if not front or e < front[-1][1]:
            front.append((w, e))
    ok = [w for w, e in front if e <= eps]
    if not ok:
        return None, None
    runs = min(ok)
    k = next(i for i, (w, e) in enumerate(front) if e <= eps)
    if k == 0:
        return runs, runs
    (w0, e0), (w1, e1) = front[k - 1], front[k]
    f = (math.log(eps) - math.log(e0)) / (math.log(e1) - math.log(e0))
    return runs, math.exp(math.log(w0) + f * (math.log(w1) - math.log(w0)))


# --------------------------------------------------------------------------
# One size
# --------------------------------------------------------------------------

def one_size(a, n, work, pin, ladders):
    nx = int(round(math.sqrt(n)))
    if nx * nx != n:
        raise SystemExit("--sizes: %d is not a perfect square" % n)
    box = np.array([2.0 * nx, 2.0 * nx])
    csv, init_cmd = sd.spam_make_initial(a.spam_ark, nx, H, work)
    pos0, vel0, mass, _ = bc.read_particles_csv(csv)
    data, table = work / ("data_%d.lmp" % nx), work / "lucy.table"
    pl.write_lammps_data(data, pos0, vel0, box, float(mass[0]))
    if not table.exists():
        pl.write_table(table, H, a.table_points, a.table_rlo)
    res = {"n": n, "nx": nx, "box": box.tolist(), "initial_cmd": init_cmd, "settings": []}

    print("\n== N = %d, h = %g, t = %g" % (n, H, T_END))
    t0 = time.perf_counter()
    ref_rec, ref = run_spam(a, "ref", REF, csv, tuple(box), work, "ref_%d" % nx, pin)
    chk_rec, chk = run_spam(a, "ref", REF_CHECK, csv, tuple(box), work, "refcheck_%d" % nx, pin)
    if ref is None or chk is None:
        raise RuntimeError("reference run failed: %s" % (ref_rec.get("error") or chk_rec.get("error")))
    conv = errors(chk, ref, box, mass)
    res["reference"] = {"method": REF[0], "rtol": REF[1], "run": ref_rec, "ke": kinetic(ref[1], mass),
                        "check_method": REF_CHECK[0], "check_rtol": REF_CHECK[1], "check_run": chk_rec,
                        "check_ke_err": conv["ke_err"], "check_pos_err": conv["pos_err"]}
    print("  reference %s rtol %g: %d steps, %.1f s; against %s rtol %g: KE %.1e, position %.1e"
          % (REF[0], REF[1], ref_rec["steps"], ref_rec["wall_s"], REF_CHECK[0], REF_CHECK[1],
             conv["ke_err"], conv["pos_err"]))

    # Interleave the programs: LAMMPS, a spam-ark setting, LAMMPS, ... in every repeat.
    spam_settings = [(c, p) for c in ("dp5", "bs3", "kdk") if c in ladders for p in ladders[c]]
    lammps_settings = [("lammps", p) for p in ladders.get("lammps", [])]
    order = []
    for k in range(max(len(spam_settings), len(lammps_settings))):
        order += lammps_settings[k:k + 1] + spam_settings[k:k + 1]
    recs = {s: {"curve": s[0], "param": s[1], "runs": [], "err": None} for s in order}
    for rep in range(a.repeats):
        for s in order:
            curve, param = s
            tag = "%s_%g_%d" % (curve, param, nx)
            if curve == "lammps":
                rec, state = run_lammps(a, param, data, table, work, tag, pin)
            else:
                rec, state = run_spam(a, curve, param, csv, tuple(box), work, tag, pin)
            if state is not None:
                e = errors(state, ref, box, mass)
                if recs[s]["err"] is None:
                    recs[s]["err"] = e
                # Every run of a setting must give the same answer (one thread, no
                # randomness); the largest KE difference between repeats is kept.
                rec["ke_dev_from_first"] = abs(e["ke"] - recs[s]["err"]["ke"]) / recs[s]["err"]["ke"]
            recs[s]["runs"].append(rec)
        print("  repeat %d of %d done (%.0f s so far)" % (rep + 1, a.repeats, time.perf_counter() - t0))
    for s in order:
        r = recs[s]
        ok = [x for x in r["runs"] if x.get("status") == "ok"]
        r["status"] = "ok" if len(ok) == len(r["runs"]) else (r["runs"][0].get("status") or "failed")
        walls = [x["wall_s"] for x in ok]
        r["wall_s"] = bc.med(walls)
        r["wall_s_runs"] = [x["wall_s"] for x in r["runs"]]
        r["cpu_s"] = bc.med([x.get("cpu_s") for x in ok])
        r["cpu_s_runs"] = [x.get("cpu_s") for x in r["runs"]]
        r["loop_s"] = bc.med([x.get("loop_s") for x in ok])
        r["loop_s_runs"] = [x.get("loop_s") for x in r["runs"]]
        r["wall_spread"] = (max(walls) / min(walls) - 1.0) if len(walls) > 1 else None
        r["steps"] = ok[0].get("steps") if ok else None
        r["rhs_evals"] = ok[0].get("rhs_evals") if ok else None
        r["repeat_ke_dev"] = max((x.get("ke_dev_from_first", 0.0) for x in ok), default=None)
        res["settings"].append(r)
    res["seconds"] = time.perf_counter() - t0
    res["tta"] = summarize(res["settings"], "wall_s")
    res["tta_loop"] = summarize(res["settings"], "loop_s")
    res["tta_cpu"] = summarize(res["settings"], "cpu_s")
    res["table_check"] = table_check(res["settings"], recs, ref, box, mass)
    return res


def table_check(settings, recs, ref, box, mass):
    """LAMMPS against spam-ark's kdk at the same dt: the same scheme on the same particles,
    so what differs is LAMMPS's linear table of the force (and round-off)."""
    out = []
    for s in settings:
        if s["curve"] != "kdk" or s["err"] is None:
            continue
        lam = recs.get(("lammps", s["param"]))
        if lam is None or lam["err"] is None:
            continue
        out.append({"dt": s["param"], "ke_rel_diff": abs(s["err"]["ke"] - lam["err"]["ke"]) / ref_ke(ref, mass),
                    "lammps_ke_err": lam["err"]["ke_err"], "kdk_ke_err": s["err"]["ke_err"],
                    "lammps_pos_err": lam["err"]["pos_err"], "kdk_pos_err": s["err"]["pos_err"]})
    return out


def ref_ke(ref, mass):
    return kinetic(ref[1], mass)


def summarize(settings, tkey):
    """Time to accuracy per curve, measure and eps, and the ratio spam-ark / LAMMPS."""
    curves = sorted({s["curve"] for s in settings}, key=list(LABELS).index)
    out = {}
    for measure in ("ke_err", "pos_err"):
        out[measure] = []
        for eps in EPS:
            row = {"eps": eps, "curves": {}}
            for c in curves:
                pts = [(s[tkey], s["err"]) for s in settings if s["curve"] == c and s["status"] == "ok"]
                runs, interp = time_to_accuracy(pts, eps, measure)
                best = None
                if runs is not None:
                    best = min((s for s in settings if s["curve"] == c and s["status"] == "ok"
                                and s["err"][measure] <= eps), key=lambda s: s[tkey])
                row["curves"][c] = {"runs_s": runs, "interp_s": interp,
                                    "setting": best["param"] if best else None}
            spam = {c: v for c, v in row["curves"].items() if c != "lammps" and v["runs_s"]}
            lam = row["curves"].get("lammps", {})
            if spam and lam.get("runs_s"):
                c_run = min(spam, key=lambda c: spam[c]["runs_s"])
                row["best_spam_runs"] = c_run
                row["ratio_runs"] = spam[c_run]["runs_s"] / lam["runs_s"]
                # Per repeat: the same repeat's runs of the two chosen settings.
                s_set = next(s for s in settings if s["curve"] == c_run
                             and s["param"] == spam[c_run]["setting"])
                l_set = next(s for s in settings if s["curve"] == "lammps"
                             and s["param"] == lam["setting"])
                per = [x / y for x, y in zip(s_set[tkey + "_runs"], l_set[tkey + "_runs"])]
                row["ratio_runs_per_repeat"] = per
                c_int = min(spam, key=lambda c: spam[c]["interp_s"])
                row["best_spam_interp"] = c_int
                row["ratio_interp"] = spam[c_int]["interp_s"] / lam["interp_s"]
            out[measure].append(row)
    return out


# --------------------------------------------------------------------------
# Report
# --------------------------------------------------------------------------

def fmt_setting(curve, param):
    if param is None:
        return "-"
    return ("dt %g" % param) if curve in ("lammps", "kdk") else ("rtol %g" % param)


def print_size(res, repeats):
    print("\n  setting                              steps  RHS evals  wall s (median)  spread  CPU s  "
          "KE error   max |dx|   RMS |dx|")
    for s in res["settings"]:
        e = s["err"] or {}
        print("  %-30s %-9s %6s %9s %12s %9s %7s   %9s %9s %9s%s"
              % (LABELS[s["curve"]][:30], fmt_setting(s["curve"], s["param"]), bc.fnum(s["steps"], "%d"),
                 bc.fnum(s["rhs_evals"], "%d"), bc.fnum(s["wall_s"], "%.3f"),
                 bc.fnum(s["wall_spread"] * 100 if s["wall_spread"] is not None else None, "%.0f%%"),
                 bc.fnum(s["cpu_s"], "%.2f"),
                 bc.fnum(e.get("ke_err"), "%.2e"), bc.fnum(e.get("pos_err"), "%.2e"),
                 bc.fnum(e.get("pos_err_rms"), "%.2e"),
                 "" if s["status"] == "ok" else "  [%s]" % s["status"]))
    for measure, name in (("ke_err", "KE(t) relative error"), ("pos_err", "max position error")):
        print("\n  time to accuracy, %s (wall s; runs / interpolated; median of %d)" % (name, repeats))
        for row, lrow, crow in zip(res["tta"][measure], res["tta_loop"][measure], res["tta_cpu"][measure]):
            parts = []
            for c, v in row["curves"].items():
                parts.append("%s %s/%s (%s)" % (c, bc.fnum(v["runs_s"]), bc.fnum(v["interp_s"]),
                                                fmt_setting(c, v["setting"])))
            line = "    eps %.0e: %s" % (row["eps"], "; ".join(parts))
            if "ratio_runs" in row:
                per = row["ratio_runs_per_repeat"]
                line += ("\n               ratio spam-ark/LAMMPS: runs %.3f (%s; repeats %.3f-%.3f), "
                         "interpolated %.3f (%s)"
                         % (row["ratio_runs"], row["best_spam_runs"], min(per), max(per),
                            row["ratio_interp"], row["best_spam_interp"]))
            if "ratio_runs" in lrow:
                line += ("\n               run loops only (no start-up, reading or writing): runs %.3f (%s), "
                         "interpolated %.3f" % (lrow["ratio_runs"], lrow["best_spam_runs"], lrow["ratio_interp"]))
            if "ratio_runs" in crow:
                per = crow["ratio_runs_per_repeat"]
                line += ("\n               CPU time of the whole processes: runs %.3f (%s; repeats %.3f-%.3f), "
                         "interpolated %.3f" % (crow["ratio_runs"], crow["best_spam_runs"], min(per), max(per),
                                                crow["ratio_interp"]))
            print(line)
    if res.get("table_check"):
        print("\n  LAMMPS against spam-ark kdk at the same dt (same scheme: the difference is LAMMPS's table):")
        for t in res["table_check"]:
            print("    dt %g: KE differs by %.1e (KE errors %.2e and %.2e; max position errors %.2e and %.2e)"
                  % (t["dt"], t["ke_rel_diff"], t["lammps_ke_err"], t["kdk_ke_err"], t["lammps_pos_err"],
                     t["kdk_pos_err"]))


def headline(results, repeats):
    for res in results:
        if res["n"] != TARGET_N:
            continue
        row = next(r for r in res["tta"]["ke_err"] if r["eps"] == TARGET_EPS)
        if "ratio_runs" not in row:
            return {"met": None, "line": "target: KE within %g at N = %d not reached by both programs"
                    % (TARGET_EPS, TARGET_N)}
        ratio = row["ratio_runs"]
        met = ratio <= TARGET_RATIO
        lrow = next(r for r in res["tta_loop"]["ke_err"] if r["eps"] == TARGET_EPS)
        crow = next(r for r in res["tta_cpu"]["ke_err"] if r["eps"] == TARGET_EPS)
        c = row["curves"]
        cs = c[row["best_spam_runs"]]
        line = ("target: N = %d, KE(t = %g) within %g, whole processes, median of %d: spam-ark %s "
                "%s %.3f s, LAMMPS %s %.3f s: ratio %.3f (per repeat %.3f-%.3f) (target <= %g): %s.\n"
                "  Interpolated to the step or tolerance that just reaches %g: %.3f; run loops only: %.3f; "
                "CPU time of the whole processes: %.3f (per repeat %.3f-%.3f)."
                % (TARGET_N, T_END, TARGET_EPS, repeats, row["best_spam_runs"],
                   fmt_setting(row["best_spam_runs"], cs["setting"]), cs["runs_s"],
                   fmt_setting("lammps", c["lammps"]["setting"]), c["lammps"]["runs_s"], ratio,
                   min(row["ratio_runs_per_repeat"]), max(row["ratio_runs_per_repeat"]),
                   TARGET_RATIO, "met" if met else "falls short", TARGET_EPS, row["ratio_interp"],
                   lrow.get("ratio_runs", float("nan")), crow.get("ratio_runs", float("nan")),
                   min(crow.get("ratio_runs_per_repeat", [float("nan")])),
                   max(crow.get("ratio_runs_per_repeat", [float("nan")]))))
        return {"met": met, "ratio_runs": ratio, "ratio_interp": row["ratio_interp"],
                "ratio_loop_runs": lrow.get("ratio_runs"), "ratio_cpu_runs": crow.get("ratio_runs"), "line": line}
    return {"met": None, "line": "target: N = %d was not run" % TARGET_N}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spam-ark", default=str(bc.REPO_ROOT / "build" / "spam-ark"))
    p.add_argument("--lmp", default="lmp")
    p.add_argument("--sizes", default="16384,65536", help="particle counts, each a perfect square")
    p.add_argument("--repeats", type=int, default=3, help="timed runs of every setting; medians reported")
    p.add_argument("--curves", default="lammps,dp5,bs3,kdk",
                   help="which ladders to run (lammps, dp5, bs3, kdk)")
    p.add_argument("--ladder", action="append", default=[], metavar="CURVE=V,V,...",
                   help="replace one curve's ladder (dt for lammps and kdk, rtol for dp5 and bs3), "
                        "e.g. --ladder lammps=0.02,0.01; may be repeated")
    p.add_argument("--quick", action="store_true", help="N = 4096, 1 repeat, two or fewer settings a curve")
    p.add_argument("--table-points", type=int, default=20000,
                   help="LAMMPS table points (default 20000, as run_bench.py; the output compares "
                        "LAMMPS with spam-ark's kdk at the same dt, which measures the table's error)")
    p.add_argument("--table-rlo", type=float, default=1e-10)
    p.add_argument("--skin", type=float, default=1.0, help="LAMMPS neighbour skin")
    p.add_argument("--cpu", type=int, default=0)
    p.add_argument("--no-pin", action="store_true")
    p.add_argument("--keep", action="store_true", help="keep the scratch directory")
    p.add_argument("--out", default=None, help="JSON (default bench/results/accuracy_<date>.json)")
    p.add_argument("--chart", default=None,
                   help="the chart (PNG; default docs/time_to_accuracy.png, with --quick "
                        "bench/results/time_to_accuracy_quick.png); '' for none")
    a = p.parse_args()
    if a.quick:
        a.sizes, a.repeats = "4096", 1
    if a.chart is None:
        a.chart = str(bc.BENCH_DIR / "results" / "time_to_accuracy_quick.png" if a.quick
                      else bc.REPO_ROOT / "docs" / "time_to_accuracy.png")
    curves = a.curves.split(",")
    own = {}
    for item in a.ladder:
        name, _, values = item.partition("=")
        if name not in LABELS or not values:
            raise SystemExit("--ladder: %r is not CURVE=V,V,... with CURVE one of %s" % (item, ", ".join(LABELS)))
        own[name] = [float(v) for v in values.split(",")]
    a.spam_ark = str(Path(a.spam_ark).resolve())
    pin = bc.pin_prefix(a.cpu, not a.no_pin)
    work = Path(tempfile.mkdtemp(prefix="spam_accuracy_"))
    stamp = datetime.datetime.now().strftime("%Y-%m-%dT%H%M%S")
    out_path = Path(a.out) if a.out else bc.BENCH_DIR / "results" / ("accuracy_%s.json" % stamp)
    head = subprocess.run(["git", "-C", str(bc.REPO_ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    print("time to accuracy, 2D expansion h = %g to t = %g: spam-ark %s (commit %s), LAMMPS %s, "
          "pinned %s, %d repeats (median), LAMMPS table %d points" % (H, T_END, a.spam_ark, head, a.lmp,
                                                                      " ".join(pin) or "no", a.repeats,
                                                                      a.table_points))
    out = {"date": datetime.datetime.now().isoformat(timespec="seconds"), "commit": head,
           "argv": sys.argv[1:], "repeats": a.repeats, "t_end": T_END, "h": H, "eps": list(EPS),
           "atol_over_rtol": ATOL_OVER_RTOL, "table_points": a.table_points, "skin": a.skin,
           "load_1min_start": os.getloadavg()[0], "results": []}
    for n in sorted(int(s) for s in a.sizes.split(",")):
        lad = dict(QUICK_LADDERS if a.quick else (LADDERS if n <= 16384 else LARGE_LADDERS))
        lad.update(own)
        res = one_size(a, n, work, pin, {c: lad[c] for c in curves})
        res["ladders"] = {c: lad[c] for c in curves}
        print_size(res, a.repeats)
        out["results"].append(res)
        out["target"] = headline(out["results"], a.repeats)
        out_path.parent.mkdir(parents=True, exist_ok=True)
        out_path.write_text(json.dumps(out, indent=1, default=str) + "\n")
    print("\n" + out["target"]["line"])
    spreads = [s["wall_spread"] for r in out["results"] for s in r["settings"] if s["wall_spread"] is not None]
    if spreads:
        runs = [x for r in out["results"] for s in r["settings"] for x in s["runs"] if x.get("cpu_s")]
        cpu_spreads = [max(v) / min(v) - 1.0 for v in
                       ([c for c in s["cpu_s_runs"] if c] for r in out["results"] for s in r["settings"])
                       if len(v) > 1]
        out["noise"] = {"median_spread": bc.med(spreads), "max_spread": max(spreads),
                        "cpu_median_spread": bc.med(cpu_spreads), "cpu_max_spread": max(cpu_spreads, default=None),
                        "wall_over_cpu_median": bc.med([x["wall_s"] / x["cpu_s"] for x in runs]),
                        "wall_over_cpu_max": max((x["wall_s"] / x["cpu_s"] for x in runs), default=None)}
        nz = out["noise"]
        print("noise: (slowest / fastest repeat - 1) of a setting's wall time: median %.0f%%, largest %.0f%%; "
              "of its CPU time: median %.0f%%, largest %.0f%%; wall / CPU time of a run: median %.2f, largest %.2f "
              "(above 1: the process waited for the core, which other work shared)"
              % (100 * nz["median_spread"], 100 * nz["max_spread"], 100 * (nz["cpu_median_spread"] or 0),
                 100 * (nz["cpu_max_spread"] or 0), nz["wall_over_cpu_median"] or 0, nz["wall_over_cpu_max"] or 0))
    out_path.write_text(json.dumps(out, indent=1, default=str) + "\n")
    print("results in %s" % out_path)
    if a.keep:
        print("kept scratch directory %s" % work)
    else:
        shutil.rmtree(work, ignore_errors=True)
    if a.chart:
        import accuracy_chart
        accuracy_chart.draw(out, Path(a.chart))
        print("chart in %s" % a.chart)


if __name__ == "__main__":
    main()
