#!/usr/bin/python3
"""-reproducible across rank counts, end to end: the same adaptive run on
1, 2 and 3 ranks takes the same steps and writes the same particles, to the bit.

The 2D expansion (24^2 particles, gamma 1.7) and the 3D expansion (8^3), Dormand-Prince at
rtol 1e-6 for about 2 sound crossings of the gas's start, with migrations after every list
build (-migrate_interval 1: each one re-sorts, resizes ERKStep's vectors and rebuilds the
list at the carried reference positions) and at the default interval; cvode on 2 ranks
(its vectors keep the first distribution). Checked against the one-rank run:
- steps.csv: every step's number, time, size and rejections identical as printed (17
  significant digits, so bit for bit): an adaptive controller turns any difference in the
  last bit of a state or an error norm into other step sizes within a few steps;
- timeseries.csv: the integrator's columns identical; the sums over particles (energies,
  momenta, entropies: diagnostics, reduced over the ranks in another order) within 1e-12
  of their scale;
- every CSV snapshot (positions, velocities, summed densities: gathered by gid on rank 0
  and printed to 17 significant digits) byte for byte the one-rank run's;
- control: the default mode on 2 ranks takes other step sizes and writes other snapshots.
PETSc's rk under its adaptor with -reproducible on several ranks is refused (PETSc sums its
rms error norm rank by rank), printed once.
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spamrun import Checks, arguments, mpiexec_env, rank_command  # noqa: E402

a = arguments()
c = Checks()
mpiexec, ENV = mpiexec_env()
SCENES = {
    "2D": ["-scene", "expansion", "-dim", 2, "-expansion_n", 24, "-h", 3, "-eos_gamma", 1.7, "-expansion_amplitude", 0.1,
           "-ts_max_time", 40, "-output_interval", 2, "-snapshot_interval", 10],
    "3D": ["-scene", "expansion", "-dim", 3, "-expansion_n", 8, "-h", 2.5, "-expansion_amplitude", 0.1,
           "-ts_max_time", 12, "-output_interval", 1, "-snapshot_interval", 3],
}
STEP_COLUMNS = ("t", "step", "rejected", "dt", "bound_limited")
TIMING = ("rhs_s", "wall_s", "rhs_evals")  # rhs_evals: a migration's resize evaluates f again


def spam(ranks, name, args, expect=0):
    out = os.path.join(a.workdir, f"{name}_np{ranks}")
    cmd, env = rank_command(mpiexec, ENV, ranks, a.spam_ark, list(args) + ["-output_dir", out])  # one rank: a singleton
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    if p.returncode != expect:
        c.check(False, f"{name} on {ranks} ranks: exit {p.returncode} {p.stderr.strip()[:300]}")
    return p.returncode, p.stderr, out


def steps(out):
    with open(os.path.join(out, "steps.csv")) as f:
        return [ln.split(",")[:4] for ln in f]  # step, t, dt, rejected


def particles(out):
    """The bytes of every CSV snapshot (gathered by gid on rank 0, 17 significant digits)."""
    files = sorted(f for f in os.listdir(out) if f.startswith("particles_"))
    return {f: open(os.path.join(out, f), "rb").read() for f in files}


def series(out):
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = [ln.rstrip("\n").split(",") for ln in f]
    return rows[0], rows[1:]


def series_match(ref, other):
    """Integrator columns identical, particle sums within 1e-12 of their scale."""
    head, x = series(ref)
    head2, y = series(other)
    if head != head2 or len(x) != len(y):
        return False, "columns or rows differ"
    worst = 0.0
    for k, name in enumerate(head):
        if name in TIMING:
            continue
        col, col2 = [r[k] for r in x], [r[k] for r in y]
        if name in STEP_COLUMNS:
            if col != col2:
                return False, f"column {name} differs"
            continue
        v, w = [float(s) for s in col], [float(s) for s in col2]
        scale = max([abs(q) for q in v if q == q] + [abs(float(r[head.index("total")])) for r in x] + [1e-300])
        for p, q in zip(v, w):
            if p == p or q == q:
                worst = max(worst, abs(p - q) / scale)
    return worst <= 1e-12, f"largest sum difference {worst:.1e} of scale"


for scene, args in SCENES.items():
    rc, _, ref = spam(1, f"{scene}_repro", args + ["-reproducible"])
    if rc:
        continue
    s1 = steps(ref)
    for ranks in (2, 3):
        for mi in (1, 20):
            name = f"{scene}_repro_mi{mi}"
            rc, _, out = spam(ranks, name, args + ["-reproducible", "-migrate_interval", mi])
            if rc:
                continue
            sn = steps(out)
            c.check(sn == s1, f"{scene}, -reproducible, {ranks} ranks, migrations every {mi} list builds: "
                              f"{len(sn) - 1} steps, every t and dt identical to one rank's ({len(s1) - 1} steps)")
            p1, pn = particles(ref), particles(out)
            differ = [f for f in p1 if p1[f] != pn.get(f)]
            c.check(len(p1) >= 4 and p1.keys() == pn.keys() and not differ,
                    f"{scene}, {ranks} ranks, every {mi}: {len(pn)} particle snapshots byte for byte those of one rank (differing: {differ or 'none'})")
            ok, why = series_match(ref, out)
            c.check(ok, f"{scene}, {ranks} ranks, every {mi}: timeseries, integrator columns identical; {why} (bound 1e-12)")
    rc, _, dref = spam(1, f"{scene}_default", args)
    rc2, _, dout = spam(2, f"{scene}_default", args)
    if not rc and not rc2:
        d1, d2 = steps(dref), steps(dout)
        first = next((k for k, (p, q) in enumerate(zip(d1, d2)) if p != q), None)
        c.check(first is not None, f"{scene}, control: the default mode on 2 ranks takes other step sizes (from step {first})")
        p1, p2 = particles(dref), particles(dout)
        c.check(any(p1[f] != p2.get(f) for f in p1 if not f.endswith("00000.csv")), f"{scene}, control: the default mode's snapshots on 2 ranks differ from one rank's")

cv = SCENES["2D"] + ["-ts_type", "cvode", "-reproducible"]
rc, _, ref = spam(1, "cvode", cv)
rc2, _, out = spam(2, "cvode", cv)
if not rc and not rc2:
    c.check(steps(out) == steps(ref), f"cvode, -reproducible, 2 ranks: {len(steps(out)) - 1} steps, every t and dt identical to one rank's")

rc, err, _ = spam(2, "rk_refused", SCENES["2D"] + ["-ts_type", "rk", "-reproducible"], expect=2)
lines = err.strip().splitlines()
c.check(rc == 2 and len([ln for ln in lines if "-reproducible" in ln]) == 1 and "adaptor" in err,
        f"rk under its adaptor, -reproducible, 2 ranks: exit {rc}, printed once: {lines[0][:200] if lines else ''}")
c.finish()
