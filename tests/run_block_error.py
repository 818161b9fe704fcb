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

Under -reproducible (the gas at -smoothing_length adaptive) a run on 2 ranks, the
particles migrating between cycles (-migrate_interval 1), must write the one-rank run's
final state and steps.csv byte for byte (every decision of the controller is a particle's
own, from its own data, and a rejected cycle is agreed by all ranks); a run stopped after a
cycle with a checkpoint and restarted must write the uninterrupted run's files (the steps
the controllers ask are in the checkpoint), on one rank and on 2.

Refused in one line each: -block_force with -block_criterion error (the estimate replaces
the force criterion), -arkode_classic_weights there, an unknown criterion, -ts_rtol with
the CFL criterion. --readings FILE: the errors and slope (docs/block_error_order.json)."""
import os
import subprocess

import numpy as np

from spamrun import Checks, arguments, mpiexec_env, one_line, rank_command, run, same_outputs, summary, table

N, E_HOT, T = 16, 20.0, 1.0
RTOLS = (1e-3, 1e-4, 1e-5)
SLOPE_TOL, DRIFT, MOMENTUM = 0.3, 1e-4, 1e-4
ERROR = ["-ts_type", "block_kdk", "-block_criterion", "error", "-block_cfl", 1]


def write_gas(path):
    rng = np.random.default_rng(1)
    with open(path, "w") as f:
        f.write("x,y,vx,vy,m,e\n")
        for j in range(N):
            for i in range(N):
                x, y = i + 0.5, j + 0.5
                e = 1.0 + E_HOT * np.exp(-((x - 5.3) ** 2 + (y - 6.1) ** 2) / 4.0)
                vx, vy = 0.1 * rng.standard_normal(2)
                f.write(f"{x!r},{y!r},{vx!r},{vy!r},1,{e!r}\n")


def scene(gas):
    return ["-scene", "file", "-file_path", gas, "-dim", 2, "-box_lo", "0,0", "-box_len", f"{N},{N}", "-periodic", "true,true", "-h", 3,
            "-material", "gas", "-gas_gamma", 1.4, "-density", "summation", "-viscosity", "monaghan", "-ts_max_time", T, "-output_interval", 0.25]


def go(name, extra):
    """(final positions, summary, timeseries, stdout) of one run, or None."""
    out = os.path.join(a.workdir, name)
    last = os.path.join(out, "final.csv")
    code, so, err = run(a.spam_ark, scene(gas) + extra + ["-final_csv", last, "-ts_view"], out)
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

# Refusals, one line each.
for extra, words in ((ERROR + ["-block_force", 0.1], "-block_force"), (ERROR + ["-arkode_classic_weights"], "-arkode_classic_weights"),
                     (["-ts_type", "block_kdk", "-block_criterion", "tolerance"], "-block_criterion"), (["-ts_type", "block_kdk", "-ts_rtol", 1e-6], "-ts_rtol")):
    code, _, err = run(a.spam_ark, scene(gas) + ["-ts_max_time", 0.01] + extra, os.path.join(a.workdir, "refused"))
    line = one_line(err) or ""
    c.check(code != 0 and words in line and len(err.strip().splitlines()) == 1, f"{' '.join(map(str, extra))}: refused in one line ({line.strip()[:200]})")

# Ranks and restarts under -reproducible.
mpiexec, ENV = mpiexec_env()
REPRO = scene(gas) + ERROR + ["-ts_rtol", 1e-4, "-ts_atol", 1e-4, "-smoothing_length", "adaptive", "-reproducible"]
MIGRATE = {1: [], 2: ["-migrate_interval", 1]}


def spam(ranks, args, out):
    cmd, env = rank_command(mpiexec, ENV, ranks, a.spam_ark, [str(x) for x in args] + ["-output_dir", out, "-output_overwrite"])
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    return p.returncode, p.stdout, p.stderr


outs = {}
for ranks in (1, 2):
    out = os.path.join(a.workdir, f"repro_np{ranks}")
    code, so, err = spam(ranks, REPRO + MIGRATE[ranks] + ["-final_csv", os.path.join(out, "final.csv"), "-ts_view"], out)
    if c.check(code == 0, f"-reproducible on {ranks} rank(s) runs (exit {code}) {one_line(err)}"):
        outs[ranks] = (out, so)
if len(outs) == 2:
    files = ("final.csv", "steps.csv")
    differ = [n for n in files if open(os.path.join(outs[1][0], n), "rb").read() != open(os.path.join(outs[2][0], n), "rb").read()]
    moved = summary(outs[2][0])["migrations"]
    c.check(not differ and moved >= 1, f"2 ranks ({moved} migrations) write the one-rank run's final state and steps.csv byte for byte (differ: {differ})")
    c.reading("repro_rejected", int(outs[1][1].split("rejected cycles")[1].split()[0]))


def restart(ranks, args, label):
    whole, part = os.path.join(a.workdir, f"{label}_whole"), os.path.join(a.workdir, f"{label}_part")
    code, _, err = spam(ranks, args, whole)
    if not c.check(code == 0, f"{label}: the whole run (exit {code}) {one_line(err)}"):
        return
    code, _, err = spam(ranks, args + ["-checkpoint_interval", 0.25, "-ts_max_steps", 1], part)
    if not c.check(code == 0 and os.path.exists(os.path.join(part, "checkpoint.h5")), f"{label}: stops after a cycle with a checkpoint (exit {code}) {one_line(err)}"):
        return
    cmd, env = rank_command(mpiexec, ENV, ranks, a.spam_ark, [str(x) for x in args] + ["-output_dir", part, "-restart", os.path.join(part, "checkpoint.h5")])
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    if not c.check(p.returncode == 0, f"{label}: restart (exit {p.returncode}) {one_line(p.stderr)}"):
        return
    s = summary(part)
    c.check(s.get("restart") == "bitwise", f"{label}: the restart says it continues bit for bit ({s.get('restart')}: {s.get('restart_why_approximate')})")
    diff = same_outputs(whole, part)
    c.check(not diff, f"{label}: the restarted run writes the uninterrupted run's files ({diff or 'the same'})")


restart(1, scene(gas) + ERROR + ["-ts_rtol", 1e-4, "-ts_atol", 1e-4], "restart_np1")
restart(2, REPRO + MIGRATE[2], "restart_np2")
c.finish(a.readings)
