#!/usr/bin/python3
"""Instructions and simulated cache misses per particle per right-hand side of the gas.

The growth of spam-ark's time per particle with N (run_bench.py's T2) is a question of
memory, which wall times on a shared machine without hardware counters answer badly. This
script runs the gas-h3 case of run_bench.py (the expansion lattice, Dormand-Prince at a
fixed step) for a few steps under valgrind's callgrind, counting inside the right-hand
side only (--toggle-collect=SpamRhs; the list's first build comes before the loop; with
--scope step inside whole steps, --toggle-collect=TSStep: ERKStep's vector work too), with
a simulated first-level data cache and last level (default 48 KiB 12-way and 8 MiB 16-way,
64-byte lines: this machine's L1d, and a share of its L3), and prints per particle and per
evaluation: instructions, first-level misses and last-level misses, in total and by
function (the pair pass, the position update, the writing of dr/dt and dv/dt). The counts
do not depend on the machine's load. A 2^20-particle run takes some 10 minutes.

    bench/run_cachegrind.py --sizes 16384,262144 --readings bench/readings/cachegrind.json
"""

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_common import REPO_ROOT, np
from spam_driver import spam_cmd, spam_make_initial

TOGGLE = {"rhs": "SpamRhs", "step": "TSStep"}
# Functions reported on their own (self cost), by the start of their symbol; the rest of
# the right-hand side is summed as "other".
PARTS = [("pair force pass", "Force"), ("list update (displacements; positions u)", "Displace"),
         ("u placed ahead of the rows", "SpamChunkedForceBlocks"),
         ("dr/dt, dv/dt written", "WriteRows"), ("dr/dt, dv/dt copied", "SpamRhsIsentrope"),
         ("accelerations cleared (memset)", "__memset")]
# With --scope step, the integrator's vector work too (ERKStep's sums, its copies, the norm
# of its "too much accuracy" test) and the list builds inside the steps.
STEP_PARTS = [("integrator: stage and solution sums", "Combine"),
              ("integrator: vector copies (memcpy)", "__memcpy"),
              ("integrator: accuracy-test norm", ("N_VWSqrSum", "AllZero")),
              ("list builds", ("AppendRow", "BuildList", "BinParticles", "WrapAll"))]


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"))
    ap.add_argument("--sizes", default="16384,262144",
                    help="particle counts, perfect squares (default 16384,262144)")
    ap.add_argument("--steps", type=int, default=2, help="Dormand-Prince steps (default 2)")
    ap.add_argument("--d1", default="49152,12,64", help="valgrind --D1 (default 49152,12,64)")
    ap.add_argument("--ll", default="8388608,16,64", help="valgrind --LL (default 8388608,16,64)")
    ap.add_argument("--scope", choices=("rhs", "step"), default="rhs",
                    help="count inside the right-hand side (rhs, default) or inside whole steps "
                         "(step: the integrator's vector work and the list builds as well)")
    ap.add_argument("--readings", default=None,
                    help="also write the table to this JSON (examples/chart_readings.py)")
    ap.add_argument("--workdir", default=None, help="scratch directory (default: a temporary one)")
    return ap.parse_args(argv)


def annotate(path):
    """{function: {event: count}} (self costs) and the totals of a callgrind file."""
    out = subprocess.run(["callgrind_annotate", "--threshold=100", str(path)],
                         capture_output=True, text=True, check=True).stdout
    events, funcs, total = None, {}, None
    for line in out.splitlines():
        if line.startswith("Events shown:"):
            events = line.split()[2:]
            continue
        if events is None or not re.match(r"^\s*[\d,]", line):
            continue
        nums = re.findall(r"([\d,]+|\.)\s*(?:\([^)]*\))?\s", line)[:len(events)]
        vals = dict(zip(events, [0 if x == "." else int(x.replace(",", "")) for x in nums]))
        if "PROGRAM TOTALS" in line:
            total = vals
        elif ":" in line:
            name = line.rsplit(" [", 1)[0].split()[-1].split(":", 1)[-1]
            funcs[name] = vals
    return funcs, total


def per_particle(vals, k):
    return {"ir": vals["Ir"] / k, "d1": (vals["D1mr"] + vals["D1mw"]) / k,
            "ll": (vals["DLmr"] + vals["DLmw"]) / k}


