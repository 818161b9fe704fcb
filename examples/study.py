#!/usr/bin/python3
"""Studies with spam-ark: work-precision, conservation under adaptive stepping, stability.

    study.py precision  [--scene-opts ...] [--method LABEL=OPTIONS ...] [--tol T ...] --out DIR
    study.py stability  [--scene expansion|planewave|chain ...] [--method LABEL=OPTIONS:STAGES ...] --out DIR
    study.py controller [--scene-opts ...] [--method LABEL=OPTIONS ...] [--loose-tol T] --out DIR
    study.py entropy    [--n N ...] --out DIR
    study.py tensile    [--sigma0 S ...] [--method LABEL=OPTIONS ...] --out DIR
    study.py drift      [--scene-opts ...] [--method LABEL=OPTIONS ...] [--fixed LABEL=OPTIONS ...] --out DIR
    study.py gallery    [--small] --out DIR  (README's gallery: all of the above, then
                        examples/study_orders.py and study_norm.py where they exist, and
                        the PRE 2004 figures of examples/pre2004_figures.py, not --small)

precision: every adaptive method x tolerance, and every fixed-step method of --fixed (default:
    the symplectic Verlet, Symp3 and Symp4 of PETSc's basicsymplectic types kdk, 3 and 4) x
    step --dt (each must divide the output interval t_end/20), runs in its own
    directory DIR/runs/<label>_<tol or dt>/ (a finished run, one whose manifest.json says ok, max_steps
    or unstable, and whose summary.json names the same spam-ark executable (its SHA-1) and
    the same options, scene's included, is skipped: an interrupted study resumes, rerunning
    with -output_overwrite any run that was interrupted, failed, made by another build or
    with other options). A reference (ARKODE Dormand-Prince 5(4) at rtol 1e-13) is run once
    per scene and cached in DIR/reference_<hash>/. Errors are RMS position and velocity
    differences from it at every snapshot time (minimum image across periodic faces);
    drifts of energy, momentum and angular momentum come from each summary.json, the
    entropy difference from the reference's. Writes DIR/precision.csv, PNG charts and
    DIR/study.md.
stability: for each fixed-step method, the largest stable step by bisection on dt (a trial
    of --steps steps is unstable when spam-ark ends it with exit code 3, e.g. kinetic energy
    above --growth times the initial energy) on the preset scenes of --scene (default all:
    the expansion in units of h/c0, the plane wave in h/c_L, the harmonic chain in 1/w_max
    with the closed-form limits of the methods' stability polynomials) or on --scene-opts
    (units of --time-unit); charted against the measured force evaluations per step.
    Writes stability.csv and stability.png.
controller: adaptive runs at a loose tolerance, where stability, not accuracy, limits the
    step: dt(t) of each controller with its rejections, and the step oscillation (RMS of
    log(dt_n+1/dt_n)); a run that ends unstable (exit 3) is drawn as such. Writes
    controllers.csv and controllers.png.
entropy: Delta S(t)/(N k ln 4) for several lattice sizes, sum and grid (CiSE 2001 Fig. 3).
    Writes entropy.csv and entropy.png.
drift: long-time energy error |E(t) - E0|/|E0| of the symplectic fixed-step methods against
    adaptive Runge-Kutta pairs on the MD rotor (options/rotor-md.opts: a spring lattice, a
    smooth Hamiltonian of positions and velocities only), 10^4 steps of the finest Verlet
    series; the exponent p of the envelope |E - E0| ~ t^p tells bounded oscillation (p near
    0) from secular drift (p near 1). Writes drift.csv and drift.png.
tensile: the tensile instability (PRE 2004 Sec. IV, options/tensile.opts): the growth rate of
    KE (a line through ln KE over the second half of each run) against the tension sigma0
    for R0, R2 and R0 with Monaghan viscosity. Writes tensile.csv, tensile.png.
Each study adds its section to DIR/study.md (other sections, e.g. those of study_orders.py,
are kept), headed by the command that made it
and the command that made it, with paths relative to the repository; every reading in it
is computed from the runs.

Needs numpy and matplotlib (/usr/bin/python3 on Debian); the spam-ark binary defaults to
build/spam-ark. Progress and an ETA are printed as runs finish.
"""
import argparse
import csv
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

