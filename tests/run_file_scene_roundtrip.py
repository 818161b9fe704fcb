#!/usr/bin/python3
"""A scene's particles written to a file, and a run's snapshot, read back by the file scene:
1. The rotor (elastic, continuity density, R0, open box) written by -initial_csv with every
   field it carries (x, v, m, e, rho, sxx, sxy, syy) and read back as
   `-scene file -material elastic -density continuity` with the rotor's box and order gives
   the rotor scene's L(t) and energy: the model is the same, so the bound is round-off,
   1e-12 of |L| (measured: equal to the last digit printed).
2. An HDF5 snapshot continues the run: the expansion (isentrope) and the rotor at a fixed
   step (rk 4, dt 0.05) to t = 2 from the straight run's snapshot at t = 2 end where the
   straight run ends at t = 4, to 1e-12 in position and velocity (the restart rebuilds the
   neighbour list, so pair sums are added in another order: round-off, not bitwise).
   An adaptive continuation (arkode) restarts the step-size history, so it agrees only to
   the tolerance: asserted within 100 rtol of the position scale h."""
import math
import os
from spamrun import Checks, arguments, run, summary, table

a = arguments()
c = Checks()
w = a.workdir
FAST = ["-monitor", 0, "-diag_entropy", 0]


def rows(path):
    """Data rows of a particles CSV as {column: float}, comments skipped."""
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f if ln.strip() and not ln.startswith("#")]
    head = lines[0].split(",")
    return [dict(zip(head, map(float, ln.split(",")))) for ln in lines[1:]]


def worst(r1, r2, keys):
    """Largest |difference| over particles and keys."""
    return max(abs(p[k] - q[k]) for p, q in zip(r1, r2) for k in keys) if len(r1) == len(r2) else math.inf


# --- 1. rotor -> file -> rotor ---------------------------------------------------------------
ROTOR = ["-ts_max_time", 20, "-output_interval", 1, "-snapshot_interval", 0] + FAST
da, db = os.path.join(w, "rotor"), os.path.join(w, "rotor_file")
init = os.path.join(w, "rotor.csv")
code, _, err = run(a.spam_ark, ["-scene", "rotor", "-rotor_n", 4, "-initial_csv", init] + ROTOR, da)
c.check(code == 0, f"rotor scene runs and writes its particles {err[:200]}")
head = open(init).readline() if code == 0 else ""
head = head if not head.startswith("#") else [ln for ln in open(init) if not ln.startswith("#")][0]
c.check(all(k in head.strip().split(",") for k in ("x", "y", "vx", "vy", "m", "e", "rho", "sxx", "sxy", "syy")),
        f"the rotor's file holds every field of its state: {head.strip()}")
s = summary(da) if code == 0 else {}
box = ["-box_lo", ",".join(str(v) for v in s.get("box_lo", [0, 0])[:2]), "-box_len", ",".join(str(v) for v in s.get("box_len", [1, 1])[:2]), "-periodic", "false"]
code, _, err = run(a.spam_ark, ["-scene", "file", "-file_path", init, "-material", "elastic", "-density", "continuity", "-sort_particles", "false"] + box + ROTOR, db)
c.check(code == 0, f"the file reads back as an elastic solid with the rotor's box {err[:300]}")
if code == 0:
    ta, tb = table(os.path.join(da, "timeseries.csv")), table(os.path.join(db, "timeseries.csv"))
    lscale = max(abs(v) for v in ta["lz"])
    dl = max(abs(x - y) for x, y in zip(ta["lz"], tb["lz"])) if len(ta["lz"]) == len(tb["lz"]) else math.inf
    de = max(abs(x - y) for x, y in zip(ta["total"], tb["total"])) if len(ta["total"]) == len(tb["total"]) else math.inf
    c.check(len(ta["t"]) == len(tb["t"]) and dl <= 1e-12 * lscale,
            f"L(t) of the file scene equals the rotor scene's: {len(tb['t'])} rows, max |dL| {dl:.3g} (|L| {lscale:.6g}, bound 1e-12 |L|)")
    c.check(de <= 1e-12 * max(abs(v) for v in ta["total"]), f"energy E(t) equal too: max |dE| {de:.3g}")
    c.check(ta["step"][-1] == tb["step"][-1], f"the same steps: {ta['step'][-1]:.0f} and {tb['step'][-1]:.0f}")
    c.reading("rotor_file.steps", int(tb["step"][-1]))


# --- 2. a snapshot continues the run -----------------------------------------------------------
def continued(label, scene_args, method, pos_keys, vel_keys, bound_x, bound_v):
    straight, first, rest = (os.path.join(w, f"{label}_{k}") for k in ("straight", "first", "rest"))
    fin_s, fin_r = straight + ".csv", rest + ".csv"
    common = scene_args + method + FAST + ["-output_interval", 0.5]
    code1, _, e1 = run(a.spam_ark, common + ["-ts_max_time", 4, "-snapshot_interval", 2, "-final_csv", fin_s], straight)
    snap = os.path.join(straight, "snap_00001.h5")
    c.check(code1 == 0 and os.path.exists(snap), f"{label}: straight run to t = 4 with a snapshot at t = 2 {e1[:200]}")
    if code1 != 0 or not os.path.exists(snap):
        return
    extra = ["-sort_particles", "false"] + (["-material", "elastic", "-density", "continuity"] if "rotor" in label else [])
    code2, _, e2 = run(a.spam_ark, ["-scene", "file", "-file_path", snap] + extra + method + FAST + ["-output_interval", 0.5, "-ts_max_time", 2, "-snapshot_interval", 0, "-final_csv", fin_r], rest)
    c.check(code2 == 0, f"{label}: the snapshot at t = 2 reads back as a file scene and runs to t + 2 {e2[:300]}")
    if code2 != 0:
        return
    rs, rr = rows(fin_s), rows(fin_r)
    dx, dv = worst(rs, rr, pos_keys), worst(rs, rr, vel_keys)
    c.check(dx <= bound_x and dv <= bound_v, f"{label}: continued run ends where the straight run does: max |dx| {dx:.3g} (bound {bound_x:g}), |dv| {dv:.3g} (bound {bound_v:g}), {len(rr)} particles")
    c.reading(f"{label}.dx", dx)


RK4 = ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_adapt_type", "none", "-ts_dt", 0.05]
continued("expansion", ["-expansion_n", 12, "-h", 3], RK4, ("x", "y"), ("vx", "vy"), 1e-12, 1e-12)
continued("rotor", ["-scene", "rotor", "-rotor_n", 4], RK4, ("x", "y"), ("vx", "vy"), 1e-12, 1e-12)
continued("expansion_arkode", ["-expansion_n", 12, "-h", 3], ["-ts_type", "arkode", "-ts_rtol", 1e-8], ("x", "y"), ("vx", "vy"), 100 * 1e-8 * 3, 1e-5)
c.finish(a.readings)
