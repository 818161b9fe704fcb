#!/usr/bin/python3
"""Conservation under adaptive stepping (Dormand-Prince 5(4), error control).

Energy is conserved by the SPAM equations exactly, so its drift is the integrator's
error: below 1e-6 at rtol 1e-8 and shrinking as rtol tightens. Momentum is conserved
to round-off by every RK method (a linear invariant) since each pair force is exactly
antisymmetric: drift below 1e-12 of the momentum scale sqrt(2 M E)."""
import os
from spamrun import Checks, arguments, run, summary

a = arguments()
c = Checks()
drift = {}
for rtol in (1e-6, 1e-8, 1e-10):
    out = os.path.join(a.workdir, f"rtol{rtol:g}")
    code, _, err = run(a.spam_ark, ["-expansion_n", 16, "-h", 3, "-ts_max_time", 32, "-ts_rtol", rtol,
                                    "-ts_atol", rtol, "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5",
                                    "-snapshot_interval", 0], out)
    c.check(code == 0, f"rtol {rtol:g}: run completes (exit {code}) {err.strip()}")
    s = summary(out)
    drift[rtol] = s["energy_rel_drift_max"]
    c.reading(f"rtol{rtol:g}.energy_drift", s["energy_rel_drift_max"])
    c.reading(f"rtol{rtol:g}.momentum_drift", s["momentum_rel_drift_max"])
    c.check(s["momentum_rel_drift_max"] < 1e-12, f"rtol {rtol:g}: momentum drift {s['momentum_rel_drift_max']:.2e} (< 1e-12)")
    c.check(abs(s["t_final"] - 32) < 1e-9 and s["status"] == "ok", f"rtol {rtol:g}: reached t = {s['t_final']} with status {s['status']}")
c.check(drift[1e-8] < 1e-6, f"rtol 1e-8: energy drift {drift[1e-8]:.2e} (< 1e-6)")
# Error per unit step scales like rtol; allow a factor 3 of slack on the 100x tightening.
c.check(drift[1e-8] < drift[1e-6] / 3 and drift[1e-10] < drift[1e-8] / 3,
        f"tightening rtol shrinks the energy drift: {drift[1e-6]:.2e} -> {drift[1e-8]:.2e} -> {drift[1e-10]:.2e}")
c.finish(a.readings)