try:
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
except ImportError:
    if os.path.realpath(sys.executable) != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("study.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402
from chart_style import style, UNSTABLE  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The reference: Dormand-Prince at rtol 1e-13. Lucy's force is only C^1 where a pair crosses
# r = h, so high-order pairs lose accuracy at every crossing and their error estimates miss
# it: on the default scene Fehlberg 8(7) at rtol 1e-12 is 4.5e-6 off, while Dormand-Prince
# at 1e-13 agrees with PETSc's rk 8vr at 1e-13 to 2.8e-9 (RMS position).
REFERENCE = ["-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5", "-ts_rtol", "1e-13", "-ts_atol", "1e-15"]
# The default matrix: adaptive pairs of orders 3 to 8, CVODE, and a PETSc pair.
DEFAULT_METHODS = ["BS3=-arkode_table ARKODE_BOGACKI_SHAMPINE_4_2_3",
                   "DP5=-arkode_table ARKODE_DORMAND_PRINCE_7_4_5",
                   "V6=-arkode_table ARKODE_VERNER_8_5_6",
                   "F8=-arkode_table ARKODE_FEHLBERG_13_7_8",
                   "CVODE=-ts_type cvode",
                   "rk5dp=-ts_type rk -ts_rk_type 5dp"]
DEFAULT_TOLS = [1e-4, 1e-6, 1e-8, 1e-10]
# The fixed-step symplectic series beside them: spam-ark's default kick-drift-kick Verlet
# (order 2, one force evaluation a step) and PETSc 3.18's basicsymplectic types 3 and 4
# (orders 3 and 4, three force evaluations a step: measured on the MD rotor, where the
# energy error falls 8x and 16x when dt halves).
DEFAULT_SYMPLECTIC = ["Verlet=-ts_type basicsymplectic",
                      "Symp3=-ts_type basicsymplectic -ts_basicsymplectic_type 3",
                      "Symp4=-ts_type basicsymplectic -ts_basicsymplectic_type 4"]
# Steps of the fixed series on the default scene (t_end 16, outputs every 0.8): divisors of
# 0.8 below Verlet's stability limit (0.95 = 0.32 h/c0 in the gallery's stability study) down.
DEFAULT_DTS = [0.4, 0.2, 0.1, 0.05, 0.025]
# Fixed-step methods for the stability study, with their force evaluations per step (the
# study measures them from the runs; the number here is used only if no trial was stable).
# PETSc's SSP types take 5 stages (rks2) or 9 (rks3) unless told: SSP3 is the 4-stage
# third-order SSP RK.
DEFAULT_FIXED = ["euler=-ts_type euler:1", "Verlet=-ts_type basicsymplectic:1", "Heun=-ts_type rk -ts_rk_type 2a -ts_adapt_type none:2",
                 "SSP3=-ts_type ssp -ts_ssp_type rks3 -ts_ssp_nstages 4:4", "RK4=-ts_type rk -ts_rk_type 4 -ts_adapt_type none:4",
                 "DP5=-ts_type rk -ts_rk_type 5dp -ts_adapt_type none:6", "V6=-ts_type rk -ts_rk_type 6vr -ts_adapt_type none:9",
                 "Symp3=-ts_type basicsymplectic -ts_basicsymplectic_type 3:3",
                 "Symp4=-ts_type basicsymplectic -ts_basicsymplectic_type 4:3"]
DEFAULT_SCENE = "-expansion_n 24 -h 3 -ts_max_time 16"


class Progress:
    """Counts finished runs and prints elapsed time and an ETA from the mean so far."""

    def __init__(self, total):
        self.total, self.done, self.t0, self.ran = total, 0, time.time(), 0

    def step(self, label, skipped=False):
        self.done += 1
        if not skipped:
            self.ran += 1
        el = time.time() - self.t0
        todo = self.total - self.done
        eta = el / self.ran * todo if self.ran else 0.0
        print(f"[{self.done}/{self.total}] {label}{' (done before, skipped)' if skipped else ''}"
              f"  elapsed {el:.0f} s  eta {eta:.0f} s", flush=True)


def spam(binary, args, outdir, refused_ok=False):
    """Runs spam-ark unless outdir already holds a finished run made by this same build of
    spam-ark with these same args (a run of another build, or of other scene options under
    the same label, is stale: the gallery regenerated after a change must not reuse it); returns (code, skipped). Exit 2 (spam-ark refused the input)
    is returned rather than raised when refused_ok."""
    summ = os.path.join(outdir, "summary.json")
    if spam_manifest.status(outdir) in spam_manifest.FINISHED and os.path.exists(summ):
        s = json.load(open(summ))
        if spam_manifest.same_build(s, binary, args):
            return s.get("exit_code", 0), True
    os.makedirs(os.path.dirname(outdir) or ".", exist_ok=True)
    # Not finished (absent, interrupted, failed): run it afresh over whatever is left.
    p = subprocess.run([binary] + [str(a) for a in args] + ["-output_dir", outdir, "-output_overwrite"],
                       capture_output=True, text=True)
    if p.returncode == 2 and refused_ok:
        return 2, False
    if p.returncode not in (0, 3):
        raise SystemExit(f"spam-ark failed (exit {p.returncode}): {' '.join(map(str, args))}\n{p.stderr.strip()}")
    spam_manifest.remember_build(outdir, binary, p.returncode, args)  # a resumed study needs no rerun
    return p.returncode, False


def snapshots(outdir):
    """{time: array (n, 6) of x,y,z,vx,vy,vz} from the CSV snapshots the manifest lists."""
    snaps = {}
    for t, path in spam_manifest.files(spam_manifest.read(outdir), outdir, "snapshot_csv"):
        snaps[round(t, 9)] = np.loadtxt(path, delimiter=",", skiprows=2, ndmin=2)[:, :6]
    return snaps


def errors(run, ref, box):
    """RMS position and velocity errors at the snapshot times both runs have."""
    out = []
    for t, a in sorted(run.items()):
        if t == 0 or t not in ref:
            continue
        b = ref[t]
        dx = a[:, :3] - b[:, :3]
        for d in range(3):  # minimum image: snapshots are wrapped into the box
            if box[d] > 0:
                dx[:, d] -= box[d] * np.round(dx[:, d] / box[d])
        dv = a[:, 3:6] - b[:, 3:6]
        out.append((t, math.sqrt(np.mean(np.sum(dx * dx, 1))), math.sqrt(np.mean(np.sum(dv * dv, 1)))))
    return out


def parse_methods(specs):
    methods = []
    for s in specs:
        label, _, opts = s.partition("=")
        methods.append((label, opts.split()))
    return methods


def scene_key(args):
    return hashlib.sha1(" ".join(map(str, args)).encode()).hexdigest()[:10]


def scene_name(opts, n_particles=None):
    """A short name of the scene for chart titles: the options file's or -scene's name
    (spam-ark's default scene is the expansion), with the particle count when known."""
    words = opts.split() if isinstance(opts, str) else [str(w) for w in opts]
    name = "expansion"
    if "-options_file" in words:
        name = os.path.basename(words[words.index("-options_file") + 1]).rsplit(".", 1)[0]
    if "-scene" in words:
        name = words[words.index("-scene") + 1]
    return name + (f", N = {n_particles}" if n_particles else "")


def precision_row(label, opts, code, d, ref, rs, box, rtol=float("nan"), dt=float("nan")):
    """One precision.csv row; a run spam-ark refused (exit 2) has status "refused" and no numbers."""
    nan = float("nan")
    if code == 2:
        s = {"status": "refused", "steps": 0, "rejected_steps": 0, "rhs_evals": 0, "wall_time_s": nan,
             "rhs_time_share": nan, "energy_rel_drift_max": nan, "momentum_rel_drift_max": nan,
             "angular_momentum_rel_drift_max": nan, "entropy_sum_final": None}
    else:
        s = json.load(open(os.path.join(d, "summary.json")))
    e = errors(snapshots(d), ref, box) if code == 0 else []
    return {"method": label, "options": " ".join(map(str, opts)), "rtol": rtol, "dt": dt, "status": s["status"],
            "steps": s["steps"], "rejected": s["rejected_steps"],
            # the cost every chart and reading uses: the method's evaluations and the
            # interpolant's (ARKODE's and CVODE's dense output evaluates f at each output)
            "rhs_evals": s.get("rhs_evals_total", s["rhs_evals"]), "rhs_method": s["rhs_evals"],
            "rhs_interpolant": s.get("interpolation_rhs_evals", 0),
            "wall_s": s["wall_time_s"], "rhs_share": s["rhs_time_share"],
            "err_x_final": e[-1][1] if e else nan, "err_v_final": e[-1][2] if e else nan,
            "err_x_max": max(x[1] for x in e) if e else nan,
            "err_v_max": max(x[2] for x in e) if e else nan,
            "energy_drift": s["energy_rel_drift_max"], "momentum_drift": s["momentum_rel_drift_max"],
            # where L is not conserved (a periodic box, walls) spam-ark writes no drift but the
            # same measure as a change, with the reason
            "angmom_drift": nan if s.get("angular_momentum_rel_change_max", s["angular_momentum_rel_drift_max"]) is None
            else s.get("angular_momentum_rel_change_max", s["angular_momentum_rel_drift_max"]),
            "angmom_not_conserved": s.get("angular_momentum_not_conserved", ""),
            "entropy_diff": abs((s["entropy_sum_final"] or 0) - (rs["entropy_sum_final"] or 0)) if code != 2 else nan}


def precision(a):
    base = a.scene_opts.split()
    common = base + ["-snapshot_interval", a.t_end / 4, "-output_interval", a.t_end / 20, "-snapshot_hdf5", 0]
    refdir = os.path.join(a.out, "reference_" + scene_key(common + REFERENCE))
    methods = parse_methods(a.method or DEFAULT_METHODS)
    fixed = parse_methods(a.fixed if a.fixed is not None else ([] if a.method else DEFAULT_SYMPLECTIC))
    tols, dts = a.tol or DEFAULT_TOLS, a.dt or DEFAULT_DTS
    wave = planewave_probe(a.spam_ark, common, os.path.join(a.out, "probe"))
    if wave:  # the period is fitted to KE(t): 40 samples (about 10 per KE oscillation over two
        # periods) fix it well; finer ones would also end more steps (every output ends one)
        common[common.index("-output_interval") + 1] = a.t_end / 40
        refdir = os.path.join(a.out, "reference_" + scene_key(common + REFERENCE))
    prog = Progress(1 + len(methods) * len(tols) + len(fixed) * len(dts))
    _, skipped = spam(a.spam_ark, common + REFERENCE, refdir)
    prog.step("reference (Dormand-Prince, rtol 1e-13)", skipped)
    ref = snapshots(refdir)
    rs = json.load(open(os.path.join(refdir, "summary.json")))
    box = rs["box_len"]
    if wave:
        ref_period, ref_amp = wave_measures(refdir, wave[0])
        wave = wave + (ref_period, 1 - ref_amp)
    cases = [(label, opts + ["-ts_rtol", tol, "-ts_atol", tol * 1e-3], f"{label}_{tol:g}", {"rtol": tol}, f"rtol {tol:g}")
             for label, opts in methods for tol in tols]
    cases += [(label, opts + ["-ts_dt", "%.10g" % dt], f"{label}_dt{dt:g}", {"dt": dt}, f"dt {dt:g}")
              for label, opts in fixed for dt in dts]
    rows = []
    for label, opts, name, knob, what in cases:
        d = os.path.join(a.out, "runs", name)
        code, skipped = spam(a.spam_ark, common + opts, d, refused_ok=True)
        prog.step(f"{label} {what}" + (" (refused by spam-ark on this scene)" if code == 2 else ""), skipped)
        rows.append(precision_row(label, opts, code, d, ref, rs, box, **knob))
        if wave:
            rows[-1].update(wave_errors(d if code == 0 else None, refdir, wave))
    write_csv(os.path.join(a.out, "precision.csv"), rows)
    scene = scene_name(base, rs.get("n_particles"))
    charts = precision_charts(rows, a.out, scene)
    report(a.out, rows, charts, common, a.made)
    if wave:
        planewave_report(a.out, rows, wave, a.made)
    return rows


def planewave_probe(binary, common, outdir):
    """The planewave scene prints the periods of its linearised SPAM equations and of the
    continuum; a run of zero steps reads them. Returns (SPAM period, continuum period), or
    None for any other scene."""
    p = subprocess.run([binary] + [str(x) for x in common] + ["-ts_max_steps", "0", "-output_dir", outdir, "-output_overwrite"],
                       capture_output=True, text=True)
    shutil.rmtree(outdir, ignore_errors=True)
    if p.returncode != 0:
        raise SystemExit(f"spam-ark failed (exit {p.returncode}) on the scene options\n{p.stderr.strip()}")
    m = re.search(r"predicted period ([0-9.eE+-]+) \(linearised SPAM\), continuum period ([0-9.eE+-]+)", p.stdout)
    return (float(m.group(1)), float(m.group(2))) if m else None


def ke_fit(t, ke, w):
    """Least squares of KE(t) on 1, t, cos 2wt, sin 2wt, t cos 2wt, t sin 2wt: a standing
    wave KE = K sin^2(w t + phi) whose K may drift linearly. Returns (residual, coefficients)."""
    basis = np.column_stack([np.ones_like(t), t, np.cos(2 * w * t), np.sin(2 * w * t),
                             t * np.cos(2 * w * t), t * np.sin(2 * w * t)])
    c, *_ = np.linalg.lstsq(basis, ke, rcond=None)
    return float(np.sum((basis @ c - ke) ** 2)), c


def wave_measures(outdir, period_guess):
    """Period and amplitude ratio A(t_end)/A(0) of the standing wave from its KE(t): the
    frequency minimising the residual of ke_fit (a scan within 5% of the guess, then golden
    section), so every sample counts and no minimum has to fall between samples. The
    oscillating part of KE is proportional to A^2."""
    with open(os.path.join(outdir, "timeseries.csv")) as f:
        ts = list(csv.DictReader(f))
    t, ke = np.array([float(r["t"]) for r in ts]), np.array([float(r["kinetic"]) for r in ts])
    w0 = 2 * math.pi / period_guess
    ws = w0 * np.linspace(0.95, 1.05, 201)
    k = int(np.argmin([ke_fit(t, ke, w)[0] for w in ws]))
    lo, hi, g = ws[max(k - 1, 0)], ws[min(k + 1, len(ws) - 1)], (math.sqrt(5) - 1) / 2
    for _ in range(80):
        m1, m2 = hi - g * (hi - lo), lo + g * (hi - lo)
        if ke_fit(t, ke, m1)[0] < ke_fit(t, ke, m2)[0]:
            hi = m2
        else:
            lo = m1
    w = 0.5 * (lo + hi)
    c = ke_fit(t, ke, w)[1]
    a0, a1 = math.hypot(c[2], c[3]), math.hypot(c[2] + c[4] * t[-1], c[3] + c[5] * t[-1])
    return 2 * math.pi / w, math.sqrt(a1 / a0)


def wave_errors(run, ref, wave):
    """Extra precision.csv columns of the plane wave: the measured period against the
    linearised SPAM period (the analytic answer for small amplitude; at A = 0.25 the
    amplitude itself shifts it by about -0.1%), against the reference run's period (the
    integrator's own error), and the amplitude's change over the run (1 - A_end/A_start)."""
    ref_period, _ = wave_measures(ref, wave[0])
    if run is None:
        return {"period": float("nan"), "period_err_spam": float("nan"), "period_err_ref": float("nan"),
                "amplitude_decay": float("nan")}
    period, amp = wave_measures(run, wave[0])
    return {"period": period, "period_err_spam": period / wave[0] - 1, "period_err_ref": period / ref_period - 1,
            "amplitude_decay": 1 - amp}


def planewave_report(out, rows, wave, made=None):
    ok = [r for r in rows if r["status"] == "ok" and r["period"] == r["period"]]
    lines = ["## Plane wave: period and amplitude", "",
             f"Linearised SPAM period {wave[0]:.6f} (continuum {wave[1]:.6f}); periods and amplitudes "
             "fitted to KE(t) ([precision.csv](precision.csv) columns period, period_err_spam, period_err_ref, "
             "amplitude_decay).", "",
             "| method | rtol | period | vs linearised SPAM | vs reference | amplitude decay |", "|---|---|---|---|---|---|"]
    for r in ok:
        lines.append(f"| {r['method']} | {r['rtol']:g} | {r['period']:.6f} | {r['period_err_spam']:+.2e} | "
                     f"{r['period_err_ref']:+.2e} | {r['amplitude_decay']:+.2e} |")
    lines += ["", f"The reference (Dormand-Prince, rtol 1e-13): period {wave[2]:.6f} ({wave[2] / wave[0] - 1:+.2e} against "
              f"linearised SPAM: the finite amplitude's own shift), amplitude decay {wave[3]:+.2e} (energy leaving the "
              "wave for other modes); a method's error is its difference from these."]
    update_report(out, "planewave", lines, made)


def write_csv(path, rows):
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(path + ".tmp", path)


MARKERS = "osD^v<>ph*"


def finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def by_method(rows, adaptive_only=False):
    """{method: [rows that ended ok]}, in the order the methods first appear."""
    out = {}
    for r in rows:
        if r["status"] == "ok" and not (adaptive_only and not finite(r["rtol"])):
            out.setdefault(r["method"], []).append(r)
    return out


def knob(r, short=False):
    """A run's tolerance (adaptive) or step (fixed), as written in the text or, short,
    beside its point on a chart."""
    if finite(r["rtol"]):
        return f"{r['rtol']:g}" if short else f"rtol {r['rtol']:g}"
    return f"dt {r['dt']:g}"


def draw_unstable(ax, rows, x):
    """Runs that ended unstable or at their step limit: hollow red X at the top of the axes,
    at their x, labelled once."""
    bad = [r for r in rows if r["status"] not in ("ok", "refused") and finite(r[x]) and r[x] > 0]
    if not bad:
        return
    top = ax.get_ylim()[1]
    ax.plot([r[x] for r in bad], [top] * len(bad), **UNSTABLE, clip_on=False,
            label="unstable / not finished: " + ", ".join(sorted({f"{r['method']} {knob(r)}" for r in bad})))
    for r in bad:
        ax.annotate(f"{r['method']} {knob(r)}", (r[x], top), textcoords="offset points", xytext=(4, -10), fontsize=6,
                    color="red")


def loglog(path, rows, x, y, xlabel, ylabel, title, adaptive_only=False):
    """One series per method (style from chart_style), each point labelled with its rtol
    (adaptive) or dt (fixed); unstable runs marked; refused methods named in the title."""
    fig, ax = plt.subplots(figsize=(7.4, 5.2))
    for m, rs in by_method(rows, adaptive_only).items():
        rs = sorted(rs, key=lambda r: r[x])
        xs, ys = [r[x] for r in rs], [max(r[y], 1e-17) for r in rs]
        fixed = not finite(rs[0]["rtol"])
        ax.loglog(xs, ys, **style(m), linestyle="--" if fixed else "-", label=m + (" (fixed dt)" if fixed else " (rtol)"))
        for r, xv, yv in zip(rs, xs, ys):
            ax.annotate(knob(r, short=True) if fixed or x != "rtol" else "", (xv, yv), textcoords="offset points", xytext=(3, 3),
                        fontsize=5.5, color=style(m)["color"])
    if not adaptive_only:
        draw_unstable(ax, rows, x)
    refused = sorted({r["method"] for r in rows if r["status"] == "refused"})
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title + (f"\n(refused by spam-ark on this scene: {', '.join(refused)})" if refused else ""), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return os.path.basename(path)


def precision_charts(rows, out, scene):
    c = {}
    c["err_rhs"] = loglog(os.path.join(out, "error_vs_rhs.png"), rows, "rhs_evals", "err_x_final",
                          "right-hand-side evaluations (method + interpolant)", "RMS position error at t_end (length units)",
                          f"Work-precision, {scene}: error against RHS evaluations")
    c["err_wall"] = loglog(os.path.join(out, "error_vs_wall.png"), rows, "wall_s", "err_x_final",
                           "wall time (s, one core)", "RMS position error at t_end (length units)",
                           f"Work-precision, {scene}: error against wall time")
    c["energy"] = loglog(os.path.join(out, "energy_drift_vs_tol.png"), rows, "rtol", "energy_drift",
                         "relative tolerance rtol", "max |E(t) - E0| / |E0|",
                         f"Energy drift under adaptive stepping, {scene}", adaptive_only=True)
    why = next((r["angmom_not_conserved"] for r in rows if r.get("angmom_not_conserved")), "")
    c["angmom"] = loglog(os.path.join(out, "angmom_drift_vs_tol.png"), rows, "rtol", "angmom_drift",
                         "relative tolerance rtol", "max |L(t) - L0| / (sqrt(2 M E0) R_g)",
                         f"Angular-momentum {'change' if why else 'drift'} under adaptive stepping, {scene}"
                         + (f"\n(L {why})" if why else ""), adaptive_only=True)
    fig, ax = plt.subplots(figsize=(7.4, 5.2))
    for m, rs in by_method(rows, adaptive_only=True).items():
        rs = sorted(rs, key=lambda r: r["rtol"])
        ax.loglog([r["rtol"] for r in rs], [r["steps"] for r in rs], **style(m), label=f"{m} accepted")
        ax.loglog([r["rtol"] for r in rs], [max(r["rejected"], 0.5) for r in rs], **style(m), mfc="none",
                  linestyle=":", label=f"{m} rejected")
    ax.set_xlabel("relative tolerance rtol")
    ax.set_ylabel("steps (rejected: 0 drawn at 0.5)")
    ax.set_title(f"Accepted and rejected steps, {scene}", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "steps_vs_tol.png"), dpi=110)
    plt.close(fig)
    c["steps"] = "steps_vs_tol.png"
    return c