def run_size(args, n, workdir):
    nx = int(round(n ** 0.5))
    if nx * nx != n:
        raise SystemExit("--sizes: %d is not a perfect square" % n)
    csv, _ = spam_make_initial(args.spam_ark, nx, 3.0, workdir)
    outdir = workdir / ("cg_%d" % n)
    outdir.mkdir(exist_ok=True)
    box = np.array([2.0 * nx, 2.0 * nx])
    cmd = spam_cmd(args.spam_ark, csv, box, 3.0, args.steps, outdir)
    cg = workdir / ("callgrind_%d.out" % n)
    vg = ["valgrind", "--tool=callgrind", "--toggle-collect=" + TOGGLE[args.scope], "--cache-sim=yes",
          "--D1=" + args.d1, "--LL=" + args.ll, "--callgrind-out-file=%s" % cg]
    log = workdir / ("callgrind_%d.log" % n)
    with open(log, "w") as fh:
        rc = subprocess.run(vg + [str(c) for c in cmd], stdout=fh, stderr=subprocess.STDOUT).returncode
    if rc != 0:
        raise SystemExit("callgrind run failed (rc %d): see %s" % (rc, log))
    summary = __import__("json").loads((outdir / "summary.json").read_text())
    evals = int(summary["rhs_evals"])
    funcs, total = annotate(cg)
    k = float(n) * evals
    rec = {"n": n, "rhs_evals": evals, "total": per_particle(total, k), "parts": {}}
    rest = dict(total)
    for label, prefix in PARTS + (STEP_PARTS if args.scope == "step" else []):
        hit = {e: 0 for e in total}
        for name, vals in funcs.items():
            if name.startswith(prefix):  # a str, or a tuple of them
                for e in total:
                    hit[e] += vals.get(e, 0)
        if hit["Ir"] >= 0.5 * k:  # a part of half an instruction a particle or more
            rec["parts"][label] = per_particle(hit, k)
            for e in total:
                rest[e] -= hit[e]
    rec["parts"]["other"] = per_particle(rest, k)
    return rec


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    if not shutil.which("valgrind") or not shutil.which("callgrind_annotate"):
        raise SystemExit("valgrind (callgrind) is needed")
    args.spam_ark = str(Path(args.spam_ark).resolve())
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    workdir = Path(args.workdir) if args.workdir else Path(tempfile.mkdtemp(prefix="spam-ark-cg-"))
    workdir.mkdir(parents=True, exist_ok=True)
    recs = [run_size(args, n, workdir) for n in sizes]
    rows = []
    for r in recs:
        rows.append([r["n"], "whole right-hand side" if args.scope == "rhs" else "whole steps", "%.1f" % r["total"]["ir"],
                     "%.2f" % r["total"]["d1"], "%.3f" % r["total"]["ll"]])
        for label, v in r["parts"].items():
            rows.append([r["n"], label, "%.1f" % v["ir"], "%.2f" % v["d1"], "%.3f" % v["ll"]])
    cols = ["N", "part", "instructions", "D1 misses", "LL misses"]
    print("per particle per RHS evaluation (D1 %s, LL %s; %d steps; counted inside %s):"
          % (args.d1, args.ll, args.steps, "whole steps" if args.scope == "step" else "the right-hand side"))
    print(" | ".join(cols))
    for row in rows:
        print(" | ".join(str(c) for c in row))
    first, last = recs[0]["total"], recs[-1]["total"]
    growth = {"instructions": last["ir"] / first["ir"] - 1, "d1": last["d1"] / first["d1"] - 1,
              "ll_ratio": last["ll"] / first["ll"] if first["ll"] else None}
    print("from N = %d to %d: instructions %+.1f%%, D1 misses %+.1f%%, LL misses x%.1f"
          % (sizes[0], sizes[-1], 100 * growth["instructions"], 100 * growth["d1"], growth["ll_ratio"]))
    if args.readings:
        sys.path.insert(0, str(REPO_ROOT / "examples"))
        import chart_readings
        chart_readings.write_json(args.readings, {
            "sizes": sizes, "steps": args.steps, "d1": args.d1, "ll": args.ll, "scope": args.scope, "runs": recs,
            "growth": growth, "table": chart_readings.table(cols, rows)})
    if not args.workdir:
        shutil.rmtree(workdir, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
