#!/usr/bin/python3
"""Mirror walls cost no more than the ghosts they add.

The convection cell (options/convection.opts, Wendland C2 at h = 3 so that the gas's square
lattice stays quiet) with its no-slip isothermal walls and gravity, against the same cell made
periodic (`-wall_ylo none -wall_yhi none -gravity 0,0`), for a fixed number of steps at each
size; the two runs alternate `--repeats` times and the best time of each is kept. Printed per
size: RHS evaluations, pair visits per RHS, ms per RHS (rhs_time_s / rhs_evals from
summary.json) and the ratios walls / periodic of the time and of the pair visits. A ratio of
times near the ratio of pairs says the walls cost what their ghost pairs cost.

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_walls.py [--sizes 32x16,128x64] [--steps 40] [--repeats 3]
"""
import argparse
import json
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run(exe, nx, ny, steps, periodic, out):
    args = [str(exe), "-options_file", str(ROOT / "options/convection.opts"), "-kernel", "wendland_c2",
            "-convection_nx", str(nx), "-convection_ny", str(ny), "-ts_max_steps", str(steps),
            "-snapshot_interval", "0", "-output_dir", str(out), "-output_overwrite"]
    if periodic:
        args += ["-wall_ylo", "none", "-wall_yhi", "none", "-gravity", "0,0"]
    subprocess.run(args, check=True, capture_output=True, cwd=str(out.parent))
    s = json.loads((out / "summary.json").read_text())
    return s["rhs_time_s"] / s["rhs_evals"] * 1e3, s["rhs_evals"], s.get("pair_interactions_per_s", 0) * s["rhs_time_s"] / s["rhs_evals"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--exe", default=str(ROOT / "build/spam-ark"))
    p.add_argument("--sizes", default="32x16,128x64")
    p.add_argument("--steps", type=int, default=40)
    p.add_argument("--repeats", type=int, default=3)
    a = p.parse_args()
    print(f"{'cell':>9} {'N':>6} {'case':>9} {'RHS':>5} {'pairs/RHS':>10} {'ms/RHS':>8}")
    with tempfile.TemporaryDirectory() as tmp:
        for size in a.sizes.split(","):
            nx, ny = (int(v) for v in size.split("x"))
            best = {}
            for _ in range(a.repeats):
                for periodic in (False, True):
                    ms, evals, pairs = run(a.exe, nx, ny, a.steps, periodic, Path(tmp) / ("p" if periodic else "w"))
                    key = "periodic" if periodic else "walls"
                    if key not in best or ms < best[key][0]:
                        best[key] = (ms, evals, pairs)
            for key in ("walls", "periodic"):
                ms, evals, pairs = best[key]
                print(f"{size:>9} {nx * ny:>6} {key:>9} {evals:>5} {pairs:>10.0f} {ms:>8.3f}")
            w, q = best["walls"], best["periodic"]
            print(f"{size:>9} ratio walls/periodic: time {w[0] / q[0]:.3f}, pair visits {w[2] / q[2]:.3f}")


if __name__ == "__main__":
    main()
