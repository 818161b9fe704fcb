#!/usr/bin/python3
"""Benchmark spam-ark against LAMMPS on the same initial particles.

Why LAMMPS is a fair peer: 2D SPAM with pressure P = rho^2/2 and particle
mass m = 1 has P_i/rho_i^2 = 1/2 for every particle, so the SPAM equation of
motion

    dv_i/dt = -sum_j m (P_i/rho_i^2 + P_j/rho_j^2) grad_i w(r_ij)
            = -sum_j grad_i w(r_ij)

is exactly molecular dynamics with Lucy's kernel w(r) as the pair potential.
LAMMPS runs that potential through `pair_style table`, with a table this
script writes.

Cases: the 2D isentropic expansion at h = 3 and h = 6 (spam-ark against
LAMMPS, same particles, steps and dt), and the elastic solid on spam-ark's
full tensor path (plane-wave scene, continuity density, R2 coordinates),
which LAMMPS cannot run; its cost is set against the LAMMPS gas only as a
reference.  Sizes N = 16384 ... 1048576.  At the end the script reports the
targets T1-T3 as "met" or "falls short".

This is a measurement, not a test: it prints a table and writes
bench/results/bench_<date>.json; the exit code is non-zero only when a run
fails.  See bench/README.md.

Only the standard library and numpy are used.
"""

import argparse
import datetime
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_common import BENCH_DIR, DT, REPO_ROOT, np, pin_prefix
from peer_lammps import validate_lammps
from spam_driver import DP_TABLE, spam_ark_works
from bench_cases import (baselines, bench_gas, bench_solid, log_view_run, parse_cases,
                         solid_reference, steps_for)
from bench_memory import run_memory
import run_verlet
from bench_report import PAGE_COLUMNS, evaluate_targets, page_rows, print_gas, print_log_view, print_solid, print_summary


DEFAULT_SIZES = "16384,65536,262144,1048576"
DEFAULT_CASES = "gas-h3,gas-h6,solid-h3"
QUICK_SIZES = "4096"
QUICK_STEPS = 20


