#!/usr/bin/python3
"""The flow scheme's convection cell grows its roll only above onset, at linear theory's rate.

The 32 x 16 cell of options/convection.opts, `-gas_scheme flow -conduction_linear
-shift_compression`, seeded with random velocities of 1e-4, run to t = 6000 at 0.9 and
1.2 Ra_c by tests/run_convection_onset.py (which measures the roll's amplitude A, its
projection on linear theory's eigenfunction, and fits its growth rate s; Ra_c from the
test-side linear-stability solver of the same cell). Regime: Pr = 1, c h / nu about 60-70,
Mach 0 at the start.

Checks, each with the number it comes from:
- 0.9 Ra_c, below onset: linear theory's roll decays (s = -6.05e-4: to 0.03 of the seed's
  projection by t = 6000). The seed's projection on the roll is about 0.05 of the seed
  (512 random velocities: 5e-6 here), and the sound that fills the cell keeps a noise floor
  of a few 1e-6 in A. So A at the end must stay below 2 x 0.05 x seed = 1e-5 (no growth).
  Measured: 8.7e-6 (4.4e-6 while the walls' images took the shift mirrored; both runs pass
  through a dip and rise slowly again, and run on to t = 12000 grow at about 0.46 x the
  magnitude of linear theory's rate: docs/gas-flow.md). Without -shift_compression the
  roll grew to 1.0e-4, without either option to 4.6e-3 (docs/gas-flow.md).
- 0.9 Ra_c: the conduction state stays: |Nu - 1| within the cell's discrete flux error at
  the start (0.017, tests/run_convection_onset.py). Measured 0.9991.
- 1.2 Ra_c, above onset: the roll grows, at s / s_linear between 0.7 and 1.4. The
  resolution study (docs/gas-flow.md) gives 1.22 on this cell (1.06 with the images'
  shift mirrored; the run sized to saturation, 1.10) and 1.22 on the 64 x 32
  cell (whose fit takes in one early decade that grows too fast, 1.8 x, as without the
  option); on this cell the rates of the single decades of A spread from 0.77 to 1.29
  about the fit (the fit's window moves with the noise floor). The bounds are that spread
  with 10 % on each side for the window. By fraction of the saturated amplitude the study's
  runs at 1.2 Ra_c grow at 1.20-1.26 x linear theory's rate below 0.02 and above 0.1 of
  saturation for every seed, and at 0.75-0.97 x between 0.02 and 0.05, where a second
  harmonic of T' peaks (docs/scenes/convection.md); this run's fit (to t = 6000, not sized)
  measured 1.225. They exclude the flow scheme without the options
  (2.17); -conduction_linear alone (1.22) fails the first check (its roll grew below onset
  to 1.0e-4).
- The energy books close: the total energy's drift net of the flow scheme's book and the
  walls' (summary.json) stays within rtol x sqrt(steps) (1e-4 x sqrt(2500) = 5e-3) at all
  times. Measured: max 2.5e-3 (1.2 Ra_c), as without the options (2.5e-3 at 0.5 Ra_c).

- Onset (Nu - 1 extrapolated to 0): two more runs from a large seed (0.1, which saturates
  soonest) at 1.1 and 1.2 Ra_c, their end times sized from the linear rate as
  tests/run_convection_onset.py sizes them, times 0.7 (10185 and 5426 time units), which
  the harness continues until the roll has saturated (to 11472 and 6493; Nu averaged from
  one e-folding time after saturation, from 5736 and 3438: the onset 0.938 Ra_c, as in the
  full-length runs of the study, 0.937). The line of Nu - 1 through them, extrapolated to Nu = 1, must lie
  within 10 % of Ra_c (the project's goal). What the line can miss by: the cell's own
  onset, which its growth rates put below Ra_c (a roll that grows at most 20 % faster than
  linear theory at 1.2 Ra_c, as the previous check allows, sets in at most
  0.2 s / (ds/dRa) = 0.04 Ra_c early); the curvature of Nu - 1 in Ra (the line through 1.1
  and 1.2 Ra_c falls 0.015 to 0.031 Ra_c below the parabola through 1.1, 1.2 and 1.5 Ra_c
  for the four seeds of the study, docs/scenes/convection.md); and the scatter of Nu over
  the averaging window (0.005 in means over 1000 time units; the line's onset moves by 3.5
  times a change of Nu at 1.1 Ra_c and 2.2 times one at 1.2 Ra_c: about 0.02 Ra_c).
  Together 0.09 Ra_c, inside the goal.
- Walls: no particle crosses a wall in any run (summary.json post_step_jumps = 0).
- 3 Ra_c, seed 1e-4, sized to saturation (2985 time units): no particle crosses a wall and
  the roll grows within the project's 20 % of linear theory's rate. While the walls'
  images took the shift mirrored (their own motion) instead of under the velocity's rule,
  the wall rows of this cell broke up from 2.5 Ra_c: 5209 wall crossings and a fitted
  rate 2.48 x linear theory's in this run (docs/scenes/convection.md). Measured now:
  0.937, 0 crossings (0.947 and 0.979 from the seeds 1e-3 and 1e-2); the fit is low by
  about 2 % (tests/run_convection_onset.py), the rest of the 20 % is the seeds' spread.

Work: 28,400 right-hand sides for the two growth runs, 41,200 for the two onset runs,
8,300 for the 3 Ra_c run."""
import json
import os
import shlex
import subprocess
import sys

from spamrun import Checks, arguments

HERE = os.path.dirname(os.path.abspath(__file__))
SEED, T_END = 1e-4, 6000
EXTRA = "-gas_scheme flow -conduction_linear -shift_compression"
ONSET_RA, ONSET_SEED, ONSET_T_SCALE = (1.1, 1.2), 0.1, 0.7
HIGH_RA = 3.0


