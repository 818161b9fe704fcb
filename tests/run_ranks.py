#!/usr/bin/python3
"""Multi-rank runs: the same run on 1, 2 and 3 ranks.

(a) Fixed steps (ERKStep, Dormand-Prince 5(4), -arkode_fixed_step), for the 2D and 3D
    expansion, the rotor with T_ij torque scaling, the elastic plane wave, and with mirror
    walls the 2D expansion in a walled box (free slip), the Couette flow (moving no-slip
    walls, the walls' books in the state) and the convection cell (gravity's hydrostatic
    images, isothermal walls): every diagnostic that is a sum over particles (kinetic,
    internal and total energy, entropy sum, angular momentum, torque sum, the work, heat and
    impulse the walls gave, each wall's force and power) agrees with the one-rank run to
    1e-11 relative at every output row. A mirror image of another rank's particle that was
    missed, or booked to no particle, moves these by one pair's share, ~1e-5. Why 1e-11: the ranks sum a particle's pairs in another order (remote ghosts
    are walked newton-off), so one RHS differs by a few ulp of the largest pair sum
    (~1e-15 relative; PARALLEL_RESTART.md section 4 measured 4.3e-15 max|a|), and a short run
    that is not chaotic carries that through some hundred stage evaluations: 1e-11 leaves
    a factor 100 of growth. A pair lost or counted twice across ranks moves these sums by
    one pair's share of the total, 1/(N * neighbours) ~ 1e-5 and more. (timeseries.csv
    prints 13 significant digits: agreement below that shows as 0.)
(b) Adaptive steps (rtol 1e-6; also the rotor pair under Gauss's principle, whose
    multipliers and per-body angular momenta are sums over every rank): the step sizes part
    once the error norms differ in their
    last bits, so the runs are compared at output times: energies within 10 rtol relative
    (1.7 rtol was measured for a non-chaotic system).
(c) Momentum on several ranks (the scenes of (a) without walls) stays at round-off: |P| <= eps * steps * sqrt(N) * sqrt(2 M K)
    (sum_i m|v_i| <= sqrt(2 M K); each step adds rounding of the per-particle sums, which add
    up like a random walk over N particles). A cross-rank pair whose two sides differed
    would leave |P| at about its force times the run time, orders above.
(d) An error on one rank ends every rank: rank 0's timeseries write fails (disk full,
    injected); the job exits 1 within the timeout, with one error line.
(e) What runs on one rank only is refused in one line, printed once: -closest_approach.
    Checkpoints run on several ranks (run_restart_ranks tests their restarts): with
    -checkpoint_wall 1e-6 each rank's clock asks at its own moment, and the ranks agree,
    writing one after every step without a hang.
(f) Migrations between steps (-migrate_interval 1: after every list build): the run agrees
    with the one-rank run as in (b), the count is kept, one RHS evaluation per migration;
    with fixed steps the final particles carry every id once and stand where one rank has
    them; with mirror walls (the Couette flow, the convection cell, whose walls' books go to
    owners that change, and the walled expansion) the fixed-step runs agree as in (a).
(h) SIGTERM to one rank: every rank stops after the same step, outputs complete, exit 143.
(g) Every options file on 2 ranks (to its first output time after t = 0): the one-rank
    energies at the output times both reached within max(10, 2 steps) times the file's rtol
    (each run is within about rtol per step of the exact solution), or a one-line refusal
    naming what is serial-only.
The one-rank runs are plain starts of spam-ark (MPI's singleton), the others mpiexec's.
"""
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spamrun import Checks, arguments, mpiexec_env, rank_command, summary, table  # noqa: E402

EPS = 2.220446049250313e-16
a = arguments()
c = Checks()
mpiexec, ENV = mpiexec_env()


def spam(ranks, name, args, env=None, timeout=300):
    """One run on `ranks` ranks (one rank: a singleton start, spamrun.rank_command)."""
    out = os.path.join(a.workdir, f"{name}_np{ranks}")
    cmd, env = rank_command(mpiexec, env or ENV, ranks, a.spam_ark, list(args) + ["-output_dir", out])
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    return p.returncode, p.stdout, p.stderr, out


