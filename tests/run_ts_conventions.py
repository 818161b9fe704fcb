#!/usr/bin/python3
"""The arkode and cvode TS types follow PETSc's and SUNDIALS' conventions.

- Their options are read by their own setfromoptions and -help lists them with defaults
  (both types', whichever is chosen).
- -ts_monitor, -ts_view and -ts_adapt_monitor report every step of every type (the loop
  steps the TS itself, so it calls TSMonitor and TSView as TSSolve would).
- -ts_adapt_type none with -ts_dt fixes arkode's step (the same run as -arkode_fixed_step);
  another adaptor is refused for arkode, any for cvode (one line, exit 2).
- -ts_init_time other than 0 is refused in one line for every type.
- -sundials_stats prints ARKODE's / CVODE's own statistics table, whose step count is the
  run's; -ts_view shows it too; other types refuse the option.
"""
import math
import os
import re
from spamrun import Checks, arguments, run, summary, table

a = arguments()
c = Checks()
BASE = ["-expansion_n", 8, "-h", 3, "-ts_max_time", 2, "-snapshot_interval", 0, "-output_interval", 0.5]
TYPES = {"arkode": [], "cvode": ["-ts_type", "cvode"], "rk": ["-ts_type", "rk"],
         "basicsymplectic": ["-ts_type", "basicsymplectic", "-ts_dt", 0.05]}
n = 0


def go(args):
    global n
    n += 1
    out = os.path.join(a.workdir, f"r{n}")
    code, stdout, err = run(a.spam_ark, BASE + args, out)
    return code, stdout, err, out


def refused(args, option, what):
    code, _, err, _ = go(args)
    lines = err.strip().splitlines()
    c.check(code == 2 and len(lines) == 1 and option in lines[0], f"{what}: exit {code}, one line naming {option}: {err.strip()}")


def stat(text, name):
    """A number of SUNDIALS' statistics table (SUN_OUTPUTFORMAT_TABLE: 'Name   = value')."""
    m = re.search(r"^" + re.escape(name) + r"\s+= (\S+)", text, re.M)
    return float(m.group(1)) if m else None


# -help: every option of both SUNDIALS types, with its default, whichever type is chosen.
for extra in ([], ["-ts_type", "cvode"], ["-ts_type", "rk"]):
    code, out, _ = run(a.spam_ark, ["-help"] + extra)
    want = ["-arkode_table", "-arkode_adapt", "-arkode_fixed_step", "-arkode_safety", "-cvode_max_order", "-sundials_stats",
            "-output_stop"]
    missing = [o for o in want if not re.search(r"^\s*" + re.escape(o) + r"  .*\[default [^]]+\]$", out, re.M)]
    c.check(code == 0 and not missing, f"-help {' '.join(extra)}: lists {want} with defaults (missing {missing})")

for name, extra in TYPES.items():
    code, out, err, d = go(extra + ["-ts_monitor", "-ts_view", "-ts_adapt_monitor"])
    if not c.check(code == 0, f"{name}: -ts_monitor -ts_view run exits 0 {err.strip()}"):
        continue
    s = summary(d)
    mon = re.findall(r"^\s*(\d+) TS dt \S+ time (\S+)", out, re.M)
    c.check(len(mon) == s["steps"] + 1 and int(mon[-1][0]) == s["steps"] and math.isclose(float(mon[-1][1]), 2.0),
            f"{name}: -ts_monitor prints step 0 and each of the {s['steps']} steps ({len(mon)} lines, last at t = {mon[-1][1] if mon else '-'})")
    c.check(re.search(r"^TS Object:", out, re.M) is not None and re.search(r"^\s+type: " + name, out, re.M) is not None,
            f"{name}: -ts_view shows the TS of type {name}")
    adapt = re.findall(r"^\s+TSAdapt .*step\s+\d+ accepted", out, re.M)
    c.check(len(adapt) >= s["steps"], f"{name}: -ts_adapt_monitor reports the {s['steps']} accepted steps ({len(adapt)} lines)")
    if name in ("arkode", "cvode"):
        c.check(stat(out, "Steps") == s["steps"], f"{name}: -ts_view shows SUNDIALS' table, Steps = {stat(out, 'Steps')} "
                f"(the run: {s['steps']})")

# -sundials_stats: SUNDIALS' own table at the end; its counts are the run's.
for name in ("arkode", "cvode"):
    code, out, err, d = go(TYPES[name] + ["-sundials_stats"])
    if not c.check(code == 0, f"{name}: -sundials_stats exits 0 {err.strip()}"):
        continue
    s = summary(d)
    steps, nfe = stat(out, "Steps"), stat(out, "RHS fn evals")
    c.check(steps == s["steps"] and nfe == s["rhs_evals"] + s["interpolation_rhs_evals"],
            f"{name}: the table's Steps {steps} and RHS fn evals {nfe} are the run's ({s['steps']}; {s['rhs_evals']} "
            f"+ {s['interpolation_rhs_evals']} by the interpolant)")
    code, out, _, _ = go(TYPES[name])
    c.check(code == 0 and stat(out, "Steps") is None, f"{name}: without -sundials_stats no table")
refused(TYPES["rk"] + ["-sundials_stats"], "-sundials_stats", "rk -sundials_stats")

# -ts_adapt_type none -ts_dt: arkode takes the fixed step, as -arkode_fixed_step does.
code, _, err, d1 = go(["-ts_adapt_type", "none", "-ts_dt", 0.05])
code2, _, err2, d2 = go(["-arkode_fixed_step", 0.05])
if c.check(code == 0 and code2 == 0, f"arkode fixed step both ways exits 0 {err.strip()} {err2.strip()}"):
    s1, s2, st = summary(d1), summary(d2), table(os.path.join(d1, "steps.csv"))
    c.check(s1["steps"] == round(2 / 0.05) and set(st["limit"]) == {"fixed"} and max(abs(x - 0.05) for x in st["dt"]) < 1e-12,
            f"arkode -ts_adapt_type none -ts_dt 0.05: {s1['steps']} steps of 0.05, limits {set(st['limit'])}")
    c.check(s1["steps"] == s2["steps"] and s1["energy_final"] == s2["energy_final"],
            f"the same run as -arkode_fixed_step 0.05 (final energy {s1['energy_final']!r} and {s2['energy_final']!r})")
refused(["-ts_adapt_type", "basic"], "-ts_adapt_type", "arkode -ts_adapt_type basic")
refused(["-ts_adapt_type", "none"], "-ts_adapt_type", "arkode -ts_adapt_type none without -ts_dt")
refused(TYPES["cvode"] + ["-ts_adapt_type", "none", "-ts_dt", 0.1], "-ts_adapt_type", "cvode -ts_adapt_type none")

# -ts_init_time: refused in one line for every type (0 passes).
for name, extra in TYPES.items():
    refused(extra + ["-ts_init_time", 1], "-ts_init_time", f"{name} -ts_init_time 1")
code, _, err, _ = go(["-ts_init_time", 0])
c.check(code == 0, f"-ts_init_time 0 runs {err.strip()}")
c.finish()