def main():
    a = arguments()
    chk = Checks()
    out = os.path.join(a.workdir, "onset.json")
    cmd = [sys.executable, os.path.join(HERE, "run_convection_onset.py"), "--spam-ark", a.spam_ark, "--workdir", os.path.join(a.workdir, "runs"),
           "--ra", "0.9,1.2", "--seeds", str(SEED), "--t-end", str(T_END), "--report-only", "--no-onset", "--extra", EXTRA, "-o", out]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    print("\n".join("  harness | " + line for line in p.stdout[-3000:].splitlines()))
    if not chk.check(p.returncode == 0 and os.path.exists(out), f"the onset harness runs ({shlex.join(cmd)}: exit {p.returncode}) {p.stderr.strip()[-300:]}"):
        chk.finish()
    with open(out) as f:
        runs = {r["ra_over_ra_c"]: r for r in json.load(f)["runs"]}
    below, above = runs.get(0.9), runs.get(1.2)
    if not chk.check(below is not None and above is not None, "both runs analysed"):
        chk.finish()
    bound = 2 * 0.05 * SEED
    chk.check(below["roll_amplitude_end"] < bound, f"0.9 Ra_c: no growth: A at t = {T_END} {below['roll_amplitude_end']:.2e} < 2 x 0.05 x seed = {bound:.1e}")
    chk.check(abs(below["nu"] - 1.0) < 0.017, f"0.9 Ra_c: conduction state kept: Nu = {below['nu']:.4f}, |Nu - 1| < 0.017")
    ratio = above["s_measured"] / above["s_theory"]
    chk.check(above["s_measured"] > 0 and 0.7 <= ratio <= 1.4, f"1.2 Ra_c: the roll grows at {ratio:.3f} x linear theory's rate {above['s_theory']:.3e} (0.7 .. 1.4)")
    for r in (below, above):
        with open(os.path.join(r["dir"], "summary.json")) as f:
            drift = json.load(f)["energy_rel_drift_max"]
        chk.check(drift < 5e-3, f"{r['ra_over_ra_c']} Ra_c: energy drift net of the books, max {drift:.2e} < rtol sqrt(steps) = 5e-3")
    onset_runs(a, chk, below, above)
    high_run(a, chk)
    chk.finish()


def high_run(a, chk):
    """3 Ra_c, seed 1e-4: no wall crossings, growth within 20 % of linear theory (module text)."""
    out = os.path.join(a.workdir, "high.json")
    cmd = [sys.executable, os.path.join(HERE, "run_convection_onset.py"), "--spam-ark", a.spam_ark, "--workdir", os.path.join(a.workdir, "high"),
           "--ra", str(HIGH_RA), "--seeds", str(SEED), "--report-only", "--no-onset", "--extra", EXTRA, "-o", out]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    print("\n".join("  harness | " + line for line in p.stdout[-1500:].splitlines()))
    if not chk.check(p.returncode == 0 and os.path.exists(out), f"the {HIGH_RA:g} Ra_c run ({shlex.join(cmd)}: exit {p.returncode}) {p.stderr.strip()[-300:]}"):
        return
    with open(out) as f:
        r = json.load(f)["runs"][0]
    with open(os.path.join(r["dir"], "summary.json")) as f:
        jumps = json.load(f).get("post_step_jumps", 0)
    chk.check(jumps == 0, f"{HIGH_RA:g} Ra_c, seed {SEED:g}: no particle crossed a wall ({jumps})")
    ratio = r["s_measured"] / r["s_theory"]
    chk.check(r["fit"] == "exponential" and abs(ratio - 1.0) < 0.2,
              f"{HIGH_RA:g} Ra_c: the roll grows at {ratio:.3f} x linear theory's rate {r['s_theory']:.3e} ({r['fit']} fit; within 20 %)")


def onset_runs(a, chk, *earlier):
    """The onset from Nu - 1 at 1.1 and 1.2 Ra_c, seed 0.1 (module text); no wall crossings."""
    out = os.path.join(a.workdir, "onset_nu.json")
    cmd = [sys.executable, os.path.join(HERE, "run_convection_onset.py"), "--spam-ark", a.spam_ark, "--workdir", os.path.join(a.workdir, "onset"),
           "--ra", ",".join(str(f) for f in ONSET_RA), "--seeds", str(ONSET_SEED), "--t-scale", str(ONSET_T_SCALE), "--report-only",
           "--extra", EXTRA, "-o", out]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    print("\n".join("  harness | " + line for line in p.stdout[-2000:].splitlines()))
    if not chk.check(p.returncode == 0 and os.path.exists(out), f"the onset runs ({shlex.join(cmd)}: exit {p.returncode}) {p.stderr.strip()[-300:]}"):
        return
    with open(out) as f:
        res = json.load(f)
    on = res["onset"].get(f"{ONSET_SEED:g}", {}).get("ra_onset", float("nan")) / res["ra_c"]
    nus = ", ".join(f"{r['nu']:.4f} at {r['ra_over_ra_c']:g}" for r in res["runs"])
    chk.check(abs(on - 1.0) < 0.1, f"onset from Nu - 1 ({nus} Ra_c, seed {ONSET_SEED:g}) extrapolated to Nu = 1: {on:.3f} Ra_c, within 10 % of Ra_c")
    for r in list(earlier) + res["runs"]:
        with open(os.path.join(r["dir"], "summary.json")) as f:
            jumps = json.load(f).get("post_step_jumps", 0)
        chk.check(jumps == 0, f"{r['ra_over_ra_c']:g} Ra_c, seed {r['amplitude']:g}: no particle crossed a wall ({jumps})")


if __name__ == "__main__":
    main()
