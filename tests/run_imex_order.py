#!/usr/bin/python3
"""The order of -ts_type arkode_imex's additive pairs (with its default stage preconditioner;
tests/run_imex_pc.py compares it with the unpreconditioned solver) on a diffusion-dominated scene with an
exact answer: the temperature mode of the conducting gas at rest (-scene heat-mode, as in
run_heat_mode.py: L = 48 along x, 12 across, h = 3, gamma = 1.4, kappa = 1, e0 = 1e-6, here
eps = 1e-4), whose conduction (the flow scheme's pair Laplacian, -diffusion_form pair) is
the implicit part; the explicit part (the pressure of a gas whose sound is 0.03 of the
conduction rate) carries almost nothing. Run to T = 1/sigma_v = 145.9 (one e-folding of
the mode) with fixed steps T/n.

The mode is a single eigenvector of the linearised equations, so a step multiplies its
amplitude a by the pair's stability function R(h lambda), and the error after T is
T |lambda| C (h lambda)^q: it falls by 2^q when the step halves, q the pair's order (3, 4,
5). The answer is the lattice's linear theory (tests/lattice_modes.py, pair form); that
theory's own rate differs from the runs by 3.2e-8 of a at T whatever the step, tolerance
or eps (measured with ARK548L2SA at T/32, rtol 1e-11 to 1e-13, eps 1e-4 and 1e-5), so the
errors are taken against the finest run, ARK548L2SA at T/16 (error ~4e-11 of a), which is
itself checked against the theory within 1e-7. The steps are the largest at which each
pair is in its asymptotic range and whose errors stay above 100 times the reference's:

measured, |a - a_ref| / a(0), and the order of each halving:
  ARK324L2SA  T/2 9.2e-4, T/4 1.28e-4, T/8 1.70e-5      2.85, 2.91
  ARK436L2SA  T/2 1.9e-5, T/4 1.20e-6, T/8 7.4e-8       4.02, 4.01
  ARK548L2SA  T/1 2.9e-5, T/2 1.06e-6, T/4 3.6e-8       4.78, 4.87
The order of the finer halving must be within 0.2 of q (the next term of the error is one
order higher and, at these steps, moves the observed order by less than 0.15).

The pair form conserves energy pair by pair in each evaluation of either part, so any
combination of stages does: the run's largest relative energy drift is round-off (measured
up to 3.7e-13; bound 1e-11, well below the steps' errors). The Newton tolerance is set by
-ts_rtol 1e-12 (the error weights of e are rtol e0: 1e-8 of the mode's amplitude, times
the Newton coefficient 0.1).

The viscous part and the walls: plane Couette flow (options/couette.opts: eta = 1, walls at
y = 0 and y = 32, the upper at U = 0.1, Re = 3.2) started from rest to t = 20, where the
velocity's pair Laplacian, its work and the walls' books are in the implicit part. Both
methods at -ts_rtol 1e-8 (velocity weights rtol c0, c0 = 1.41; energy weights rtol e)
must agree within the sum of their step errors, (steps) rtol c0 for v and (steps) rtol e0
for e (~55 steps each: 7.8e-7 and 5.5e-7; measured 5.7e-10 and 1.4e-8 with the preconditioner,
unpreconditioned 5.9e-10 and 1.2e-8), and the total
energy with the walls' work booked must drift by less than that bound (measured 7.7e-10,
DP5 1.4e-10)."""
import csv
import math
import os

import numpy as np

from lattice_modes import heat_mode
from spamrun import Checks, arguments, run, summary

L, LY, E0, EPS, GAMMA, KAPPA, H = 48, 12, 1e-6, 1e-4, 1.4, 1.0, 3.0
K = 2 * math.pi / L
T = 1 / ((GAMMA - 1) * KAPPA * K * K)
PAIRS = (("ARK324L2SA", 3, (2, 4, 8)), ("ARK436L2SA", 4, (2, 4, 8)), ("ARK548L2SA", 5, (1, 2, 4)))
REFERENCE = ("ARK548L2SA", 16)
COUETTE_RTOL, COUETTE_C0 = 1e-8, math.sqrt(2.0)
THEORY_TOL, ORDER_TOL, DRIFT_TOL, REF_ERROR_X25 = 1e-7, 0.2, 1e-11, 1e-9


def columns(path, names):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return [np.array([float(r[n]) for r in rows]) for n in names]


