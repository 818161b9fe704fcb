#!/usr/bin/python3
"""Block individual steps (-ts_type block_kdk) on several ranks, under -reproducible and in
the default mode, and their checkpoints.

On several ranks the bins' neighbour walk reads the other ranks' particles through the
halo, every decision of a cycle (top step, next tick, bins, wakes) is agreed over the
ranks, and the pass restricted to the active particles takes the other ranks' particles
as ghost slots. Under -reproducible the right-hand side is the canonical rows' (the same
bits on any rank count) and the walk takes those rows too, each pair from its row's side;
its signal speeds and deepest neighbour bins are maxima, whose bits do not depend on the
order. So a run on 2 ranks must be the one-rank run to the bit: every CSV snapshot
(gathered by gid, 17 significant digits) and steps.csv byte for byte, with the particles
migrating between cycles (-migrate_interval 1: each migration re-makes the TS on the new
vector and carries the rates each particle's next cycle starts from, by id). Asked of
- the 2D Sedov blast (options/sedov.opts at -sedov_n 32, the adaptive kernel range, which
  -reproducible needs for the gas with energy), block_cfl = block_force 0.1, to t = 1
  (2 cycles, deepest bin 8: the bins spread and particles are woken, across the cut);
- the periodic 2D expansion of the isentropic gas (24^2, h 3, gamma 1.7), block_cfl 0.1,
  to t = 20, and the 3D one (8^3, h 2.5) to t = 6;
- the blast with bins by error control (-block_criterion error, rtol = atol 1e-3, bounded
  by -block_cfl 0.25): each particle's controller reads its own estimate, from its own
  data, so its bins are the one-rank run's too.
Each run's energy must be kept: |dE/E| at most 1e-3 (energy_rel_drift_max), the bound the
block steps are asked to meet on the blast (measured: 3.7e-4, 4.0e-4, 1.8e-4).

The default mode (the same blast at fixed h, the restricted pass): see below.

Checkpoints: the Sedov runs on 2 ranks (with their migrations; the error-controlled one
keeps the steps its controllers ask in the checkpoint) stopped after their first cycle
with a checkpoint (-ts_max_steps 1) and restarted must write exactly the files of the
uninterrupted 2-rank run (snapshots, steps.csv, timeseries.csv but for its timing
columns) and say it continued bit for bit; the same in the default mode (the restricted
pass) on one rank and on 2.
Slow (multi-rank starts). --readings FILE: the drifts and differences (docs/block_ranks.json)."""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402
from spamrun import Checks, arguments, mpiexec_env, one_line, rank_command, same_outputs, summary, table  # noqa: E402

a = arguments()
c = Checks()
mpiexec, ENV = mpiexec_env()
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRIFT = 1e-3
ROUNDOFF = 1e-11
FIELDS = ("x", "y", "vx", "vy", "e")
BLOCK = ["-ts_type", "block_kdk", "-block_cfl", 0.1, "-block_force", 0.1]
SEDOV_OPTS = os.path.join(a.workdir, "sedov_no_rtol.opts")  # block_kdk refuses -ts_rtol given
with open(os.path.join(ROOT, "options", "sedov.opts")) as f, open(SEDOV_OPTS, "w") as g:
    g.writelines(ln for ln in f if not ln.startswith("-ts_rtol"))
SEDOV = ["-options_file", SEDOV_OPTS, "-sedov_n", 32, "-ts_max_time", 1, "-output_interval", 0.5, "-snapshot_interval", 0.5] + BLOCK
REPRO = {
    "sedov": SEDOV + ["-smoothing_length", "adaptive", "-reproducible"],
    "expansion": ["-scene", "expansion", "-dim", 2, "-expansion_n", 24, "-h", 3, "-eos_gamma", 1.7, "-expansion_amplitude", 0.1,
                  "-ts_max_time", 20, "-output_interval", 4, "-snapshot_interval", 10, "-reproducible"] + BLOCK,
    "expansion3d": ["-scene", "expansion", "-dim", 3, "-expansion_n", 8, "-h", 2.5, "-expansion_amplitude", 0.1,
                    "-ts_max_time", 6, "-output_interval", 1, "-snapshot_interval", 3, "-reproducible"] + BLOCK,
    # bins by error control: each particle's controller reads its own estimate only
    "sedov_error": SEDOV[:SEDOV.index("-ts_type")] + ["-ts_type", "block_kdk", "-block_criterion", "error", "-block_cfl", 0.25, "-ts_rtol", 1e-3, "-ts_atol", 1e-3,
                                                      "-smoothing_length", "adaptive", "-reproducible"],
}


MIGRATE = {1: [], 2: ["-migrate_interval", 1]}  # a migration at the end of every cycle that built the list


def spam(ranks, args, out):
    cmd, env = rank_command(mpiexec, ENV, ranks, a.spam_ark, list(args) + ["-output_dir", out, "-output_overwrite"])
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    return p.returncode, p.stdout, p.stderr


def snapshots_and_steps(d):
    names = sorted(n for n in os.listdir(d) if n.startswith("particles_") and n.endswith(".csv")) + ["steps.csv"]
    return {n: open(os.path.join(d, n), "rb").read() for n in names}


