#!/usr/bin/python3
"""Kernel smoothness at r = h against the order a fixed-step Runge-Kutta method attains.

    study_orders.py [--out DIR] [--spam-ark PATH] [--kernel K ...] [--method M ...] [--scene S ...]

For every kernel x method x scene, a series of fixed steps (STEPS: halving, or by about
sqrt(2) for V6 and F8) runs to t = 8 and its
RMS position error at t = 8 (minimum image) is measured against a reference of the same
kernel and scene; the order is the least-squares slope of log error against log dt over the
asymptotic range (the smallest steps whose error stands clear of the reference's own error,
within a factor 3 in dt; see fit_order). Two scenes:

  expansion  the 2D expansion, 16 x 16 particles, h = 3: pairs cross r = h all the time;
  lattice    the periodic 16 x 16 square lattice of tests/run_order.py with small random
             velocities (0.003), h = 2.91 between the lattice distances sqrt(8) and 3:
             no pair reaches r = h (nor a spline's inner joint; the study measures how
             close any pair comes from snapshots of the reference run).

A pair crossing r = h sees a force whose m-th time derivative jumps when the kernel is C^m
there (w^(m+1) jumps; docs/kernels.md): a step that holds the crossing makes a local error
O(dt^(m+1)), and a run holds a fixed number of crossings however small dt is, so the global
error falls as dt^min(p, m+1) instead of dt^p. The study compares that with what it measures.

Methods: RK4 (PETSc rk 4: ARKODE 6.4.1 has no classical 4th-order table), ARKODE
Dormand-Prince 5(4), Verner 6(5) and Fehlberg 8(7) with -arkode_fixed_step. The reference is
ARKODE Dormand-Prince at rtol 1e-14 (its step controller shrinks the steps that hold a
crossing), checked against PETSc rk 8vr at rtol 1e-14: their difference is the reference's
error floor, and an error within 10 times that floor is left out of the fit.

Writes DIR/orders.csv (every run), DIR/orders.png (measured order against the kernel's
smoothness at r = h), DIR/wp_kernels.png (error against RHS evaluations, a panel per kernel)
and the section <!-- orders --> of DIR/study.md (table, readings and command).
Runs go to DIR/orders_runs/<scene>/<kernel>/<method>_<N>steps/ (and reference/, check/); a
finished run of the same options (args.txt) is not run again, so a rerun redraws at once.
The whole study (300 runs of 256 particles, about 1 s each, most of it the start of MPI)
takes about 5 minutes on one core.
"""
import argparse
import csv
import json
import math
import os
import random
import re
import subprocess
import sys
import time

