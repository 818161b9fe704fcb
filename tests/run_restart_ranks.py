#!/usr/bin/python3
"""Checkpoints and restarts on several ranks.

A run on P = 2 or 3 ranks stopped by -ts_max_steps with checkpoints on writes one
checkpoint.h5 holding every rank's particles in its local order, the cut and the migration
state; `-restart` on the same P ranks must then write exactly the files the uninterrupted
P-rank run writes: steps.csv and every snapshot (HDF5 and CSV) byte for byte,
timeseries.csv byte for byte but for its two timing columns, and the same steps, RHS
evaluations and migrations. Asked of ERKStep Dormand-Prince 5(4), adaptive, with a
migration after every list build (-migrate_interval 1), on the 2D expansion (three stops)
and on two walled scenes, the Couette flow (2 ranks) and the convection cell (3 ranks), one
stop each; on the expansion also with PETSc's rk 5dp at fixed steps (3 ranks, migrations)
and kick-drift-kick Verlet (2 ranks, no migrations); the rotor of springs (bonds across
ranks, 3 ranks, its file's Verlet steps). At least one of the stops comes right
after a migration that re-made the integrator's vectors. A run writing a checkpoint every
time unit is the same run. Another rank count is refused in one line
naming both counts (3 -> 2, 3 -> 1, 1 -> 2); a write failure injected on rank 1 or 2 ends
every rank with exit 1 and one line naming that rank, leaving no temporary; a damaged byte
in a rank's particles is refused by that rank's checksum."""
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spamrun import Checks, arguments, mpiexec_env, rank_command, same_outputs, steps_table, summary  # noqa: E402

a = arguments()
c = Checks()
mpiexec, ENV = mpiexec_env()
OPTS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DP5 = ["-ts_type", "arkode", "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5", "-ts_rtol", 1e-7, "-ts_atol", 1e-10,
       "-migrate_interval", 1]
