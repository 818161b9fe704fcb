#!/usr/bin/python3
"""What a checkpoint costs on 1, 2 and 3 ranks, against the one-rank
write measured in the same run of this script.

The 2D expansion of N = n^2 particles (default n = 128: N = 16384) runs 5 steps with
checkpoints on (-ts_max_steps 5 -checkpoint_interval 1e9: the step limit writes one) on P
ranks; summary.json gives checkpoint_bytes and checkpoint_write_s (the whole write: the
entries gathered, on P > 1 the blocks written collectively through MPI-IO and rank 0's
entries added, fsync, rename). The layouts alternate, --repeats rounds; the best and median
of each are printed with the ratio of medians to one rank. A measurement, not a test. On
this machine's 2 cores 3 ranks are oversubscribed.

Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_checkpoint_ranks.py [--n 128] [--repeats 5] [--readings FILE]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
import bench_common as bc  # noqa: E402
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_pml="ob1")


def write_once(exe, ranks, n, out):
    if out.exists():
        shutil.rmtree(out)
    args = [str(exe), "-scene", "expansion", "-dim", "2", "-expansion_n", str(n), "-h", "3", "-ts_max_steps", "5",
            "-checkpoint_interval", "1e9", "-snapshot_interval", "0", "-output_interval", "0", "-output_dir", str(out)]
    subprocess.run(["mpiexec", "--oversubscribe", "-n", str(ranks)] + args, check=True, capture_output=True, env=ENV)
    s = json.loads((out / "summary.json").read_text())
    return int(s["checkpoint_bytes"]), s["checkpoint_write_s"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--n", type=int, default=128)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--exe", default=str(ROOT / "build" / "spam-ark"))
    p.add_argument("--readings", default=None, help="also write the table docs/checkpoints.md quotes to this JSON")
    a = p.parse_args()
    load0 = os.getloadavg()[0]
    times, size = {1: [], 2: [], 3: []}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.repeats):
            for ranks in times:
                size[ranks], t = write_once(a.exe, ranks, a.n, Path(tmp) / f"np{ranks}")
                times[ranks].append(t)
    base = statistics.median(times[1])
    print(f"2D expansion, N = {a.n * a.n}, {a.repeats} rounds, layouts alternating; load average {os.getloadavg()[0]:.1f}")
    cols = ["ranks", "bytes", "best ms", "median ms", "median / one rank"]
    rows = [[str(ranks), str(size[ranks]), f"{1e3 * min(ts):.1f}", f"{1e3 * statistics.median(ts):.1f}",
             f"{statistics.median(ts) / base:.2f}"] for ranks, ts in times.items()]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    if a.readings:
        bc.page_readings(a.readings, {"table": {"columns": cols, "rows": rows}, "n_particles": a.n * a.n,
                                      "repeats": a.repeats, "load_1min_start": load0})


if __name__ == "__main__":
    main()
