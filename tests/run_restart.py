#!/usr/bin/python3
"""Checkpoint and restart.

A run stopped by -ts_max_steps with checkpoints on (or by SIGTERM) writes checkpoint.h5 at
the step it reached; `-restart` in the same directory must then write exactly the files the
uninterrupted run writes: steps.csv byte for byte, timeseries.csv byte for byte but for its
two timing columns (rhs_s, wall_s), every snapshot (HDF5 and CSV) byte for byte, and the
same summary counters. This is asked of arkode (Dormand-Prince 5(4), Verner 6(5),
Bogacki-Shampine 3(2)), PETSc rk 5dp with the basic adaptor and kick-drift-kick Verlet, at
three interruption points each: an early one, one just after a step with a rejected
attempt, and one just before such a step (the first step of the restarted run is then
rejected). CVODE restarts approximately: its error against a tight reference must stay
within a small factor of the uninterrupted run's. Checkpoints of another version, other
physics options, truncated or corrupt files, and a restart outside the checkpoint's own
directory are refused with exit 2 and one line."""
import os
import signal
import subprocess
import time
from spamrun import Checks, arguments, run, same_outputs, steps_table, summary

a = arguments()
c = Checks()

# The expansion of a 12 x 12 patch (144 particles) with h = 3 into a 24 x 24 box; the
# perturbed lattice gives the controller rejected attempts early on.
BASE = ["-scene", "expansion", "-dim", 2, "-expansion_n", 12, "-h", 3, "-mass", 1, "-eos_gamma", 2, "-eos_kappa", 0.5,
        "-expansion_amplitude", 0.05, "-expansion_seed", 3, "-ts_max_time", 12, "-output_interval", 0.5,
        "-snapshot_interval", 3, "-diag_grid_spacing", 1]
