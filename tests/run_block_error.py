#!/usr/bin/python3
"""Block individual steps with bins by error control (-ts_type block_kdk -block_criterion
error) on the small scene of run_block_order.py: 16 x 16 particles of the ideal gas (gamma
1.4, unit lattice, periodic, h = 3, summation density, Monaghan's viscosity), e = 1 + 20
exp(-r^2/4) about an off-centre point and random velocities (deviation 0.1, fixed seed), to
T = 1.

Each particle's step is held by its controller to -ts_rtol, -ts_atol: the estimate (the
kick-drift-kick step against the embedded first-order one, of order dt^2) asks for
dt ~ rtol^(1/2), and the method being second order the error at T goes as dt^2 ~ rtol:
slope 1 in rtol. Checked: the position error max |x - x_ref| against DP5 at rtol 1e-11 at
rtol 1e-3, 1e-4, 1e-5 (-block_cfl 1, so that the tolerance and not the CFL bound sets the
steps at all three) falls at each decade, and the slope of its least-squares line is
within SLOPE_TOL of 1 (measured: see the output; the estimate is asymptotic, so the
coarsest tolerance may stray). Conservation: |dE/E| falls with rtol too and stays below
DRIFT at 1e-5; the momentum is kept to the method's order with mixed bins (a pair's forces
act on its particles at each one's own step ends), its change below MOMENTUM of the summed
|m v| at rtol 1e-5.

With -block_reject 2 a step above twice the tolerance rejects its cycle, redone from the
cycle's start with that particle's step cut: the run completes with its error that of
the run without. A run stopped after a cycle with a checkpoint and restarted must write
the uninterrupted run's files (the steps the controllers ask are in the checkpoint; on 2
ranks under -reproducible, and 1 against 2 ranks: tests/run_block_ranks.py).

Refused in one line each: -block_force with -block_criterion error (the estimate replaces
the force criterion), -arkode_classic_weights there, an unknown criterion, -ts_rtol and
-block_reject with the CFL criterion. About 1.5 s of CPU (labelled fast). --readings FILE:
the errors and slope (docs/block_error_order.json)."""
import os

import numpy as np

from block_gas_scene import N, T, scene, write_gas  # noqa: F401
from spamrun import Checks, arguments, one_line, run, same_outputs, summary, table

RTOLS = (1e-3, 1e-4, 1e-5)
SLOPE_TOL, DRIFT, MOMENTUM, REJECT = 0.3, 1e-4, 1e-4, 2
ERROR = ["-ts_type", "block_kdk", "-block_criterion", "error", "-block_cfl", 1]


def go(name, extra):
    """(final positions, summary, timeseries, stdout) of one run, or None."""
    out = os.path.join(a.workdir, name)
    last = os.path.join(out, "final.csv")
    code, so, err = run(a.spam_ark, scene(gas, 0.25) + extra + ["-final_csv", last, "-ts_view"], out)
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()[-300:]}"):
        return None
    f = table(last)
    order = np.argsort(f["id"])
    return np.array([f["x"], f["y"]]).T[order], np.array([f["vx"], f["vy"]]).T[order], summary(out), table(os.path.join(out, "timeseries.csv")), so


a = arguments()
c = Checks()
gas = os.path.join(a.workdir, "gas.csv")
write_gas(gas)
ref = go("reference", ["-ts_rtol", 1e-11, "-ts_atol", 1e-11])
runs = [go(f"error_{r:g}", ERROR + ["-ts_rtol", r, "-ts_atol", r]) for r in RTOLS]
if ref is not None and all(r is not None for r in runs):
    xerr, drift, mom, steps, rejected = [], [], [], [], []
    for x, v, s, ts, so in runs:
        dx = x - ref[0]
        dx -= N * np.round(dx / N)
        xerr.append(float(np.max(np.abs(dx))))
        drift.append(s["energy_rel_drift_max"])
        mom.append(max(max(abs(p - ts[k][0]) for p in ts[k]) for k in ("px", "py")) / float(np.sum(np.linalg.norm(v, axis=1))))
        steps.append(int(so.split("particle steps")[1].split()[0]))
        rejected.append(int(so.split("rejected cycles")[1].split()[0]))
    slope = float(np.polyfit(np.log(RTOLS), np.log(xerr), 1)[0])
    print("     rtol " + ", ".join(f"{r:g}" for r in RTOLS) + ": x errors " + ", ".join(f"{e:.3e}" for e in xerr) + "; |dE/E| " + ", ".join(f"{e:.2e}" for e in drift)
          + "; momentum " + ", ".join(f"{e:.2e}" for e in mom) + f"; particle steps {steps}; rejected cycles {rejected}")
    c.check(all(e1 < e0 for e0, e1 in zip(xerr, xerr[1:])), f"the position error falls at each decade of rtol ({', '.join(f'{e:.2e}' for e in xerr)})")
    c.check(abs(slope - 1) < SLOPE_TOL, f"slope of log error against log rtol {slope:.2f} (1 within {SLOPE_TOL}: error ~ dt^2, dt ~ rtol^(1/2))")
    c.check(all(s1 > s0 for s0, s1 in zip(steps, steps[1:])), f"the particle steps grow as the tolerance tightens {steps}")
    c.check(drift[-1] < drift[0] and drift[-1] <= DRIFT, f"|dE/E| falls with rtol and is {drift[-1]:.1e} <= {DRIFT:g} at rtol {RTOLS[-1]:g}")
    c.check(mom[-1] <= MOMENTUM, f"momentum change {mom[-1]:.1e} of sum |m v| <= {MOMENTUM:g} at rtol {RTOLS[-1]:g} (kept to the method's order with mixed bins)")
    c.reading("rtols", list(RTOLS))
    c.reading("x_errors", xerr)
    c.reading("slope", slope)
    c.reading("energy_drift", drift)
    c.reading("momentum", mom)
    c.reading("particle_steps", steps)
    c.reading("rejected", rejected)