def common_rows(out1, out2):
    """The two runs' timeseries and the pairs of rows (one run's, the other's) at equal t."""
    t1, t2 = table(os.path.join(out1, "timeseries.csv")), table(os.path.join(out2, "timeseries.csv"))
    return t1, t2, [(i, t2["t"].index(t)) for i, t in enumerate(t1["t"]) if t in t2["t"]]


SUMS = ["kinetic", "internal", "total", "entropy_sum", "lz", "torque_sum"]
SCENES = {
    "expansion2d": ["-scene", "expansion", "-dim", 2, "-expansion_n", 24, "-h", 3, "-eos_gamma", 2, "-eos_kappa", 0.5,
                    "-expansion_amplitude", 0.01, "-expansion_seed", 1, "-ts_max_time", 6, "-output_interval", 1],
    "expansion3d": ["-scene", "expansion", "-dim", 3, "-expansion_n", 10, "-h", 2.5, "-eos_gamma", 5.0 / 3.0, "-eos_kappa", 0.5,
                    "-expansion_amplitude", 0.01, "-expansion_seed", 2, "-ts_max_time", 4, "-output_interval", 1],
    "rotor_tij": ["-options_file", "options/rotor.opts", "-angmom", "Tij", "-ts_max_time", 12, "-output_interval", 2],
    "planewave": ["-options_file", "options/planewave.opts", "-ts_max_time", 6, "-output_interval", 1],
    "expansion_walls": ["-scene", "expansion", "-dim", 2, "-expansion_n", 24, "-h", 3, "-eos_gamma", 2, "-eos_kappa", 0.5,
                        "-expansion_amplitude", 0.01, "-expansion_seed", 1, "-ts_max_time", 6, "-output_interval", 1,
                        "-wall_xlo", "freeslip", "-wall_xhi", "freeslip", "-wall_ylo", "freeslip", "-wall_yhi", "freeslip"],
    "couette": ["-options_file", "options/couette.opts", "-couette_start", "rest", "-ts_max_time", 48, "-output_interval", 8],
    # Rayleigh-Benard at 5 times the critical Ra is unstable: two runs' rounding differences
    # grow about 4 times per 10 time units (measured: 2e-13 at t = 40, 1e-11 at t = 60), so
    # its run ends at t = 40.
    "convection": ["-options_file", "options/convection.opts", "-ts_max_time", 40, "-output_interval", 10],
}
# Two bodies held by Gauss's principle (its multipliers are sums over every rank) and the
# per-body angular momenta (bodies labelled on rank 0 at the start, labels carried).
GAUSS = ["-options_file", "options/rotor-pair.opts", "-angmom", "gauss", "-ts_max_time", 12, "-output_interval", 2]
SUMS.extend(["l_body0", "l_body1"])
WALL_FORCES = [f"wall_{f}_{q}" for f in ("xlo", "xhi", "ylo", "yhi") for q in ("fx", "fy")]
WALL_POWERS = [f"wall_{f}_{q}" for f in ("xlo", "xhi", "ylo", "yhi") for q in ("work_rate", "heat_rate")]
# The walls' books and rates (wall_books.h): sums over every rank's mirror images.
SUMS.extend(["wall_work", "wall_heat", "wall_impulse_x", "wall_impulse_y"] + WALL_FORCES + WALL_POWERS)
WALLED = ("expansion_walls", "couette", "convection")
FIXED = {"expansion2d": 0.05, "expansion3d": 0.05, "rotor_tij": 0.1, "planewave": 0.05, "expansion_walls": 0.05, "couette": 1.0,
         "convection": 1.0}
OPTS_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def args_of(name):
    args = GAUSS if name == "rotor_pair_gauss" else SCENES[name]
    return [os.path.join(OPTS_DIR, x) if isinstance(x, str) and x.startswith("options/") else x for x in args]


def relative(x, y, scale):
    return abs(x - y) / scale


def largest(t1, cols, rows):
    return max([abs(v) for g in cols if g in t1 for v in t1[g][:rows] if not math.isnan(v)] + [0.0])