def cheapest_to(rows, target):
    """The run with the fewest RHS evaluations among those whose final RMS position error is
    at most target (None if none is)."""
    ok = [r for r in rows if r["status"] == "ok" and finite(r["err_x_final"]) and r["err_x_final"] <= target]
    return min(ok, key=lambda r: r["rhs_evals"]) if ok else None


def fitted_orders(rows):
    """{fixed-step method: slope of log error against log dt} over its runs that ended ok
    with an error above 1e-12 (below, round-off and the reference's own error dominate)."""
    out = {}
    for m, rs in by_method(rows).items():
        rs = [r for r in rs if finite(r["dt"]) and finite(r["err_x_final"]) and r["err_x_final"] > 1e-12]
        if len(rs) >= 2:
            out[m] = float(np.polyfit(np.log([r["dt"] for r in rs]), np.log([r["err_x_final"] for r in rs]), 1)[0])
    return out


def energy_slopes(rows):
    """{adaptive method: d log(energy drift) / d log(rtol)} between its loosest and tightest run."""
    slope = {}
    for m, rs in by_method(rows, adaptive_only=True).items():
        rs = sorted(rs, key=lambda r: r["rtol"])
        if len(rs) >= 2 and rs[0]["energy_drift"] > 0 and rs[-1]["energy_drift"] > 0:
            slope[m] = math.log(rs[-1]["energy_drift"] / rs[0]["energy_drift"]) / math.log(rs[-1]["rtol"] / rs[0]["rtol"])
    return slope


