#!/usr/bin/python3
"""The error norm of adaptive stepping (-error_norm rms|max) against the number of particles.

    study_norm.py --out DIR [--spam-ark PATH] [--sizes 16,...,512] [--rtol 1e-6]
                  [--tols 1e-4,...,1e-9] [--tol-size 64] [--t-end 4] [--h 3] [--ref-rtol 1e-11]

An adaptive method holds the norm of its weighted local error estimate to 1. The rms norm,
sqrt(sum (e_i w_i)^2 / L) over the L = 4N components of a 2D gas, lets an error confined
to a few particles grow with sqrt(L) before it is seen; the max norm, max_i |e_i w_i|, holds
every particle to its tolerance. The scene is the free expansion (-scene expansion, a lattice
gas in one corner of a periodic box of twice its edge) at a fixed end time, so that at every
N the same front, a few lattice spacings wide, carries the motion while the interior is
still at rest: the moving particles are a share ~1/n of N = n^2. The end time (default 4,
before the fronts of the periodic images meet at n = 16) is short because the expanding gas
is chaotic: differences between two runs grow on their own (at n = 32 they were 56 to 220
times larger at t = 16 than at t = 4), which would hide the per-step error the norm controls.

Lucy's force is only C^1 where a pair crosses r = h (its second derivative in r jumps there),
so the third time derivative of the positions jumps and a step across a crossing has a local
error of third order in dt whatever the method's order. Once every step holds crossings (many
particles), the error estimate is of that order too: the step goes as rtol^(1/3), the error
per step as rtol, and the error at t_end, summed over ~rtol^(-1/3) steps, as rtol^(2/3).

For every n in --sizes: a reference (Dormand-Prince, max norm, at --ref-rtol), and runs of
both norms at --rtol; at --tol-size also both norms at every --tols. The error of a run is
the largest distance of a particle from its place in the reference at t_end (minimum image
across the periodic faces); its cost, the RHS evaluations in its summary.json. Each run has
its own directory DIR/runs/<name>/ (a finished run is not repeated: an interrupted study
resumes); the reference at --tol-size is checked against one at 10 times its tolerance. Writes DIR/norm.csv, DIR/norm.png and the section <!-- norm --> of DIR/study.md
with the command and readings computed from the data.
"""
import argparse
import csv
import json
import math
import os
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
    sys.exit("study_norm.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NORMS = ("rms", "max")
# One colour and marker per norm in every panel; a failed run is a hollow red X.
STYLE = {"rms": dict(color="tab:blue", marker="o", label="-error_norm rms"),
         "max": dict(color="tab:green", marker="s", label="-error_norm max")}
FAILED = dict(marker="X", markerfacecolor="none", markeredgecolor="red", linestyle="none", markersize=10)
TABLE = "ARKODE_DORMAND_PRINCE_7_4_5"


def scene(a, n):
    return ["-scene", "expansion", "-expansion_n", n, "-h", a.h, "-ts_max_time", a.t_end,
            "-arkode_table", TABLE, "-output_interval", a.t_end, "-snapshot_interval", a.t_end,
            "-snapshot_hdf5", "false", "-diag_entropy", "false"]


def tolerances(rtol):
    # atol far below rtol h and rtol c0, so that rtol alone sets every weight
    return ["-ts_rtol", "%g" % rtol, "-ts_atol", "%g" % (rtol * 1e-3)]


def spam(binary, args, outdir):
    """Runs spam-ark unless outdir holds a finished run; returns the summary (None: failed)."""
    summ = os.path.join(outdir, "summary.json")
    if spam_manifest.status(outdir) in spam_manifest.FINISHED and os.path.exists(summ):
        s = json.load(open(summ))
        if spam_manifest.same_build(s, binary, args):  # another build's run is stale
            return s
    os.makedirs(os.path.dirname(outdir), exist_ok=True)
    p = subprocess.run([binary] + [str(x) for x in args] + ["-output_dir", outdir, "-output_overwrite"],
                       capture_output=True, text=True)
    if p.returncode not in (0, 3):
        raise SystemExit(f"spam-ark failed (exit {p.returncode}): {' '.join(map(str, args))}\n{p.stderr.strip()}")
    spam_manifest.remember_build(outdir, binary, p.returncode, args)
    return json.load(open(summ)) if os.path.exists(summ) else None


def final_positions(outdir):
    """(t, array (n, 3)) of the last CSV snapshot the manifest lists."""
    t, path = spam_manifest.files(spam_manifest.read(outdir), outdir, "snapshot_csv")[-1]
    return t, np.loadtxt(path, delimiter=",", skiprows=2, ndmin=2)[:, :3]


def position_errors(run_dir, ref_dir, box):
    """Largest and RMS distance of a particle from its reference place at t_end."""
    t, x = final_positions(run_dir)
    tr, xr = final_positions(ref_dir)
    if abs(t - tr) > 1e-9 * max(abs(tr), 1.0):
        raise SystemExit(f"{run_dir}: last snapshot at t = {t}, the reference's at {tr}")
    d = x - xr
    for k in range(3):  # minimum image: snapshots are wrapped into the box
        if box[k] > 0:
            d[:, k] -= box[k] * np.round(d[:, k] / box[k])
    r = np.sqrt(np.sum(d * d, 1))
    return float(r.max()), float(math.sqrt(np.mean(r * r)))


def run_all(a):
    plan = []
    for n in a.sizes:
        plan += [(n, norm, a.rtol) for norm in NORMS]
    plan += [(a.tol_size, norm, t) for t in a.tols for norm in NORMS if (a.tol_size, norm, t) not in plan]
    total, t0, rows = len(plan) + len(set(n for n, _, _ in plan)) + 1, time.time(), []
    done, refs = 0, {}

    def progress(label):
        nonlocal done
        done += 1
        el = time.time() - t0
        print(f"[{done}/{total}] {label}  elapsed {el:.0f} s  eta {el / done * (total - done):.0f} s", flush=True)

    for n in sorted(set(n for n, _, _ in plan)):
        d = os.path.join(a.out, "runs", f"ref_n{n}")
        s = spam(a.spam_ark, scene(a, n) + tolerances(a.ref_rtol) + ["-error_norm", "max"], d)
        if not s or s["status"] != "ok":
            raise SystemExit(f"the reference at n = {n} did not finish: {d}")
        refs[n] = (d, s)
        progress(f"reference n = {n} (max norm, rtol {a.ref_rtol:g})")
    # How far the reference itself is from converged: against one at 10 times its tolerance.
    d = os.path.join(a.out, "runs", f"refcheck_n{a.tol_size}")
    s = spam(a.spam_ark, scene(a, a.tol_size) + tolerances(10 * a.ref_rtol) + ["-error_norm", "max"], d)
    a.ref_check = position_errors(d, refs[a.tol_size][0], refs[a.tol_size][1]["box_len"])[0] if s and s["status"] == "ok" else float("nan")
    progress(f"reference check n = {a.tol_size} (rtol {10 * a.ref_rtol:g})")
    for n, norm, rtol in plan:
        d = os.path.join(a.out, "runs", f"{norm}_n{n}_rtol{rtol:g}")
        s = spam(a.spam_ark, scene(a, n) + tolerances(rtol) + ["-error_norm", norm], d)
        ok = bool(s) and s["status"] == "ok"
        emax, erms = position_errors(d, refs[n][0], refs[n][1]["box_len"]) if ok else (float("nan"),) * 2
        rows.append(dict(n=n, N=n * n, norm=norm, rtol=rtol, status=s["status"] if s else "failed",
                         err_max=emax, err_rms=erms, err_max_over_rtol_h=emax / (rtol * a.h),
                         # the cost: method and interpolant (outputs only at t_end: none interpolated)
                         rhs_evals=s.get("rhs_evals_total", s["rhs_evals"]) if s else 0, steps=s["steps"] if s else 0,
                         rejected=s["rejected_steps"] if s else 0, wall_s=s["wall_time_s"] if s else 0.0,
                         ref_rhs_evals=refs[n][1].get("rhs_evals_total", refs[n][1]["rhs_evals"])))
        progress(f"{norm} n = {n} rtol {rtol:g}")
    return rows


def write_csv(path, rows):
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(path + ".tmp", path)


def series(rows, norm, pick, key):
    rs = sorted((r for r in rows if r["norm"] == norm and pick(r)), key=lambda r: r[key])
    return [r for r in rs if r["status"] == "ok"], [r for r in rs if r["status"] != "ok"]


def panel(ax, rows, pick, x, y, label_tol):
    for norm in NORMS:
        ok, bad = series(rows, norm, pick, x)
        st = STYLE[norm]
        ax.loglog([r[x] for r in ok], [r[y] for r in ok], marker=st["marker"], color=st["color"], label=st["label"])
        if label_tol:
            for r in ok:
                ax.annotate(f"{r['rtol']:g}", (r[x], r[y]), textcoords="offset points", xytext=(4, 4), fontsize=6, color=st["color"])
        if bad:
            yb = [r[y] if r[y] == r[y] and r[y] > 0 else ax.get_ylim()[1] for r in bad]
            ax.loglog([r[x] for r in bad], yb, label=f"{norm}: failed", **FAILED)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def chart(a, rows, path):
    fig, ax = plt.subplots(2, 2, figsize=(11, 8.5))
    at_rtol = lambda r: r["rtol"] == a.rtol  # noqa: E731
    at_size = lambda r: r["n"] == a.tol_size  # noqa: E731
    panel(ax[0, 0], rows, at_rtol, "N", "err_max", True)
    ax[0, 0].set(xlabel="particles N", ylabel="largest particle position error at t_end (lattice spacings)",
                 title=f"Max-particle error against N (rtol {a.rtol:g})")
    panel(ax[0, 1], rows, at_size, "rtol", "err_max", True)
    ax[0, 1].loglog(a.tols, [t * a.h for t in a.tols], "k:", label="rtol h (the position tolerance)")
    ok, _ = series(rows, "max", at_size, "rtol")
    if ok:  # the slope 2/3 of a C^1 force, through the max norm's geometric middle
        mid = ok[len(ok) // 2]
        ax[0, 1].loglog(a.tols, [mid["err_max"] * (t / mid["rtol"]) ** (2 / 3) for t in a.tols], color="grey",
                        linestyle="--", label="slope 2/3 (C^1 force)")
    ax[0, 1].legend(fontsize=7)
    ax[0, 1].set(xlabel="relative tolerance rtol", ylabel="largest particle position error at t_end (lattice spacings)",
                 title=f"Max-particle error against rtol (N = {a.tol_size}^2)")
    panel(ax[1, 0], rows, at_rtol, "N", "rhs_evals", True)
    ax[1, 0].set_yscale("linear")  # a ratio of 1.2 reads better from zero
    ax[1, 0].set_ylim(bottom=0)
    ax[1, 0].legend(fontsize=7, loc="lower right")
    ax[1, 0].set(xlabel="particles N", ylabel="right-hand-side evaluations to t_end", title=f"Cost against N (rtol {a.rtol:g})")
    panel(ax[1, 1], rows, at_size, "rhs_evals", "err_max", True)
    ax[1, 1].set(xlabel="right-hand-side evaluations", ylabel="largest particle position error at t_end (lattice spacings)",
                 title=f"Work-precision (N = {a.tol_size}^2, rtol beside points)")
    fig.suptitle(f"Free expansion (-scene expansion, h = {a.h:g}, t_end = {a.t_end:g}): rms and max error norms, "
                 f"Dormand-Prince 5(4)", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def slope(rs, x, y):
    """Least-squares slope of log y against log x."""
    if len(rs) < 2:
        return float("nan")
    return float(np.polyfit(np.log([r[x] for r in rs]), np.log([r[y] for r in rs]), 1)[0])


def loglog_interp(rs, x, y, at):
    """log-log interpolation of y(x) at x = at over rows sorted by x (None outside them)."""
    rs = sorted(rs, key=lambda r: r[x])
    for r0, r1 in zip(rs, rs[1:]):
        if r0[x] <= at <= r1[x]:
            f = math.log(at / r0[x]) / math.log(r1[x] / r0[x])
            return math.exp(math.log(r0[y]) + f * math.log(r1[y] / r0[y]))
    return None


def readings(a, rows):
    ok = [r for r in rows if r["status"] == "ok"]
    by = {(r["norm"], r["n"], r["rtol"]): r for r in ok}
    lines = []
    sizes = [n for n in a.sizes if ("rms", n, a.rtol) in by and ("max", n, a.rtol) in by]
    if sizes:
        lo, hi = sizes[0], sizes[-1]
        ratio = {n: by[("rms", n, a.rtol)]["err_max"] / by[("max", n, a.rtol)]["err_max"] for n in sizes}
        cost = {n: by[("max", n, a.rtol)]["rhs_evals"] / by[("rms", n, a.rtol)]["rhs_evals"] for n in sizes}
        srms = slope([by[("rms", n, a.rtol)] for n in sizes], "N", "err_max")
        smax = slope([by[("max", n, a.rtol)] for n in sizes], "N", "err_max")
        lines += [f"At rtol {a.rtol:g} the largest particle error under the rms norm is "
                  + ", ".join(f"{ratio[n]:.1f}" for n in sizes)
                  + " times the max norm's at N = " + ", ".join(f"{n}^2" for n in sizes)
                  + f"; fitted against N it grows as N^{srms:.2f} (rms) and N^{smax:.2f} (max). "
                  "Largest particle error / (rtol h) over N = " + f"{lo}^2 to {hi}^2: "
                  + ", ".join(f"{norm} {min(by[(norm, n, a.rtol)]['err_max_over_rtol_h'] for n in sizes):.2g} to "
                              f"{max(by[(norm, n, a.rtol)]['err_max_over_rtol_h'] for n in sizes):.2g}" for norm in NORMS) + ".", "",
                  "The max norm costs " + ", ".join(f"{cost[n]:.2f}" for n in sizes)
                  + " times the RHS evaluations of the rms norm at the same sizes and rtol.", ""]
    tols = {norm: sorted((r for r in ok if r["norm"] == norm and r["n"] == a.tol_size and r["rtol"] in a.tols),
                         key=lambda r: r["rtol"]) for norm in NORMS}
    if all(len(v) >= 2 for v in tols.values()):
        lines += [f"At N = {a.tol_size}^2 the largest particle error goes as rtol^{slope(tols['rms'], 'rtol', 'err_max'):.2f} "
                  f"(rms) and rtol^{slope(tols['max'], 'rtol', 'err_max'):.2f} (max) over rtol {min(a.tols):g} to {max(a.tols):g}; "
                  f"error / (rtol h) stays within {min(r['err_max_over_rtol_h'] for r in tols['max']):.2g} to "
                  f"{max(r['err_max_over_rtol_h'] for r in tols['max']):.2g} for max, "
                  f"{min(r['err_max_over_rtol_h'] for r in tols['rms']):.2g} to {max(r['err_max_over_rtol_h'] for r in tols['rms']):.2g} for rms."]
        # At equal work: the max norm's error interpolated at each rms run's RHS count.
        gains = []
        for r in tols["rms"]:
            e = loglog_interp(tols["max"], "rhs_evals", "err_max", r["rhs_evals"])
            if e:
                gains.append((r, r["err_max"] / e))
        if gains:
            lines += ["", "At equal RHS evaluations (interpolated along the max norm's work-precision line) the rms run's "
                      "largest particle error is " + ", ".join(f"{g:.2f}x (rms rtol {r['rtol']:g})" for r, g in gains)
                      + " the max norm's."]
    refs = sorted({r["n"]: r["ref_rhs_evals"] for r in ok}.items())
    floor = min((r["err_max"] for r in ok), default=0.0)
    lines += ["", f"References: Dormand-Prince, -error_norm max, rtol {a.ref_rtol:g} (RHS evaluations "
              + ", ".join(f"{v} at {n}^2" for n, v in refs) + f"); at {a.tol_size}^2 the reference is {a.ref_check:.1e} "
              f"from the run at rtol {10 * a.ref_rtol:g} (largest particle distance), "
              + ("below every error above." if a.ref_check < floor else "NOT below every error above.")]
    return lines


def update_report(out, part, lines):
    """Replaces (or appends) the section <!-- part --> ... <!-- /part --> of DIR/study.md; its
    text is also written to DIR/<part>.json with the command and commit (chart_readings), and
    the page marks the section as that file's text (tools/docs_numbers.py checks the two)."""
    path = os.path.join(out, "study.md")
    text = open(path).read() if os.path.exists(path) else "# spam-ark study\n"
    begin, end = f"<!-- {part} -->\n", f"<!-- /{part} -->\n"
    body = "\n".join(lines) + "\n"
    chart_readings.write_json(os.path.join(out, part + ".json"), {"section": body}, chart=part + ".png")
    section = begin + f"<!--text {part}.json section-->\n" + body + "<!--/text-->\n" + end
    if begin in text and end in text:
        text = text[:text.index(begin)] + section + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + section
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def floats(s):
    return [float(x) for x in s.split(",")]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", required=True)
    p.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    p.add_argument("--sizes", type=lambda s: [int(x) for x in s.split(",")], default=[16, 32, 64, 128, 256, 512],
                   help="lattice points per direction, N = n^2 (default 16,32,64,128,256,512)")
    p.add_argument("--rtol", type=float, default=1e-6, help="the tolerance of the sweep over N")
    p.add_argument("--tols", type=floats, default=[1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9], help="the tolerances at --tol-size")
    p.add_argument("--tol-size", type=int, default=64)
    p.add_argument("--ref-rtol", type=float, default=1e-11)
    p.add_argument("--t-end", type=float, default=4.0)
    p.add_argument("--h", type=float, default=3.0)
    a = p.parse_args(argv)
    a.spam_ark = os.path.abspath(a.spam_ark)
    os.makedirs(a.out, exist_ok=True)
    rows = run_all(a)
    write_csv(os.path.join(a.out, "norm.csv"), rows)
    chart(a, rows, os.path.join(a.out, "norm.png"))
    # relative paths only: study.md must not carry a path of the machine that wrote it
    words = [os.path.relpath(w, REPO) if os.path.isabs(w) else w for w in (argv if argv is not None else sys.argv[1:])]
    command = "examples/study_norm.py " + " ".join(words)
    lines = ["## Error norm: rms against max (-error_norm)", "",
             f"Command `{command}`. Table: [norm.csv](norm.csv).", "",
             "![rms and max error norms](norm.png)", ""] + readings(a, rows)
    update_report(a.out, "norm", lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
