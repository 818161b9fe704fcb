#!/usr/bin/python3
"""Short multi-rank runs of every kind of model and output, fast enough for the
sanitizer build (tools/sanitize.sh runs the fast tests under AddressSanitizer and UBSan), so
that the program itself, not only the MPI unit tests, runs on several ranks there: a leak
on ranks other than 0 with snapshots was found this way, by hand.

On 2 and 3 ranks, each with a migration after every list build where the model migrates:
(a) the 2D expansion with every output (HDF5 and CSV snapshots, grid fields, the final
    particles): exit 0, the final CSV holds every id once, the summary counts every
    particle and the snapshots the manifest lists exist;
(b) the Couette flow (mirror walls with their books, the tensor path) and the chain of
    springs (bonds across ranks; its file's Verlet steps): exit 0, the energy at the last row
    within 1e-11 relative of the one-rank run's (fixed steps; run_ranks derives the bound);
(c) no sanitizer report (spamrun's check, and the exit code 86 it would set);
(d) summary.json's list updates and ghost placements per RHS evaluation (on several ranks
    the placement is the halo's exchange of positions) exactly 1 for the gas (the
    expansion of (a) on 2 and 3 ranks) and for the tensor path (the Couette flow on 1, 2 and 3
    ranks, whose mirror walls give ghost slots on one rank too): a pass that updates the
    list again or exchanges the positions twice makes it 2.
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from spamrun import Checks, arguments, manifest_files, mpiexec_env, rank_command, summary, table  # noqa: E402

a = arguments()
c = Checks()
mpiexec, ENV = mpiexec_env()
OPTS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "options")


def spam(ranks, name, args):
    out = os.path.join(a.workdir, f"{name}_np{ranks}")
    cmd, env = rank_command(mpiexec, ENV, ranks, a.spam_ark, list(args) + ["-output_dir", out])  # one rank: a singleton
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    if any(s in p.stderr for s in ("ERROR: AddressSanitizer", "LeakSanitizer", "runtime error:")):
        c.check(False, f"{name} on {ranks} ranks: sanitizer report:\n{p.stderr[-3000:]}")
    return p.returncode, p.stderr, out


def check_passes(what, s):
    c.check(s["rhs_evals_process"] > 0 and s["list_updates_per_rhs"] == 1 and s["ghost_placements_per_rhs"] == 1,
            f"{what}: {s['list_updates_per_rhs']} list updates and {s['ghost_placements_per_rhs']} ghost placements per RHS "
            f"over {s['rhs_evals_process']} evaluations (1 and 1)")


# (a) every output
expansion = ["-scene", "expansion", "-dim", 2, "-expansion_n", 16, "-h", 3, "-eos_gamma", 2, "-eos_kappa", 0.5,
             "-expansion_amplitude", 0.01, "-expansion_seed", 1, "-ts_max_time", 3, "-output_interval", 1,
             "-snapshot_interval", 1, "-snapshot_csv", "-diag_grid_spacing", 2, "-grid_interval", 1, "-migrate_interval", 1]
for ranks in (2, 3):
    final = os.path.join(a.workdir, f"final_np{ranks}.csv")
    code, err, out = spam(ranks, "outputs", expansion + ["-final_csv", final])
    if not c.check(code == 0, f"expansion with every output on {ranks} ranks: exit {code} {err.strip()[-300:]}"):
        continue
    ids = sorted(int(v) for v in table(final)["id"])
    s = summary(out)
    snaps = manifest_files(out, "snapshot_h5") + manifest_files(out, "snapshot_csv")
    c.check(ids == list(range(256)) and s["n_particles"] == 256 and s["migrations"] > 0,
            f"{ranks} ranks: final ids 0..255 once each ({len(ids)} rows), {s['n_particles']} particles, {s['migrations']} migrations")
    # -snapshot_interval 1 to t = 3: t = 0, 1, 2, 3, each as HDF5 and as CSV
    c.check(len(snaps) == 8 and all(os.path.getsize(f) > 0 for f in snaps), f"{ranks} ranks: {len(snaps)} snapshots listed and written (8 due)")
    check_passes(f"expansion on {ranks} ranks", s)

# (b) walls with books (migrating on several ranks; -migrate_interval is refused on one),
#     springs (which never migrate)
for name, args in (("couette", ["-options_file", os.path.join(OPTS, "couette.opts"), "-ts_max_time", 16, "-output_interval", 8,
                                "-arkode_fixed_step", 1, "-snapshot_interval", 8]),
                   ("chain", ["-options_file", os.path.join(OPTS, "chain.opts"), "-ts_max_steps", 40, "-snapshot_interval", 0])):
    runs = {}
    for ranks in (1, 2, 3):
        code, err, out = spam(ranks, name, args + (["-migrate_interval", 1] if ranks > 1 and name == "couette" else []))
        if c.check(code == 0, f"{name} on {ranks} ranks: exit {code} {err.strip()[-300:]}"):
            runs[ranks] = table(os.path.join(out, "timeseries.csv"))["total"]
            if name == "couette":
                check_passes(f"couette on {ranks} ranks", summary(out))
    for ranks in (2, 3):
        if 1 in runs and ranks in runs:
            d = abs(runs[ranks][-1] - runs[1][-1]) / abs(runs[1][-1])
            c.check(d <= 1e-11, f"{name}: total energy on {ranks} ranks within {d:.1e} of one rank's (bound 1e-11)")
c.finish()