try:
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    if os.path.realpath(sys.executable) != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("study_orders.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KERNELS = ["lucy", "cubic_spline", "wendland_c2", "quintic_spline", "wendland_c4", "wendland_c6"]
# Inner joints of the piecewise kernels (s = r/h), where they are as smooth as at r = h.
JOINTS = {"cubic_spline": [0.5], "quintic_spline": [1 / 3, 2 / 3]}
END_TIME = 8.0
COMMON = ["-dim", 2, "-ts_max_time", END_TIME, "-diag_entropy", 0, "-output_interval", 0]


def arkode(table):
    return lambda dt: ["-arkode_table", table, "-arkode_fixed_step", "%.17g" % dt]


# label, nominal order, options for a fixed step dt. One colour and marker per method.
METHODS = [("RK4", 4, lambda dt: ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_adapt_type", "none", "-ts_dt", "%.17g" % dt]),
           ("DP5", 5, arkode("ARKODE_DORMAND_PRINCE_7_4_5")),
           ("V6", 6, arkode("ARKODE_VERNER_8_5_6")),
           ("F8", 8, arkode("ARKODE_FEHLBERG_13_7_8"))]
STYLE = {"RK4": ("tab:blue", "o"), "DP5": ("tab:orange", "s"), "V6": ("tab:green", "^"), "F8": ("tab:purple", "D")}
# Measured on the Lucy expansion: DP5 at rtol 1e-13 is 1.4e-10 from DP5 at 1e-14, which agrees
# with rk 8vr at 1e-14 to 2.0e-11.
REFERENCE = ["-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5", "-ts_rtol", "1e-14", "-ts_atol", "1e-16"]
CHECK = ["-ts_type", "rk", "-ts_rk_type", "8vr", "-ts_rtol", "1e-14", "-ts_atol", "1e-16"]
FLOOR_FACTOR = 10.0   # errors within this factor of the reference's error are not fitted
FIT_SPAN = 3.0        # the asymptotic range: usable steps within this factor of the smallest usable one
FIT_POINTS = 3        # and at least this many of them


def lattice_file(path):
    """The lattice of tests/run_order.py: 16 x 16 unit spacing, velocities +-0.003 (seed 5)."""
    rng = random.Random(5)
    with open(path + ".tmp", "w") as f:
        f.write("x,y,vx,vy\n")
        for j in range(16):
            for i in range(16):
                f.write(f"{i + 0.5},{j + 0.5},{rng.uniform(-0.003, 0.003)!r},{rng.uniform(-0.003, 0.003)!r}\n")
    os.replace(path + ".tmp", path)


def scenes(runs):
    """name -> (options, box edge). The lattice file is written once into runs/."""
    lattice = os.path.join(runs, "lattice.csv")
    if not os.path.exists(lattice):
        lattice_file(lattice)
    return {"expansion": (["-scene", "expansion", "-expansion_n", 16, "-h", 3], 32.0),
            "lattice": (["-scene", "file", "-file_path", lattice, "-box_len", "16,16", "-h", 2.91], 16.0)}


# Steps to t = 8 of each series, per scene and method: each series spans the errors between
# the method's stability or pre-asymptotic end and the reference's floor, with steps about
# sqrt(2) apart where a high-order method crosses that window in a few halvings. On the
# expansion RK4 and DP5 run dt = 0.2 ... 0.0125 (an earlier ladder, 0.2 ... 0.025, and one more).
STEPS = {("expansion", "RK4"): [40, 80, 160, 320, 640], ("expansion", "DP5"): [40, 80, 160, 320, 640],
         ("expansion", "V6"): [20, 28, 40, 56, 80, 160, 320], ("expansion", "F8"): [10, 14, 20, 28, 40, 80, 160],
         ("lattice", "RK4"): [8, 16, 32, 64, 128], ("lattice", "DP5"): [8, 16, 32, 64, 128],
         ("lattice", "V6"): [8, 12, 16, 24, 32, 64], ("lattice", "F8"): [6, 8, 12, 16, 24, 32]}


def smoothness(kernel, dim=2):
    """Derivatives of w continuous at r = h, as src/kernels/kernel_<name>.h declares it (and
    tests/test_kernel.c measures it): '.smooth = dim == 1 ? A : B,' or '.smooth = A,'."""
    src = open(os.path.join(REPO, "src", "kernels", f"kernel_{kernel}.h")).read()
    m = re.search(r"\.smooth\s*=\s*(?:dim\s*==\s*1\s*\?\s*(\d+)\s*:\s*)?(\d+)\s*[,;}]", src)
    if not m:
        sys.exit(f"cannot read the smoothness of {kernel} from src/kernels/kernel_{kernel}.h")
    return int(m.group(1)) if dim == 1 and m.group(1) else int(m.group(2))


def spam(binary, args, outdir, counts):
    """Runs spam-ark into outdir unless a finished run of the same options is there; returns
    its summary.json and counts the run in counts["ran"] or counts["cached"]."""
    summ, argf = os.path.join(outdir, "summary.json"), os.path.join(outdir, "args.txt")
    line = " ".join(map(str, args)) + "\n"
    if os.path.exists(summ) and os.path.exists(os.path.join(outdir, "final.csv")) and os.path.exists(argf) \
            and open(argf).read() == line:
        s = json.load(open(summ))
        if s.get("status") in ("ok", "unstable") and spam_manifest.same_build(s, binary):
            counts["cached"] += 1
            return s
    counts["ran"] += 1
    os.makedirs(outdir, exist_ok=True)
    p = subprocess.run([binary] + [str(a) for a in args] + ["-final_csv", os.path.join(outdir, "final.csv"),
                                                            "-output_dir", outdir, "-output_overwrite"],
                       capture_output=True, text=True)
    if p.returncode not in (0, 3):
        sys.exit(f"spam-ark failed (exit {p.returncode}): {' '.join(map(str, args))}\n{p.stderr.strip()}")
    with open(argf, "w") as f:   # the options that made this run: other options run it again
        f.write(line)
    spam_manifest.remember_build(outdir, binary, p.returncode)  # and the build: another build runs it again
    s = json.load(open(summ))
    if p.returncode == 3 and not os.path.exists(os.path.join(outdir, "final.csv")):
        open(os.path.join(outdir, "final.csv"), "w").close()
    return s


def positions(outdir):
    rows = np.loadtxt(os.path.join(outdir, "final.csv"), delimiter=",", skiprows=1, ndmin=2)
    return rows[:, :2]


def rms_position(p, q, box):
    d = p - q
    d -= box * np.round(d / box)   # minimum image: the final CSV wraps positions into the box
    return float(np.sqrt(np.mean(np.sum(d * d, axis=1))))


def joint_clearance(outdir, box, h, kernel):
    """Over the reference run's snapshots (0.25 apart): the closest approach of any pair
    distance to r = h or a spline joint (in units of h), and how many times a pair distance
    crossed r = h and crossed an inner joint between consecutive snapshots (a lower bound)."""
    joints = [1.0] + JOINTS.get(kernel, [])
    clearance, crossings, before = math.inf, [0] * len(joints), None
    for _, p in sorted(snapshot_positions(outdir), key=lambda tp: tp[0]):
        d = p[:, None, :] - p[None, :, :]
        d -= box * np.round(d / box)
        s = np.sqrt(np.sum(d * d, axis=2))[np.triu_indices(len(p), 1)] / h
        near = s < 1.2
        for j in joints:
            clearance = min(clearance, float(np.min(np.abs(s[near] - j))))
        if before is not None:
            for i, j in enumerate(joints):
                crossings[i] += int(np.sum((before < j) != (s < j)))
        before = s
    return clearance, crossings[0], sum(crossings[1:])


def snapshot_positions(outdir):
    man = json.load(open(os.path.join(outdir, "manifest.json")))
    for e in man["files"]:
        if e.get("kind") == "snapshot_csv":
            rows = np.loadtxt(os.path.join(outdir, e["name"]), delimiter=",", skiprows=2, ndmin=2)
            yield e["t"], rows[:, :2]


def fit_order(points, floor):
    """points: [(dt, error)], largest dt first. The asymptotic range: the steps whose error
    exceeds FLOOR_FACTOR x floor and that lie within a factor FIT_SPAN of the smallest such
    step (at least FIT_POINTS of them, taking larger steps if needed). Returns (order, scatter,
    local orders, dts used): the least-squares slope of log error against log dt, the
    standard error of that slope (nan with two points), and the order of each neighbouring
    pair of steps. A crossing's error depends on where in its step the crossing falls, so the
    errors scatter about the line and the standard error says by how much."""
    usable = [(dt, e) for dt, e in points if e is not None and math.isfinite(e) and e > FLOOR_FACTOR * floor]
    if not usable:
        return math.nan, math.nan, [], []
    smallest = usable[-1][0]
    rng = [(dt, e) for dt, e in usable if dt <= FIT_SPAN * smallest * (1 + 1e-9)]
    if len(rng) < FIT_POINTS:
        rng = usable[-FIT_POINTS:]
    local = [math.log(e1 / e2) / math.log(d1 / d2) for (d1, e1), (d2, e2) in zip(rng, rng[1:])]
    if len(rng) < 2:
        return math.nan, math.nan, local, [dt for dt, _ in rng]
    x = np.log([dt for dt, _ in rng])
    y = np.log([e for _, e in rng])
    slope, icept = np.polyfit(x, y, 1)
    if len(rng) > 2:
        res = y - (slope * x + icept)
        scatter = float(math.sqrt(np.sum(res ** 2) / (len(rng) - 2) / np.sum((x - x.mean()) ** 2)))
    else:
        scatter = math.nan
    return float(slope), scatter, local, [dt for dt, _ in rng]


def attainable(p, smooth):
    """The order a method of order p keeps when a fixed number of steps hold a crossing of a
    kernel that is C^smooth at r = h: the crossing step's local error is O(dt^(smooth+1))."""
    return min(p, smooth + 1)


class Progress:
    def __init__(self, total):
        self.total, self.done, self.t0 = total, 0, time.time()

    def step(self, label):
        self.done += 1
        el = time.time() - self.t0
        print(f"[{self.done}/{self.total}] {label}  elapsed {el:.0f} s  eta {el / self.done * (self.total - self.done):.0f} s",
              flush=True)


def study(a):
    runs = os.path.join(a.out, "orders_runs")
    os.makedirs(runs, exist_ok=True)
    sc = {k: v for k, v in scenes(runs).items() if k in a.scene}
    methods = [m for m in METHODS if m[0] in a.method]
    total = sum(len(a.kernel) * (2 + sum(len(STEPS[(scene, m[0])]) for m in methods)) for scene in sc)
    prog = Progress(total)
    rows, refs = [], {}
    for scene, (opts, box) in sc.items():
        h = float(opts[opts.index("-h") + 1])
        for kernel in a.kernel:
            base = COMMON + opts + ["-kernel", kernel]
            fixed = base + ["-snapshot_interval", 0]
            rdir = os.path.join(runs, scene, kernel, "reference")
            # Snapshots of the reference every 0.25 for the clearance from r = h and the joints.
            spam(a.spam_ark, base + ["-snapshot_interval", 0.25, "-snapshot_hdf5", 0] + REFERENCE, rdir, a.counts)
            prog.step(f"{scene} {kernel} reference")
            cdir = os.path.join(runs, scene, kernel, "check")
            spam(a.spam_ark, fixed + CHECK, cdir, a.counts)
            prog.step(f"{scene} {kernel} check")
            ref = positions(rdir)
            floor = rms_position(positions(cdir), ref, box)
            clearance, crossings, inner = joint_clearance(rdir, box, h, kernel)
            refs[(scene, kernel)] = {"floor": floor, "clearance": clearance, "crossings": crossings, "inner": inner}
            for label, p, args in methods:
                for n in STEPS[(scene, label)]:
                    dt = END_TIME / n
                    d = os.path.join(runs, scene, kernel, f"{label}_{n}steps")
                    s = spam(a.spam_ark, fixed + args(dt), d, a.counts)
                    ok = s.get("status") == "ok" and s.get("steps") == n and s.get("t_final") == END_TIME
                    if s.get("status") == "ok" and not ok:
                        sys.exit(f"{d}: {s.get('steps')} steps to t = {s.get('t_final')}, not {n} to {END_TIME:g}")
                    err = rms_position(positions(d), ref, box) if ok else None
                    rows.append({"scene": scene, "kernel": kernel, "smooth": smoothness(kernel), "method": label,
                                 "nominal": p, "dt": dt, "status": s.get("status"),
                                 # the cost of every chart: method and interpolant (none here: no outputs between)
                                 "rhs_evals": s.get("rhs_evals_total", s.get("rhs_evals")),
                                 "error": err, "reference_floor": floor})
                    prog.step(f"{scene} {kernel} {label} dt {dt:g}: " + (f"error {err:.3e}" if ok else s.get("status")))
    return rows, refs


def fits(rows, refs):
    out = []
    keys = []
    for r in rows:
        k = (r["scene"], r["kernel"], r["method"])
        if k not in keys:
            keys.append(k)
    for scene, kernel, method in keys:
        rs = sorted((r for r in rows if (r["scene"], r["kernel"], r["method"]) == (scene, kernel, method)),
                    key=lambda r: -r["dt"])
        order, scatter, local, used = fit_order([(r["dt"], r["error"]) for r in rs], refs[(scene, kernel)]["floor"])
        out.append({"scene": scene, "kernel": kernel, "method": method, "nominal": rs[0]["nominal"],
                    "smooth": rs[0]["smooth"], "order": order, "scatter": scatter, "local": local, "dts": used,
                    "predicted": attainable(rs[0]["nominal"], rs[0]["smooth"]) if scene == "expansion" else rs[0]["nominal"]})
    return out


def write_csv(path, rows, fitted):
    fit = {(f["scene"], f["kernel"], f["method"]): f for f in fitted}
    with open(path + ".tmp", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["scene", "kernel", "smooth_at_h", "method", "nominal_order", "dt", "status", "rhs_evals",
                    "rms_position_error", "reference_floor", "fitted_order", "fit_scatter", "fit_dts", "fit_local_orders"])
        for r in rows:
            f = fit[(r["scene"], r["kernel"], r["method"])]
            w.writerow([r["scene"], r["kernel"], r["smooth"], r["method"], r["nominal"], "%g" % r["dt"], r["status"],
                        r["rhs_evals"], "" if r["error"] is None else "%.6e" % r["error"], "%.3e" % r["reference_floor"],
                        "%.3f" % f["order"], "%.3f" % f["scatter"], " ".join("%.4g" % d for d in f["dts"]),
                        " ".join("%.3f" % o for o in f["local"])])
    os.replace(path + ".tmp", path)


def chart_orders(path, fitted, methods, kernels):
    scenes_ = sorted({f["scene"] for f in fitted}, key=lambda s: ["expansion", "lattice"].index(s))
    fig, axes = plt.subplots(1, len(scenes_), figsize=(6.2 * len(scenes_), 5.2), sharey=True, squeeze=False)
    offs = {m: (i - (len(methods) - 1) / 2) * 0.09 for i, m in enumerate(methods)}
    # Kernels of the same smoothness share an abscissa: the second is shifted right a little.
    slot, seen = {}, {}
    for k in kernels:
        m = smoothness(k)
        slot[k] = m + 0.45 * seen.get(m, 0)
        seen[m] = seen.get(m, 0) + 1
    for ax, scene in zip(axes[0], scenes_):
        for method in methods:
            col, mk = STYLE[method]
            fs = [f for f in fitted if f["scene"] == scene and f["method"] == method]
            ok = [f for f in fs if math.isfinite(f["order"])]
            ax.errorbar([slot[f["kernel"]] + offs[method] for f in ok], [f["order"] for f in ok],
                        yerr=[0 if not math.isfinite(f["scatter"]) else f["scatter"] for f in ok],
                        color=col, marker=mk, ls="none", capsize=2, label=f"{method} (order {fs[0]['nominal']})")
            bad = [f for f in fs if not math.isfinite(f["order"])]
            if bad:
                ax.plot([slot[f["kernel"]] + offs[method] for f in bad], [1.2] * len(bad), "x", color="red", ms=9,
                        mew=2, label=f"{method}: no fit (errors at the reference's floor)")
            for f in fs:   # the prediction: a short dashed bar at each kernel's abscissa
                ax.plot([slot[f["kernel"]] - 0.2, slot[f["kernel"]] + 0.2], [f["predicted"]] * 2, color=col, lw=1.2,
                        ls="--", alpha=0.8)
        for k in kernels:
            ax.annotate(k, (slot[k], 0.6), rotation=90, fontsize=7, ha="center", va="bottom", color="0.3")
        ax.set_xlabel("kernel smoothness at r = h: w is C^m (m, 2D)")
        ax.set_xticks(range(2, 8))
        ax.grid(alpha=0.3)
        what = "pairs cross r = h" if scene == "expansion" else "no pair reaches r = h"
        ax.set_title(f"{scene} (2D, 16 x 16, t = {END_TIME:g}): {what}", fontsize=10)
        ax.set_ylim(0.5, 9.5)
    axes[0][0].set_ylabel("measured order (slope of log RMS position error vs log dt)")
    axes[0][0].plot([], [], "k--", lw=0.8, label="predicted: min(p, m + 1) where pairs cross, else p")
    axes[0][0].legend(fontsize=7, loc="upper left")
    fig.suptitle("Fixed-step order against the kernel's smoothness at r = h (error bars: standard error of the fitted slope)")
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=110)
    plt.close(fig)
    os.replace(path + ".tmp.png", path)


def chart_wp(path, rows, methods, kernels, refs):
    n = len(kernels)
    cols = 3 if n > 2 else n
    fig, axes = plt.subplots((n + cols - 1) // cols, cols, figsize=(4.6 * cols, 3.9 * ((n + cols - 1) // cols)),
                             squeeze=False, sharey=True)
    for i, kernel in enumerate(kernels):
        ax = axes[i // cols][i % cols]
        for method in methods:
            col, mk = STYLE[method]
            for scene, ls, mfc in (("expansion", "-", col), ("lattice", ":", "white")):
                rs = sorted((r for r in rows if r["kernel"] == kernel and r["method"] == method and r["scene"] == scene),
                            key=lambda r: r["rhs_evals"] or 0)
                ok = [r for r in rs if r["error"] is not None]
                if ok:
                    ax.loglog([r["rhs_evals"] for r in ok], [max(r["error"], 1e-16) for r in ok], ls=ls, marker=mk,
                              color=col, mfc=mfc, ms=5)
                bad = [r for r in rs if r["error"] is None]
                if bad:
                    ax.loglog([r["rhs_evals"] or 1 for r in bad], [1.0] * len(bad), "x", color="red", ms=9, mew=2)
                    ax.annotate("unstable", (bad[0]["rhs_evals"] or 1, 1.0), color="red", fontsize=7)
        for scene, ls in (("expansion", "-"), ("lattice", ":")):
            if (scene, kernel) in refs:
                ax.axhline(FLOOR_FACTOR * refs[(scene, kernel)]["floor"], color="0.5", ls=ls, lw=0.7)
        ax.set_title(f"{kernel} (C^{smoothness(kernel)} at r = h)", fontsize=10)
        ax.grid(alpha=0.3, which="both")
        if i % cols == 0:
            ax.set_ylabel("RMS position error at t = 8 (reduced units)")
        if i // cols == (n - 1) // cols:
            ax.set_xlabel("RHS evaluations")
    for j in range(n, axes.size):
        axes[j // cols][j % cols].axis("off")
    handles = [plt.Line2D([], [], color=STYLE[m][0], marker=STYLE[m][1], label=m) for m in methods]
    handles += [plt.Line2D([], [], color="k", ls="-", marker="o", label="expansion (pairs cross r = h)"),
                plt.Line2D([], [], color="k", ls=":", marker="o", mfc="white", label="lattice (no crossing)"),
                plt.Line2D([], [], color="0.5", lw=0.7, label=f"{FLOOR_FACTOR:g} x reference error (not fitted below)")]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    fig.suptitle("Work-precision per kernel: fixed-step RK4, DP5, V6, F8 on the 2D expansion and lattice (16 x 16, t = 8)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    fig.savefig(path + ".tmp.png", dpi=100)
    plt.close(fig)
    os.replace(path + ".tmp.png", path)


def fmt(f):
    if not math.isfinite(f["order"]):
        return "–"
    sc = "" if not math.isfinite(f["scatter"]) else " ± %.2f" % f["scatter"]
    return "%.2f%s" % (f["order"], sc)


def section(a, rows, fitted, refs, methods, kernels, elapsed):
    out = os.path.relpath(a.out, REPO)
    cmd = "examples/study_orders.py --out " + (a.out if out.startswith("..") else out)
    fit = {(f["scene"], f["kernel"], f["method"]): f for f in fitted}
    lines = ["## Kernel smoothness at r = h and the attainable order", "",
             f"Command `{cmd}` ({len(rows) + 2 * len(refs)} runs: {a.counts['ran']} run now, "
             f"{a.counts['cached']} finished before and reused; {elapsed:.0f} s). "
             "Table of every run: [orders.csv](orders.csv).", "",
             "Fixed steps to t = 8 (2D, 16 x 16 particles, isentrope γ = 2); error: RMS position at t = 8 against "
             "ARKODE Dormand-Prince at rtol 1e-14 (floor: its difference from PETSc rk 8vr at rtol 1e-14); order: "
             f"least-squares slope of log error against log dt over the steps whose error exceeds {FLOOR_FACTOR:g} x "
             f"the floor and that lie within a factor {FIT_SPAN:g} of the smallest such step (at least {FIT_POINTS}), "
             "± the standard error of the slope. "
             "RK4 is PETSc's rk 4 (ARKODE 6.4.1 has no classical 4th-order table). In brackets: min(p, m + 1) "
             "on the expansion, where pairs cross r = h (w is C^m there), p on the lattice, where none do.", ""]
    for scene, (dts_note) in (("expansion", "pairs cross r = h"), ("lattice", "no pair reaches r = h")):
        if not any(f["scene"] == scene for f in fitted):
            continue
        steps = "; ".join(f"{m} " + ", ".join(str(n) for n in STEPS[(scene, m)]) for m in methods)
        lines += [f"**{scene}** ({dts_note}; steps to t = 8: {steps}):", "",
                  "| kernel | C^m at h | " + " | ".join(methods) + " | reference floor |",
                  "|---|---|" + "---|" * len(methods) + "---|"]
        for k in kernels:
            if (scene, k, methods[0]) not in fit:
                continue
            cells = [f"{fmt(fit[(scene, k, m)])} ({fit[(scene, k, m)]['predicted']})" for m in methods]
            lines.append(f"| `{k}` | {smoothness(k)} | " + " | ".join(cells) + f" | {refs[(scene, k)]['floor']:.1e} |")
        lines.append("")
    lines += ["![order against smoothness](orders.png)", "", "![work-precision per kernel](wp_kernels.png)", ""]
    lines += readings(rows, fitted, refs, methods, kernels)
    return lines


def readings(rows, fitted, refs, methods, kernels):
    """Paragraphs computed from the fits: one per scene, then what could not be fitted."""
    ok = [f for f in fitted if math.isfinite(f["order"])]
    exp = [f for f in ok if f["scene"] == "expansion"]
    lat = [f for f in ok if f["scene"] == "lattice"]
    paras = []
    if exp:
        near = [f for f in exp if abs(f["order"] - f["predicted"]) <= 0.5]
        lucy = [f for f in exp if f["kernel"] == "lucy"]
        t = [f"Reading (expansion): {len(near)} of {len(exp)} fitted orders lie within 0.5 of min(p, m + 1)"
             + (" (not: " + ", ".join(f"{f['kernel']} {f['method']} {f['order']:.2f} for {f['predicted']}"
                                     for f in exp if f not in near) + ")" if len(near) < len(exp) else "") + "."]
        if lucy:
            t.append(f"With Lucy's kernel every method is held to {min(f['order'] for f in lucy):.2f}–"
                     f"{max(f['order'] for f in lucy):.2f}.")
        t.append("The highest order per kernel: " + ", ".join(
            f"{k} {max(f['order'] for f in exp if f['kernel'] == k):.2f}" for k in kernels
            if any(f['kernel'] == k for f in exp)) + ".")
        cr = [refs[k]["crossings"] for k in refs if k[0] == "expansion"]
        inner = {k[1]: refs[k]["inner"] for k in refs if k[0] == "expansion" and k[1] in JOINTS}
        t.append(f"Pair distances crossing r = h in a reference run (counted between snapshots 0.25 apart, "
                 f"a lower bound): {min(cr)}–{max(cr)}" + ("; crossing a spline's inner joint: " + ", ".join(
                     f"{k} {v}" for k, v in inner.items()) if inner else "") + ".")
        t.append(work_reading(rows, kernels))
        paras.append(" ".join(t))
    if lat:
        near = [f for f in lat if f["order"] >= f["nominal"] - 0.5]
        t = [f"Reading (lattice): {len(near)} of {len(lat)} fitted orders reach p − 0.5 or more"
             + (" (not: " + ", ".join(f"{f['kernel']} {f['method']} {f['order']:.2f}" for f in lat if f not in near)
                + ")" if len(near) < len(lat) else "") + "."]
        lr = [refs[k] for k in refs if k[0] == "lattice"]
        t.append(f"Crossings of r = h or of a spline joint between the lattice reference's snapshots: "
                 f"{sum(r['crossings'] + r['inner'] for r in lr)}.")
        cl = {k[1]: refs[k]["clearance"] for k in refs if k[0] == "lattice"}
        t.append("Closest approach of a pair distance to r = h or a spline joint over the reference run, in "
                 "units of h: " + ", ".join(f"{k} {v:.3f}" for k, v in cl.items()) + ".")
        paras.append(" ".join(t))
    t = []
    nofit = [f for f in fitted if not math.isfinite(f["order"])]
    if nofit:
        t.append("No fit (fewer than two steps above the floor): " + ", ".join(
            f"{f['scene']} {f['kernel']} {f['method']}" for f in nofit) + ".")
    bad = [r for r in rows if r["error"] is None]
    if bad:
        t.append("Unstable or unfinished runs (red X in the charts, not fitted): " + ", ".join(
            f"{r['scene']} {r['kernel']} {r['method']} dt {r['dt']:.4g} ({r['status']})" for r in bad) + ".")
    if t:
        paras.append(" ".join(t))
    return [x for p in paras for x in (p, "")]


def work_reading(rows, kernels, budget=600):
    """The smallest expansion error each kernel reaches within a budget of RHS evaluations
    (the wp_kernels chart read at one abscissa), and the method that reaches it."""
    parts = []
    for k in kernels:
        rs = [r for r in rows if r["scene"] == "expansion" and r["kernel"] == k and r["error"] is not None
              and r["rhs_evals"] <= budget]
        if rs:
            best = min(rs, key=lambda r: r["error"])
            parts.append(f"{k} {best['error']:.1e} ({best['method']})")
    return (f"Smallest expansion error within {budget} RHS evaluations: " + ", ".join(parts) + ".") if parts else ""


def write_section(out, lines, fitted):
    """Replaces (or appends) the <!-- orders --> section of DIR/study.md. The section's text
    and the fitted orders (scene, kernel, method; and each kernel's range over the methods)
    are also written to DIR/orders.json with the command and commit (chart_readings), and
    the page marks the section as that file's text (tools/docs_numbers.py checks the two)."""
    path = os.path.join(out, "study.md")
    text = open(path).read() if os.path.exists(path) else "# spam-ark study\n"
    begin, end = "<!-- orders -->\n", "<!-- /orders -->\n"
    body = "\n".join(lines) + "\n"
    order, span = {}, {}
    for f in fitted:
        if math.isfinite(f["order"]):
            order.setdefault(f["scene"], {}).setdefault(f["kernel"], {})[f["method"]] = f["order"]
    by_method = {}
    for scene, ks in order.items():
        span[scene] = {k: [min(v.values()), max(v.values())] for k, v in ks.items()}
        ms = {}
        for v in ks.values():
            for m, o in v.items():
                ms.setdefault(m, []).append(o)
        by_method[scene] = {m: [min(o), max(o)] for m, o in ms.items()}
    chart_readings.write_json(os.path.join(out, "orders.json"), {"section": body, "order": order, "range": span,
                                                                 "method_range": by_method}, chart="orders.png")
    sec = begin + "<!--text orders.json section-->\n" + body + "<!--/text-->\n" + end
    if begin in text and end in text:
        text = text[:text.index(begin)] + sec + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + sec
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(REPO, "docs", "gallery"), help="output directory (default docs/gallery)")
    ap.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"), help="the binary (default build/spam-ark)")
    ap.add_argument("--kernel", nargs="+", default=KERNELS, choices=KERNELS)
    ap.add_argument("--method", nargs="+", default=[m[0] for m in METHODS], choices=[m[0] for m in METHODS])
    ap.add_argument("--scene", nargs="+", default=["expansion", "lattice"], choices=["expansion", "lattice"])
    a = ap.parse_args()
    a.out = os.path.abspath(a.out)
    a.spam_ark = os.path.abspath(a.spam_ark)
    # OpenMPI's singleton start without its PMIx server (as the tests run it): about 0.5 s
    # less per start of spam-ark, and this study starts it some 220 times.
    os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")
    t0 = time.time()
    a.counts = {"ran": 0, "cached": 0}
    rows, refs = study(a)
    fitted = fits(rows, refs)
    methods = [m for m in a.method]
    write_csv(os.path.join(a.out, "orders.csv"), rows, fitted)
    chart_orders(os.path.join(a.out, "orders.png"), fitted, methods, a.kernel)
    chart_wp(os.path.join(a.out, "wp_kernels.png"), rows, methods, a.kernel, refs)
    lines = section(a, rows, fitted, refs, methods, a.kernel, time.time() - t0)
    write_section(a.out, lines, fitted)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
