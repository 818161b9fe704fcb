#!/usr/bin/python3
"""-reproducible on one rank: the trajectory does not depend on -threads
or on the particles' local order. (Across rank counts: test_reproducible_np1..3 for the
right-hand side and the norm; end-to-end runs come with the multi-rank program.)

- The 2D expansion (adaptive Dormand-Prince, rtol 1e-6, 2 sound crossings of its start)
  with -threads 1, 2 and 3, the 3D expansion with 1 and 2, cvode and PETSc's rk under its
  basic adaptor with 1 and 2: every snapshot, steps.csv (every step size) and the
  timeseries (but its timing columns) byte for byte the same. Control: the default mode
  with -threads 1 and 2 gives other snapshots (its threads add partial sums).
- A file scene of unequal masses read in its file order and sorted by cells
  (-sort_particles): the same snapshots and steps with -reproducible (each pair sum
  follows the partners' ids, not the local order); the timeseries' step columns the same
  and its particle sums (momenta, energies, entropies: diagnostics summed in local order,
  not part of the trajectory) within 1e-12 of their scale. The default mode differs.
- Reproducible against default at a fixed step (only the order of additions differs):
  final positions within 1e-11 h, as -threads is held to in run_threads.py.
- Refused, one line naming -reproducible (exit 2): the elastic solid, the tensor-path gas,
  the springs, mirror walls, -periodic_images minimum, a periodic edge below twice the list
  range (a particle would need images on both sides); -reproducible false on a solid is
  an option that run does not use.
"""
import os
from spamrun import Checks, arguments, run, table

a = arguments()
c = Checks()
H = 3.0
gas2 = ["-scene", "expansion", "-dim", 2, "-expansion_n", 24, "-h", H, "-eos_gamma", 1.7,
        "-expansion_amplitude", 0.1, "-ts_max_time", 20, "-output_interval", 2, "-snapshot_interval", 5]
gas3 = ["-scene", "expansion", "-dim", 3, "-expansion_n", 8, "-h", 2.5, "-expansion_amplitude", 0.1,
        "-ts_max_time", 8, "-output_interval", 1, "-snapshot_interval", 4]
TIMING = ("rhs_s", "wall_s")


def go(name, args):
    out = os.path.join(a.workdir, name)
    rc, _, err = run(a.spam_ark, args, out)
    c.check(rc == 0, f"{name}: exit {rc} {err.strip()[:200]}")
    return out


def outputs(out):
    """The bytes of every snapshot and of steps.csv, and the timeseries without timing."""
    files = {}
    for f in sorted(os.listdir(out)):
        if f.startswith("particles_") or f == "steps.csv":
            with open(os.path.join(out, f), "rb") as h:
                files[f] = h.read()
    with open(os.path.join(out, "timeseries.csv")) as h:  # as text: nan columns compare equal
        rows = [ln.rstrip("\n").split(",") for ln in h]
    keep = [i for i, k in enumerate(rows[0]) if k not in TIMING]
    files["timeseries (no timing)"] = [[r[i] for i in keep] for r in rows]
    return files


# Columns set by the integrator alone; the others are sums over the particles in their
# local order (momenta, energies, entropies: diagnostics, outside the trajectory).
STEP_COLUMNS = ("t", "step", "rejected", "rhs_evals", "dt", "bound_limited")


def sums_close(x, y):
    """Timeseries x and y (text rows): integrator columns equal, the particle sums within
    1e-12 of their scale (the column's largest value, and sqrt(2 M |E|) for momenta)."""
    head = x[0]
    num = lambda r: [float(v) for v in r]
    X, Y = [num(r) for r in x[1:]], [num(r) for r in y[1:]]
    if head != y[0] or len(X) != len(Y):
        return False
    pscale = max((2 * r[head.index("mass")] * abs(r[head.index("total")])) ** 0.5 for r in X)
    for k, name in enumerate(head):
        col, other = [r[k] for r in X], [r[k] for r in Y]
        if name in STEP_COLUMNS:
            if col != other:
                return False
            continue
        scale = max([abs(v) for v in col if v == v] + [pscale, 1e-300])
        if any(not (abs(p - q) <= 1e-12 * scale) for p, q in zip(col, other) if p == p or q == q):
            return False
    return True


def same(name, x, y, sums_in_order=False):
    key = "timeseries (no timing)"
    differ = [k for k in x if x[k] != y.get(k) and not (sums_in_order and k == key and sums_close(x[k], y[k]))]
    c.check(x.keys() == y.keys() and not differ and len(x) > 2,
            f"{name}: {len(x)} outputs compared, differing: {differ[:4] or 'none'}")


