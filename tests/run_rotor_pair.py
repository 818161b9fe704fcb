#!/usr/bin/python3
"""Two counter-rotating hexagons (PRE Sec. IX), R2 with T_ij torque scaling, to 120
degrees. Their total angular momentum is zero whatever happens, so global scaling has
nothing to correct: the total stays zero while each body's L decays as in plain SPAM.
Scaling per body keeps each body's L to 1e-9."""
import math
import os

from spamrun import Checks, arguments, run, table

a = arguments()
c = Checks()
for scope in ("global", "body"):
    out = os.path.join(a.workdir, scope)
    code, _, err = run(a.spam_ark, ["-scene", "rotor-pair", "-coordinates", "R2", "-angmom", "Tij", "-angmom_scope", scope,
                                    "-ts_max_time", 160 * math.pi / 3, "-ts_rtol", 1e-10, "-ts_atol", 1e-10,
                                    "-snapshot_interval", 0], out)
    c.check(code == 0, f"{scope}: run completes (exit {code}) {err.strip()}")
    ts = table(os.path.join(out, "timeseries.csv"))
    c.check(ts["bodies"][0] == 2, f"{scope}: two bodies found")
    a0, b0 = ts["l_body0"][0], ts["l_body1"][0]
    c.check(abs(a0 + b0) < 1e-9 * abs(a0), f"{scope}: the bodies counter-rotate (L = {a0:.6g}, {b0:.6g})")
    tot = max(abs(x) for x in ts["lz"]) / abs(a0)
    c.check(tot < 1e-9, f"{scope}: total L stays zero ({tot:.1e} of one body's L)")
    drift = max(max(abs(x / a0 - 1) for x in ts["l_body0"]), max(abs(x / b0 - 1) for x in ts["l_body1"]))
    c.reading(f"{scope}.total_l_max", tot)
    c.reading(f"{scope}.body_l_drift_max", drift)
    if scope == "global":
        c.check(drift > 0.01, f"global: each body's L drifts ({drift:.3%} after 120 degrees)")
    else:
        c.check(drift < 1e-9, f"body: each body's L kept ({drift:.1e} after 120 degrees)")
c.finish(a.readings)