def report(out, rows, charts, common, made=None):
    ok = [r for r in rows if r["status"] == "ok" and finite(r["err_x_final"])]
    lines = ["## Work-precision", f"Scene: `spam-ark {relative(' '.join(map(str, common)))}`; "
             f"reference ARKODE Dormand-Prince at rtol 1e-13. Table: [precision.csv](precision.csv).", ""]
    refused = sorted({r["method"] for r in rows if r["status"] == "refused"})
    bad = [r for r in rows if r["status"] not in ("ok", "refused")]
    if refused:
        lines += [f"Refused by spam-ark on this scene (exit 2): {', '.join(refused)}.", ""]
    if bad:
        lines += ["Ended unstable or at the step limit: " + ", ".join(f"{r['method']} {knob(r)} ({r['status']})" for r in bad)
                  + ".", ""]
    if ok:
        best = min(ok, key=lambda r: r["err_x_final"])  # the most accurate run
        winner = cheapest_to(ok, 1e-6)
        lines += [f"![error vs RHS]({charts['err_rhs']})", "",
                  (f"Reading: to reach 1e-6 in position, {winner['method']} needs the fewest RHS evaluations "
                   f"({winner['rhs_evals']} at {knob(winner)}); the most accurate run is {best['method']} at "
                   f"{knob(best)} ({best['err_x_final']:.1e}).") if winner else
                  f"Reading: no run reached 1e-6; the most accurate is {best['method']} at {knob(best)} "
                  f"({best['err_x_final']:.1e}).", ""]
        orders = fitted_orders(rows)
        if orders:
            lines += ["Fixed-step series: fitted order (slope of log error against log dt) "
                      + ", ".join(f"{m} {v:.2f}" for m, v in orders.items()) + ".", ""]
        fastest = min(ok, key=lambda r: r["wall_s"])
        lines += [f"![error vs wall time]({charts['err_wall']})", "",
                  f"Reading: wall time follows RHS evaluations (the RHS takes {100 * np.median([r['rhs_share'] for r in ok]):.0f}% "
                  f"of the wall time, median); the fastest run was {fastest['method']} at {knob(fastest)} "
                  f"({fastest['wall_s']:.2f} s; the machine's load {machine_load()} when the study was written).", ""]
        slope = energy_slopes(rows)
        lines += [f"![energy drift]({charts['energy']})", "",
                  "Reading: energy drift against tolerance, fitted slopes " +
                  ", ".join(f"{m} {v:.2f}" for m, v in slope.items()) + " (1 means drift proportional to rtol).", ""]
        adaptive = [r for r in ok if finite(r["rtol"])]
        worst = max(adaptive or ok, key=lambda r: r["angmom_drift"])
        why = worst.get("angmom_not_conserved", "")
        lines += [f"![angular momentum drift]({charts['angmom']})", "",
                  f"Reading: the largest angular-momentum {'change' if why else 'drift'} is {worst['angmom_drift']:.1e} "
                  f"({worst['method']}, {knob(worst)})" +
                  (f"; L is {why} (summary.json `angular_momentum_not_conserved`: images break rotational "
                   f"symmetry), so compare methods here against each other, not against zero." if why else "."), ""]
        rej = sum(r["rejected"] for r in adaptive)
        lines += [f"![steps]({charts['steps']})", "",
                  f"Reading: steps grow as rtol tightens; {rej} rejected steps in all {len(adaptive)} adaptive runs.", ""]
    update_report(out, "precision", lines, made)


def machine_load():
    """The 1-minute load average and the cores, as a page quotes them beside a timing."""
    m = chart_readings.machine()
    return f"{m['load_1min']:.1f} on {m['cores']} cores" if m["load_1min"] is not None else f"unknown on {m['cores']} cores"


def relative(text):
    """text with every absolute path made relative to the repository (study.md must not
    carry a path of the machine that wrote it)."""
    return re.sub(r"(?<![\w.)}])/[^\s`'\"]+", lambda m: os.path.relpath(m.group(0), REPO), text)


def made_line(argv):
    """The provenance line of every section: the command, relative paths only (the pages
    name no commit: git's history of study.md says which one made it)."""
    words = [relative(os.path.abspath(sys.argv[0]))] + [relative(w) for w in argv]
    cmd = " ".join(w if w and not re.search(r"[\s'\"]", w) else "'" + w + "'" for w in words)
    return f"*Made by `{cmd}` (run from the repository root).*"


def update_report(out, part, lines, made=None):
    """Replaces (or appends) the section of one study in DIR/study.md, so the studies run
    one at a time (and resumed) each keep their own lines; sections written by other
    scripts (any <!-- name --> ... <!-- /name --> pair) are left as they are. The line
    `made` (the command) follows the section's heading. The section's text is also written
    to DIR/<part>.json with the command, commit and machine load that made it, and the page
    marks it as that file's text (tools/docs_numbers.py checks the two agree)."""
    path = os.path.join(out, "study.md")
    text = open(path).read() if os.path.exists(path) else "# spam-ark study\n"
    if made:
        lines = lines[:1] + ["", made, ""] + (lines[2:] if lines[1:2] == [""] else lines[1:])
    begin, end = f"<!-- {part} -->\n", f"<!-- /{part} -->\n"
    body = "\n".join(lines) + "\n"
    chart_readings.write_json(os.path.join(out, part + ".json"), {"section": body})
    section = begin + f"<!--text {part}.json section-->\n" + body + "<!--/text-->\n" + end
    if begin in text and end in text:
        text = text[:text.index(begin)] + section + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + section
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


class Refused(Exception):
    """spam-ark refused a method for this scene (exit 2, e.g. Verlet on a state with more than x, v)."""


def stable(a, common, opts, dt, outdir):
    """A fixed number of steps (not a fixed time), so a large step cannot pass by taking few;
    kinetic energy above --growth times the initial energy counts as a blow-up."""
    code, _ = spam(a.spam_ark, common + opts + ["-ts_dt", "%.10g" % dt, "-ts_max_steps", a.steps,
                                                "-ts_max_time", "%.10g" % (dt * (a.steps + 0.5)),
                                                "-unstable_energy_growth", a.growth], outdir, refused_ok=True)
    if code == 2:
        raise Refused()
    return code == 0


def largest_stable_step(a, common, opts, label, lo, hi):
    """Bisection on dt between a stable lo and an unstable hi, to a relative width --rel.
    A method with no stable step at all (Euler or Heun on a purely oscillatory problem,
    whose stability regions miss the imaginary axis, given enough steps) stops shrinking
    after 20 halvings and reports 0."""
    k, trial = 0, lambda dt: stable(a, common, opts, dt, os.path.join(a.out, "stability", f"{label}_{dt:.10g}"))
    while trial(hi):
        lo, hi = hi, hi * 2  # grow until a step is unstable
    halvings = 0
    while not trial(lo):
        hi, lo, halvings = lo, lo / 2, halvings + 1  # shrink until a step is stable
        if halvings == 20:
            return 0.0, hi
    while (hi - lo) > a.rel * lo and k < 40:
        mid = 0.5 * (lo + hi)
        if trial(mid):
            lo = mid
        else:
            hi = mid
        k += 1
    return lo, hi


# Scenes of the stability study: options, the time unit of the chart and its name.
# The expansion gas has c0 = 1 (gamma 2, kappa 1/2 at rho 1) and h = 3; the plane-wave
# crystal's fastest sound is longitudinal, c_L = sqrt((lambda + 2 eta) / rho0) = sqrt(9/8);
# the chain's unit is 1/w_max = sqrt(m/k)/2, so w_max dt is read off directly.
STABILITY_SCENES = {
    "expansion": ("-expansion_n 16 -h 3", 3.0, "h/c0"),
    "planewave": (f"-options_file {os.path.join(REPO, 'options', 'planewave.opts')}", 3.0 / math.sqrt(9.0 / 8.0), "h/c_L"),
    "chain": ("-scene chain -dim 1 -chain_n 64", 0.5, "1/w_max"),
}
# Stability polynomials R(z) = sum c_k z^k of the default Runge-Kutta methods: Euler,
# Heun and RK4 are the truncated exponentials of degree 1, 2, 4; the 4-stage SSP RK3 adds
# z^4/48; Dormand-Prince's fifth-order solution adds z^6/600 to the degree-5 truncation.
STABILITY_POLYNOMIALS = {"euler": [1, 1], "Heun": [1, 1, 1 / 2], "SSP3": [1, 1, 1 / 2, 1 / 6, 1 / 48],
                         "RK4": [1, 1, 1 / 2, 1 / 6, 1 / 24], "DP5": [1, 1, 1 / 2, 1 / 6, 1 / 24, 1 / 120, 1 / 600]}