def scale_of(t1, col, rows):
    """A sum's scale: its largest value over the run, or the size of the terms it sums where
    they cancel. The torque sum adds pair torques r_ij x F_ij, each at most the pair's
    virial |r_ij||F_ij|, whose sum is of the order of dim P V, at least the internal energy:
    its rounding is relative to that. The walls' quantities at the scale of their kind: a
    wall's tangential force under free slip, or a resting wall's power (the Couette flow's
    lower wall), is round-off of the others'; the walls' impulses cancel in a steady shear
    (equal and opposite), so they are compared at the largest wall force times the run's
    duration."""
    if col == "torque_sum":
        return largest(t1, ["torque_sum", "internal"], rows)
    if col in ("wall_work", "wall_heat"):
        return largest(t1, ["wall_work", "wall_heat", "kinetic"], rows)
    if col.startswith("wall_impulse"):
        return max(largest(t1, ["wall_impulse_x", "wall_impulse_y"], rows), largest(t1, WALL_FORCES, rows) * t1["t"][rows - 1])
    if col in WALL_FORCES:
        return largest(t1, WALL_FORCES, rows)
    if col in WALL_POWERS:
        return largest(t1, WALL_POWERS, rows)
    return largest(t1, [col], rows)


def compare(name, t1, tn, ranks, tol, what):
    worst, where = 0.0, ""
    rows = min(len(t1["t"]), len(tn["t"]))
    energy = max(abs(v) for v in t1["total"][:rows])
    for col in SUMS:
        if col not in t1 or any(math.isnan(v) for v in t1[col][:rows]):
            continue
        # Each sum at the scale of its largest value over the run. A sum that is round-off
        # on one rank too (lz of an expansion from rest, the torque sum of a plane wave:
        # below 1e-9 of the energy in the run's units) has no digits to compare; momentum
        # and angular momentum at round-off are (c)'s business.
        scale = scale_of(t1, col, rows)
        if scale == 0.0 or (col in ("lz", "torque_sum") and scale < 1e-9 * energy):
            continue
        for k in range(rows):
            d = relative(t1[col][k], tn[col][k], scale)
            if d > worst:
                worst, where = d, f"{col} at t = {t1['t'][k]:g}"
    c.check(rows == len(t1["t"]) and worst <= tol, f"{name} {what}, {ranks} ranks vs 1: {rows} rows, largest difference {worst:.2e} ({where}) <= {tol:g}")


# The one-rank runs of (a) and (b), by name: (f) and the ids' check compare with the same runs
# (the same options) instead of running them again. The 2D expansion's fixed-step run also
# writes its final particles for the ids' check (an output only: its timeseries is the same).
ONE_RANK_FIXED, ONE_RANK_ADAPTIVE = {}, {}
IDS_NP1 = os.path.join(a.workdir, "ids_np1.csv")

# (a) fixed steps, (c) momentum
for name in SCENES:
    base = args_of(name) + ["-arkode_fixed_step", FIXED[name], "-snapshot_interval", 0]
    runs = {}
    for ranks in (1, 2, 3):
        final = ["-final_csv", IDS_NP1] if name == "expansion2d" and ranks == 1 else []
        code, so, se, out = spam(ranks, f"{name}_fixed", base + final)
        if not c.check(code == 0, f"{name} fixed steps on {ranks} ranks: exit {code} {se.strip()[-300:]}"):
            continue
        runs[ranks] = table(os.path.join(out, "timeseries.csv"))
        if ranks == 1:
            ONE_RANK_FIXED[name] = out
    if 1 not in runs:
        continue
    for ranks in (2, 3):
        if ranks in runs:
            compare(name, runs[1], runs[ranks], ranks, 1e-11, "fixed steps")
            if name in WALLED:  # the walls (and gravity) exchange momentum: their impulse is compared above
                continue
            t = runs[ranks]
            M, N = t["mass"][-1], t["mass"][-1]  # unit masses in these scenes: N = M
            steps = t["step"][-1]
            worst = 0.0
            for k in range(len(t["t"])):
                p = math.sqrt(t["px"][k] ** 2 + t["py"][k] ** 2 + t["pz"][k] ** 2)
                bound = EPS * max(steps, 1) * math.sqrt(N) * math.sqrt(2 * M * max(t["kinetic"][k], 1e-300))
                worst = max(worst, p / bound if bound > 0 else (0.0 if p == 0 else math.inf))
            c.check(worst <= 1.0, f"{name} on {ranks} ranks: momentum |P| at most {worst:.2e} of eps*steps*sqrt(N)*sqrt(2MK)")