SCENES = {
    "expansion2d": ["-scene", "expansion", "-dim", 2, "-expansion_n", 16, "-h", 3, "-eos_gamma", 2, "-eos_kappa", 0.5,
                    "-expansion_amplitude", 0.05, "-expansion_seed", 3, "-ts_max_time", 6, "-output_interval", 0.5,
                    "-snapshot_interval", 2, "-snapshot_csv"] + DP5,
    # PETSc rk with fixed steps follows migrations through TSReset; Verlet keeps the first
    # distribution (its checkpoint's blocks are the start's: the placement moves nothing).
    "expansion2d_rk": ["-scene", "expansion", "-dim", 2, "-expansion_n", 16, "-h", 3, "-eos_gamma", 2, "-eos_kappa", 0.5,
                       "-expansion_amplitude", 0.05, "-expansion_seed", 3, "-ts_max_time", 4, "-output_interval", 0.5,
                       "-snapshot_interval", 2, "-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "none", "-ts_dt", 0.1,
                       "-migrate_interval", 1],
    "expansion2d_verlet": ["-scene", "expansion", "-dim", 2, "-expansion_n", 16, "-h", 3, "-eos_gamma", 2, "-eos_kappa", 0.5,
                           "-expansion_amplitude", 0.05, "-expansion_seed", 3, "-ts_max_time", 3, "-output_interval", 0.5,
                           "-snapshot_interval", 1, "-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "kdk", "-ts_dt", 0.05],
    "couette": ["-options_file", os.path.join(OPTS_DIR, "options/couette.opts"), "-couette_start", "linear",
                "-ts_max_time", 48, "-output_interval", 8, "-snapshot_interval", 16] + DP5,
    "convection": ["-options_file", os.path.join(OPTS_DIR, "options/convection.opts"), "-ts_max_time", 40,
                   "-output_interval", 10, "-snapshot_interval", 20, "-snapshot_csv"] + DP5,
    # Spring bonds across ranks (kept by id, their remote partners through a PetscSF): the
    # rotor of springs with the file's Verlet steps.
    "rotor_md": ["-options_file", os.path.join(OPTS_DIR, "options/rotor-md.opts"), "-ts_max_steps", 60, "-snapshot_interval", 0],
}


def spam(ranks, args, out, env=None):
    cmd, env = rank_command(mpiexec, env or ENV, ranks, a.spam_ark, list(args) + ["-output_dir", out])  # one rank: a singleton
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    return p.returncode, p.stdout, p.stderr


def errors(stderr):
    return [x for x in stderr.splitlines() if x.startswith("spam-ark: error:")]










def stops(steps, count):
    """count steps spread over the run after which the next step is not cut at an output
    time or the end (a checkpoint there holds no pending stop-time clamp: bitwise)."""
    free = [int(steps[k]["step"]) for k in range(3, len(steps) - 3) if steps[k + 1]["limit"] in ("accuracy", "fixed")]
    return [free[(i + 1) * len(free) // (count + 1)] for i in range(count)] if len(free) >= count else []


def followed(path):
    """The checkpoint's flag: a migration re-made the integrator's vectors at that step."""
    p = subprocess.run(["h5dump", "-d", "/checkpoint/migration_loop", "-w", "0", path], capture_output=True, text=True)
    data = p.stdout.split("DATA {")[-1].split("}")[0].replace("(0):", "")
    return float(data.split(",")[5]) != 0.0


def restart_case(name, ranks, nstops):
    args = SCENES[name]
    ref = os.path.join(a.workdir, f"{name}_np{ranks}_ref")
    code, out, err = spam(ranks, args, ref)
    if not c.check(code == 0, f"{name} on {ranks} ranks: the uninterrupted run (exit {code}) {err.strip()[:200]}"):
        return []
    sref = summary(ref)
    d = os.path.join(a.workdir, f"{name}_np{ranks}_every")
    code, out, err = spam(ranks, args + ["-checkpoint_interval", 1], d)
    s = summary(d) if code == 0 else {}
    c.check(code == 0 and s.get("checkpoints_written", 0) >= 2 and same_outputs(ref, d) == "",
            f"{name} on {ranks} ranks: a run writing {s.get('checkpoints_written')} checkpoints is the same run: "
            f"{same_outputs(ref, d) if code == 0 else err.strip()[:200] or 'outputs identical'}")
    flags = []
    for k in stops(steps_table(ref), nstops) or [None]:
        if not c.check(k is not None, f"{name} on {ranks} ranks: steps without a pending clamp to stop at"):
            continue
        d = os.path.join(a.workdir, f"{name}_np{ranks}_{k}")
        code, out, err = spam(ranks, args + ["-ts_max_steps", k, "-checkpoint_interval", 1000], d)
        ck = os.path.join(d, "checkpoint.h5")
        if not c.check(code == 0 and os.path.exists(ck), f"{name} on {ranks} ranks: stopped at step {k} with a checkpoint (exit {code}) {err.strip()[:200]}"):
            continue
        flags.append(followed(ck))
        code, out, err = spam(ranks, args + ["-restart", ck], d)
        s = summary(d) if code == 0 else {}
        diff = same_outputs(ref, d) if code == 0 else f"exit {code}: {err.strip()[:300]}"
        c.check(code == 0 and diff == "" and s.get("restart") == "bitwise",
                f"{name} on {ranks} ranks: restart at step {k} (t = {s.get('restart_t', 0):.6g}, migration just before: "
                f"{flags[-1]}) reproduces the uninterrupted run: {diff or 'steps.csv, timeseries.csv, snapshots identical'} "
                f"({s.get('restart', '?')})")
        keys = ("steps", "rejected_steps", "rhs_evals", "migrations", "particles_migrated")
        c.check(code == 0 and all(s[x] == sref[x] for x in keys),
                f"{name} on {ranks} ranks, restart at step {k}: " + ", ".join(f"{x} {s.get(x)}/{sref[x]}" for x in keys))
    return flags


flags = restart_case("expansion2d", 2, 3) + restart_case("expansion2d", 3, 3) + restart_case("couette", 2, 1) + restart_case("convection", 3, 1)
flags += restart_case("expansion2d_rk", 3, 1) + restart_case("expansion2d_verlet", 2, 1) + restart_case("rotor_md", 3, 1)
# The restart after a migration re-made ERKStep's vectors (its next step evaluates f anew,
# counted in rhs_evals, not booked to the restart) must be among the cases.
c.check(any(flags), f"{sum(flags)} of the {len(flags)} stops follow a migration at that very step")

# Another rank count: refused in one line naming both counts.
base = SCENES["expansion2d"]
ck3 = os.path.join(a.workdir, "expansion2d_np3_every", "checkpoint.h5")
serial = base[:base.index("-migrate_interval")] + base[base.index("-migrate_interval") + 2:]  # one rank refuses it
for ranks in (2, 1):
    args = base if ranks > 1 else serial
    code, out, err = spam(ranks, args + ["-restart", ck3], os.path.dirname(ck3))
    lines = errors(err)
    c.check(code == 2 and len(lines) == 1 and "written on 3 ranks and this run has " + str(ranks) in lines[0],
            f"a 3-rank checkpoint restarted on {ranks} rank(s): exit {code}, {lines}")
one = os.path.join(a.workdir, "one_rank")
code, out, err = spam(1, serial + ["-ts_max_steps", 10, "-checkpoint_interval", 1000], one)
code, out, err = spam(2, serial + ["-restart", os.path.join(one, "checkpoint.h5")], one)
lines = errors(err)
c.check(code == 2 and len(lines) == 1 and "written on 1 rank and this run has 2" in lines[0],
        f"a one-rank checkpoint restarted on 2 ranks: exit {code}, {lines}")

# A write failure on a rank other than 0 (its second block) ends every rank, in one line.
for rank in (1, 2):
    d = os.path.join(a.workdir, f"fail_rank{rank}")
    env = dict(ENV, SPAM_TEST_FAIL_WRITE="checkpoint.h5:2", SPAM_TEST_FAIL_RANK=str(rank))
    try:
        code, out, err = spam(3, base + ["-checkpoint_interval", 1], d, env=env)
    except subprocess.TimeoutExpired:
        code, err = "timeout (a rank hung)", ""
    lines = errors(err)
    left = sorted(n for n in os.listdir(d) if n.endswith(".tmp")) if os.path.isdir(d) else ["(no directory)"]
    s = summary(d) if os.path.exists(os.path.join(d, "summary.json")) else {}
    c.check(code == 1 and len(lines) == 1 and f"rank {rank}'s particles" in lines[0] and "No space left" in lines[0]
            and not left and s.get("status") == "failed" and not os.path.exists(os.path.join(d, "checkpoint.h5")),
            f"a checkpoint write failing on rank {rank} of 3: exit {code}, {lines}, temporaries left {left}, status {s.get('status')}")

# One byte of a rank's particles changed: that rank's checksum refuses the file.
d = os.path.join(a.workdir, "expansion2d_np2_every")
ck = os.path.join(d, "checkpoint.h5")
p = subprocess.run(["h5dump", "-m", "%.17g", "-d", "/particles/state", "-s", "37", "-c", "2", "-w", "0", ck], capture_output=True, text=True)
vals = [float(x) for x in p.stdout.split("DATA {")[-1].split("}")[0].replace("(37):", "").split(",")] if "DATA {" in p.stdout else []
raw = bytearray(open(ck, "rb").read())
addr = raw.find(struct.pack("<2d", *vals)) if len(vals) == 2 else -1  # values 37 and 38 of /particles/state
if c.check(addr > 0 and raw.count(struct.pack("<2d", *vals)) == 1, f"values 37-38 of /particles/state found once in the file (at byte {addr})"):
    raw[addr + 3] ^= 0x10  # one bit of value 37, in rank 0's block
    bad = os.path.join(d, "damaged.h5")
    open(bad, "wb").write(bytes(raw))
    code, out, err = spam(2, base + ["-restart", bad], d)
    lines = errors(err)
    c.check(code == 2 and len(lines) == 1 and "rank 0's particles disagree with their checksum" in lines[0],
            f"a checkpoint with one bit of the particles flipped: exit {code}, {lines}")
c.finish()
