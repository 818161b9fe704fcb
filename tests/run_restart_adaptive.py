#!/usr/bin/python3
"""Checkpoint and restart at the adaptive kernel range (-smoothing_length adaptive).

Each right-hand side solves rho_i h_i^D = eta^D m_i by Newton from the h_i of the last
solve, to 1e-10: the h_i it returns, and so the right-hand side's last bits, depend on where
the solve started. So the run is bit for bit one run only if every solve starts where it
would have in the uninterrupted run:
- outputs (their density sums and the interpolant's right-hand sides solve too) must not
  move the start: a run writing a row every 0.05 takes the same steps, bit for bit, as one
  writing a row every 0.5 (steps.csv compared byte for byte);
- a checkpoint holds the h_i the next solve starts from, and the restarted method's first
  evaluation (the FSAL stage that the uninterrupted run kept) starts from the h_i solved at
  that same state, so it settles at once with the same bits: a run stopped by
  -ts_max_steps and restarted writes the files of the uninterrupted run (steps.csv,
  snapshots, timeseries.csv but for its timing columns; same_outputs) and reports
  "restart": "bitwise", for Dormand-Prince 5(4) (FSAL) and Bogacki-Shampine 3(2), at an
  early, a middle and a late step; a run writing checkpoints is the same run.
The blast: -scene sedov in 2D, 24 x 24 particles, h = 3, E0 = 1e3, to t = 1 (the shock
reaches R = 7.0; h_i spread from 1.9 to 6 by then).
At -smoothing_length evolved h_i is a component of the state (integrated, no solve), so the
checkpoint's state carries it: Dormand-Prince 5(4), the same checks at the middle step."""
import os

from spamrun import Checks, arguments, run, same_outputs, steps_table, summary

a = arguments()
c = Checks()

BASE = ["-scene", "sedov", "-dim", 2, "-sedov_n", 24, "-h", 3, "-sedov_energy", 1e3, "-ts_max_time", 1,
        "-output_interval", 0.05, "-snapshot_interval", 0.25, "-ts_rtol", 1e-6]
METHODS = {
    "DP5": ["-ts_type", "arkode", "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5"],
    "BS3": ["-ts_type", "arkode", "-arkode_table", "ARKODE_BOGACKI_SHAMPINE_4_2_3"],
}

CASES = [(name, method, "adaptive") for name, method in METHODS.items()] + [("DP5 evolved", METHODS["DP5"], "evolved")]

for name, method, mode in CASES:
    args = BASE + method + ["-smoothing_length", mode]
    tag = name.replace(" ", "_")
    ref = os.path.join(a.workdir, tag + "_ref")
    code, _, err = run(a.spam_ark, args, ref)
    if not c.check(code == 0, f"{name}: the uninterrupted run (exit {code}) {err.strip()[:200]}"):
        continue
    sref, steps = summary(ref), steps_table(ref)
    few = os.path.join(a.workdir, tag + "_few_rows")
    code, _, _ = run(a.spam_ark, args + ["-output_interval", 0.5], few)
    same = code == 0 and open(os.path.join(ref, "steps.csv"), "rb").read() == open(os.path.join(few, "steps.csv"), "rb").read()
    c.check(same, f"{name}: rows every 0.05 or every 0.5, the same {sref['steps']} steps bit for bit (outputs do not move the solve's start)")
    ckd = os.path.join(a.workdir, tag + "_with_checkpoints")
    code, _, _ = run(a.spam_ark, args + ["-checkpoint_interval", 0.25], ckd)
    s = summary(ckd) if code == 0 else {}
    diff = same_outputs(ref, ckd) if code == 0 else f"exit {code}"
    c.check(code == 0 and s.get("checkpoints_written", 0) >= 3 and diff == "",
            f"{name}: a run writing {s.get('checkpoints_written')} checkpoints is the same run: {diff or 'outputs identical'}")
    for k in (3, len(steps) // 2, len(steps) - 5) if mode == "adaptive" else (len(steps) // 2,):
        d = os.path.join(a.workdir, f"{tag}_{k}")
        code, _, err = run(a.spam_ark, args + ["-ts_max_steps", k, "-checkpoint_interval", 1000], d)
        if not c.check(code == 0 and os.path.exists(os.path.join(d, "checkpoint.h5")), f"{name}: stopped at step {k} with a checkpoint (exit {code}) {err.strip()[:200]}"):
            continue
        code, _, err = run(a.spam_ark, args + ["-restart", os.path.join(d, "checkpoint.h5")], d)
        s = summary(d) if code == 0 else {}
        diff = same_outputs(ref, d) if code == 0 else f"exit {code}: {err.strip()[:300]}"
        c.check(code == 0 and diff == "" and s.get("restart") == "bitwise" and s.get("rhs_evals") == sref["rhs_evals"],
                f"{name}: restart at step {k} of {len(steps)} (t = {s.get('restart_t', 0):.6g}) reproduces the uninterrupted run: "
                f"{diff or 'steps.csv, timeseries.csv, snapshots identical'} ({s.get('restart', '?')}; rhs_evals {s.get('rhs_evals')}/{sref['rhs_evals']})")
c.finish()