def imaginary_axis_limit(label):
    """The closed-form limit w_max dt on a harmonic problem: the largest y with |R(iy)| <= 1
    on all of [0, y], the smallest positive root of |R(iy)|^2 - 1 (RK4: 2 sqrt 2; SSP3:
    2 sqrt(sqrt 10 - 2); 0 for Euler and Heun, whose |R(iy)| exceeds 1 for every y > 0).
    Verlet's step map has trace 2 - y^2: stable to y = 2. NaN for other methods."""
    if label == "Verlet":
        return 2.0
    if label not in STABILITY_POLYNOMIALS:
        return float("nan")
    c = STABILITY_POLYNOMIALS[label]
    re = np.polynomial.Polynomial([ck * (1j ** k).real for k, ck in enumerate(c)])
    im = np.polynomial.Polynomial([ck * (1j ** k).imag for k, ck in enumerate(c)])
    excess = re * re + im * im - 1
    if excess(1e-3) > 0:
        return 0.0
    roots = [r.real for r in excess.roots() if abs(r.imag) < 1e-9 and r.real > 1e-6]
    return min(roots) if roots else float("inf")


def measured_stages(trial_dir, declared):
    """Force evaluations per step of a finished stable trial (Verlet's cached force: 1),
    or the declared number when there is no such trial."""
    summ = os.path.join(trial_dir, "summary.json")
    if not os.path.exists(summ):
        return int(declared or 0)
    s = json.load(open(summ))
    return int(round(s["rhs_evals"] / max(s["steps"], 1)))


def stability_scenes(a):
    """The scenes asked for by --scene (presets), or the one of --scene-opts, or all presets."""
    if a.scene:
        return [(name,) + STABILITY_SCENES[name] for name in a.scene]
    if a.scene_opts is not None:
        return [("scene", a.scene_opts, a.time_unit, "h/c0")]
    return [(name,) + v for name, v in STABILITY_SCENES.items()]


def stability(a):
    rows = []
    specs = a.method or DEFAULT_FIXED
    scenes = stability_scenes(a)
    prog, refused = Progress(len(specs) * len(scenes)), {}
    for scene, opts_scene, unit, unit_name in scenes:
        common = opts_scene.split() + ["-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0]
        b = argparse.Namespace(**vars(a))
        b.out = os.path.join(a.out, scene) if len(scenes) > 1 or a.scene else a.out
        for spec in specs:
            head, _, stages = spec.rpartition(":")
            label, _, opts = head.partition("=")
            try:
                lo, hi = largest_stable_step(b, common, opts.split(), label, a.dt_guess * unit, 2 * a.dt_guess * unit)
            except Refused:
                prog.step(f"{scene}, {label}: refused by spam-ark for this scene")
                refused.setdefault(scene, []).append(label)
                continue
            exact = imaginary_axis_limit(label) if scene == "chain" else float("nan")
            stages = measured_stages(os.path.join(b.out, "stability", f"{label}_{lo:.10g}"), stages)
            rows.append({"scene": scene, "unit": unit_name, "method": label, "options": opts,
                         "force_evals_per_step": int(stages), "dt_stable": lo, "dt_unstable": hi,
                         "dt_limit": lo / unit, "closed_form": exact,
                         "error": (lo / unit / exact - 1) if exact > 0 else float("nan"),
                         "cost_per_unit_time": int(stages) / lo if lo > 0 else float("inf")})
            prog.step(f"{scene}, {label}: stable up to dt {lo:.5g} ({lo / unit:.4f} {unit_name})")
    write_csv(os.path.join(a.out, "stability.csv"), rows)
    stability_chart(rows, [s[0] for s in scenes], os.path.join(a.out, "stability.png"), refused)
    lines = ["## Stability limits", "", "![stability](stability.png)", "",
             *(["Refused by spam-ark (exit 2): " + "; ".join(f"{k}: {', '.join(v)}" for k, v in refused.items()) + ".", ""]
               if refused else []),
             f"Largest stable fixed step by bisection ({a.steps} steps a trial, unstable when KE > {a.growth:g} x the "
             f"initial energy; [stability.csv](stability.csv)). On the chain (a linear oscillator) the closed form is "
             "where the method's stability region leaves the imaginary axis.", "",
             "| scene | method | stages | limit | unit | closed form | error |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['method']} | {r['force_evals_per_step']} | {r['dt_limit']:.4f} | {r['unit']} | "
                     + (f"{r['closed_form']:.4f} | " if r["closed_form"] == r["closed_form"] else "- | ")
                     + (f"{r['error']:+.2%} |" if r["error"] == r["error"] else "- |"))
    lines += ["", stability_reading(rows)]
    update_report(a.out, "stability", lines, a.made)
    return rows


def stability_reading(rows):
    """Which found limits agree with their closed forms to 1% and which do not (those whose
    |R(iy)| exceeds 1 only slightly past the limit grow too slowly to reach the bound within
    a trial), and the cheapest method per unit time on each scene: all from the rows."""
    known = [r for r in rows if r["error"] == r["error"]]
    agree = [f"{r['method']} {r['error']:+.2%}" for r in known if abs(r["error"]) <= 0.01]
    off = [f"{r['method']} {r['error']:+.2%}" for r in known if abs(r["error"]) > 0.01]
    text = "Reading: " + (f"on the chain the found limits match their closed forms within 1% for {', '.join(agree)}"
                          if agree else "no found limit matches a closed form within 1%" if known
                          else "no method here has a closed form")
    if off:
        text += (f"; not for {', '.join(off)}: past its limit |R(iy)| exceeds 1 only slightly, so the growth is too "
                 "slow to reach the bound within a trial and the found limit depends on --steps and --growth")
    cheap = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        rs = [r for r in rows if r["scene"] == scene and r["dt_limit"] > 0]
        if rs:
            b = min(rs, key=lambda r: r["cost_per_unit_time"])
            cheap.append(f"{scene} {b['method']} ({b['force_evals_per_step'] / b['dt_limit']:.2f} per {b['unit']})")
    return text + ". Fewest force evaluations per unit time at the limit: " + "; ".join(cheap) + "."


def stability_chart(rows, scenes, path, refused):
    """One panel per scene: the largest stable step against stages, closed forms hollow;
    methods spam-ark refused on a scene named in its panel's title."""
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.2 * len(scenes), 4.4), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        rs = [r for r in rows if r["scene"] == scene]
        for r in rs:
            ax.plot(r["force_evals_per_step"], r["dt_limit"], **style(r["method"]), ms=8, linestyle="none", label=r["method"])
            if r["closed_form"] == r["closed_form"]:
                ax.plot(r["force_evals_per_step"], r["closed_form"], **style(r["method"]), ms=13, mfc="none", linestyle="none")
        ax.set_xlabel("force evaluations per step (stages)")
        ax.set_ylabel(f"largest stable step (units of {rs[0]['unit'] if rs else '?'})")
        ax.set_title(scene + (" (hollow: closed form)" if scene == "chain" else "")
                     + (f"\nrefused by spam-ark here: {', '.join(refused[scene])}" if refused.get(scene) else ""), fontsize=9)
        ax.grid(True, alpha=0.3)
        if rs:
            ax.legend(fontsize=7)
    fig.suptitle("Stability limit of fixed-step methods (scenes: " + ", ".join(scenes) + ")")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


DEFAULT_CONTROLLERS = ["ARKODE I=-arkode_adapt i", "ARKODE PI=-arkode_adapt pi", "ARKODE PID=-arkode_adapt pid",
                       "PETSc basic (rk 5dp)=-ts_type rk -ts_rk_type 5dp -ts_adapt_type basic",
                       "PETSc dsp (rk 5dp)=-ts_type rk -ts_rk_type 5dp -ts_adapt_type dsp"]


