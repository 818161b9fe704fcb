#!/usr/bin/python3
"""The adaptive kernel range on two ranks: the 2D Sedov blast (24^2 particles, h_i from
rho_i h_i^2 = 3^2 m, the list range 2 h + skin), the other rank's particles ghost slots
within that range.

- -reproducible, one rank against two with a migration after every list build (each one
  re-sorts the particles, and the h_i every solve starts from travel with them): every
  step's number, time, size and rejections identical (17 digits), every CSV snapshot
  (positions, velocities, energies, summed densities at the solved h_i) byte for byte.
  The canonical rows sum each particle's partners in id order on any number of ranks, so
  nothing but a wrong halo (a partner missing, a ghost's h_j, rho_j, q_j or v_j stale)
  can make them differ.
- Checkpoint and restart on two ranks: the run above stopped at step 30 with a checkpoint
  (it holds each rank's h_i, the next solve's start) and restarted on two ranks writes the
  uninterrupted run's steps and snapshots byte for byte and reports a bitwise restart.
- The default mode at a fixed step (ERKStep, dt 0.004 to t = 0.2): the two ranks' sums
  add the same terms in another order (the local rows, then the ghost rows), so the
  trajectories differ by roundings only: positions within 1e-11 h, energies and summed
  densities (every particle's, at its solved h_i) within 1e-11 of the largest
  (run_reproducible.py holds the reordered sums of one rank to the same bound), and --
  the control -- not bit for bit.
"""
import csv
import json
import os
import subprocess

from spamrun import Checks, arguments, mpiexec_env, rank_command

a = arguments()
c = Checks()
mpiexec, ENV = mpiexec_env()
H = 3.0
SEDOV = ["-scene", "sedov", "-dim", 2, "-sedov_n", 24, "-h", H, "-sedov_energy", 1e4, "-smoothing_length", "adaptive",
         "-h_eta", H, "-snapshot_hdf5", 0, "-quiet"]


def spam(ranks, name, args):
    out = os.path.join(a.workdir, f"{name}_np{ranks}")
    cmd, env = rank_command(mpiexec, ENV, ranks, a.spam_ark, SEDOV + list(args) + ["-output_dir", out])  # one rank: a singleton
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    c.check(p.returncode == 0, f"{name} on {ranks} ranks: exit {p.returncode} {p.stderr.strip()[-300:]}")
    return out if p.returncode == 0 else None


def steps(out):
    with open(os.path.join(out, "steps.csv")) as f:
        return [ln.split(",")[:4] for ln in f]  # step, t, dt, rejected (rhs_evals: a migration adds one)


def snapshots(out):
    files = sorted(f for f in os.listdir(out) if f.startswith("particles_"))
    return {f: open(os.path.join(out, f), "rb").read() for f in files}


repro = ["-reproducible", "-ts_max_time", 0.4, "-output_interval", 0.1, "-snapshot_interval", 0.2]
r1, r2 = spam(1, "repro", repro), spam(2, "repro", repro + ["-migrate_interval", 1])
if r1 and r2:
    s1, s2 = steps(r1), steps(r2)
    c.check(s1 == s2, f"-reproducible, 2 ranks (migrations every build): {len(s2) - 1} steps, every t and dt identical to one rank's ({len(s1) - 1})")
    p1, p2 = snapshots(r1), snapshots(r2)
    differ = [f for f in p1 if p1[f] != p2.get(f)]
    c.check(len(p1) == 3 and p1.keys() == p2.keys() and not differ,
            f"-reproducible, 2 ranks: {len(p2)} snapshots byte for byte one rank's (differing: {differ or 'none'})")

if r2:
    ck = spam(2, "stopped", repro + ["-migrate_interval", 1, "-ts_max_steps", 30, "-checkpoint_interval", 1000])
    if ck and spam(2, "stopped", repro + ["-migrate_interval", 1, "-restart", os.path.join(ck, "checkpoint.h5")]):
        with open(os.path.join(ck, "summary.json")) as f:
            how = json.load(f).get("restart")
        pr, pc = snapshots(r2), snapshots(ck)
        c.check(how == "bitwise" and steps(ck) == steps(r2) and pr == pc,
                f"restart at step 30 on 2 ranks: {how}; steps and {len(pc)} snapshots {'byte for byte' if pr == pc else 'NOT'} the uninterrupted run's")

# The evolved range: h_i in the state, migrated with it; the same bits on 1 and 2 ranks.
ev = repro + ["-smoothing_length", "evolved"]
e1, e2 = spam(1, "evolved", ev), spam(2, "evolved", ev + ["-migrate_interval", 1])
if e1 and e2:
    p1, p2 = snapshots(e1), snapshots(e2)
    differ = [f for f in p1 if p1[f] != p2.get(f)]
    c.check(steps(e1) == steps(e2) and len(p1) == 3 and p1.keys() == p2.keys() and not differ,
            f"-smoothing_length evolved -reproducible, 2 ranks: steps and {len(p2)} snapshots byte for byte one rank's (differing: {differ or 'none'})")

fixed = ["-ts_max_time", 0.2, "-arkode_fixed_step", 0.004, "-output_interval", 0.2, "-snapshot_interval", 0.2]
finals = {}
for ranks in (1, 2):
    out = spam(ranks, "fixed", fixed)
    if out:
        with open(os.path.join(out, "particles_00001.csv")) as fh:
            fh.readline()  # "# t=0.2"
            rows = list(csv.DictReader(fh))
        finals[ranks] = {k: [float(r[k]) for r in rows] for k in ("id", "x", "y", "e", "rho_sum")}
if len(finals) == 2:
    f1, f2 = finals[1], finals[2]
    order1, order2 = sorted(range(len(f1["id"])), key=lambda k: f1["id"][k]), sorted(range(len(f2["id"])), key=lambda k: f2["id"][k])

    def most(col):
        """The largest difference of a column, 2 ranks against 1, particle by particle."""
        return max(abs(f1[col][p] - f2[col][q]) for p, q in zip(order1, order2))
    dx, de, drho = max(most("x"), most("y")), most("e") / max(map(abs, f1["e"])), most("rho_sum") / max(f1["rho_sum"])
    # Every particle's summed density at its solved h_i: a partner missing across the rank
    # boundary or a periodic face would move it by m w / rho ~ 1e-2.
    c.check(len(order1) == 576 == len(order2) and dx <= 1e-11 * H and de <= 1e-11 and drho <= 1e-11,
            f"default mode, fixed step, 2 ranks against 1 at t = 0.2: positions within {dx:.2e} (bound 1e-11 h), energies within {de:.2e} "
            f"and summed densities within {drho:.2e} of the largest (bound 1e-11)")
    c.check(dx > 0.0 or de > 0.0 or drho > 0.0, f"control: the default mode's sums on 2 ranks round otherwise (largest position difference {dx:.1e})")
c.finish()