# (b) adaptive steps
rtol = 1e-6
for name in ("expansion2d", "rotor_tij", "rotor_pair_gauss"):
    base = args_of(name) + ["-ts_rtol", rtol, "-ts_atol", 1e-9, "-snapshot_interval", 0]
    runs = {}
    for ranks in (1, 2, 3):
        code, so, se, out = spam(ranks, f"{name}_adaptive", base)
        if c.check(code == 0, f"{name} adaptive on {ranks} ranks: exit {code} {se.strip()[-300:]}"):
            runs[ranks] = table(os.path.join(out, "timeseries.csv"))
            if ranks == 1:
                ONE_RANK_ADAPTIVE[name] = out
    for ranks in (2, 3):
        if 1 in runs and ranks in runs:
            compare(name, runs[1], runs[ranks], ranks, 10 * rtol, "adaptive at output times")

# (f) migrations between steps: ERKStep follows the particles (ERKStepResize) and the run is
#     the same within the adaptive bound; each migration costs one RHS evaluation (ERKStep
#     evaluates f at the new vector); the particle count is kept.
t1 = None
base = args_of("expansion2d") + ["-ts_rtol", rtol, "-ts_atol", 1e-9, "-snapshot_interval", 0]
out1 = ONE_RANK_ADAPTIVE.get("expansion2d")  # (b)'s run of these options on one rank
if c.check(out1 is not None, "expansion2d for migrations on 1 rank: (b)'s adaptive run"):
    t1 = table(os.path.join(out1, "timeseries.csv"))
    s1 = summary(out1)
    for ranks in (2, 3):
        code, so, se, out = spam(ranks, "migrate", base + ["-migrate_interval", 1])
        if not c.check(code == 0, f"expansion2d with -migrate_interval 1 on {ranks} ranks: exit {code} {se.strip()[-300:]}"):
            continue
        s = summary(out)
        c.check(s["migrations"] >= 5 and s["particles_migrated"] > 0 and s["n_particles"] == s1["n_particles"],
                f"{ranks} ranks: {s['migrations']} migrations moved {s['particles_migrated']:g} particles, {s['n_particles']} particles kept")
        c.check(s["rhs_evals"] - s1["rhs_evals"] <= s["migrations"] + 0.2 * s1["rhs_evals"],
                f"{ranks} ranks: {s['rhs_evals']} RHS evaluations against {s1['rhs_evals']} on one rank with {s['migrations']} migrations (one each, and the steps part within rtol)")
        compare("expansion2d", t1, table(os.path.join(out, "timeseries.csv")), ranks, 10 * rtol, "with migrations, at output times")