METHODS = {
    "arkode DP5": ["-ts_type", "arkode", "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5", "-ts_rtol", 1e-7, "-ts_atol", 1e-10],
    "arkode V6": ["-ts_type", "arkode", "-arkode_table", "ARKODE_VERNER_8_5_6", "-ts_rtol", 1e-7, "-ts_atol", 1e-10],
    "arkode BS3": ["-ts_type", "arkode", "-arkode_table", "ARKODE_BOGACKI_SHAMPINE_4_2_3", "-ts_rtol", 1e-7, "-ts_atol", 1e-10],
    "rk 5dp": ["-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "basic", "-ts_rtol", 1e-7, "-ts_atol", 1e-10],
    "verlet": ["-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "kdk", "-ts_dt", 0.05],
}










def points(steps):
    """Three interruption steps: early, just after a step with a rejection, just before one;
    a method that rejects nothing (fixed steps): early, middle, late."""
    rej = [k for k in range(1, len(steps)) if int(steps[k]["rejected"]) > int(steps[k - 1]["rejected"])]
    if not rej:
        return [("early", 3), ("middle", len(steps) // 2), ("late", len(steps) - 5)]
    after = next((int(steps[k]["step"]) for k in rej if 3 < k < len(steps) - 3), None)
    before = next((int(steps[k]["step"]) - 1 for k in rej if 4 < k < len(steps) - 3 and int(steps[k]["step"]) - 1 != after), None)
    return [("early", 3), ("after a rejection", after), ("before a rejection", before)]


for name, method in METHODS.items():
    args = BASE + method
    ref = os.path.join(a.workdir, name.replace(" ", "_") + "_ref")
    code, out, err = run(a.spam_ark, args, ref)
    if not c.check(code == 0, f"{name}: the uninterrupted run (exit {code}) {err.strip()[:200]}"):
        continue
    sref = summary(ref)
    steps = steps_table(ref)
    ckd = os.path.join(a.workdir, name.replace(" ", "_") + "_with_checkpoints")
    code, out, err = run(a.spam_ark, args + ["-checkpoint_interval", 2], ckd)
    s = summary(ckd) if code == 0 else {}
    c.check(code == 0 and s.get("checkpoints_written", 0) >= 4 and same_outputs(ref, ckd) == "",
            f"{name}: a run writing {s.get('checkpoints_written')} checkpoints (every 2 time units, "
            f"{s.get('checkpoint_bytes', 0) / 1e3:.0f} kB) is the same run: {same_outputs(ref, ckd) or 'outputs identical'}")
    for label, k in points(steps):
        if not c.check(k is not None, f"{name}: a step {label} exists"):
            continue
        d = os.path.join(a.workdir, f"{name.replace(' ', '_')}_{k}")
        code, out, err = run(a.spam_ark, args + ["-ts_max_steps", k, "-checkpoint_interval", 1000], d)
        ok = code == 0 and os.path.exists(os.path.join(d, "checkpoint.h5"))
        if not c.check(ok, f"{name}: stopped at step {k} ({label}) with a checkpoint (exit {code}) {err.strip()[:200]}"):
            continue
        code, out, err = run(a.spam_ark, args + ["-restart", os.path.join(d, "checkpoint.h5")], d)
        s = summary(d) if code == 0 else {}
        diff = same_outputs(ref, d) if code == 0 else f"exit {code}: {err.strip()[:300]}"
        c.check(code == 0 and diff == "" and s["restart"] == "bitwise",
                f"{name}: restart at step {k} ({label}, t = {s.get('restart_t', 0):.6g}) reproduces the uninterrupted run: "
                f"{diff or 'steps.csv, timeseries.csv, snapshots identical'} ({s.get('restart', '?')})")
        same = code == 0 and all(s[key] == sref[key] for key in ("steps", "rejected_steps", "rhs_evals", "energy_rel_drift_max"))
        c.check(same, f"{name}: restart at step {k}: steps {s.get('steps')}/{sref['steps']}, rejected {s.get('rejected_steps')}/"
                f"{sref['rejected_steps']}, rhs_evals {s.get('rhs_evals')}/{sref['rhs_evals']} (+{s.get('restart_rhs_evals')} "
                f"booked to the restart), energy drift {s.get('energy_rel_drift_max')}/{sref['energy_rel_drift_max']}")

# -checkpoint_wall: a wall-clock period of 1 microsecond asks for one after every step (each
# takes longer): the run is still the same run.
ref = os.path.join(a.workdir, "arkode_DP5_ref")
d = os.path.join(a.workdir, "wall")
code, out, err = run(a.spam_ark, BASE + METHODS["arkode DP5"] + ["-checkpoint_wall", 1e-6], d)
s, sref = summary(d), summary(ref)
c.check(code == 0 and s["checkpoints_written"] >= sref["steps"] - 2 and same_outputs(ref, d) == "",
        f"-checkpoint_wall 1e-6: {s['checkpoints_written']} checkpoints in {s['steps']} steps, outputs "
        f"{same_outputs(ref, d) or 'identical to the run without'}")
c.reading("wall.checkpoints", s["checkpoints_written"])
c.reading("wall.steps", s["steps"])

# SIGTERM in mid-run, then -restart: the straight run's files.
LONG = BASE[:] + METHODS["arkode DP5"]
LONG[LONG.index("-ts_rtol") + 1] = 1e-9
LONG[LONG.index("-ts_max_time") + 1] = 40
ref = os.path.join(a.workdir, "sigterm_ref")
code, _, _ = run(a.spam_ark, LONG, ref)
sref = summary(ref)
d = os.path.join(a.workdir, "sigterm")
p = subprocess.Popen([a.spam_ark] + [str(x) for x in LONG] + ["-output_dir", d], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
deadline, rows = time.time() + 60, 0
while time.time() < deadline and p.poll() is None and rows < 20:
    tmp = [n for n in (os.listdir(d) if os.path.isdir(d) else []) if n.startswith("timeseries.csv.")]
    rows = open(os.path.join(d, tmp[0])).read().count("\n") - 1 if tmp else 0
    time.sleep(0.01)
p.send_signal(signal.SIGTERM)
out, err = p.communicate(timeout=120)
s = summary(d)
c.check(p.returncode == 143 and os.path.exists(os.path.join(d, "checkpoint.h5")) and "checkpoint at t" in out,
        f"SIGTERM after {rows} rows: exit {p.returncode}, interrupted at t = {s['t_final']:.6g} of {s['t_end']:g} with a checkpoint "
        f"({s['checkpoint_bytes'] / 1e3:.0f} kB in {s['checkpoint_write_s'] * 1e3:.1f} ms)")
code, out, err = run(a.spam_ark, LONG + ["-restart", os.path.join(d, "checkpoint.h5")], d)
s = summary(d) if code == 0 else {}
diff = same_outputs(ref, d) if code == 0 else f"exit {code}: {err.strip()[:300]}"
c.check(code == 0 and diff == "" and s["steps"] == sref["steps"] and s["rhs_evals"] == sref["rhs_evals"],
        f"SIGTERM then -restart (from t = {s.get('restart_t', 0):.6g}, step {s.get('restart_step')}): {diff or 'the straight run, file for file'}; "
        f"steps {s.get('steps')}/{sref['steps']}, rhs_evals {s.get('rhs_evals')}/{sref['rhs_evals']}")
c.reading("sigterm.steps", sref["steps"])
c.reading("sigterm.rhs_evals", sref["rhs_evals"])

# A restart may extend the run: to t = 16 from a checkpoint of a run to 12 is the straight
# run to 16 (outputs are interpolated, so the old end clamped no step before it; the first
# step is given, since ERKStep's estimate of it depends on the end time).
longer = BASE + METHODS["arkode DP5"] + ["-ts_dt", 1e-3]
longer16 = longer[:]
longer16[longer16.index("-ts_max_time") + 1] = 16
ref16 = os.path.join(a.workdir, "to16_ref")
run(a.spam_ark, longer16 + ["-output_interval", 0.5, "-snapshot_interval", 3], ref16)
d = os.path.join(a.workdir, "to16")
run(a.spam_ark, longer + ["-ts_max_steps", 20, "-checkpoint_interval", 1000], d)
code, out, err = run(a.spam_ark, longer16 + ["-restart", os.path.join(d, "checkpoint.h5")], d)
diff = same_outputs(ref16, d) if code == 0 else f"exit {code}: {err.strip()[:300]}"
c.check(code == 0 and diff == "", f"a restart with -ts_max_time 16 from a run to 12 is the straight run to 16: {diff or 'identical'}")

# CVODE: approximate. Error against a tight reference (arkode DP5, rtol 1e-11) at t = 12.
CV = BASE + ["-ts_type", "cvode", "-ts_rtol", 1e-6, "-ts_atol", 1e-9]
tight = os.path.join(a.workdir, "cvode_tight")
run(a.spam_ark, BASE + ["-ts_type", "arkode", "-ts_rtol", 1e-11, "-ts_atol", 1e-14, "-final_csv", os.path.join(a.workdir, "tight.csv")], tight)
cvref = os.path.join(a.workdir, "cvode_ref")
run(a.spam_ark, CV + ["-final_csv", os.path.join(a.workdir, "cv_ref.csv")], cvref)
d = os.path.join(a.workdir, "cvode")
run(a.spam_ark, CV + ["-ts_max_steps", 40, "-checkpoint_interval", 1000], d)
code, out, err = run(a.spam_ark, CV + ["-restart", os.path.join(d, "checkpoint.h5"), "-final_csv", os.path.join(a.workdir, "cv_restart.csv")], d)


def positions(path):
    with open(path) as f:
        head = f.readline().strip().split(",")
        ix, iy = head.index("x"), head.index("y")
        return [(float(r.split(",")[ix]), float(r.split(",")[iy])) for r in f if r.strip()]


def max_distance(p, q):
    return max(((x1 - x2) ** 2 + (y1 - y2) ** 2) ** 0.5 for (x1, y1), (x2, y2) in zip(p, q))


if c.check(code == 0, f"cvode restart runs (exit {code}) {err.strip()[:200]}"):
    s = summary(d)
    P = positions(os.path.join(a.workdir, "tight.csv"))
    e_ref = max_distance(P, positions(os.path.join(a.workdir, "cv_ref.csv")))
    e_rst = max_distance(P, positions(os.path.join(a.workdir, "cv_restart.csv")))
    # Both runs hold the local error to rtol; the restart re-enters at order 1 with the old
    # step, so its global error may differ, but by no more than a small factor (3).
    c.check(s["restart"] == "approximate" and "CVODE" in s["restart_why_approximate"] and e_rst <= 3 * e_ref + 1e-9,
            f"cvode: restart {s['restart']} ({s['restart_why_approximate'][:60]}...); largest position error at t = 12 against "
            f"DP5 rtol 1e-11: {e_rst:.3e} restarted, {e_ref:.3e} uninterrupted (bound 3x)")
    c.reading("cvode.error_restarted", e_rst)
    c.reading("cvode.error_uninterrupted", e_ref)

# Refusals: exit 2, one line on stderr naming what differs.
base = BASE + METHODS["arkode DP5"]
d = os.path.join(a.workdir, "refuse")
run(a.spam_ark, base + ["-ts_max_steps", 10, "-checkpoint_interval", 1000], d)
ck = os.path.join(d, "checkpoint.h5")
blob = open(ck, "rb").read()


def refused(label, args, want, path=ck, outdir=d):
    code, out, err = run(a.spam_ark, args + ["-restart", path], outdir)
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    c.check(code == 2 and len(lines) == 1 and want in lines[0], f"refused, {label}: exit {code}: {lines[0] if lines else ''!r}")


changed = base[:]
changed[changed.index("-h") + 1] = 2.5
refused("a changed physics option", changed, "-h")
refused("another method", BASE + METHODS["rk 5dp"], "in the checkpoint and is")
refused("another directory", base, "directory", outdir=os.path.join(a.workdir, "elsewhere"))
for label, data, want in (("a truncated file", blob[: len(blob) // 2], "checkpoint"),
                          ("a text file", b"not a checkpoint\n", "checkpoint"),
                          ("a changed digit in its saved steps.csv", None, "checksum")):
    bad = os.path.join(d, "bad.h5")
    if data is None:
        data = bytearray(blob)
        at = data.find(b"step,t,dt,rejected,rhs_evals,limit\n") + 36  # the first row's step number
        data[at] = ord("7") if data[at] != ord("7") else ord("8")
        data = bytes(data)
    open(bad, "wb").write(data)
    refused(label, base, want, bad)
# another build: SPAM_TEST_VERSION (test only, like SPAM_TEST_FAIL_WRITE) stands in for the
# version of the program that writes the checkpoint
v = os.path.join(a.workdir, "version")
env = dict(os.environ, SPAM_TEST_VERSION="0.0.9")
subprocess.run([a.spam_ark] + [str(x) for x in base + ["-ts_max_steps", 10, "-checkpoint_interval", 1000, "-output_dir", v]], env=env, capture_output=True)
code, out, err = run(a.spam_ark, base + ["-restart", os.path.join(v, "checkpoint.h5")], v)
lines = [ln for ln in err.strip().splitlines() if ln.strip()]
c.check(code == 2 and len(lines) == 1 and "0.0.9" in lines[0], f"refused, another version: exit {code}: {lines[0] if lines else ''!r}")
os.remove(os.path.join(d, "bad.h5"))
code, out, err = run(a.spam_ark, base + ["-restart", ck, "-snapshot_csv", 0, "-monitor"], d)
c.check(code == 0, f"output-only options may change at a restart (-snapshot_csv 0 -monitor): exit {code} {err.strip()[:200]}")
c.finish(a.readings)