# -block_reject: a step above REJECT times the tolerance rejects the cycle, which is redone
# with that particle's step cut: at rtol 1e-4 some cycle is rejected, the run completes and
# its error stays that of the run without rejections (within a factor 2: only a few
# particles' steps change).
rej = go("reject", ERROR + ["-ts_rtol", 1e-4, "-ts_atol", 1e-4, "-block_reject", REJECT])
if rej is not None and ref is not None and runs[1] is not None:
    n_rej = int(rej[4].split("rejected cycles")[1].split()[0])
    dx = rej[0] - ref[0]
    dx -= N * np.round(dx / N)
    e_rej = float(np.max(np.abs(dx)))
    c.check(n_rej >= 1 and e_rej <= 2 * xerr[1], f"-block_reject {REJECT}: {n_rej} cycle(s) rejected and redone, error {e_rej:.2e} (without: {xerr[1]:.2e})")
    c.reading("reject.cycles", n_rej)
    c.reading("reject.x_error", e_rej)

# Refusals, one line each.
for extra, words in ((ERROR + ["-block_force", 0.1], "-block_force"), (ERROR + ["-arkode_classic_weights"], "-arkode_classic_weights"),
                     (["-ts_type", "block_kdk", "-block_criterion", "tolerance"], "-block_criterion"), (["-ts_type", "block_kdk", "-ts_rtol", 1e-6], "-ts_rtol"), (["-ts_type", "block_kdk", "-block_reject", 2], "-block_reject")):
    code, _, err = run(a.spam_ark, scene(gas, 0.25) + ["-ts_max_time", 0.01] + extra, os.path.join(a.workdir, "refused_" + words.strip("-")))
    line = one_line(err) or ""
    c.check(code != 0 and words in line and len(err.strip().splitlines()) == 1, f"{' '.join(map(str, extra))}: refused in one line ({line.strip()[:200]})")

# A restart from a checkpoint after the first cycle (one rank; 2 ranks with migrations:
# tests/run_block_ranks.py).
mpiexec, ENV = None, dict(os.environ)


def spam(ranks, args, out):
    code, so, err = run(a.spam_ark, list(args) + ["-output_overwrite"], out)
    return code, so, err


def restart(ranks, args, label):
    whole, part = os.path.join(a.workdir, f"{label}_whole"), os.path.join(a.workdir, f"{label}_part")
    code, _, err = spam(ranks, args, whole)
    if not c.check(code == 0, f"{label}: the whole run (exit {code}) {one_line(err)}"):
        return
    code, _, err = spam(ranks, args + ["-checkpoint_interval", 0.25, "-ts_max_steps", 1], part)
    if not c.check(code == 0 and os.path.exists(os.path.join(part, "checkpoint.h5")), f"{label}: stops after a cycle with a checkpoint (exit {code}) {one_line(err)}"):
        return
    code, _, err = run(a.spam_ark, list(args) + ["-restart", os.path.join(part, "checkpoint.h5")], part)
    if not c.check(code == 0, f"{label}: restart (exit {code}) {one_line(err)}"):
        return
    s = summary(part)
    c.check(s.get("restart") == "bitwise", f"{label}: the restart says it continues bit for bit ({s.get('restart')}: {s.get('restart_why_approximate')})")
    diff = same_outputs(whole, part)
    c.check(not diff, f"{label}: the restarted run writes the uninterrupted run's files ({diff or 'the same'})")


restart(1, scene(gas, 0.25) + ERROR + ["-ts_rtol", 1e-4, "-ts_atol", 1e-4, "-block_reject", REJECT], "restart_np1")
c.finish(a.readings)
