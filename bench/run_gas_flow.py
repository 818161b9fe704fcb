#!/usr/bin/python3
"""What the gas flow scheme costs per right-hand-side evaluation, against the plain scheme
in the same run.

The Taylor-Green vortex at Re = 100, Mach 0.1 (options/taylor-green-re100.opts) and the
convection cell (options/convection.opts: walls and gravity) at each size, for a fixed
number of steps, alternately with `-gas_scheme plain` and with the default flow scheme
(background pressure, transport shift and their corrections: one more pair sum and a
moment in the gradient walk, two reductions over the ranks; viscosity and conduction as
pair Laplacians) and with the flow scheme's two-pass diffusion (`-diffusion_form
gradient`), `--repeats` times; the best time of each is kept. Printed per case: ms per RHS
(rhs_time_s / rhs_evals from summary.json) of each, and the ratios flow / plain and pair
diffusion / gradient diffusion. Then, where diffusion bounds the step (options/couette.opts,
options/heat-mode.opts), the time each form reaches in --reach-steps adaptive steps: the
pair form damps the particle-scale modes the two-pass form leaves, and pays in step length.

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_gas_flow.py [--steps 40] [--repeats 3]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_common as bc  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CASES = {
    "taylor-green 96^2": ["-options_file", "options/taylor-green-re100.opts"],
    "taylor-green 192^2": ["-options_file", "options/taylor-green-re100.opts", "-taylorgreen_n", "192"],
    "convection 64x32": ["-options_file", "options/convection.opts", "-convection_nx", "64", "-convection_ny", "32"],
}


VARIANTS = {"plain": ["-gas_scheme", "plain"], "flow": ["-gas_scheme", "flow"],
            "flow, gradient": ["-gas_scheme", "flow", "-diffusion_form", "gradient"]}


def ms_per_rhs(exe, case, variant, steps, out):
    args = [str(exe), *CASES[case], *VARIANTS[variant], "-ts_max_steps", str(steps), "-snapshot_interval", "0",
            "-output_dir", str(out), "-output_overwrite"]
    subprocess.run(args, check=True, capture_output=True, cwd=str(ROOT))
    s = json.loads((out / "summary.json").read_text())
    return 1e3 * s["rhs_time_s"] / s["rhs_evals"]


REACH = {"couette": ["-options_file", "options/couette.opts"],
         "heat mode": ["-options_file", "options/heat-mode.opts"]}


def time_reached(exe, case, form, steps, out):
    args = [str(exe), *REACH[case], "-diffusion_form", form, "-ts_max_steps", str(steps), "-snapshot_interval", "0",
            "-output_dir", str(out), "-output_overwrite"]
    subprocess.run(args, check=True, capture_output=True, cwd=str(ROOT))
    return json.loads((out / "summary.json").read_text())["t_final"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", default=str(ROOT / "build/spam-ark"))
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--reach-steps", type=int, default=30, help="steps of the step-length comparison (default 30)")
    ap.add_argument("--readings", default=None, help="also write the table bench/README.md quotes to this JSON")
    a = ap.parse_args()
    load0, rows = os.getloadavg()[0], []
    print(f"{'case':<22} {'plain ms/RHS':>13} {'flow ms/RHS':>12} {'flow/plain':>11} {'gradient form ms/RHS':>21} {'pair/gradient':>14}")
    with tempfile.TemporaryDirectory() as tmp:
        for case in CASES:
            best = {v: float("inf") for v in VARIANTS}
            for _ in range(a.repeats):
                for v in best:
                    best[v] = min(best[v], ms_per_rhs(a.exe, case, v, a.steps, Path(tmp) / v.replace(", ", "_")))
            g = best["flow, gradient"]
            print(f"{case:<22} {best['plain']:>13.3f} {best['flow']:>12.3f} {best['flow'] / best['plain']:>11.3f} {g:>21.3f} {best['flow'] / g:>14.3f}")
            rows.append([case, f"{best['plain']:.3f}", f"{best['flow']:.3f}", f"{best['flow'] / best['plain']:.3f}", f"{g:.3f}",
                         f"{best['flow'] / g:.3f}"])
        reach = []
        for case in REACH:
            t = {form: time_reached(a.exe, case, form, a.reach_steps, Path(tmp) / form) for form in ("pair", "gradient")}
            print(f"{case}: {a.reach_steps} steps reach t = {t['pair']:.4g} (pair form), {t['gradient']:.4g} (two-pass)")
            reach.append([case, f"{t['pair']:.4g}", f"{t['gradient']:.4g}", f"{t['pair'] / t['gradient']:.3f}"])
    if a.readings:
        cols = ["case", "plain ms/RHS", "flow ms/RHS", "flow / plain", "flow, two-pass ms/RHS", "pair / two-pass"]
        bc.page_readings(a.readings, {"table": {"columns": cols, "rows": rows}, "steps": a.steps, "repeats": a.repeats,
                                      "load_1min_start": load0, "reach_steps": a.reach_steps,
                                      "reach": {"columns": ["case", "t, pair form", "t, two-pass form", "pair / two-pass"],
                                                "rows": reach}})


if __name__ == "__main__":
    main()
