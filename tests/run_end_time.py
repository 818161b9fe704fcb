#!/usr/bin/python3
"""Output and end times reached to round-off: in options/rotor.opts the
last output time 240 * 2.0943951023931953 is one ulp below t_end = 502.6548245743669, and a
method's step sums to its target only to an ulp or so. Such times are one time: each output
time gets exactly one timeseries row, each snapshot time one snapshot, the last steps.csv
row ends at t_end, and no step is spent closing a gap of round-off (before the fix every run
below ended with a step of 5.7e-14 that repeated the last row, snapshot and steps.csv line).
Checked for the self-stepping ARKODE and CVODE paths and for PETSc's adaptive and
fixed-step RK, on the SPAM rotor and the spring (MD) rotor."""
import math
import os

from spamrun import Checks, arguments, manifest_files, run, table

OPTIONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options")
T_END, OUT, SNAP = 502.6548245743669, 2.0943951023931953, 167.5516081914556  # as in the .opts


def schedule(interval, t_end):
    """Multiples of interval up to t_end, the last one replaced by t_end itself."""
    n = math.ceil(t_end / interval - 1e-9)
    return [k * interval for k in range(n)] + [t_end]


def same_times(a, b, rel):
    return len(a) == len(b) and all(abs(x - y) <= rel * T_END for x, y in zip(a, b))


a = arguments()
c = Checks()
runs = (("rotor.opts", "arkode", []),
        ("rotor.opts", "cvode", ["-ts_type", "cvode"]),
        ("rotor.opts", "rk 5dp", ["-ts_type", "rk", "-ts_rk_type", "5dp"]),
        ("rotor-md.opts", "arkode", []),
        ("rotor-md.opts", "rk 4 fixed", ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_dt", 0.1]))
for opts, method, extra in runs:
    name = f"{opts[:-5]} {method}"
    out = os.path.join(a.workdir, name.replace(" ", "_"))
    code, _, err = run(a.spam_ark, ["-options_file", os.path.join(OPTIONS, opts)] + extra, out)
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()}"):
        continue
    fixed = "-ts_dt" in extra
    # With a fixed step the intervals are rounded up to whole steps (time_loop.c).
    out_i, snap_i = (0.1 * math.ceil(x / 0.1 - 1e-9) for x in (OUT, SNAP)) if fixed else (OUT, SNAP)
    snaps = schedule(snap_i, T_END)
    rows = sorted(set(schedule(out_i, T_END)) | set(snaps))
    rows = [t for i, t in enumerate(rows) if i == 0 or t - rows[i - 1] > 1e-12 * T_END]
    ts = table(os.path.join(out, "timeseries.csv"))["t"]
    # timeseries.csv prints t to 10 significant digits.
    c.check(same_times(ts, rows, 1e-9), f"{name}: {len(ts)} timeseries rows at the {len(rows)} output and snapshot times, "
            f"none repeated (distinct: {len(set(ts))})")
    st = table(os.path.join(out, "steps.csv"))
    c.check(abs(st["t"][-1] - T_END) <= 1e-15 * T_END, f"{name}: last step ends at t = {st['t'][-1]!r} "
            f"(t_end {T_END!r}, difference {st['t'][-1] - T_END:.1e})")
    short = [dt for dt, lim in zip(st["dt"], st["limit"]) if lim in ("output", "end") and dt < 1e-9 * T_END]
    c.check(not short, f"{name}: no step cut to an output time is shorter than 1e-9 t_end (found {short})")
    c.check(len(set(st["t"])) == len(st["t"]), f"{name}: {len(st['t'])} steps.csv rows, each at its own time")
    h5 = manifest_files(out, "snapshot_h5")
    c.check(len(h5) == len(snaps), f"{name}: {len(h5)} snapshots (expected {len(snaps)}: t = 0, "
            + ", ".join(f"{t:.4f}" for t in snaps[1:]) + ")")
c.finish()
