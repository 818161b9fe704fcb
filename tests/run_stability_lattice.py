#!/usr/bin/python3
"""The stability finder of examples/study.py against limits known in closed form. The
periodic harmonic chain (scene chain: 64 equal masses, unit springs, even N) has the
largest frequency w_max = 2 sqrt(k/m) = 2, reached by the zone-boundary mode in which it
starts. On a linear oscillatory problem a one-step method is stable while w_max dt lies
inside its stability region on the imaginary axis: classical RK4 to 2 sqrt(2), the
4-stage SSP RK3 (R = 1 + z + z^2/2 + z^3/6 + z^4/48) to 2 sqrt(sqrt(10) - 2) = 2.156,
kick-drift-kick Verlet to 2. The
bisection's largest stable step must be within 2% of each.

Steps and growth bound. A trial is called unstable when KE exceeds G times the initial
energy within N steps. Just above the limit, w_max dt = y0 (1 + eps), the mode's energy
grows slowly per step: for RK4, |R(iy)|^2 = 1 - y^6/72 + y^8/576 has slope y0^5/36 at
y0 = 2 sqrt 2, so ln |R|^2 = 14.2 eps per step (SSP3: 2.2 eps); for Verlet the eigenvalue
of the step map obeys l + 1/l = 2 - y^2, so |l| = 1 + 2 sqrt(2 eps), much faster. The
trial sees the instability once N times that rate exceeds ln G plus the start-up (the
unstable mode's share of the initial state, here all of it). With N = 500 and G = 2,
RK4 resolves eps = ln 2 / (14.2 x 500) = 1e-4 and SSP3 6e-4, both well under the 2%
asked (and the bisection stops at a relative width of 1e-3). Below the limit no trial
can fail: RK4 and SSP3 damp every mode (|R| < 1), Verlet conserves a modified energy
that bounds KE by the initial energy, so KE stays under G E0 = 2 E0 for any N. G = 2
also keeps the growing mode's amplitude (0.01 sqrt 2) far from where neighbours would
cross, so the chain stays linear. The first step tried (0.3/w_max) is not commensurate
with the limits, so the bisection cannot land on one by chance."""
import csv
import math
import os
import subprocess
import sys

from spamrun import Checks, arguments

a = arguments()
c = Checks()
here = os.path.dirname(os.path.abspath(__file__))
study = os.path.join(here, "..", "examples", "study.py")
out = os.path.join(a.workdir, "stability")
methods = {"RK4": ("-ts_type rk -ts_rk_type 4 -ts_adapt_type none:4", 2 * math.sqrt(2)),
           "SSP3": ("-ts_type ssp -ts_ssp_type rks3 -ts_ssp_nstages 4:4", 2 * math.sqrt(math.sqrt(10) - 2)),
           "Verlet": ("-ts_type basicsymplectic -ts_basicsymplectic_type kdk:1", 2.0)}
cmd = [sys.executable, study, "stability", "--scene", "chain", "--out", out, "--spam-ark", a.spam_ark,
       "--steps", "500", "--growth", "2", "--rel", "1e-3", "--dt-guess", "0.3"]
for label, (opts, _) in methods.items():
    cmd += ["--method", f"{label}={opts}"]
p = subprocess.run(cmd, capture_output=True, text=True)
c.check(p.returncode == 0, f"stability study runs (exit {p.returncode}) {p.stderr.strip()[-300:]}")
with open(os.path.join(out, "stability.csv")) as f:
    rows = {r["method"]: r for r in csv.DictReader(f)}
for label, (_, exact) in methods.items():
    r = rows[label]
    lo, hi = float(r["dt_stable"]) / 0.5, float(r["dt_unstable"]) / 0.5  # in units of 1/w_max = 0.5
    c.check(abs(lo / exact - 1) < 0.02 and abs(hi / exact - 1) < 0.02,
            f"{label}: stable at w_max dt = {lo:.5f}, unstable at {hi:.5f}; closed form {exact:.5f} "
            f"({lo / exact - 1:+.3%}, tolerance 2%)")
    c.reading(f"{label}.stable", lo)
    c.reading(f"{label}.closed_form", exact)
    c.reading(f"{label}.rel_error", lo / exact - 1)
    c.check(abs(float(r["closed_form"]) - exact) < 1e-12, f"{label}: stability.csv carries the closed form {float(r['closed_form']):.6f}")
    stages = {"RK4": 4, "SSP3": 4, "Verlet": 1}[label]
    c.check(int(r["force_evals_per_step"]) == stages, f"{label}: {r['force_evals_per_step']} force evaluations per step measured ({stages})")
c.check(os.path.getsize(os.path.join(out, "stability.png")) > 1000, "stability.png written")
c.finish(a.readings)
