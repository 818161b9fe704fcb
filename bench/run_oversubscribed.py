#!/usr/bin/python3
"""Wall time of one rank against two on a machine whose cores other jobs keep busy: two
ranks that poll (OMPI_MCA_mpi_yield_when_idle=0) against two under spam-ark's default, which
yields a waiting rank's core when the node has fewer idle cores than ranks
(src/app/mpi_yield.c).

The case: the 2D expansion of --n^2 particles to t = --t-end, no snapshots; each round runs
the three commands one after the other, --rounds rounds. Printed and, with --readings FILE,
written for docs/parallel.md: each command's fastest and slowest wall time, the ratios
within each round (polling / one rank, polling / yield; smallest and largest) and the load average before and after, since the
figures mean something only beside the load they were taken under.

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_oversubscribed.py [--n 64] [--t-end 40] [--rounds 4] [--readings FILE]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples"))
import chart_readings  # noqa: E402

MODES = (("one_rank", 1, None), ("polling", 2, "0"), ("yield", 2, None))


def one_run(spam, n, t_end, ranks, yield_env, out):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_pml="ob1",
               OMP_NUM_THREADS="1")
    env.pop("OMPI_MCA_mpi_yield_when_idle", None)
    if yield_env is not None:
        env["OMPI_MCA_mpi_yield_when_idle"] = yield_env
    cmd = [spam, "-scene", "expansion", "-dim", "2", "-expansion_n", str(n), "-ts_max_time", repr(t_end),
           "-snapshot_interval", "0", "-output_dir", out, "-output_overwrite", "-quiet"]
    if ranks > 1:
        cmd = ["mpiexec", "-n", str(ranks)] + cmd
    t0 = time.monotonic()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()[-300:]}")
    return wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(ROOT / "build" / "spam-ark"))
    ap.add_argument("--n", type=int, default=64)
    ap.add_argument("--t-end", type=float, default=40.0)
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--readings", default=None, help="write the figures docs/parallel.md quotes to this JSON")
    a = ap.parse_args()
    load_before = os.getloadavg()
    walls = {name: [] for name, _, _ in MODES}
    with tempfile.TemporaryDirectory(prefix="spam_oversub_") as d:
        for _ in range(a.rounds):
            for name, ranks, y in MODES:
                walls[name].append(one_run(a.spam_ark, a.n, a.t_end, ranks, y, os.path.join(d, "o")))
    load_after = os.getloadavg()
    lo = {k: min(v) for k, v in walls.items()}
    hi = {k: max(v) for k, v in walls.items()}

    def paired(a_, b_):  # the ratio within each round (the load changes between rounds), smallest and largest
        r = [x / y for x, y in zip(walls[a_], walls[b_])]
        return [min(r), max(r)]
    ratios = {"polling_over_one": paired("polling", "one_rank"), "polling_over_yield": paired("polling", "yield"),
              "yield_over_one": paired("yield", "one_rank")}
    print(f"load average before {load_before[0]:.2f}, after {load_after[0]:.2f} ({os.cpu_count()} cores)")
    for k in walls:
        print(f"  {k:9s} " + " ".join(f"{w:.2f}" for w in walls[k]) + " s")
    print("  polling / one rank {:.1f}-{:.1f}x, polling / yield {:.1f}-{:.1f}x".format(
        *ratios["polling_over_one"], *ratios["polling_over_yield"]))
    if a.readings:
        chart_readings.write_json(a.readings, {
            "rounds": a.rounds, "walls": walls, "min": lo, "max": hi, "ratios": ratios, "cores": os.cpu_count(),
            "load_before": load_before[0], "load_after": load_after[0],
            "load_low": min(load_before[0], load_after[0]), "load_high": max(load_before[0], load_after[0])})


if __name__ == "__main__":
    main()
