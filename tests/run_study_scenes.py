#!/usr/bin/python3
"""The study driver on the scenes with an answer (examples/study.py). Plane wave: a
precision study of Dormand-Prince at rtol 1e-4 and 1e-8 adds the columns period,
period_err_spam, period_err_ref and amplitude_decay; the period fitted to KE(t) is within
0.5% of the linearised SPAM period (run_planewave's tolerance at amplitude 0.25, where the
amplitude itself shifts it by -0.11%), and the error against the reference run falls as
the tolerance tightens (a fifth-order pair: by more than 10x for 10^4x in rtol, as in
run_study). Tensile: at sigma0 = 0.02 standard SPAM (R0) grows KE at a fitted rate above
0.02 per unit time and R2 does not (|rate| < 0.01), the bounds of run_tensile; tensile.csv,
tensile.png and the study.md section are written, and a second call reruns nothing."""
import csv
import os
import subprocess
import sys

from spamrun import Checks, arguments

a = arguments()
c = Checks()
here = os.path.dirname(os.path.abspath(__file__))
study = os.path.join(here, "..", "examples", "study.py")
opts = os.path.join(here, "..", "options", "planewave.opts")

out = os.path.join(a.workdir, "planewave")
p = subprocess.run([sys.executable, study, "precision", "--out", out, "--spam-ark", a.spam_ark,
                    "--scene-opts", f"-options_file {opts} -ts_max_time 72", "--t-end", "72",
                    "--method", "DP5=-arkode_table ARKODE_DORMAND_PRINCE_7_4_5", "--tol", "1e-4", "--tol", "1e-8"],
                   capture_output=True, text=True)
c.check(p.returncode == 0, f"plane-wave precision study runs (exit {p.returncode}) {p.stderr.strip()[-300:]}")
with open(os.path.join(out, "precision.csv")) as f:
    rows = {float(r["rtol"]): r for r in csv.DictReader(f)}
c.check(list(rows[1e-4])[-4:] == ["period", "period_err_spam", "period_err_ref", "amplitude_decay"],
        f"precision.csv ends with the wave columns: {list(rows[1e-4])[-4:]}")
for tol, r in rows.items():
    c.check(abs(float(r["period_err_spam"])) < 5e-3, f"rtol {tol:g}: period {float(r['period']):.6f}, "
            f"{float(r['period_err_spam']):+.2e} against linearised SPAM (tolerance 5e-3)")
e4, e8 = abs(float(rows[1e-4]["period_err_ref"])), abs(float(rows[1e-8]["period_err_ref"]))
c.check(e8 < e4 / 10, f"period error against the reference {e4:.2e} at rtol 1e-4 -> {e8:.2e} at 1e-8")
md = open(os.path.join(out, "study.md")).read()
c.check("## Plane wave: period and amplitude" in md and "## Work-precision" in md, "study.md has both sections")

out = os.path.join(a.workdir, "tensile")
cmd = [sys.executable, study, "tensile", "--out", out, "--spam-ark", a.spam_ark, "--sigma0", "0.02",
       "--method", "R0=-coordinates R0", "--method", "R2=-coordinates R2"]
p = subprocess.run(cmd, capture_output=True, text=True)
c.check(p.returncode == 0, f"tensile study runs (exit {p.returncode}) {p.stderr.strip()[-300:]}")
with open(os.path.join(out, "tensile.csv")) as f:
    rate = {r["variant"]: float(r["rate"]) for r in csv.DictReader(f)}
c.check(rate["R0"] > 0.02, f"R0 at sigma0 0.02: KE grows at {rate['R0']:.4f} per unit time (> 0.02)")
c.check(abs(rate["R2"]) < 0.01, f"R2 at sigma0 0.02: rate {rate['R2']:+.4f} (|rate| < 0.01)")
c.check(os.path.getsize(os.path.join(out, "tensile.png")) > 1000 and "## Tensile instability" in open(os.path.join(out, "study.md")).read(),
        "tensile.png and the study.md section written")
p = subprocess.run(cmd, capture_output=True, text=True)
c.check(p.returncode == 0 and p.stdout.count("skipped") == 2, f"second call: {p.stdout.count('skipped')} of 2 runs skipped")
c.finish()