# PETSc's rk with fixed steps follows by TSReset + TSSetSolution (its first stage evaluated
# again): the fixed-step bound of (a) holds.
rk = args_of("expansion2d") + ["-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "none", "-ts_dt", 0.05, "-snapshot_interval", 0]
code, so, se, out1 = spam(1, "migrate_rk", rk)
code2, so, se, out2 = spam(2, "migrate_rk", rk + ["-migrate_interval", 1])
if c.check(code == 0 and code2 == 0, f"rk 5dp fixed steps, 1 rank and 2 ranks with migrations: exit {code}, {code2} {se.strip()[-300:]}"):
    c.check(summary(out2)["migrations"] >= 5, f"rk: {summary(out2)['migrations']} migrations")
    compare("expansion2d rk 5dp", table(os.path.join(out1, "timeseries.csv")), table(os.path.join(out2, "timeseries.csv")), 2, 1e-11, "fixed steps with migrations")
# Mirror walls with migrations: the walls' books go back to their particles' owners, which
# change; the fixed-step bound of (a) holds. (The Couette flow starts on its linear profile:
# from rest the particles hardly move and none changes rank. Its ranks are cut across the
# channel, so each wall's images are local; the convection cell's cut runs to the walls, and
# there another rank's particles come as mirror images with their books.)
for name, extra in (("couette", ["-couette_start", "linear"]), ("convection", []), ("expansion_walls", [])):
    cw = args_of(name) + extra + ["-arkode_fixed_step", FIXED[name], "-snapshot_interval", 0]
    if not extra and name in ONE_RANK_FIXED:  # (a)'s run of these options on one rank
        code1, out1 = 0, ONE_RANK_FIXED[name]
    else:
        code1, so, se, out1 = spam(1, f"migrate_{name}", cw)
    code2, so, se, out2 = spam(2, f"migrate_{name}", cw + ["-migrate_interval", 1])
    if c.check(code1 == 0 and code2 == 0, f"{name} fixed steps, 1 rank and 2 ranks with migrations: exit {code1}, {code2} {se.strip()[-300:]}"):
        c.check(summary(out2)["migrations"] >= 5 and summary(out2)["particles_migrated"] > 0,
                f"{name}: {summary(out2)['migrations']} migrations moved {summary(out2)['particles_migrated']:g} particles")
        compare(name, table(os.path.join(out1, "timeseries.csv")), table(os.path.join(out2, "timeseries.csv")), 2, 1e-11, "fixed steps with migrations")
# Ids across migrations: fixed steps, a migration after every list build, the final
# particles (-final_csv, gathered by id): every id once on 3 ranks, and each particle where
# the one-rank run has it (fixed steps: within 1e-9 of the box edge; differences are the
# sums' rounding carried over 120 steps).
fixed = args_of("expansion2d") + ["-arkode_fixed_step", FIXED["expansion2d"], "-snapshot_interval", 0]
o1 = ONE_RANK_FIXED.get("expansion2d")  # (a)'s run of these options on one rank, with -final_csv IDS_NP1
code1 = 0 if o1 and os.path.exists(IDS_NP1) else "(a)'s run missing"
code3, so, se, o3 = spam(3, "ids", fixed + ["-migrate_interval", 1, "-final_csv", os.path.join(a.workdir, "ids_np3.csv")])
if c.check(code1 == 0 and code3 == 0, f"final particles on 1 and 3 ranks with migrations: exit {code1}, {code3} {se.strip()[-300:]}"):
    p1, p3 = table(IDS_NP1), table(os.path.join(a.workdir, "ids_np3.csv"))
    ids = sorted(int(v) for v in p3["id"])
    c.check(ids == list(range(len(p1["id"]))), f"3 ranks, {summary(o3)['migrations']} migrations: ids 0..{len(ids) - 1} each once ({len(ids)} rows, {len(set(ids))} distinct)")
    at = {int(v): k for k, v in enumerate(p3["id"])}
    worst = max(abs(p1[col][k] - p3[col][at[int(p1["id"][k])]]) for col in ("x", "y") for k in range(len(p1["id"])))
    edge = summary(o1)["box_len"][0]
    c.check(worst <= 1e-9 * edge, f"3 ranks with migrations: final positions within {worst:.1e} of one rank's (bound 1e-9 x box edge {edge:g})")
code, so, se, out = spam(1, "migrate_one", base + ["-migrate_interval", 1])
c.check(code == 2 and "several ranks" in se, f"-migrate_interval on one rank refused: exit {code} {se.strip()[-200:]}")

# (i) The springs model (chain, rotor-md) on 1, 2 and 3 ranks. Its bonds are made once, at
#     set-up on rank 0, and travel by gid through the first distribution; a bond whose
#     partner another rank holds is computed on both ranks (newton off), its energy half on
#     each. The model never rebuilds its neighbour list, so it never migrates after the first
#     distribution (-migrate_interval is refused for it): what is checked is that the first
#     distribution keeps every bond and every particle. Fixed-step DP5 as (a): energies and L
#     within 1e-11 of one rank at every output row, by (a)'s argument (a bond lost or counted
#     twice moves the spring energy by one bond's share, ~1/(3N) of it, at once), and
#     momentum at round-off by (c)'s bound. Then the final particles on 3 ranks: every id
#     once, each where one rank has it within 1e-11 x box edge (the same rounding argument
#     for positions; a lost bond moves a particle by its displacement amplitude, 1e-2).
SPRINGS = {"chain": (["-scene", "chain", "-dim", 1, "-chain_n", 64, "-spring_k", 1, "-chain_amplitude", 0.01,
                      "-ts_max_time", 8, "-output_interval", 1], 0.1),
           "rotor-md": (["-scene", "rotor-md", "-dim", 2, "-rotor_n", 8, "-rotor_speed", 0.1, "-spring_k", 1, "-spring_range", 1.1,
                         "-ts_max_time", 12, "-output_interval", 2], 0.1)}


def momentum_roundoff(t):
    """Largest |P| over the run as a fraction of (c)'s eps * steps * sqrt(N) * sqrt(2MK)."""
    M = t["mass"][-1]  # unit masses: N = M
    worst = 0.0
    for k in range(len(t["t"])):
        p = math.sqrt(t["px"][k] ** 2 + t["py"][k] ** 2 + t["pz"][k] ** 2)
        bound = EPS * max(t["step"][-1], 1) * math.sqrt(M) * math.sqrt(2 * M * max(t["kinetic"][k], 0.0))
        worst = max(worst, p / bound if bound > 0 else (0.0 if p == 0 else math.inf))
    return worst


for name, (args, dt) in SPRINGS.items():
    runs, finals = {}, {}
    for ranks in (1, 2, 3):
        final = os.path.join(a.workdir, f"springs_{name}_np{ranks}.csv")
        code, so, se, out = spam(ranks, f"springs_{name}", args + ["-arkode_fixed_step", dt, "-snapshot_interval", 0, "-final_csv", final])
        if not c.check(code == 0, f"{name} fixed steps on {ranks} ranks: exit {code} {se.strip()[-300:]}"):
            continue
        runs[ranks], finals[ranks], s = table(os.path.join(out, "timeseries.csv")), table(final), summary(out)
        edge = s["box_len"][0]
        if ranks > 1:  # every rank holds a piece (imbalance P: one rank holds all, no bond crosses)
            c.check(s["ranks"] == ranks and s["rank_imbalance_final"] <= 1.25, f"{name} on {ranks} ranks: imbalance {s['rank_imbalance_final']:.3f} (fullest rank / mean)")
    if 1 not in runs:
        continue
    for ranks in (2, 3):
        if ranks not in runs:
            continue
        compare(name, runs[1], runs[ranks], ranks, 1e-11, "fixed steps")
        worst = momentum_roundoff(runs[ranks])
        c.check(worst <= 1.0, f"{name} on {ranks} ranks: momentum |P| at most {worst:.2e} of eps*steps*sqrt(N)*sqrt(2MK)")
        p1, pn = finals[1], finals[ranks]
        ids = sorted(int(v) for v in pn["id"])
        c.check(ids == list(range(len(p1["id"]))), f"{name} on {ranks} ranks: final ids 0..{len(p1['id']) - 1} each once ({len(ids)} rows, {len(set(ids))} distinct)")
        at = {int(v): k for k, v in enumerate(pn["id"])}
        cols = [col for col in ("x", "y", "z") if col in p1]
        worst = max(abs(p1[col][k] - pn[col][at[int(p1["id"][k])]]) for col in cols for k in range(len(p1["id"])) if int(p1["id"][k]) in at)
        c.check(worst <= 1e-11 * edge, f"{name} on {ranks} ranks: final positions within {worst:.1e} of one rank's (bound 1e-11 x box edge {edge:g})")
code, so, se, out = spam(2, "springs_migrate", SPRINGS["rotor-md"][0] + ["-migrate_interval", 1])
lines = [x for x in se.splitlines() if x.startswith("spam-ark: error:")]
c.check(code == 2 and len(lines) == 1 and "-migrate_interval" in lines[0] and "springs" in lines[0], f"-migrate_interval with the springs on 2 ranks refused once: exit {code}, {lines}")

# (g) every options file on 2 ranks: the one-rank answer at the output times both reached
#     (energies within 10 rtol of the file's tolerance, as (b)), or refused in one line that
#     names what is serial-only. Each pair of runs ends at the file's first output time after
#     t = 0 (its -output_interval; its end time where that is 0, start and end only): the rows
#     at t = 0 and at that time are the two the comparison needs, and a pair lost or counted
#     twice across ranks shows from the first right-hand side on (the bound, 2 rtol per step,
#     shrinks with the steps). At most 100 steps: a file that has not reached the time by then
#     fails (one common row). A file that sets no interval (the scene's default) runs 30
#     steps, or 100 where 30 reached no output time after t = 0.


def first_output_time(path):
    """The options file's first output time after t = 0, or None where it sets no interval."""
    opts = {}
    for line in open(path):
        words = line.split()
        if len(words) >= 2 and words[0] in ("-output_interval", "-ts_max_time"):
            opts[words[0]] = float(words[1])
    interval, end = opts.get("-output_interval"), opts.get("-ts_max_time")
    if interval is None or (interval == 0 and end is None):
        return None
    return end if interval == 0 else min(interval, end) if end else interval


REFUSED = {}  # options files refused on several ranks, by name: the option named
# Options files at the sizes their pages quote, run here smaller and shorter: the same model
# on both rank counts is what (g) compares, from the first right-hand side on. The 3D
# adaptive blast at 48^3 took 28 CPU-s a rank count to its first output (t = 0.5); 28^3 is
# the least lattice its deposit radius (6) accepts, and to t = 0.05 it takes 11 steps.
SMALLER = {"sedov-adaptive-3d": ["-sedov_n", 28, "-output_interval", 0.05, "-ts_max_time", 0.05]}
optdir = os.path.join(OPTS_DIR, "options")
for fname in sorted(os.listdir(optdir)):
    if not fname.endswith(".opts"):
        continue
    name, path = fname[:-5], os.path.join(optdir, fname)
    tol = 1e-6
    for line in open(path):
        if line.split()[:1] == ["-ts_rtol"]:
            tol = float(line.split()[1])
    stop = first_output_time(path)
    small = SMALLER.get(name, [])
    if "-ts_max_time" in small:
        stop = small[small.index("-ts_max_time") + 1]
        small = small[:small.index("-ts_max_time")] + small[small.index("-ts_max_time") + 2:]
    if stop is not None:
        args = ["-options_file", path, "-ts_max_time", repr(stop), "-ts_max_steps", 100, "-snapshot_interval", 0]
    else:
        args = ["-options_file", path, "-ts_max_steps", 30, "-snapshot_interval", 0]
    args += small
    code1, so, se1, out1 = spam(1, f"file_{name}", args)
    t_rows = table(os.path.join(out1, "timeseries.csv"))["t"] if code1 == 0 else [0.0]
    if stop is None and name not in REFUSED and code1 == 0 and not any(0 < t < t_rows[-1] for t in t_rows):
        # 30 steps did not reach an output time after t = 0 (the one-rank run tells, before
        # the two-rank run is started): a run whose step the viscosity or conduction bounds
        # (h^2 / nu) or whose output interval is long. Both run to 100 steps instead.
        args[args.index("-ts_max_steps") + 1] = 100
        name = f"{name}_long"
        code1, so, se1, out1 = spam(1, f"file_{name}", args)
    code2, so, se2, out2 = spam(2, f"file_{name}", args)
    lines = [x for x in se2.splitlines() if x.startswith("spam-ark: error:")]
    if name in REFUSED:
        c.check(code1 == 0 and code2 == 2 and len(lines) == 1 and REFUSED[name] in lines[0] and "one rank" in lines[0],
                f"{fname} on 2 ranks refused ({REFUSED[name]}): exit {code2}, {lines}")
        continue
    until = f"to t = {stop:g}, at most 100 steps" if stop is not None else f"{args[args.index('-ts_max_steps') + 1]} steps"
    if not c.check(code1 == 0 and code2 == 0, f"{fname} on 1 and 2 ranks ({until}): exit {code1}, {code2} {lines}"):
        continue
    t1, t2, common = common_rows(out1, out2)
    # Each adaptive run is within its accumulated local errors of the exact solution, at
    # most about rtol per step (relative, no damping assumed), so two runs that step
    # differently differ by up to 2 rtol per step taken; never less than (b)'s 10 rtol.
    worst, where = 0.0, ""
    for col in ("kinetic", "internal", "total"):
        scale = max(abs(v) for v in t1[col]) or 1.0
        for i, j in common:
            d = abs(t1[col][i] - t2[col][j]) / scale / (max(10.0, 2.0 * t1["step"][i]) * tol)
            if d > worst:
                worst, where = d, f"{col} at t = {t1['t'][i]:g}, step {t1['step'][i]:g}"
    c.check(len(common) >= 2 and worst <= 1.0,
            f"{fname}: 2 ranks vs 1 at {len(common)} common output times, largest energy difference {worst:.2f} of max(10, 2 steps) x rtol {tol:g} ({where})")

# (d) a failure on rank 0 ends every rank
env = dict(ENV, SPAM_TEST_FAIL_WRITE="timeseries.csv:3")
try:
    code, so, se, out = spam(2, "fail", args_of("expansion2d"), env=env, timeout=120)
    lines = [x for x in se.splitlines() if x.startswith("spam-ark: error:")]
    c.check(code == 1 and len(lines) == 1 and "timeseries.csv" in lines[0], f"rank 0's failed write on 2 ranks: exit {code}, error lines {lines}")
except subprocess.TimeoutExpired:
    c.check(False, "rank 0's failed write on 2 ranks: the job hung (timeout 120 s)")

# (h) SIGTERM to one rank only (a batch system signals the ranks; OpenMPI's mpiexec, if
#     signalled itself, stops forwarding their output and kills them a second later): every
#     rank stops after the same step (SignalAgreed), the outputs are complete, exit 143.
import time  # noqa: E402
out = os.path.join(a.workdir, "sigterm_np2")
log = os.path.join(a.workdir, "sigterm_np2.log")
cmd = [mpiexec, "--oversubscribe", "-n", "2", a.spam_ark] + [str(x) for x in args_of("expansion2d") + ["-ts_max_time", 1e5, "-snapshot_interval", 0, "-output_interval", 1, "-output_dir", out]]
with open(log, "w") as f:
    p = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT, env=ENV)
