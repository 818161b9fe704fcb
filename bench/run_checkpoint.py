#!/usr/bin/python3
"""What a checkpoint costs: bytes per particle and the time to write one, against
LAMMPS's write_restart of the same particles in the same run of this script.

spam-ark: the expansion scene of N = n^2 particles (default n = 256: N = 65536) runs one step
with checkpoints on (-ts_max_steps 1 -checkpoint_interval 1e9: the step limit writes one);
summary.json gives checkpoint_bytes and checkpoint_write_s (the whole write: gathering the
entries, HDF5, fsync, rename). The peer: LAMMPS reads the same positions and velocities
(atom_style atomic, the initial particles spam-ark wrote with -initial_csv) and times its
write_restart with wall-clock stamps from its shell command (less the cost of a stamp). Each side runs --repeats times; the best and median are
printed, and the ratios spam-ark / LAMMPS. The checkpoint also carries the output series so
far (one row here), so its size is the particles' and a constant. A measurement, not a test.

Usage (spam-ark built in build/, LAMMPS from tools/deps.sh --bench):
    /usr/bin/python3 bench/run_checkpoint.py [--n 256] [--repeats 5]
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ENV = dict(os.environ, OMPI_MCA_pml="ob1")


def spam_run(exe, n, out):
    if out.exists():
        shutil.rmtree(out)
    args = [str(exe), "-scene", "expansion", "-dim", "2", "-expansion_n", str(n), "-h", "3", "-ts_max_steps", "1",
            "-checkpoint_interval", "1e9", "-snapshot_interval", "0", "-output_interval", "0", "-output_dir", str(out),
            "-initial_csv", str(out.parent / "initial.csv")]
    subprocess.run(args, check=True, capture_output=True, env=ENV)
    s = json.loads((out / "summary.json").read_text())
    return int(s["checkpoint_bytes"]), s["checkpoint_write_s"]


def lammps_data(csv_path, data_path):
    """The initial particles as a LAMMPS data file (2D, atomic, box from the CSV's range)."""
    with open(csv_path) as f:
        lines = [ln for ln in f if ln.strip() and not ln.startswith("#")]
    head = lines[0].strip().split(",")
    ix, iy, ivx, ivy = (head.index(k) for k in ("x", "y", "vx", "vy"))
    rows = [ln.split(",") for ln in lines[1:]]
    xs = [float(r[ix]) for r in rows]
    ys = [float(r[iy]) for r in rows]
    lo, hi = min(min(xs), min(ys)) - 1, max(max(xs), max(ys)) + 1
    with open(data_path, "w") as f:
        f.write(f"spam-ark checkpoint bench\n\n{len(rows)} atoms\n1 atom types\n\n{lo} {hi} xlo xhi\n{lo} {hi} ylo yhi\n"
                "-0.5 0.5 zlo zhi\n\nMasses\n\n1 1.0\n\nAtoms # atomic\n\n")
        f.writelines(f"{k + 1} 1 {r[ix]} {r[iy]} 0\n" for k, r in enumerate(rows))
        f.write("\nVelocities\n\n")
        f.writelines(f"{k + 1} {r[ivx]} {r[ivy]} 0\n" for k, r in enumerate(rows))
    return len(rows)


def lammps_run(lmp, data, work):
    restart = work / "peer.restart"
    if restart.exists():
        restart.unlink()
    (work / "in.ckpt").write_text(
        "units lj\ndimension 2\nboundary p p p\natom_style atomic\n"
        f"read_data {data}\npair_style zero 3.0\npair_coeff * *\nmass 1 1.0\n"
        # Debian's LAMMPS (2022) has no timer variable: three wall-clock stamps from the shell,
        # the first two back to back, so that the cost of starting `date` is subtracted.
        "shell date +STAMP%s%N\nshell date +STAMP%s%N\n"
        f"write_restart {restart}\n"
        "shell date +STAMP%s%N\n")
    p = subprocess.run([lmp, "-in", "in.ckpt", "-log", "none"], cwd=str(work), capture_output=True, text=True, env=ENV, check=True)
    t0, t1, t2 = (int(v) for v in re.findall(r"STAMP(\d+)", p.stdout))
    return restart.stat().st_size, 1e-9 * ((t2 - t1) - (t1 - t0))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=str(ROOT / "build/spam-ark"))
    p.add_argument("--lmp", default=shutil.which("lmp") or "lmp")
    p.add_argument("--n", type=int, default=256)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--readings", default=None, help="also write the table bench/README.md quotes to this JSON")
    a = p.parse_args()
    load0 = os.getloadavg()[0]
    commit = subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True, text=True).stdout.strip()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        spam = [spam_run(a.exe, a.n, work / "out") for _ in range(a.repeats)]
        N = lammps_data(work / "initial.csv", work / "peer.data")
        peer = [lammps_run(a.lmp, work / "peer.data", work) for _ in range(a.repeats)]
    sb, st = spam[0][0], [t for _, t in spam]
    pb, pt = peer[0][0], [t for _, t in peer]
    print(f"checkpoint of N = {N} particles (2D expansion, commit {commit}, {a.repeats} repeats each, "
          f"best / median; command: bench/run_checkpoint.py --n {a.n} --repeats {a.repeats})")
    print(f"{'':12} {'bytes':>10} {'B/particle':>11} {'write best (ms)':>16} {'median (ms)':>12}")
    print(f"{'spam-ark':12} {sb:>10d} {sb / N:>11.1f} {1e3 * min(st):>16.2f} {1e3 * statistics.median(st):>12.2f}")
    print(f"{'LAMMPS':12} {pb:>10d} {pb / N:>11.1f} {1e3 * min(pt):>16.2f} {1e3 * statistics.median(pt):>12.2f}")
    print(f"ratio spam-ark / LAMMPS: size {sb / pb:.2f}, write time {min(st) / min(pt):.2f} (best), "
          f"{statistics.median(st) / statistics.median(pt):.2f} (median)")
    if a.readings:
        sys.path.insert(0, str(ROOT / "bench"))
        import bench_common as bc
        rows = [[name, str(b), f"{b / N:.1f}", f"{1e3 * min(t):.2f}", f"{1e3 * statistics.median(t):.2f}"]
                for name, b, t in (("spam-ark", sb, st), ("LAMMPS", pb, pt))]
        bc.page_readings(a.readings, {"table": {"columns": ["", "bytes", "bytes per particle", "write, best (ms)", "median (ms)"],
                                                "rows": rows}, "n": N, "repeats": a.repeats, "load_1min_start": load0,
                                      "size_ratio": sb / pb, "write_ratio_best": min(st) / min(pt),
                                      "write_ratio_median": statistics.median(st) / statistics.median(pt)})


if __name__ == "__main__":
    main()