def parse_args(argv):
    ap = argparse.ArgumentParser(
        description="Benchmark spam-ark against LAMMPS (pair_style table with "
                    "Lucy's kernel) on the same initial particles, and the "
                    "spam-ark elastic solid on its own.")
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"),
                    help="spam-ark binary (default: <repo>/build/spam-ark)")
    ap.add_argument("--lmp", default="lmp", help="LAMMPS binary (default: lmp)")
    ap.add_argument("--sizes", default=None,
                    help="comma-separated particle counts, each a perfect square "
                         "(default %s; %s with --quick)" % (DEFAULT_SIZES, QUICK_SIZES))
    ap.add_argument("--cases", default=DEFAULT_CASES,
                    help="comma-separated cases gas-hH and solid-hH (default %s)"
                         % DEFAULT_CASES)
    ap.add_argument("--steps", type=int, default=None,
                    help="steps for every case and size (default: per case and size, "
                         "a few seconds of spam-ark per run; see bench/README.md)")
    ap.add_argument("--lammps-steps", type=int, default=None,
                    help="override LAMMPS steps only")
    ap.add_argument("--spam-steps", type=int, default=None,
                    help="override spam-ark steps only")
    ap.add_argument("--repeats", type=int, default=None,
                    help="timed runs per program, case and size; the median is "
                         "reported (default 5, 1 with --quick)")
    ap.add_argument("--quick", action="store_true",
                    help="smoke run: N = %s, %d steps, 1 repeat" % (QUICK_SIZES, QUICK_STEPS))
    ap.add_argument("--max-seconds", type=float, default=600.0,
                    help="skip a size (and all larger ones) when its runs are predicted, "
                         "from the previous size, to take longer than this "
                         "(default 600; 0: no limit)")
    ap.add_argument("--log-view", action="store_true",
                    help="one extra untimed spam-ark run (gas h = 3, N = --log-view-size) "
                         "with PETSc's -log_view; the file goes next to the JSON")
    ap.add_argument("--log-view-size", type=int, default=65536,
                    help="N of the --log-view run (default 65536)")
    ap.add_argument("--verlet-n", type=int, default=None,
                    help="N of the whole-process row: velocity Verlet, spam-ark kdk against "
                         "LAMMPS fix nve, whole processes timed (run_verlet.py; default 65536, "
                         "4096 with --quick; 0: no such row)")
    ap.add_argument("--verlet-steps", type=int, default=None,
                    help="steps of the whole-process row (default 200, %d with --quick)" % QUICK_STEPS)
    ap.add_argument("--skin", type=float, default=1.0,
                    help="LAMMPS neighbour skin (default 1.0, the fastest of "
                         "0.3/0.5/0.8/1.0/1.5 measured here on this problem)")
    ap.add_argument("--table-points", type=int, default=20000,
                    help="points in the LAMMPS table (default 20000)")
    ap.add_argument("--table-rlo", type=float, default=1e-10,
                    help="inner radius of the LAMMPS table (default 1e-10; the Lucy "
                         "potential is soft, so streams interpenetrate and pairs "
                         "can come very close)")
    ap.add_argument("--cpu", type=int, default=0, help="core to pin to (default 0)")
    ap.add_argument("--no-pin", action="store_true", help="do not use taskset")
    ap.add_argument("--lammps-only", action="store_true",
                    help="skip spam-ark (and so the solid); the initial lattice is "
                         "made with numpy")
    ap.add_argument("--numpy-initial", action="store_true",
                    help="make the initial gas lattice with numpy (unperturbed, sites "
                         "at i+0.5) instead of spam-ark -initial_csv")
    ap.add_argument("--validate-lammps", action="store_true",
                    help="also check the LAMMPS table, forces and energy drift (h = 3)")
    ap.add_argument("--memory", action="store_true",
                    help="only the memory tables (no LAMMPS, no timing): (peak RSS - "
                         "baseline) / N of gas-h3 and the 2D expansion at --memory-sizes, "
                         "and the resident bytes a particle by owner (bench/memory_owners.c "
                         "preloaded into the gas-h3 run at N = 65536 and 262144)")
    ap.add_argument("--memory-sizes", default="16384,65536,262144",
                    help="N of the --memory RSS runs (default 16384,65536,262144)")
    ap.add_argument("--workdir", default=None,
                    help="scratch directory (default: a fresh temporary one)")
    ap.add_argument("--keep", action="store_true", help="keep the scratch directory")
    ap.add_argument("--out", default=None,
                    help="JSON output (default bench/results/bench_<date>.json)")
    ap.add_argument("--readings", default=None,
                    help="also write the table and targets bench/README.md quotes to this JSON "
                         "(with the command and commit, examples/chart_readings.py)")
    args = ap.parse_args(argv)
    try:
        args.memory_sizes = [int(v) for v in args.memory_sizes.split(",") if v.strip()]
    except ValueError:
        raise SystemExit("--memory-sizes: %r is not a list of integers" % args.memory_sizes)
    if args.quick:
        if args.sizes is None:
            args.sizes = QUICK_SIZES
        if args.steps is None:
            args.steps = QUICK_STEPS
        if args.repeats is None:
            args.repeats = 1
        if args.verlet_n is None:
            args.verlet_n = 4096
        if args.verlet_steps is None:
            args.verlet_steps = QUICK_STEPS
    if args.sizes is None:
        args.sizes = DEFAULT_SIZES
    if args.verlet_n is None:
        args.verlet_n = 65536
    if args.verlet_steps is None:
        args.verlet_steps = 200
    if args.verlet_n and int(round(args.verlet_n ** 0.5)) ** 2 != args.verlet_n:
        raise SystemExit("--verlet-n must be a perfect square")
    if args.repeats is None:
        args.repeats = 5
    if args.repeats < 1:
        raise SystemExit("--repeats must be at least 1")
    return args