def amplitude(a, c, table, n):
    """a(T)/a(0) of one run at the fixed step T/n: e projected on cos(k x_i(0)); None if it failed."""
    name = f"{table}_{n}"
    out = os.path.join(a.workdir, name)
    first, last = os.path.join(out, "initial.csv"), os.path.join(out, "final.csv")
    args = ["-dim", 2, "-scene", "heat-mode", "-heatmode_n", L, "-heatmode_ny", LY, "-h", H, "-gas_gamma", GAMMA,
            "-gas_e0", E0, "-heatmode_eps", EPS, "-conductivity", KAPPA, "-ts_max_time", T, "-ts_type", "arkode_imex",
            "-arkode_imex_table", table, "-arkode_fixed_step", T / n, "-ts_rtol", 1e-12, "-ts_atol", 1e-20,
            "-output_interval", 0, "-initial_csv", first, "-final_csv", last]
    code, _, err = run(a.spam_ark, args, out)
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()[-300:]}"):
        return None
    s = summary(out)
    drift = s["energy_rel_drift_max"]
    c.check(s["diffusion_form"] == "pair" and s["rhs_evals_diffusion"] > 0, f"{name}: the pair form's diffusion solved implicitly ({s['rhs_evals_diffusion']} of {s['rhs_evals_process']} evaluations)")
    c.check(abs(drift) < DRIFT_TOL, f"{name}: energy drift {drift:.1e} (bound {DRIFT_TOL:g})")
    (x0,) = columns(first, ["x"])
    (e,) = columns(last, ["e"])
    return 2 / len(e) * np.sum((e - e.mean()) * np.cos(K * x0)) / (E0 * EPS)


def couette(a, c):
    """Couette from rest to t = 20 with DP5 and arkode_imex: the final state of each, or None."""
    got = {}
    for method in ("arkode", "arkode_imex"):
        out = os.path.join(a.workdir, f"couette_{method}")
        last = os.path.join(out, "final.csv")
        opts = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "couette.opts")
        code, _, err = run(a.spam_ark, ["-options_file", opts, "-ts_type", method, "-ts_rtol", COUETTE_RTOL, "-ts_max_time", 20,
                                        "-output_interval", 0, "-snapshot_interval", 0, "-final_csv", last], out)
        if not c.check(code == 0, f"couette {method}: run completes (exit {code}) {err.strip()[-300:]}"):
            return None
        s = summary(out)
        got[method] = (columns(last, ["vx", "e"]), s["steps"], s["energy_rel_drift_max"])
    return got


a = arguments()
c = Checks()
cou = couette(a, c)
if cou:
    (v0, e0), n0, _ = cou["arkode"]
    (v1, e1), n1, drift = cou["arkode_imex"]
    steps = n0 + n1
    dv, de = np.max(np.abs(v1 - v0)), np.max(np.abs(e1 - e0))
    c.check(dv < steps * COUETTE_RTOL * COUETTE_C0, f"couette: |vx imex - vx dp5| {dv:.1e} within {steps} rtol c0 = {steps * COUETTE_RTOL * COUETTE_C0:.1e}")
    c.check(de < steps * COUETTE_RTOL, f"couette: |e imex - e dp5| {de:.1e} within {steps} rtol e0 = {steps * COUETTE_RTOL:.1e}")
    c.check(abs(drift) < steps * COUETTE_RTOL, f"couette imex: energy drift with the walls' books {drift:.1e} (bound {steps * COUETTE_RTOL:.1e})")
    c.reading("couette.dv", dv)
    c.reading("couette.de", de)
discrete, _, _ = heat_mode(2, L, H, E0, GAMMA, KAPPA, "pair")
ref = amplitude(a, c, *REFERENCE)
if ref is not None:
    gap = ref - discrete(T)
    c.check(abs(gap) < THEORY_TOL, f"reference {REFERENCE[0]} T/{REFERENCE[1]}: a(T) = {ref:.12f}, lattice theory {discrete(T):.12f} (difference {gap:.1e}, bound {THEORY_TOL:g})")
    c.reading("reference_minus_theory", gap)
    for table, q, steps in PAIRS:
        amps = [amplitude(a, c, table, n) for n in steps]
        if any(x is None for x in amps):
            continue
        err = [abs(x - ref) for x in amps]
        orders = [math.log2(e1 / e2) for e1, e2 in zip(err, err[1:])]
        print(f"     {table}: errors " + ", ".join(f"T/{n} {e:.3e}" for n, e in zip(steps, err)) + "; orders " + ", ".join(f"{p:.2f}" for p in orders))
        c.check(abs(orders[-1] - q) < ORDER_TOL, f"{table}: order {orders[-1]:.2f} from T/{steps[-2]} to T/{steps[-1]} (nominal {q}, within {ORDER_TOL})")
        c.check(err[-1] > REF_ERROR_X25, f"{table}: finest error {err[-1]:.1e} above 25 times the reference's own (~4e-11)")
        for n, e in zip(steps, err):
            c.reading(f"{table}.T{n}.error", e)
        c.reading(f"{table}.order", orders[-1])
        c.reading(f"{table}.orders", orders)
c.finish(a.readings)
