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
    /usr/bin/python3 bench/run_checkpoint_ranks.py [--n 128] [--repeats 5]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
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
    a = p.parse_args()
    times, size = {1: [], 2: [], 3: []}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.repeats):
            for ranks in times:
                size[ranks], t = write_once(a.exe, ranks, a.n, Path(tmp) / f"np{ranks}")
                times[ranks].append(t)
    base = statistics.median(times[1])
    print(f"2D expansion, N = {a.n * a.n}, {a.repeats} rounds, layouts alternating; load average {os.getloadavg()[0]:.1f}")
    print("| ranks | bytes | best ms | median ms | median / one rank |")
    print("|---|---|---|---|---|")
    for ranks, ts in times.items():
        med = statistics.median(ts)
        print(f"| {ranks} | {size[ranks]} | {1e3 * min(ts):.1f} | {1e3 * med:.1f} | {med / base:.2f} |")


if __name__ == "__main__":
    main()
