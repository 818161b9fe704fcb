#!/usr/bin/python3
"""Failure is a result, not a crash; and the optional physical step bound.

1. A fixed step ten times the CFL bound (dt = 9 = 10 x 0.3 h / c0 with h = 3, c0 ~ 1) goes
   unstable for every kind of method: the run ends with exit code 3 (not 0, not the 2 of bad
   input, never a signal), summary.json says "status": "unstable" with a reason naming the
   time and step, and the last good state is kept as a snapshot.
2. With -step_cfl C (or -step_force C'), adaptive steps are capped by C h / c_max (or
   C' sqrt(h/|a|max)); steps.csv says which limit set each step and summary.json counts
   them. In the expansion the density only falls, so c_max <= c_max(0) and every CFL-limited
   step is at least C h / c_max(0).
3. Too many rejections: a first step of 5 (about 1.7 h/c0) at rtol 1e-10 is rejected by
   every adaptive method; -ts_max_reject 1 makes that a failure (exit 3, the method's own
   flag in the reason), while the default (10) lets the controller recover."""
import math
import os
from spamrun import Checks, arguments, manifest, manifest_files, run, summary, table

a = arguments()
c = Checks()
common = ["-expansion_n", 16, "-h", 3, "-diag_entropy", 0]
for name, extra in (("arkode", ["-arkode_fixed_step", 9]),
                    ("rk4", ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_adapt_type", "none", "-ts_dt", 9]),
                    ("verlet", ["-ts_type", "basicsymplectic", "-ts_dt", 9]),
                    ("euler", ["-ts_type", "euler", "-ts_dt", 9]),
                    ("ssp", ["-ts_type", "ssp", "-ts_dt", 9])):
    out = os.path.join(a.workdir, "unstable_" + name)
    code, stdout, err = run(a.spam_ark, common + ["-ts_max_time", 300] + extra, out)
    s = summary(out)
    c.check(code == 3 and s["status"] == "unstable" and " at t = " in s["reason"] and "step" in s["reason"],
            f"{name} at 10x the CFL step: exit {code}, status {s['status']}: {s['reason']}")
    c.check("unstable:" in stdout and manifest_files(out, "snapshot_csv_last_good") and manifest(out)["status"] == "unstable",
            f"{name}: the monitor reports it, the last good state is kept (manifest status unstable)")

# The CFL bound at t = 0: c = sqrt(rho) for gamma = 2, kappa = 1/2, at the largest summed density.
CFL, FORCE, H = 0.05, 0.02, 3.0
out0 = os.path.join(a.workdir, "probe")
run(a.spam_ark, common + ["-ts_max_steps", 0, "-snapshot_interval", 1], out0)
with open(manifest_files(out0, "snapshot_csv")[0]) as f:
    rows = [line.split(",") for line in f if not line.startswith(("#", "x"))]
c0 = math.sqrt(max(float(r[6]) for r in rows))
for method, extra in (("arkode", []), ("rk 5dp", ["-ts_type", "rk", "-ts_rk_type", "5dp"])):
    for limit, opt, value in (("cfl", "-step_cfl", CFL), ("force", "-step_force", FORCE)):
        out = os.path.join(a.workdir, f"{limit}_{method}".replace(" ", "_"))
        code, _, err = run(a.spam_ark, common + extra + [opt, value], out)
        s = summary(out)
        steps = table(os.path.join(out, "steps.csv"))
        limited = [dt for dt, why in zip(steps["dt"], steps["limit"]) if why == limit]
        c.check(code == 0 and s["bound_limited_steps"] == len(limited) > 0,
                f"{method} {opt} {value}: {len(limited)} of {s['steps']} steps set by {limit}, summary counts {s['bound_limited_steps']}")
        if limit == "cfl" and limited:
            c.check(min(limited) >= CFL * H / c0 * (1 - 1e-9),
                    f"{method}: CFL-limited steps >= C h / c_max(0) = {CFL * H / c0:.4f} (smallest {min(limited):.4f})")
code, _, _ = run(a.spam_ark, common + ["-step_cfl", -1], os.path.join(a.workdir, "bad"))
c.check(code == 2, f"-step_cfl -1 is bad input (exit {code})")
for name, extra, flag in (("arkode", [], "ARK_ERR_FAILURE"), ("cvode", ["-ts_type", "cvode"], "CV_"),
                          ("rk 5dp", ["-ts_type", "rk", "-ts_rk_type", "5dp"], "DIVERGED_STEP_REJECTED")):
    for max_reject, want in ((1, 3), (None, 0)):
        out = os.path.join(a.workdir, f"reject_{name.replace(' ', '')}_{max_reject}")
        args = common + ["-ts_max_time", 5, "-output_interval", 0, "-snapshot_interval", 0, "-ts_rtol", 1e-10, "-ts_dt", 5] + extra
        code, _, err = run(a.spam_ark, args + (["-ts_max_reject", max_reject] if max_reject else []), out)
        s = summary(out)
        ok = code == want and (flag in s["reason"] if want else s["status"] == "ok" and s["rejected_steps"] >= 1)
        c.check(ok, f"{name}, -ts_max_reject {max_reject or 'default'}: exit {code}, {s['rejected_steps']} rejected, {s['reason'] or s['status']}")
c.finish()