def controller(a):
    """Adaptive steps near the stability limit: a loose tolerance lets accuracy allow steps
    that stability does not, so the controller must find the limit by rejections. Charted:
    dt(t) per controller, rejections marked, a run that ended unstable (exit 3) ended by a
    hollow red X and named so in the legend; the oscillation is the RMS of log(dt_n+1/dt_n)."""
    common = a.scene_opts.split() + ["-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0,
                                     "-ts_rtol", a.loose_tol, "-ts_atol", a.loose_tol]
    specs = a.method or DEFAULT_CONTROLLERS
    prog, rows = Progress(len(specs)), []
    fig, ax = plt.subplots(figsize=(7.6, 4.8))
    for spec in specs:
        label, _, opts = spec.partition("=")
        d = os.path.join(a.out, "controller", label.replace(" ", "_").replace("(", "").replace(")", ""))
        code, skipped = spam(a.spam_ark, common + opts.split(), d)
        prog.step(label, skipped)
        s = json.load(open(os.path.join(d, "summary.json")))
        with open(os.path.join(d, "steps.csv")) as f:
            st = list(csv.DictReader(f))
        t = np.array([float(r["t"]) for r in st])
        dt = np.array([float(r["dt"]) for r in st])
        rej = np.array([int(r["rejected"]) for r in st])
        keep = np.array([r["limit"] not in ("output", "end") for r in st])
        ratio = np.diff(np.log(dt[keep])) if keep.sum() > 2 else np.array([0.0])
        nrej = int(rej[-1]) if len(rej) else 0
        sty = style(label)
        tag = f"UNSTABLE at t = {s['t_final']:.4g} ({nrej} rejected before)" if code == 3 else f"{nrej} rejected"
        ax.semilogy(t, dt, "-", lw=1, color=sty["color"], label=f"{label}: {tag}")
        jumps = np.nonzero(np.diff(np.concatenate([[0], rej])) > 0)[0]
        ax.semilogy(t[jumps], dt[jumps], linestyle="none", marker=sty["marker"], color=sty["color"], ms=4)
        if code == 3 and len(t):
            ax.semilogy([t[-1]], [dt[-1]], **UNSTABLE)
        rows.append({"controller": label, "options": opts, "exit_code": code, "status": s["status"],
                     "t_final": s["t_final"], "steps": len(st), "rejected": nrej,
                     "dt_median": float(np.median(dt)) if len(dt) else 0.0,
                     "oscillation_rms_log_ratio": float(np.sqrt(np.mean(ratio ** 2)))})
    ax.plot([], [], **UNSTABLE, label="run ended unstable (exit 3)")
    ax.set_xlabel("t (reduced time units)")
    ax.set_ylabel("accepted step dt (markers: step after a rejection)")
    ax.set_title(f"Controllers near the stability limit, {scene_name(a.scene_opts)} (rtol = atol = {a.loose_tol:g})",
                 fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "controllers.png"), dpi=110)
    plt.close(fig)
    write_csv(os.path.join(a.out, "controllers.csv"), rows)
    lines = ["## Step controllers near the stability limit", "![controllers](controllers.png)", "",
             f"Scene: `spam-ark {relative(' '.join(map(str, common)))}` with each controller's options "
             "([controllers.csv](controllers.csv)).", "",
             "| controller | status | t_final | steps | rejected | median dt | RMS log(dt_n+1/dt_n) |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['controller']} | {r['status']} | {r['t_final']:.4g} | {r['steps']} | {r['rejected']} | "
                     f"{r['dt_median']:.4g} | {r['oscillation_rms_log_ratio']:.4f} |")
    lines += ["", controller_reading(rows)]
    update_report(a.out, "controller", lines, a.made)
    return rows


def controller_reading(rows):
    unstable = [r for r in rows if r["exit_code"] == 3]
    done = [r for r in rows if r["exit_code"] == 0]
    text = f"Reading: {len(unstable)} of {len(rows)} controllers ended unstable (exit 3)"
    if unstable:
        text += (", having rejected " + ", ".join(f"{r['rejected']}" for r in unstable) + " steps before"
                 " (the error estimate does not see the instability grow, so the step is not cut)")
    if done:
        calm = min(done, key=lambda r: r["oscillation_rms_log_ratio"])
        text += (f"; of those that finished, {calm['controller']} oscillates least "
                 f"(RMS log ratio {calm['oscillation_rms_log_ratio']:.4f}, {calm['rejected']} rejected)")
    return text + "."


def entropy(a):
    rows, fig = [], plt.figure(figsize=(6.8, 4.8))
    ax = fig.gca()
    prog = Progress(len(a.n))
    for k, n in enumerate(a.n):
        d = os.path.join(a.out, "entropy", f"n{n}")
        _, skipped = spam(a.spam_ark, ["-expansion_n", n, "-h", a.h, "-snapshot_interval", 0], d)
        prog.step(f"expansion n = {n}", skipped)
        s = json.load(open(os.path.join(d, "summary.json")))
        with open(os.path.join(d, "timeseries.csv")) as f:
            ts = list(csv.DictReader(f))
        tau = s["sound_traversal_time"]
        t = [float(r["t"]) / tau for r in ts]
        ax.plot(t, [float(r["dS_sum_ratio"]) for r in ts], "-", color=f"C{k}", label=f"N = {n * n}, sum")
        ax.plot(t, [float(r["dS_grid_ratio"]) for r in ts], "--", color=f"C{k}", label=f"N = {n * n}, grid")
        rows.append({"n": n, "N": n * n, "h": a.h, "t_final_over_tau": t[-1], "dS_sum_final": s["dS_sum_ratio_final"],
                     "dS_grid_final": s["dS_grid_ratio_final"]})
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel("t / tau (sound traversal times)")
    ax.set_ylabel("Delta S / (N k ln 4)")
    ax.set_title(f"Entropy of the fourfold free expansion (scene expansion), h = {a.h:g}", fontsize=9)
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "entropy.png"), dpi=110)
    plt.close(fig)
    write_csv(os.path.join(a.out, "entropy.csv"), rows)
    lines = ["## Entropy of the free expansion", "![entropy](entropy.png)", "",
             f"Scene: `spam-ark -expansion_n N -h {a.h:g} -snapshot_interval 0` for each n ([entropy.csv](entropy.csv)); "
             "Delta S/(N k ln 4) from the particles' densities (sum) and on the grid, 1 for the ideal gas's fourfold expansion.",
             "", "| n | N | t_end / tau | Delta S sum | Delta S grid |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['n']} | {r['N']} | {r['t_final_over_tau']:.2f} | {r['dS_sum_final']:.4f} | {r['dS_grid_final']:.4f} |")
    best = min(rows, key=lambda r: abs(r["dS_sum_final"] - 1))
    lines += ["", f"Reading: at the end the summed entropy ratio ranges over "
              f"{min(r['dS_sum_final'] for r in rows):.4f} to {max(r['dS_sum_final'] for r in rows):.4f}, the grid's over "
              f"{min(r['dS_grid_final'] for r in rows):.4f} to {max(r['dS_grid_final'] for r in rows):.4f}; closest to 1 "
              f"(summed): N = {best['N']} ({best['dS_sum_final']:.4f})."]
    update_report(a.out, "entropy", lines, a.made)
    return rows


# The drift study's scene: the MD rotor (options/rotor-md.opts), 217 particles joined by
# Hookean springs, spinning. Its state is positions and velocities only and its force derives
# from a smooth potential, so it is a Hamiltonian system: backward error analysis gives a
# symplectic method a nearby energy it conserves (bounded oscillation of E), while a
# Runge-Kutta pair's error adds up (secular drift). The plane wave cannot be used: its
# elastic model carries e, rho and the stress, and spam-ark refuses a symplectic split there.
DRIFT_SCENE = "-options_file " + os.path.join(REPO, "options", "rotor-md.opts") + " -ts_max_time 2000"
DRIFT_T_END = 2000.0
DRIFT_DTS = [0.4, 0.2]          # Verlet at 0.2: 10^4 steps of t_end 2000
DRIFT_ADAPTIVE = ["BS3=-arkode_table ARKODE_BOGACKI_SHAMPINE_4_2_3", "DP5=-arkode_table ARKODE_DORMAND_PRINCE_7_4_5"]
DRIFT_TOLS = [1e-4, 1e-6]


def drift_exponent(t, err):
    """Exponent p of the envelope of |E(t) - E0|/|E0| (its running maximum) ~ t^p, fitted
    over the last 90% of the run in log-log: a bounded oscillation gives p near 0, a
    secular drift p near 1 (or more, if it accelerates)."""
    t, env = np.asarray(t), np.maximum.accumulate(np.asarray(err))
    sel = (t >= 0.1 * t[-1]) & (env > 0)
    return float(np.polyfit(np.log(t[sel]), np.log(env[sel]), 1)[0]) if sel.sum() >= 3 else float("nan")


def drift(a):
    """Energy error over a long run (10^4 steps and more) of the symplectic fixed-step series
    against adaptive Runge-Kutta pairs at a comparable number of RHS evaluations."""
    base = a.scene_opts.split()
    common = base + ["-snapshot_interval", 0, "-output_interval", a.t_end / 400]
    cases = [(label, opts + ["-ts_rtol", tol, "-ts_atol", tol * 1e-3], f"{label}_{tol:g}", {"rtol": tol, "dt": float("nan")})
             for label, opts in parse_methods(a.method or DRIFT_ADAPTIVE) for tol in (a.tol or DRIFT_TOLS)]
    cases += [(label, opts + ["-ts_dt", "%.10g" % dt], f"{label}_dt{dt:g}", {"rtol": float("nan"), "dt": dt})
              for label, opts in parse_methods(a.fixed if a.fixed is not None else DEFAULT_SYMPLECTIC) for dt in (a.dt or DRIFT_DTS)]
    prog, rows, series = Progress(len(cases)), [], {}
    for label, opts, name, k, what in [(c[0], c[1], c[2], c[3], knob(c[3])) for c in cases]:
        d = os.path.join(a.out, "drift", name)
        code, skipped = spam(a.spam_ark, common + opts, d)
        prog.step(f"drift {label} {what}", skipped)
        s = json.load(open(os.path.join(d, "summary.json")))
        ts = table_of(os.path.join(d, "timeseries.csv"))
        err = np.abs(ts["total"] / ts["total"][0] - 1)
        series[name] = (ts["t"], err)
        rows.append({"method": label, "options": " ".join(map(str, opts)), **k, "status": s["status"],
                     # the cost as in precision: the method's evaluations and the interpolant's
                     "steps": s["steps"], "rhs_evals": s.get("rhs_evals_total", s["rhs_evals"]), "t_final": s["t_final"],
                     "energy_err_final": float(err[-1]), "energy_err_max": float(err.max()),
                     "drift_exponent": drift_exponent(ts["t"][1:], err[1:]), "run": name})
    write_csv(os.path.join(a.out, "drift.csv"), rows)
    scene = scene_name(base, json.load(open(os.path.join(a.out, "drift", rows[0]["run"], "summary.json"))).get("n_particles"))
    drift_chart(rows, series, scene, os.path.join(a.out, "drift.png"))
    lines = ["## Long-time energy drift: symplectic against adaptive", "![drift](drift.png)", "",
             f"Scene: `spam-ark {relative(' '.join(map(str, common)))}` with each method's options ([drift.csv](drift.csv)): "
             "the MD rotor, a spring lattice whose state is positions and velocities only and whose force derives "
             "from a smooth potential, so it is Hamiltonian and a symplectic method keeps a nearby energy (the plane "
             "wave's elastic state carries e, rho and the stress, which spam-ark refuses to split). p is the exponent of "
             "the envelope of |E(t) - E0|/|E0| ~ t^p over the last 90% of the run (0: bounded, 1: secular drift).", "",
             "| method | rtol or dt | steps | RHS evaluations | max \\|dE\\|/E0 | final \\|dE\\|/E0 | p |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['method']} | {knob(r)} | {r['steps']} | {r['rhs_evals']} | {r['energy_err_max']:.2e} | "
                     f"{r['energy_err_final']:.2e} | {r['drift_exponent']:.2f} |")
    lines += ["", drift_reading(rows)]
    update_report(a.out, "drift", lines, a.made)
    return rows