for name, args in REPRO.items():
    outs = {}
    for ranks in (1, 2):
        out = os.path.join(a.workdir, f"{name}_np{ranks}")
        code, _, err = spam(ranks, args + MIGRATE[ranks], out)
        if c.check(code == 0, f"{name} on {ranks} rank(s) runs (exit {code}) {one_line(err)}"):
            outs[ranks] = out
            drift = summary(out)["energy_rel_drift_max"]
            if ranks == 2:
                moved = summary(out)["migrations"]
                c.check(moved >= 2, f"{name} on 2 ranks: the particles migrate between cycles ({moved} migrations)")
            c.reading(f"{name}.drift_np{ranks}", drift)
            c.check(drift <= DRIFT, f"{name} on {ranks} rank(s): |dE/E| {drift:.3g} <= {DRIFT:g}")
    if len(outs) == 2:
        one, two = snapshots_and_steps(outs[1]), snapshots_and_steps(outs[2])
        differ = [n for n in one if one[n] != two.get(n)]
        c.reading(f"{name}.files_equal", len(one) - len(differ))
        c.check(len(one) > 2 and not differ and one.keys() == two.keys(),
                f"{name}: 2 ranks write the one-rank run's {len(one) - 1} snapshots and steps.csv byte for byte (differ: {differ})")


def counts(stdout):
    """(particle steps, woken, restricted evaluations) from -ts_view."""
    lines = stdout.splitlines()
    line = next(ln for ln in lines if "block cycles" in ln)
    rline = next(ln for ln in lines if "restricted evaluations" in ln)
    return (int(line.split("particle steps")[1].split()[0]), int(line.split("woken")[1].split(")")[0]),
            int(rline.split("restricted evaluations")[1].split()[0]))


def final(path):
    """Each field of a -final_csv file, rows sorted by id."""
    t = {k: np.array(v) for k, v in table(path).items()}
    order = np.argsort(t["id"])
    return {k: v[order] for k, v in t.items()}


# The default mode (fixed h, the pass restricted to the active particles, sums in each
# rank's order: not bitwise) on 2 ranks against one rank and against the whole right-hand
# side at each tick on 2 ranks (-block_restricted 0): the same bins (particle steps and
# woken counts: the bins are decided from rates and signal speeds that differ in round-off
# only, which moves no bin here) and the states within ROUNDOFF of each field's largest
# magnitude (measured at most 4e-13, in the velocities: the blast amplifies round-off;
# one rank's restricted pass against its full pass 3e-14). Without the other ranks'
# marks in the limiter's walk 2 ranks took 53748 particle steps against 53764; without
# the near densities carried to the other ranks' slots the velocities differed by 0.64.
default = {}
for ranks, extra in ((1, []), (2, []), (2, ["-block_restricted", 0])):
    label = f"sedov_default_np{ranks}" + ("_full" if extra else "")
    code, so, err = spam(ranks, SEDOV + ["-ts_view", "-final_csv", os.path.join(a.workdir, label + ".csv")] + MIGRATE[ranks] + extra,
                         os.path.join(a.workdir, label))
    if c.check(code == 0, f"{label} runs (exit {code}) {one_line(err)}"):
        default[label] = (counts(so), final(os.path.join(a.workdir, label + ".csv")))
if len(default) == 3:
    (one, s1), (two, s2), (full, sf) = default["sedov_default_np1"], default["sedov_default_np2"], default["sedov_default_np2_full"]
    c.check(two[2] > 0 and full[2] == 0, f"sedov, default mode: 2 ranks take the restricted pass ({two[2]} restricted evaluations; {full[2]} with -block_restricted 0)")
    c.check(one[:2] == two[:2] == full[:2] and one[1] > 0, f"sedov, default mode: the same particle steps and woken particles on 1 and 2 ranks, restricted and full {one[:2]} {two[:2]} {full[:2]}")
    for name, ref in (("2 ranks' full pass", sf), ("one rank", s1)):
        worst = max(float(np.max(np.abs(s2[k] - ref[k])) / np.max(np.abs(ref[k]))) for k in FIELDS)
        c.reading(f"restricted_np2_vs.{'full_np2' if ref is sf else 'np1'}", worst)
        c.check(worst <= ROUNDOFF, f"sedov, default mode: 2 ranks' restricted pass within {ROUNDOFF:g} of {name} (largest relative difference {worst:.1e})")


def restart(ranks, args, label):
    """Stop after the first cycle with a checkpoint, restart, compare with the whole run."""
    whole = os.path.join(a.workdir, f"{label}_whole")
    part = os.path.join(a.workdir, f"{label}_part")
    if label in ("sedov_np2", "sedov_error_np2", "sedov_default_np1", "sedov_default_np2"):  # the whole run is one above
        whole = os.path.join(a.workdir, label)  # a run above
    else:
        code, _, err = spam(ranks, args, whole)
        if not c.check(code == 0, f"{label}: the whole run (exit {code}) {one_line(err)}"):
            return
    code, _, err = spam(ranks, args + ["-checkpoint_interval", 0.5, "-ts_max_steps", 1], part)
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


restart(2, REPRO["sedov"] + MIGRATE[2], "sedov_np2")
restart(2, REPRO["sedov_error"] + MIGRATE[2], "sedov_error_np2")
restart(1, SEDOV, "sedov_default_np1")
restart(2, SEDOV + MIGRATE[2], "sedov_default_np2")

c.finish(a.readings)