# Rank 0 prints its first line once every rank has opened the run (the output directory's
# agreement): from then on each rank has its handler; the steps would go on for hours.
deadline = time.time() + 120
while time.time() < deadline and "spam-ark: scene" not in open(log).read():
    time.sleep(0.1)
time.sleep(1.0)
ranks = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
if ranks:
    os.kill(int(ranks[-1]), 15)
try:
    p.wait(timeout=60)
    s = summary(out)
    c.check(len(ranks) == 2 and p.returncode == 143 and s["status"] == "interrupted" and "SIGTERM" in s["reason"] and s["steps"] > 0,
            f"SIGTERM to one of {len(ranks)} ranks: exit {p.returncode}, status {s['status']} ({s['reason']}) after {s['steps']} steps")
except subprocess.TimeoutExpired:
    p.kill()
    c.check(False, "SIGTERM to one rank: the job hung (timeout 60 s)")
except FileNotFoundError as e:
    c.check(False, f"SIGTERM to one rank: no summary ({e}); exit {p.returncode}")

# (e) refusals, once
for what, args in [("closest approach", args_of("rotor_tij") + ["-closest_approach", 0.5])]:
    code, so, se, out = spam(2, "refused", args)
    lines = [x for x in se.splitlines() if x.startswith("spam-ark: error:")]
    c.check(code == 2 and len(lines) == 1 and "one rank" in lines[0], f"{what} on 2 ranks refused once: exit {code}, {lines}")
code, so, se, out = spam(2, "checkpoint_wall", args_of("expansion2d") + ["-checkpoint_wall", 1e-6])
s = summary(out) if code == 0 else {}
c.check(code == 0 and s.get("checkpoints_written", 0) >= s.get("steps", 1) - 2,
        f"-checkpoint_wall 1e-6 on 2 ranks: exit {code}, {s.get('checkpoints_written')} checkpoints in {s.get('steps')} steps {se.strip()[:200]}")
c.finish()
