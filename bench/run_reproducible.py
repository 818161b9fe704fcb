#!/usr/bin/python3
"""Cost of -reproducible against the default mode, on one rank and one thread.

The same run twice in alternation, -reproducible and not: the expansion scene (2D: 128^2
particles at h = 3, gamma 1.7; 3D: 24^3 at h = 2.5, gamma 5/3: the density pass runs), Dormand-
Prince at a fixed step for --steps steps (the same RHS evaluations in both modes),
snapshots and entropy off. From each run's -log_view: the time in the RHS (SpamRHS, list
builds included) per evaluation, and its parts -- the density pass (SpamDensity), the force
pass (SpamForce) and the list builds (SpamNbrBuild, which under -reproducible also make
the sorted full rows). Printed: medians over --repeats pairs of runs and the ratio
reproducible / default of each, measured in the same invocation.

What the ratio holds: the default mode visits each pair once (a half list, vectorised
chunked loops for Lucy's kernel) and the reproducible mode twice (each row its own sum in
vectorised chunks summed in row order, periodic images as ghost slots); its list build
adds the full rows (the half list's pairs entered in both rows, the ghost partners) and a
sort of each row by partner id.

Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_reproducible.py [--steps 20] [--repeats 5] [--dims 2,3]
"""
import argparse
import datetime
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_common as bc  # noqa: E402
import spam_driver as sd  # noqa: E402

CASES = {
    2: ["-scene", "expansion", "-dim", 2, "-expansion_n", 128, "-h", 3, "-eos_gamma", 1.7, "-arkode_fixed_step", 0.1],
    3: ["-scene", "expansion", "-dim", 3, "-expansion_n", 24, "-h", 2.5, "-arkode_fixed_step", 0.1],
}
EVENTS = ("SpamRHS", "SpamDensity", "SpamForce", "SpamNbrBuild")


def one_run(binary, dim, steps, reproducible, work, tag, pin):
    """Seconds per RHS evaluation of each event, from -log_view."""
    out = work / tag
    cmd = pin + [binary] + [str(x) for x in CASES[dim]] + [
        "-ts_max_steps", steps, "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0,
        "-output_dir", out, "-output_overwrite", "-log_view", "-threads", 1]
    if reproducible:
        cmd.append("-reproducible")
    log = work / (tag + ".log")
    rc, _, _ = bc.run_measured([str(x) for x in cmd], bc.REPO_ROOT, log)
    if rc != 0:
        raise RuntimeError("spam-ark failed (rc=%d): %s\n%s" % (rc, " ".join(map(str, cmd)), bc.tail(log)))
    rows, _ = sd.parse_log_view(log.read_text(), EVENTS)
    summary = json.loads((out / "summary.json").read_text())
    evals = summary["rhs_evals"]
    per = {e: sum(r["time_s"] for r in rows if r["event"] == e) / evals for e in EVENTS}
    per["builds"] = sum(r["count"] for r in rows if r["event"] == "SpamNbrBuild")
    per["rhs_evals"] = evals
    return per


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spam-ark", default=str(bc.REPO_ROOT / "build" / "spam-ark"))
    p.add_argument("--steps", type=int, default=20)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--dims", default="2,3")
    p.add_argument("--cpu", type=int, default=0)
    p.add_argument("--no-pin", action="store_true")
    p.add_argument("--out", default=None, help="JSON results (default bench/results/reproducible_<date>.json)")
    p.add_argument("--readings", default=None, help="also write the table docs/parallel.md quotes to this JSON")
    a = p.parse_args()
    pin = bc.pin_prefix(a.cpu, not a.no_pin)
    work = Path(tempfile.mkdtemp(prefix="spam_repro_"))
    results = {"date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
               "steps": a.steps, "repeats": a.repeats, "load_before": os.getloadavg(), "cases": {}}
    # The machine may be shared: its load (1, 5, 15 min) says how far to trust the times.
    print("load average before: %.2f %.2f %.2f" % os.getloadavg())
    for dim in [int(d) for d in a.dims.split(",")]:
        runs = {"default": [], "reproducible": []}
        for k in range(a.repeats):  # alternating: a load change hits both modes alike
            for mode in ("default", "reproducible"):
                runs[mode].append(one_run(a.spam_ark, dim, a.steps, mode == "reproducible", work, "%dd_%s_%d" % (dim, mode, k), pin))
        med = {m: {e: statistics.median(r[e] for r in runs[m]) for e in EVENTS} for m in runs}
        print("%dD expansion, %s, %d steps (%d RHS evaluations, %d list builds): medians of %d runs, ms per RHS evaluation"
              % (dim, " ".join(map(str, CASES[dim][2:])), a.steps, runs["default"][0]["rhs_evals"], runs["default"][0]["builds"], a.repeats))
        print("  %-14s %10s %13s %8s" % ("event", "default", "reproducible", "ratio"))
        for e in EVENTS:
            d, r = med["default"][e], med["reproducible"][e]
            print("  %-14s %10.3f %13.3f %8.2f" % (e, 1e3 * d, 1e3 * r, r / d if d > 0 else float("nan")))
        results["cases"]["%dd" % dim] = {"args": [str(x) for x in CASES[dim]], "median_s_per_rhs": med,
                                         "ratio_rhs": med["reproducible"]["SpamRHS"] / med["default"]["SpamRHS"], "runs": runs}
    results["load_after"] = os.getloadavg()
    print("load average after: %.2f %.2f %.2f" % results["load_after"])
    out = Path(a.out) if a.out else bc.BENCH_DIR / "results" / ("reproducible_%s.json" % datetime.date.today().isoformat())
    out.write_text(json.dumps(results, indent=1) + "\n")
    print("results: %s" % out)
    if a.readings:
        rows = []
        for dim, case in results["cases"].items():
            md, mr = case["median_s_per_rhs"]["default"], case["median_s_per_rhs"]["reproducible"]
            run0 = case["runs"]["default"][0]
            name = ("2D expansion, 128², h = 3, γ = 1.7" if dim == "2d" else "3D expansion, 24³, h = 2.5, γ = 5/3") + \
                " (%d builds)" % run0["builds"]
            rows.append([name, "%.3f" % (1e3 * md["SpamRHS"]), "%.3f" % (1e3 * mr["SpamRHS"]), "%.2f" % case["ratio_rhs"],
                         ", ".join("%.2f" % (mr[e] / md[e]) for e in ("SpamDensity", "SpamForce", "SpamNbrBuild"))])
        bc.page_readings(a.readings, {
            "steps": a.steps, "repeats": a.repeats, "rhs_evals": run0["rhs_evals"],
            "load_before": results["load_before"][0], "load_after": results["load_after"][0],
            "ratio_rhs": {d: c["ratio_rhs"] for d, c in results["cases"].items()},
            "table": {"columns": ["case", "default ms/RHS", "reproducible ms/RHS", "ratio",
                                  "of which: density, force, list builds"], "rows": rows}})


if __name__ == "__main__":
    main()