def table_of(path):
    with open(path) as f:
        rs = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rs]) for k in ("t", "total")}


def drift_reading(rows):
    """The symplectic runs' largest exponent against the adaptive runs' smallest, and the
    pair of runs of nearest cost (RHS evaluations) with their final energy errors."""
    ok = [r for r in rows if r["status"] == "ok"]
    fixed = [r for r in ok if finite(r["dt"])]
    adaptive = [r for r in ok if finite(r["rtol"])]
    if not fixed or not adaptive:
        return "Reading: no comparison (a series is missing or did not finish)."
    f_max = max(fixed, key=lambda r: r["drift_exponent"])
    a_min = min(adaptive, key=lambda r: r["drift_exponent"])
    f, ad = min(((f, ad) for f in fixed for ad in adaptive),
                key=lambda p: abs(math.log(p[0]["rhs_evals"] / p[1]["rhs_evals"])))
    return (f"Reading: envelope exponents p of the fixed-step symplectic runs are at most {f_max['drift_exponent']:.2f} "
            f"({f_max['method']} {knob(f_max)}), of the adaptive runs at least {a_min['drift_exponent']:.2f} "
            f"({a_min['method']} {knob(a_min)}). At nearest cost, {f['method']} {knob(f)} ({f['rhs_evals']} RHS "
            f"evaluations) ends with |dE|/E0 = {f['energy_err_final']:.1e}, {ad['method']} at {knob(ad)} "
            f"({ad['rhs_evals']}) with {ad['energy_err_final']:.1e}.")