# Threads.
for label, base, counts in (("2D expansion, arkode", gas2, (1, 2, 3)), ("3D expansion, arkode", gas3, (1, 2)),
                            ("2D expansion, cvode", gas2 + ["-ts_type", "cvode"], (1, 2)),
                            ("2D expansion, rk 5dp + basic adaptor", gas2 + ["-ts_type", "rk", "-ts_rk_type", "5dp"], (1, 2))):
    tag = label.replace(" ", "_").replace(",", "").replace("+", "")
    ref = outputs(go(f"{tag}_t{counts[0]}", base + ["-reproducible", "-threads", counts[0]]))
    for t in counts[1:]:
        same(f"{label}, -reproducible: -threads {t} against 1", outputs(go(f"{tag}_t{t}", base + ["-reproducible", "-threads", t])), ref)
d1 = outputs(go("default_t1", gas2 + ["-threads", 1]))
d2 = outputs(go("default_t2", gas2 + ["-threads", 2]))
c.check(any(d1[k] != d2[k] for k in d1), "control: the default mode with -threads 2 writes other snapshots than with 1")

# Local order: a file scene (unequal masses) in file order and sorted by cells.
src = os.path.join(a.workdir, "gas.csv")
rc, _, err = run(a.spam_ark, gas2 + ["-ts_max_time", 0, "-final_csv", src], os.path.join(a.workdir, "make_file"))
c.check(rc == 0, f"writing the file scene: exit {rc} {err.strip()[:200]}")
with open(src) as f:
    lines = [ln for ln in f if ln.strip() and not ln.startswith("#")]
head = lines[0].strip().split(",")
im, iid = head.index("m"), head.index("id")
with open(src, "w") as f:  # masses 1 .. 1.25 by id, the rows reversed (ids stay)
    f.write(lines[0])
    for ln in reversed(lines[1:]):
        v = ln.strip().split(",")
        v[im] = repr(1.0 + 0.25 * ((int(v[iid]) * 7919) % 101) / 100.0)
        f.write(",".join(v) + "\n")
filescene = ["-scene", "file", "-file_path", src, "-box_len", 48, "-h", H, "-eos_gamma", 1.7,
             "-ts_max_time", 10, "-output_interval", 2, "-snapshot_interval", 5]
r_sorted = outputs(go("file_sorted", filescene + ["-reproducible", "-sort_particles", "true"]))
r_plain = outputs(go("file_plain", filescene + ["-reproducible", "-sort_particles", "false"]))
same("file scene, unequal masses, -reproducible: sorted by cells against file order (timeseries sums to 1e-12)", r_sorted, r_plain, True)
f_sorted = outputs(go("file_sorted_default", filescene + ["-sort_particles", "true"]))
f_plain = outputs(go("file_plain_default", filescene + ["-sort_particles", "false"]))
c.check(any(f_sorted[k] != f_plain[k] for k in f_sorted), "control: the default mode writes other snapshots for the two orders")

# Against the default mode at a fixed step: only the order of the additions differs.
fixed = ["-scene", "expansion", "-dim", 2, "-expansion_n", 32, "-h", H, "-eos_gamma", 1.4, "-expansion_amplitude", 0.2,
         "-ts_max_time", 10, "-arkode_fixed_step", 0.05, "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0]
fin = {}
for mode in ("default", "reproducible"):
    path = os.path.join(a.workdir, f"fixed_{mode}.csv")
    go(f"fixed_{mode}", fixed + ["-final_csv", path] + (["-reproducible"] if mode == "reproducible" else []))
    fin[mode] = table(path)
dev = max(abs(p - q) for col in ("x", "y") for p, q in zip(fin["default"][col], fin["reproducible"][col]))
c.check(len(fin["default"]["x"]) == 1024 and dev < 1e-11 * H,
        f"fixed step 0.05 to t = 10: reproducible against default, largest position difference {dev:.3e} (bound 1e-11 h)")

# Refusals.
opts = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options")
for label, args, word in (
        ("elastic solid", ["-options_file", os.path.join(opts, "planewave.opts"), "-reproducible"], "elastic"),
        ("tensor-path gas", gas2 + ["-material", "gas", "-reproducible"], "gas"),
        ("springs", ["-scene", "chain", "-dim", 1, "-reproducible"], "spring"),
        ("mirror wall", gas2 + ["-wall_ylo", "noslip", "-reproducible"], "wall"),
        ("minimum image", gas2 + ["-periodic_images", "minimum", "-reproducible"], "ghost"),
        ("periodic edge 6 below 2 (h + skin) = 6.6", ["-expansion_n", 3, "-h", 3, "-reproducible"], "twice the list range")):
    rc, _, err = run(a.spam_ark, args, os.path.join(a.workdir, "refused"))
    lines = err.strip().splitlines()
    c.check(rc == 2 and len(lines) == 1 and "-reproducible" in lines[0] and word in lines[0],
            f"{label}: exit {rc}, {len(lines)} line(s): {lines[0][:160] if lines else ''}")
rc, _, err = run(a.spam_ark, ["-options_file", os.path.join(opts, "planewave.opts"), "-reproducible", "false"], os.path.join(a.workdir, "refused"))
c.check(rc == 2 and "-reproducible" in err and "isentrope" in err, f"-reproducible false on the elastic solid: exit {rc}: {err.strip()[:160]}")
c.finish()