def predict_seconds(prev, n_next, cases, args):
    """Seconds the next size will take, scaled from the previous size's
    blocks: timed runs by N x steps, the rest (initial state, pair counts,
    data files, census) by N."""
    total = 0.0
    for case in cases:
        p = prev.get(case["name"])
        if not p:
            continue
        _, s_next = steps_for(case, n_next, args)
        timed = p["timed"] * (n_next * s_next) / (p["n"] * p["steps"])
        other = p["other"] * n_next / p["n"]
        total += timed + other
    return total


def memory_only(args):
    """--memory: the memory tables alone, written to bench/results/memory_<date>.json."""
    args.spam_ark = str(Path(args.spam_ark).resolve())
    ok, why = spam_ark_works(args.spam_ark)
    if not ok:
        sys.exit("spam-ark unusable: %s" % why)
    workdir = Path(args.workdir).resolve() if args.workdir else Path(tempfile.mkdtemp(prefix="spam-ark-mem-"))
    workdir.mkdir(parents=True, exist_ok=True)
    res = run_memory(args, workdir)
    stamp = datetime.datetime.now().strftime("%Y-%m-%dT%H%M%S")
    out_path = Path(args.out).resolve() if args.out else BENCH_DIR / "results" / ("memory_%s.json" % stamp)
    out_path.parent.mkdir(parents=True, exist_ok=True)
    out_path.write_text(json.dumps(res, indent=1))
    print("wrote %s" % out_path)
    if args.readings:
        sys.path.insert(0, str(REPO_ROOT / "examples"))
        import chart_readings
        chart_readings.write_json(args.readings, {"tables": res["tables"], "owners_n": res["owners_n"]})
    if not args.workdir and not args.keep:
        shutil.rmtree(workdir, ignore_errors=True)
    return 0


# The goal for the whole process (run_verlet.py's row): spam-ark's wall time at most
# this share of LAMMPS's.
VERLET_PROCESS_GOAL = 0.35