def drift_chart(rows, series, scene, path):
    """Left: |E(t) - E0|/|E0| against t for every run (log scale; symplectic dashed). Right:
    the final energy error against RHS evaluations, rtol or dt beside each point."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12.5, 4.8))
    for r in rows:
        t, err = series[r["run"]]
        sty = style(r["method"])
        fixed = finite(r["dt"])
        ax1.semilogy(t[1:], np.maximum(err[1:], 1e-17), "--" if fixed else "-", color=sty["color"], lw=0.8,
                     label=f"{r['method']} {knob(r)}" + ("" if r["status"] == "ok" else f" ({r['status'].upper()})"))
        if r["status"] != "ok":
            ax1.semilogy([t[-1]], [max(err[-1], 1e-17)], **UNSTABLE)
    ax1.set_xlabel("t (reduced time units)")
    ax1.set_ylabel("|E(t) - E0| / |E0|")
    ax1.set_title(f"Energy error over time, {scene}", fontsize=9)
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=6, ncol=2)
    for m in dict.fromkeys(r["method"] for r in rows):
        rs = sorted([r for r in rows if r["method"] == m and r["status"] == "ok"], key=lambda r: r["rhs_evals"])
        if not rs:
            continue
        fixed = finite(rs[0]["dt"])
        ax2.loglog([r["rhs_evals"] for r in rs], [max(r["energy_err_final"], 1e-17) for r in rs], **style(m),
                   linestyle="--" if fixed else "-", label=m + (" (fixed dt)" if fixed else " (rtol)"))
        for r in rs:
            ax2.annotate(knob(r, short=True), (r["rhs_evals"], max(r["energy_err_final"], 1e-17)), textcoords="offset points",
                         xytext=(3, 3), fontsize=6, color=style(m)["color"])
    bad = [r for r in rows if r["status"] != "ok"]
    if bad:
        ax2.plot([r["rhs_evals"] for r in bad], [max(r["energy_err_final"], 1e-17) for r in bad], **UNSTABLE,
                 label="unstable / not finished")
    ax2.set_xlabel("right-hand-side evaluations (method + interpolant)")
    ax2.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax2.set_ylabel("|E(t_end) - E0| / |E0|")
    ax2.set_title(f"Final energy error against cost, {scene}", fontsize=9)
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# The tensile-instability variants (PRE Sec. IV): standard SPAM, Monaghan's velocity
# averaging, and standard SPAM with Monaghan's artificial viscosity.
TENSILE_VARIANTS = ["R0=-coordinates R0", "R2=-coordinates R2", "R0 + viscosity=-coordinates R0 -viscosity monaghan"]
DEFAULT_SIGMA0 = [0.005, 0.01, 0.015, 0.02, 0.025, 0.03]


def growth_rate(t, ke):
    """Exponential rate of KE: slope of a least-squares line through ln KE over the second
    half of the run, after the kick has spread into the growing modes (the first half
    holds the transient of the single-particle kick)."""
    t, ke = np.asarray(t), np.asarray(ke)
    sel = (t >= 0.5 * t[-1]) & (ke > 0)
    return float(np.polyfit(t[sel], np.log(ke[sel]), 1)[0]) if sel.sum() >= 3 else float("nan")


def tensile(a):
    """KE growth rate of the tensile crystal (options/tensile.opts: KE growth is the
    measurement, the energy-growth failure bound is off) against the tension sigma0, for
    each variant. Writes tensile.csv, tensile.png and its lines in study.md."""
    base = ["-options_file", os.path.join(REPO, "options", "tensile.opts"), "-snapshot_interval", 0, "-output_interval", 1]
    variants = parse_methods(a.method or TENSILE_VARIANTS)
    sigmas = a.sigma0 or DEFAULT_SIGMA0
    prog, rows, series = Progress(len(variants) * len(sigmas)), [], {}
    for label, opts in variants:
        for s0 in sigmas:
            d = os.path.join(a.out, "tensile", f"{label.replace(' ', '').replace('+', '_')}_{s0:g}")
            code, skipped = spam(a.spam_ark, base + opts + ["-tensile_stress", s0], d)
            prog.step(f"tensile {label}, sigma0 {s0:g}", skipped)
            with open(os.path.join(d, "timeseries.csv")) as f:
                ts = list(csv.DictReader(f))
            t, ke = [float(r["t"]) for r in ts], [float(r["kinetic"]) for r in ts]
            series[(label, s0)] = (t, ke)
            rows.append({"variant": label, "options": " ".join(opts), "sigma0": s0, "exit_code": code,
                         "t_end": t[-1], "ke_initial": ke[0], "ke_final": ke[-1], "ke_max_ratio": max(ke) / ke[0],
                         "rate": growth_rate(t, ke)})
    write_csv(os.path.join(a.out, "tensile.csv"), rows)
    tensile_chart(rows, series, os.path.join(a.out, "tensile.png"))
    lines = ["## Tensile instability", "", "![tensile](tensile.png)", "",
             "KE growth rate (per unit time, fitted to ln KE over the second half of each run; "
             "[tensile.csv](tensile.csv)):", "", "| sigma0 | " + " | ".join(v for v, _ in variants) + " |",
             "|---" * (1 + len(variants)) + "|"]
    for s0 in sigmas:
        lines.append(f"| {s0:g} | " + " | ".join(f"{r['rate']:.4f}" for r in rows if r["sigma0"] == s0) + " |")
    grow = [r for r in rows if r["rate"] > 0.01]
    lines += ["", f"Reading: {len(grow)} of {len(rows)} runs grow faster than 0.01 per unit time: "
              + (", ".join(sorted({r['variant'] for r in grow})) or "none") + "."]
    update_report(a.out, "tensile", lines, a.made)
    return rows


def tensile_chart(rows, series, path):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    sigmas = sorted({r["sigma0"] for r in rows})
    for k, v in enumerate(variants):
        rs = [r for r in rows if r["variant"] == v]
        ax2.plot([r["sigma0"] for r in rs], [r["rate"] for r in rs], **style(v), label=v)
        for j, s0 in enumerate(sigmas):
            t, ke = series[(v, s0)]
            ax1.semilogy(t, ke, ["-", "--", ":"][k % 3], color=plt.cm.viridis(j / max(len(sigmas) - 1, 1)), lw=1,
                         label=f"sigma0 {s0:g}" if k == 0 else None)
    ax1.set_xlabel("t (reduced time units)")
    ax1.set_ylabel("kinetic energy (reduced units)")
    ax1.set_title("Tensile crystal, KE(t): " + ", ".join(f"{v} {['solid', 'dashed', 'dotted'][k % 3]}" for k, v in enumerate(variants)), fontsize=8)
    ax1.legend(fontsize=7)
    ax1.grid(True, which="both", alpha=0.3)
    ax2.axhline(0, color="k", lw=0.8)
    ax2.set_xlabel("tension sigma0 (reduced stress units)")
    ax2.set_ylabel("fitted growth rate of KE (per unit time)")
    ax2.set_title("Tensile crystal (options/tensile.opts): growth rate against tension", fontsize=9)
    ax2.legend(fontsize=8)
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# The small gallery (--small): every study on a scene small enough that all of them run in
# about a minute (tests/run_gallery.py); the numbers are not meant for README.
SMALL = {"precision": dict(scene_opts="-expansion_n 10 -h 3 -ts_max_time 8", t_end=8.0,
                           method=DEFAULT_METHODS[:2], tol=[1e-4, 1e-7], fixed=[DEFAULT_SYMPLECTIC[0], DEFAULT_SYMPLECTIC[2]],
                           dt=[0.2, 0.1]),
         "planewave": dict(scene_opts=f"-options_file {os.path.join(REPO, 'options', 'planewave.opts')} -planewave_nx 12 "
                                      "-planewave_ny 12 -ts_max_time 36", t_end=36.0, method=[DEFAULT_METHODS[1]],
                           tol=[1e-4, 1e-7], fixed=DEFAULT_SYMPLECTIC[:1], dt=[0.45]),
         "stability": dict(scene_opts=None, scene=["chain"], steps=200, rel=0.02,
                           method=["Verlet=-ts_type basicsymplectic:1", "RK4=-ts_type rk -ts_rk_type 4 -ts_adapt_type none:4"]),
         "controller": dict(scene_opts="-expansion_n 10 -h 3 -ts_max_time 60",
                            method=[DEFAULT_CONTROLLERS[1], DEFAULT_CONTROLLERS[4]]),
         "entropy": dict(n=[8, 12], h=3.0),
         "tensile": dict(method=TENSILE_VARIANTS[:1], sigma0=[0.02]),
         "drift": dict(scene_opts=f"-options_file {os.path.join(REPO, 'options', 'rotor-md.opts')} -rotor_n 4 -ts_max_time 200",
                       t_end=200.0, method=[DRIFT_ADAPTIVE[1]], tol=[1e-4], fixed=DEFAULT_SYMPLECTIC[:1], dt=[0.2])}
FULL = {"precision": dict(scene_opts=DEFAULT_SCENE, t_end=16.0, method=None, tol=None, fixed=None, dt=None),
        "planewave": dict(scene_opts=f"-options_file {os.path.join(REPO, 'options', 'planewave.opts')} -ts_max_time 72",
                          t_end=72.0, method=None, tol=None, fixed=None, dt=[0.45]),
        "stability": dict(scene_opts=None, scene=None, method=None, steps=1000),
        "controller": dict(scene_opts="-expansion_n 24 -h 3 -ts_max_time 240", method=None),
        "entropy": dict(n=[32, 48, 64], h=7.0),
        "tensile": dict(method=None, sigma0=None),
        "drift": dict(scene_opts=DRIFT_SCENE, t_end=DRIFT_T_END, method=None, tol=None, fixed=None, dt=None)}
# Standalone studies of other scripts that write their own sections of study.md.
OTHER_STUDIES = ["study_orders.py", "study_norm.py"]


def gallery(a):
    """README's gallery, each part on the scene that shows it; --small: the same parts on
    small scenes (for the test). Then the standalone studies of OTHER_STUDIES that exist."""
    sizes = SMALL if a.small else FULL

    def part(fn, key, **kw):
        b = argparse.Namespace(**vars(a))
        for k, v in dict(sizes[key], **kw).items():
            setattr(b, k, v)
        return fn(b)
    part(precision, "precision")
    part(precision, "planewave", out=os.path.join(a.out, "planewave"))
    part(stability, "stability")
    part(controller, "controller")
    part(entropy, "entropy")
    part(tensile, "tensile")
    part(drift, "drift")
    failed = []
    for name in OTHER_STUDIES:
        script = os.path.join(REPO, "examples", name)
        if not os.path.exists(script):
            print(f"study.py: {name} not found, skipped", flush=True)
            continue
        cmd = [sys.executable, script, "--out", a.out, "--spam-ark", a.spam_ark]
        if a.small:
            helptext = subprocess.run([sys.executable, script, "-h"], capture_output=True, text=True).stdout
            if "--small" not in helptext:
                print(f"study.py: {name} has no --small, skipped in the small gallery", flush=True)
                continue
            cmd.append("--small")
        print("study.py: running", " ".join(relative(w) for w in cmd), flush=True)
        if subprocess.run(cmd).returncode != 0:
            failed.append(name)
    if not a.small:  # the PRE 2004 figures (examples/fig*.png), their runs under DIR/pre2004/
        script = os.path.join(REPO, "examples", "pre2004_figures.py")
        print("study.py: running examples/pre2004_figures.py", flush=True)
        if subprocess.run([sys.executable, script, "--spam-ark", a.spam_ark, "--out", os.path.join(a.out, "pre2004")]).returncode:
            failed.append("pre2004_figures.py")
    if failed:
        raise SystemExit(f"study.py: {', '.join(failed)} failed (the rest of the gallery is written)")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["precision", "stability", "controller", "entropy", "tensile", "drift", "gallery"])
    p.add_argument("--out", required=True)
    p.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    p.add_argument("--scene-opts", help=f"scene options (default '{DEFAULT_SCENE}'; drift: options/rotor-md.opts "
                   "to t = 2000; stability: the presets of --scene)")
    p.add_argument("--scene", action="append", choices=list(STABILITY_SCENES),
                   help="stability: preset scene (repeatable; default all: " + ", ".join(STABILITY_SCENES) + ")")
    p.add_argument("--t-end", type=float, help="end time (must match -ts_max_time in --scene-opts; default 16, drift 2000)")
    p.add_argument("--method", action="append", help="LABEL=OPTIONS (stability: LABEL=OPTIONS:FORCE_EVALS_PER_STEP)")
    p.add_argument("--tol", action="append", type=float)
    p.add_argument("--fixed", action="append", help="precision, drift: fixed-step LABEL=OPTIONS run at each --dt "
                   "(default the symplectic Verlet, Symp3, Symp4 unless --method is given)")
    p.add_argument("--dt", action="append", type=float, help="precision, drift: steps of the --fixed series "
                   "(default " + ", ".join(map(str, DEFAULT_DTS)) + "; drift " + ", ".join(map(str, DRIFT_DTS)) + ")")
    p.add_argument("--small", action="store_true", help="gallery: small scenes (about a minute; for the test)")
    p.add_argument("--dt-guess", type=float, default=0.2, help="stability: first step tried, in the scene's time unit")
    p.add_argument("--time-unit", type=float, default=3.0, help="stability: h/c0 of the scene")
    p.add_argument("--steps", type=int, default=2000, help="stability: steps of each trial run")
    p.add_argument("--growth", type=float, default=1.5, help="stability: KE / initial energy that counts as unstable")
    p.add_argument("--rel", type=float, default=0.005, help="stability: relative width at which the bisection stops")
    p.add_argument("--loose-tol", type=float, default=1e-2, help="controller: the loose tolerance")
    p.add_argument("--n", action="append", type=int, help="entropy: lattice sizes (default 32, 48, 64)")
    p.add_argument("--h", type=float, default=7.0, help="entropy: kernel range")
    p.add_argument("--sigma0", action="append", type=float, help="tensile: tensions (default " + ", ".join(map(str, DEFAULT_SIGMA0)) + ")")
    a = p.parse_args(argv)
    a.made = made_line(argv)
    os.makedirs(a.out, exist_ok=True)
    # OpenMPI makes its session directory under TMPDIR at every start of spam-ark; two
    # starts by different jobs sharing /tmp now and then collide there (exit 1 in
    # orte_session_dir), so this study's runs get a directory of their own.
    private_tmp = tempfile.mkdtemp(prefix="spam-study-")
    os.environ["TMPDIR"] = private_tmp
    if not os.access(a.spam_ark, os.X_OK):
        sys.exit(f"study.py: no spam-ark at {a.spam_ark} (build it, or pass --spam-ark)")
    if a.what in ("precision", "controller"):
        a.scene_opts = a.scene_opts or DEFAULT_SCENE
    if a.what == "drift":
        a.scene_opts = a.scene_opts or DRIFT_SCENE
        a.t_end = a.t_end or DRIFT_T_END
    a.t_end = a.t_end or 16.0
    try:
        if a.what == "gallery":
            gallery(a)
        else:
            a.n = a.n or [32, 48, 64]
            {"precision": precision, "stability": stability, "controller": controller, "entropy": entropy,
             "tensile": tensile, "drift": drift}[a.what](a)
    finally:
        shutil.rmtree(private_tmp, ignore_errors=True)
    print(f"study.py: results in {a.out}")


if __name__ == "__main__":
    main()
