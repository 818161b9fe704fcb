#!/usr/bin/python3
"""The study driver (examples/study.py): a 2 x 2 precision study (Dormand-Prince and PETSc
rk 5dp at rtol 1e-4 and 1e-8) on a small expansion writes precision.csv with the documented
columns, five charts and study.md; Dormand-Prince's RMS position error falls as the
tolerance tightens (by more than 10x for 10^4x in rtol: the global error of an adaptive
fifth-order pair falls at least as rtol^(1/4) even with the C^1 kernel); a study whose
runs were partly lost resumes by running only the missing case; and one resumed with another
build of spam-ark reruns every case, and one resumed with other scene options in the same
directory reruns every case too (the run directories are named by method and tolerance
only, so the cache must compare the options)."""
import csv
import os
import shutil
import subprocess
import sys
from spamrun import Checks, arguments

a = arguments()
c = Checks()
here = os.path.dirname(os.path.abspath(__file__))
study = os.path.join(here, "..", "examples", "study.py")
out = os.path.join(a.workdir, "study")
cmd = [sys.executable, study, "precision", "--out", out, "--spam-ark", a.spam_ark,
       "--scene-opts", "-expansion_n 12 -h 3 -ts_max_time 8", "--t-end", "8",
       "--method", "DP5=-arkode_table ARKODE_DORMAND_PRINCE_7_4_5", "--method", "rk5dp=-ts_type rk -ts_rk_type 5dp",
       "--tol", "1e-4", "--tol", "1e-8"]
p = subprocess.run(cmd, capture_output=True, text=True)
c.check(p.returncode == 0, f"study runs (exit {p.returncode}) {p.stderr.strip()[-300:]}")
with open(os.path.join(out, "precision.csv")) as f:
    rows = list(csv.DictReader(f))
cols = ["method", "options", "rtol", "dt", "status", "steps", "rejected", "rhs_evals", "rhs_method", "rhs_interpolant", "wall_s", "rhs_share", "err_x_final",
        "err_v_final", "err_x_max", "err_v_max", "energy_drift", "momentum_drift", "angmom_drift", "angmom_not_conserved", "entropy_diff"]
c.check(len(rows) == 4 and list(rows[0]) == cols, f"precision.csv: {len(rows)} rows, columns {list(rows[0])}")
# The cost plotted is the whole cost: the method's evaluations and the interpolant's.
c.check(all(int(r["rhs_evals"]) == int(r["rhs_method"]) + int(r["rhs_interpolant"]) for r in rows if r["status"] == "ok"),
        "precision.csv: rhs_evals = rhs_method + rhs_interpolant in every row")
# The periodic box does not conserve L: the measure is a change, with spam-ark's reason.
c.check(all(r["angmom_not_conserved"] == "not conserved: periodic box" and float(r["angmom_drift"]) >= 0 for r in rows),
        f"precision.csv: angular momentum a change with its reason {sorted({r['angmom_not_conserved'] for r in rows})}")
dp = {float(r["rtol"]): float(r["err_x_final"]) for r in rows if r["method"] == "DP5"}
c.check(dp[1e-8] < dp[1e-4] / 10, f"Dormand-Prince error {dp[1e-4]:.2e} at rtol 1e-4 -> {dp[1e-8]:.2e} at 1e-8")
for png in ("error_vs_rhs.png", "error_vs_wall.png", "energy_drift_vs_tol.png", "angmom_drift_vs_tol.png",
            "steps_vs_tol.png", "study.md"):
    path = os.path.join(out, png)
    c.check(os.path.exists(path) and os.path.getsize(path) > 1000, f"{png} written ({os.path.getsize(path) if os.path.exists(path) else 0} bytes)")
shutil.rmtree(os.path.join(out, "runs", "rk5dp_1e-08"))
p = subprocess.run(cmd, capture_output=True, text=True)
skipped = p.stdout.count("skipped")
c.check(p.returncode == 0 and skipped == 4 and p.stdout.count("[") == 5,
        f"resumed study: {skipped} of 5 runs skipped (reference + 3), one rerun")
# Other scene options, same labels and tolerances: every run directory's name is reused, but
# the runs are another problem's, so none may be skipped (the reference has a new directory).
scene = cmd.index("--scene-opts") + 1
other_scene = cmd[:scene] + ["-expansion_n 10 -h 3 -ts_max_time 8"] + cmd[scene + 1:]
p = subprocess.run(other_scene, capture_output=True, text=True)
c.check(p.returncode == 0 and p.stdout.count("skipped") == 0 and p.stdout.count("[") == 5,
        f"study resumed with other scene options: {p.stdout.count('skipped')} of 5 runs skipped (none may be)")
# Another build: the same executable with one byte appended (an ELF file ignores trailing
# bytes) has another SHA-1, so every run, the reference too, is stale and made again.
other = os.path.join(a.workdir, "spam-ark-other-build")
shutil.copyfile(a.spam_ark, other)
with open(other, "ab") as f:
    f.write(b"\0")
os.chmod(other, 0o755)
p = subprocess.run(cmd[:cmd.index("--spam-ark") + 1] + [other] + cmd[cmd.index("--spam-ark") + 2:], capture_output=True, text=True)
c.check(p.returncode == 0 and p.stdout.count("skipped") == 0 and p.stdout.count("[") == 5,
        f"study resumed with another build of spam-ark: {p.stdout.count('skipped')} of 5 runs skipped (none may be)")
c.finish()