def verlet_row(args, workdir, pin, out):
    """The whole-process row: velocity Verlet in both programs (run_verlet.measure), the
    same repeats as the cases; printed, and returned without the runs (None on failure)."""
    print("\nwhole process: velocity Verlet, N = %d, %d steps (run_verlet.py)" % (args.verlet_n, args.verlet_steps))
    try:
        # The cases' LAMMPS table (--table-points): run_verlet.py's finer default, made for
        # its 1e-9 energy check, takes LAMMPS seconds to read, which would count here.
        res = run_verlet.measure(args.spam_ark, args.lmp, args.verlet_n, steps=args.verlet_steps,
                                 repeats=args.repeats, table_points=args.table_points, skin=args.skin,
                                 pin=pin, work=workdir / "verlet")
    except RuntimeError as exc:
        print("FAILED\n%s" % exc)
        out["failures"].append({"case": "verlet", "n": args.verlet_n, "error": str(exc)})
        return None
    lines = run_verlet.report_lines(res, VERLET_PROCESS_GOAL)
    print("\n".join(lines))
    res = {k: v for k, v in res.items() if not k.endswith("_runs")}
    res["lines"] = lines
    return res


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        sizes = sorted({int(s) for s in args.sizes.split(",") if s.strip()})
    except ValueError:
        raise SystemExit("--sizes: %r is not a list of integers" % args.sizes)
    cases = parse_cases(args.cases)
    if args.memory:
        return memory_only(args)
    if shutil.which(args.lmp) is None and not Path(args.lmp).is_file():
        sys.exit("LAMMPS binary %r not found (Debian: apt-get install lammps)" % args.lmp)
    args.lmp = shutil.which(args.lmp) or str(Path(args.lmp).resolve())
    args.spam_ark = str(Path(args.spam_ark).resolve())
    pin = pin_prefix(args.cpu, not args.no_pin)

    spam_ok = False
    spam_note = "skipped (--lammps-only)"
    if not args.lammps_only:
        spam_ok, why = spam_ark_works(args.spam_ark)
        spam_note = "ok" if spam_ok else why
        if not spam_ok:
            print("warning: spam-ark unusable (%s); running the LAMMPS half only, "
                  "on a numpy-made lattice" % why)
    if not spam_ok and any(c["kind"] == "solid" for c in cases):
        print("note: the solid cases need spam-ark; skipping them")
        cases = [c for c in cases if c["kind"] != "solid"]

    stamp = datetime.datetime.now().strftime("%Y-%m-%dT%H%M%S")
    if args.out:
        out_path = Path(args.out).resolve()
    else:
        out_path = BENCH_DIR / "results" / ("bench_%s.json" % stamp)
    log_view_path = out_path.with_name(out_path.stem + "_log_view.txt")

    if args.workdir:
        workdir = Path(args.workdir).resolve()
        workdir.mkdir(parents=True, exist_ok=True)
        own_workdir = False
    else:
        workdir = Path(tempfile.mkdtemp(prefix="spam-ark-bench-"))
        own_workdir = True

    print("spam-ark bench: spam-ark %s [%s]; LAMMPS %s; pinning: %s; OMP_NUM_THREADS=1; "
          "repeats %d (median); LAMMPS skin %g, table %d points"
          % (args.spam_ark, spam_note, args.lmp, " ".join(pin) or "none",
             args.repeats, args.skin, args.table_points))
    print("scratch: %s" % workdir)
    print("cases: %s" % "; ".join(c["label"] for c in cases))
    print("steps (both programs, dt = %g, Dormand-Prince for spam-ark, velocity Verlet "
          "for LAMMPS):" % DT)
    for c in cases:
        print("  %-9s %s" % (c["name"], ", ".join("N=%d: %d" % (n, steps_for(c, n, args)[1])
                                                 for n in sizes)))
    if args.max_seconds > 0:
        print("size guard: a size predicted to take more than %.0f s is skipped, with "
              "all larger ones (--max-seconds)" % args.max_seconds)

    t_start = time.perf_counter()
    out = {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "host": platform.node(), "machine": platform.machine(),
        "cpu_count": os.cpu_count(), "python": sys.version.split()[0],
        "numpy": np.__version__, "spam_ark": args.spam_ark, "spam_ark_status": spam_note,
        "lammps": args.lmp, "pin": pin, "repeats": args.repeats, "dt": DT,
        "integrator_spam_ark": DP_TABLE, "integrator_lammps": "fix nve (velocity Verlet)",
        "cases": cases, "lammps_skin": args.skin, "table_points": args.table_points,
        "table_rlo": args.table_rlo, "sizes": sizes, "max_seconds": args.max_seconds,
        "quick": args.quick, "results": [], "skipped": [], "failures": [],
        "argv": sys.argv[1:] if argv is None else list(argv), "load_1min_start": os.getloadavg()[0],
    }
    try:
        lv = subprocess.run([args.lmp, "-h"], capture_output=True, text=True, timeout=60)
        m = re.search(r"LAMMPS.*?- (.+)", lv.stdout)
        out["lammps_version"] = m.group(1).strip() if m else None
    except (OSError, subprocess.TimeoutExpired):
        out["lammps_version"] = None
    try:
        out["git_head"] = subprocess.run(["git", "-C", str(REPO_ROOT), "rev-parse", "HEAD"],
                                         capture_output=True, text=True).stdout.strip()
    except OSError:
        out["git_head"] = None

    try:
        if args.validate_lammps:
            print("\nLAMMPS checks")
            gas_h = [c["h"] for c in cases if c["kind"] == "gas"]
            out["lammps_validation"] = validate_lammps(args, workdir, pin,
                                                       gas_h[0] if gas_h else 3.0)
        base = {}
        for c in cases:
            base[c["name"]] = baselines(args, workdir, pin, spam_ok, c)
        out["baseline"] = base
        table_cache = {}
        prev = {}
        for i, n in enumerate(sizes):
            if prev and args.max_seconds > 0:
                pred = predict_seconds(prev, n, cases, args)
                if pred > args.max_seconds:
                    for m_ in sizes[i:]:
                        out["skipped"].append({"n": m_, "predicted_s_first": pred,
                                               "reason": "--max-seconds %.0f" % args.max_seconds})
                    print("\nskipping N = %s: N = %d is predicted to take %.0f s "
                          "(> --max-seconds %.0f)"
                          % (", ".join(str(m_) for m_ in sizes[i:]), n, pred,
                             args.max_seconds))
                    break
                print("\nN = %d: predicted %.0f s" % (n, pred))
            t_size = time.perf_counter()
            # prev keeps each case's latest completed size, so a case that
            # failed at this size is still predicted from an earlier one.
            for c in cases:
                t_case = time.perf_counter()
                try:
                    if c["kind"] == "gas":
                        res = bench_gas(n, c, args, workdir, pin, spam_ok, table_cache,
                                        base[c["name"]])
                    else:
                        res = bench_solid(n, c, args, workdir, pin, base[c["name"]])
                except RuntimeError as exc:
                    print("\n== %s, N = %d: FAILED\n%s" % (c["label"], n, exc))
                    out["failures"].append({"case": c["name"], "n": n, "error": str(exc)})
                    continue
                res["block_seconds"] = time.perf_counter() - t_case
                out["results"].append(res)
                if c["kind"] == "gas":
                    print_gas(res, base[c["name"]])
                else:
                    print_solid(res, out["results"])
                print("  (this block took %.0f s, of which %.0f s in timed runs)"
                      % (res["block_seconds"], res["timed_seconds"]))
                prev[c["name"]] = {"n": n, "steps": res["spam_steps"],
                                   "timed": res["timed_seconds"],
                                   "other": res["block_seconds"] - res["timed_seconds"]}
            print("\nN = %d took %.0f s" % (n, time.perf_counter() - t_size))
        # A solid's nearest gas may have been run after it: recompute.
        for r in out["results"]:
            if r.get("kind") == "solid":
                r["reference"] = solid_reference(r, out["results"])
        if args.verlet_n > 0 and spam_ok:
            out["verlet"] = verlet_row(args, workdir, pin, out)
        if args.log_view:
            log_view_path.parent.mkdir(parents=True, exist_ok=True)
            try:
                out["log_view"] = log_view_run(args, workdir, pin, log_view_path, spam_ok)
            except RuntimeError as exc:
                out["log_view"] = {"error": str(exc)}
                out["failures"].append({"case": "log_view", "error": str(exc)})
                print("\n--log-view run FAILED\n%s" % exc)
    finally:
        if own_workdir and not args.keep:
            shutil.rmtree(workdir, ignore_errors=True)
        elif own_workdir:
            print("kept scratch directory %s" % workdir)

    if out["results"]:
        print_summary(out["results"])
    if out.get("log_view") and "n" in out["log_view"]:
        print_log_view(out["log_view"])
    targets, lines = evaluate_targets(out["results"])
    if out.get("verlet"):
        lines.append("W   " + out["verlet"]["lines"][-1].strip())
    out["targets"] = targets
    print()
    print("Targets (a measurement: the exit code does not depend on them)")
    for line in lines:
        print("  " + line)
    if out["skipped"]:
        print("  sizes skipped by --max-seconds: %s"
              % ", ".join(str(s["n"]) for s in out["skipped"]))
    out["total_seconds"] = time.perf_counter() - t_start

    out_path.parent.mkdir(parents=True, exist_ok=True)
    out_path.write_text(json.dumps(out, indent=1, default=str) + "\n")
    print("\nwrote %s (total %.0f s)" % (out_path, out["total_seconds"]))
    if args.readings:
        sys.path.insert(0, str(REPO_ROOT / "examples"))
        import chart_readings
        chart_readings.write_json(args.readings, {
            "table": chart_readings.table(PAGE_COLUMNS, page_rows(out["results"])),
            "targets": "\n".join("    " + line for line in lines) + "\n", "repeats": args.repeats,
            "seconds": out["total_seconds"], "load_1min_start": out.get("load_1min_start"),
            "verlet": out.get("verlet"),
            "log_view": out.get("log_view")})
    if out["failures"]:
        print("%d run(s) failed: %s" % (len(out["failures"]),
                                        ", ".join("%s N=%s" % (f["case"], f.get("n", "-"))
                                                  for f in out["failures"])))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
