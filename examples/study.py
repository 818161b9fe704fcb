#!/usr/bin/env python3
"""Studies with spam-ark: work-precision, conservation under adaptive stepping, stability.

    study.py precision  [--scene-opts ...] [--method LABEL=OPTIONS ...] [--tol T ...] --out DIR
    study.py stability  [--scene expansion|planewave|chain ...] [--method LABEL=OPTIONS:STAGES ...] --out DIR
    study.py controller [--scene-opts ...] [--method LABEL=OPTIONS ...] [--loose-tol T] --out DIR
    study.py entropy    [--n N ...] --out DIR
    study.py tensile    [--sigma0 S ...] [--method LABEL=OPTIONS ...] --out DIR
    study.py gallery    --out DIR        (the default study of README's gallery: all of the above)

precision: every method x tolerance (or x fixed step, for fixed-step methods) runs in its own
    directory DIR/runs/<label>_<tol>/ (a finished run, one whose manifest.json says ok, max_steps
    or unstable, is skipped: an interrupted study resumes, rerunning with -output_overwrite any
    run that was interrupted or failed). A reference (ARKODE Dormand-Prince 5(4) at rtol 1e-13) is run once
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
    log(dt_n+1/dt_n)). Writes controllers.csv and controllers.png.
entropy: Delta S(t)/(N k ln 4) for several lattice sizes, sum and grid (CiSE 2001 Fig. 3).
tensile: the tensile instability (PRE 2004 Sec. IV, options/tensile.opts): the growth rate of
    KE (a line through ln KE over the second half of each run) against the tension sigma0
    for R0, R2 and R0 with Monaghan viscosity. Writes tensile.csv, tensile.png.
Each study adds its section to DIR/study.md.

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
import time

try:
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    if os.path.realpath(sys.executable) != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("study.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import spam_manifest  # noqa: E402

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
# Fixed-step methods for the stability study, with their force evaluations per step (the
# study measures them from the runs; the number here is used only if no trial was stable).
# PETSc's SSP types take 5 stages (rks2) or 9 (rks3) unless told: SSP3 is the 4-stage
# third-order SSP RK.
DEFAULT_FIXED = ["euler=-ts_type euler:1", "Verlet=-ts_type basicsymplectic:1", "Heun=-ts_type rk -ts_rk_type 2a -ts_adapt_type none:2",
                 "SSP3=-ts_type ssp -ts_ssp_type rks3 -ts_ssp_nstages 4:4", "RK4=-ts_type rk -ts_rk_type 4 -ts_adapt_type none:4",
                 "DP5=-ts_type rk -ts_rk_type 5dp -ts_adapt_type none:6", "V6=-ts_type rk -ts_rk_type 6vr -ts_adapt_type none:9"]
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
    """Runs spam-ark unless outdir already holds a finished run; returns (code, skipped).
    Exit 2 (spam-ark refused the input) is returned rather than raised when refused_ok."""
    summ = os.path.join(outdir, "summary.json")
    if spam_manifest.status(outdir) in spam_manifest.FINISHED and os.path.exists(summ):
        return json.load(open(summ)).get("exit_code", 0), True
    os.makedirs(os.path.dirname(outdir) or ".", exist_ok=True)
    # Not finished (absent, interrupted, failed): run it afresh over whatever is left.
    p = subprocess.run([binary] + [str(a) for a in args] + ["-output_dir", outdir, "-output_overwrite"],
                       capture_output=True, text=True)
    if p.returncode == 2 and refused_ok:
        return 2, False
    if p.returncode not in (0, 3):
        raise SystemExit(f"spam-ark failed (exit {p.returncode}): {' '.join(map(str, args))}\n{p.stderr.strip()}")
    if os.path.exists(summ):  # remember the exit code so a resumed study needs no rerun
        s = json.load(open(summ))
        s["exit_code"] = p.returncode
        with open(summ + ".tmp", "w") as f:
            json.dump(s, f, indent=1)
        os.replace(summ + ".tmp", summ)
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


def precision(a):
    base = a.scene_opts.split()
    common = base + ["-snapshot_interval", a.t_end / 4, "-output_interval", a.t_end / 20, "-snapshot_hdf5", 0]
    refdir = os.path.join(a.out, "reference_" + scene_key(common + REFERENCE))
    methods = parse_methods(a.method or DEFAULT_METHODS)
    tols = a.tol or DEFAULT_TOLS
    wave = planewave_probe(a.spam_ark, common, os.path.join(a.out, "probe"))
    if wave:  # the period is fitted to KE(t): 40 samples (about 10 per KE oscillation over two
        # periods) fix it well; finer ones would also end more steps (every output ends one)
        common[common.index("-output_interval") + 1] = a.t_end / 40
        refdir = os.path.join(a.out, "reference_" + scene_key(common + REFERENCE))
    prog = Progress(1 + len(methods) * len(tols))
    _, skipped = spam(a.spam_ark, common + REFERENCE, refdir)
    prog.step("reference (Dormand-Prince, rtol 1e-13)", skipped)
    ref = snapshots(refdir)
    rs = json.load(open(os.path.join(refdir, "summary.json")))
    box = rs["box_len"]
    rows = []
    for label, opts in methods:
        for tol in tols:
            d = os.path.join(a.out, "runs", f"{label}_{tol:g}")
            code, skipped = spam(a.spam_ark, common + opts + ["-ts_rtol", tol, "-ts_atol", tol * 1e-3], d)
            prog.step(f"{label} rtol {tol:g}", skipped)
            s = json.load(open(os.path.join(d, "summary.json")))
            e = errors(snapshots(d), ref, box) if code == 0 else []
            rows.append({"method": label, "options": " ".join(opts), "rtol": tol, "status": s["status"],
                         "steps": s["steps"], "rejected": s["rejected_steps"], "rhs_evals": s["rhs_evals"],
                         "wall_s": s["wall_time_s"], "rhs_share": s["rhs_time_share"],
                         "err_x_final": e[-1][1] if e else float("nan"), "err_v_final": e[-1][2] if e else float("nan"),
                         "err_x_max": max(x[1] for x in e) if e else float("nan"),
                         "err_v_max": max(x[2] for x in e) if e else float("nan"),
                         "energy_drift": s["energy_rel_drift_max"], "momentum_drift": s["momentum_rel_drift_max"],
                         "angmom_drift": s["angular_momentum_rel_drift_max"],
                         "entropy_diff": abs((s["entropy_sum_final"] or 0) - (rs["entropy_sum_final"] or 0))})
            if wave and len(wave) == 2:
                ref_period, ref_amp = wave_measures(refdir, wave[0])
                wave = wave + (ref_period, 1 - ref_amp)
            if wave:
                rows[-1].update(wave_errors(d, refdir, wave) if code == 0 else wave_errors(None, refdir, wave))
    write_csv(os.path.join(a.out, "precision.csv"), rows)
    charts = precision_charts(rows, a.out)
    report(a.out, rows, charts, common)
    if wave:
        planewave_report(a.out, rows, wave)
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


def planewave_report(out, rows, wave):
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
    update_report(out, "planewave", lines)


def write_csv(path, rows):
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    os.replace(path + ".tmp", path)


MARKERS = "osD^v<>ph*"


def by_method(rows):
    out = {}
    for r in rows:
        if r["status"] == "ok":
            out.setdefault(r["method"], []).append(r)
    return out


def loglog(path, rows, x, y, xlabel, ylabel, title, annotate_tol=False):
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for k, (m, rs) in enumerate(by_method(rows).items()):
        rs = sorted(rs, key=lambda r: r[x])
        xs, ys = [r[x] for r in rs], [max(r[y], 1e-17) for r in rs]
        ax.loglog(xs, ys, marker=MARKERS[k % len(MARKERS)], label=m)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return os.path.basename(path)


def precision_charts(rows, out):
    c = {}
    c["err_rhs"] = loglog(os.path.join(out, "error_vs_rhs.png"), rows, "rhs_evals", "err_x_final",
                          "right-hand-side evaluations", "RMS position error at t_end (length units)",
                          "Work-precision: error against RHS evaluations")
    c["err_wall"] = loglog(os.path.join(out, "error_vs_wall.png"), rows, "wall_s", "err_x_final",
                           "wall time (s, one core)", "RMS position error at t_end (length units)",
                           "Work-precision: error against wall time")
    c["energy"] = loglog(os.path.join(out, "energy_drift_vs_tol.png"), rows, "rtol", "energy_drift",
                         "relative tolerance rtol", "max |E(t) - E0| / |E0|", "Energy drift under adaptive stepping")
    c["angmom"] = loglog(os.path.join(out, "angmom_drift_vs_tol.png"), rows, "rtol", "angmom_drift",
                         "relative tolerance rtol", "max |L(t) - L0| / (sqrt(2 M E0) R_g)",
                         "Angular-momentum drift under adaptive stepping")
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for k, (m, rs) in enumerate(by_method(rows).items()):
        rs = sorted(rs, key=lambda r: r["rtol"])
        ax.loglog([r["rtol"] for r in rs], [r["steps"] for r in rs], marker=MARKERS[k % len(MARKERS)], label=f"{m} accepted")
        ax.loglog([r["rtol"] for r in rs], [max(r["rejected"], 0.5) for r in rs], marker=MARKERS[k % len(MARKERS)],
                  linestyle=":", color=ax.lines[-1].get_color(), label=f"{m} rejected")
    ax.set_xlabel("relative tolerance rtol")
    ax.set_ylabel("steps (rejected: 0 drawn at 0.5)")
    ax.set_title("Accepted and rejected steps")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "steps_vs_tol.png"), dpi=110)
    plt.close(fig)
    c["steps"] = "steps_vs_tol.png"
    return c


def report(out, rows, charts, common):
    ok = [r for r in rows if r["status"] == "ok" and r["err_x_final"] == r["err_x_final"]]
    lines = ["## Work-precision", "", f"Scene: `spam-ark {' '.join(map(str, common))}`; "
             f"reference ARKODE Dormand-Prince at rtol 1e-13. Table: [precision.csv](precision.csv).", ""]
    if ok:
        best = min(ok, key=lambda r: r["err_x_final"])  # the most accurate run
        cheapest = {}
        for r in ok:
            if r["err_x_final"] <= 1e-6 and (r["method"] not in cheapest or r["rhs_evals"] < cheapest[r["method"]]["rhs_evals"]):
                cheapest[r["method"]] = r
        winner = min(cheapest.values(), key=lambda r: r["rhs_evals"]) if cheapest else None
        lines += [f"![error vs RHS]({charts['err_rhs']})", "",
                  (f"Reading: to reach 1e-6 in position, {winner['method']} needs the fewest RHS evaluations "
                   f"({winner['rhs_evals']} at rtol {winner['rtol']:g}); the most accurate run is {best['method']} at "
                   f"rtol {best['rtol']:g} ({best['err_x_final']:.1e}).") if winner else
                  f"Reading: no run reached 1e-6; the most accurate is {best['method']} at rtol {best['rtol']:g}.", ""]
        fastest = min(ok, key=lambda r: r["wall_s"])
        lines += [f"![error vs wall time]({charts['err_wall']})", "",
                  f"Reading: wall time follows RHS evaluations (the RHS takes {100 * np.median([r['rhs_share'] for r in ok]):.0f}% "
                  f"of the wall time, median); the fastest run was {fastest['method']} at rtol {fastest['rtol']:g} "
                  f"({fastest['wall_s']:.2f} s).", ""]
        slope = {}
        for m, rs in by_method(rows).items():
            rs = sorted(rs, key=lambda r: r["rtol"])
            if len(rs) >= 2 and rs[0]["energy_drift"] > 0 and rs[-1]["energy_drift"] > 0:
                slope[m] = math.log(rs[-1]["energy_drift"] / rs[0]["energy_drift"]) / math.log(rs[-1]["rtol"] / rs[0]["rtol"])
        lines += [f"![energy drift]({charts['energy']})", "",
                  "Reading: energy drift against tolerance, fitted slopes " +
                  ", ".join(f"{m} {v:.2f}" for m, v in slope.items()) + " (1 means drift proportional to rtol).", ""]
        worst = max(ok, key=lambda r: r["angmom_drift"])
        lines += [f"![angular momentum drift]({charts['angmom']})", "",
                  f"Reading: the largest angular-momentum drift is {worst['angmom_drift']:.1e} ({worst['method']}, rtol "
                  f"{worst['rtol']:g}); in a periodic box L is not a conserved quantity (images break rotational "
                  f"symmetry), so compare methods here against each other, not against zero.", ""]
        rej = sum(r["rejected"] for r in ok)
        lines += [f"![steps]({charts['steps']})", "",
                  f"Reading: steps grow as rtol tightens; {rej} rejected steps in all {len(ok)} runs.", ""]
    update_report(out, "precision", lines)


def update_report(out, part, lines):
    """Replaces (or appends) the section of one study in DIR/study.md, so the studies run
    one at a time (and resumed) each keep their own lines."""
    path = os.path.join(out, "study.md")
    text = open(path).read() if os.path.exists(path) else "# spam-ark study\n"
    begin, end = f"<!-- {part} -->\n", f"<!-- /{part} -->\n"
    section = begin + "\n".join(lines) + "\n" + end
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
    prog = Progress(len(specs) * len(scenes))
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
    stability_chart(rows, [s[0] for s in scenes], os.path.join(a.out, "stability.png"))
    lines = ["## Stability limits", "", "![stability](stability.png)", "",
             f"Largest stable fixed step by bisection ({a.steps} steps a trial, unstable when KE > {a.growth:g} x the "
             f"initial energy; [stability.csv](stability.csv)). On the chain (a linear oscillator) the closed form is "
             "where the method's stability region leaves the imaginary axis.", "",
             "| scene | method | stages | limit | unit | closed form | error |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['method']} | {r['force_evals_per_step']} | {r['dt_limit']:.4f} | {r['unit']} | "
                     + (f"{r['closed_form']:.4f} | " if r["closed_form"] == r["closed_form"] else "- | ")
                     + (f"{r['error']:+.2%} |" if r["error"] == r["error"] else "- |"))
    lines += ["", "Reading: a method whose |R(iy)| exceeds 1 only slightly past its limit (Dormand-Prince beyond "
              "w dt = 0.997, Euler and Heun everywhere) grows too slowly to reach the bound within a trial, so its "
              "found limit depends on --steps and --growth; RK4, SSP3 and Verlet grow fast past theirs."]
    update_report(a.out, "stability", lines)
    return rows


def stability_chart(rows, scenes, path):
    """One panel per scene: the largest stable step against stages, closed forms hollow."""
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.2 * len(scenes), 4.4), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        rs = [r for r in rows if r["scene"] == scene]
        for k, r in enumerate(rs):
            m = MARKERS[k % len(MARKERS)]
            ax.plot(r["force_evals_per_step"], r["dt_limit"], m, color=f"C{k}", ms=8, label=r["method"])
            if r["closed_form"] == r["closed_form"]:
                ax.plot(r["force_evals_per_step"], r["closed_form"], m, color=f"C{k}", ms=13, mfc="none")
        ax.set_xlabel("force evaluations per step (stages)")
        ax.set_ylabel(f"largest stable step (units of {rs[0]['unit'] if rs else '?'})")
        ax.set_title(scene + (" (hollow: closed form)" if scene == "chain" else ""), fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Stability limit of fixed-step methods")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


DEFAULT_CONTROLLERS = ["ARKODE I=-arkode_adapt i", "ARKODE PI=-arkode_adapt pi", "ARKODE PID=-arkode_adapt pid",
                       "PETSc basic (rk 5dp)=-ts_type rk -ts_rk_type 5dp -ts_adapt_type basic",
                       "PETSc dsp (rk 5dp)=-ts_type rk -ts_rk_type 5dp -ts_adapt_type dsp"]


def controller(a):
    """Adaptive steps near the stability limit: a loose tolerance lets accuracy allow steps
    that stability does not, so the controller must find the limit by rejections. Charted:
    dt(t) per controller, rejections marked; the oscillation is the RMS of log(dt_n+1/dt_n)."""
    common = a.scene_opts.split() + ["-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0,
                                     "-ts_rtol", a.loose_tol, "-ts_atol", a.loose_tol]
    specs = a.method or DEFAULT_CONTROLLERS
    prog, rows = Progress(len(specs)), []
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    for k, spec in enumerate(specs):
        label, _, opts = spec.partition("=")
        d = os.path.join(a.out, "controller", label.replace(" ", "_").replace("(", "").replace(")", ""))
        code, skipped = spam(a.spam_ark, common + opts.split(), d)
        prog.step(label, skipped)
        with open(os.path.join(d, "steps.csv")) as f:
            st = list(csv.DictReader(f))
        t = np.array([float(r["t"]) for r in st])
        dt = np.array([float(r["dt"]) for r in st])
        rej = np.array([int(r["rejected"]) for r in st])
        keep = np.array([r["limit"] != "output" for r in st])
        ratio = np.diff(np.log(dt[keep])) if keep.sum() > 2 else np.array([0.0])
        line, = ax.semilogy(t, dt, "-", lw=1, label=f"{label}: {rej[-1] if len(rej) else 0} rejected")
        jumps = np.nonzero(np.diff(np.concatenate([[0], rej])) > 0)[0]
        ax.semilogy(t[jumps], dt[jumps], "x", color=line.get_color())
        rows.append({"controller": label, "options": opts, "exit_code": code, "steps": len(st),
                     "rejected": int(rej[-1]) if len(rej) else 0, "dt_median": float(np.median(dt)) if len(dt) else 0.0,
                     "oscillation_rms_log_ratio": float(np.sqrt(np.mean(ratio ** 2)))})
    ax.set_xlabel("t")
    ax.set_ylabel("accepted step dt (x: step after a rejection)")
    ax.set_title(f"Controllers near the stability limit (rtol = atol = {a.loose_tol:g})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "controllers.png"), dpi=110)
    plt.close(fig)
    write_csv(os.path.join(a.out, "controllers.csv"), rows)
    return rows


def entropy(a):
    rows, fig = [], plt.figure(figsize=(6.4, 4.6))
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
        rows.append({"n": n, "N": n * n, "h": a.h, "dS_sum_final": s["dS_sum_ratio_final"], "dS_grid_final": s["dS_grid_ratio_final"]})
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel("t / tau (sound traversal times)")
    ax.set_ylabel("Delta S / (N k ln 4)")
    ax.set_title(f"Entropy of the fourfold free expansion, h = {a.h:g}")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "entropy.png"), dpi=110)
    plt.close(fig)
    write_csv(os.path.join(a.out, "entropy.csv"), rows)
    return rows


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
    update_report(a.out, "tensile", lines)
    return rows


def tensile_chart(rows, series, path):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    sigmas = sorted({r["sigma0"] for r in rows})
    for k, v in enumerate(variants):
        rs = [r for r in rows if r["variant"] == v]
        ax2.plot([r["sigma0"] for r in rs], [r["rate"] for r in rs], marker=MARKERS[k], label=v)
        for j, s0 in enumerate(sigmas):
            t, ke = series[(v, s0)]
            ax1.semilogy(t, ke, ["-", "--", ":"][k % 3], color=plt.cm.viridis(j / max(len(sigmas) - 1, 1)), lw=1,
                         label=f"sigma0 {s0:g}" if k == 0 else None)
    ax1.set_xlabel("t")
    ax1.set_ylabel("kinetic energy")
    ax1.set_title("KE(t): " + ", ".join(f"{v} {['solid', 'dashed', 'dotted'][k % 3]}" for k, v in enumerate(variants)), fontsize=8)
    ax1.legend(fontsize=7)
    ax1.grid(True, which="both", alpha=0.3)
    ax2.axhline(0, color="k", lw=0.8)
    ax2.set_xlabel("tension sigma0")
    ax2.set_ylabel("fitted growth rate of KE (per unit time)")
    ax2.set_title("Tensile instability: growth rate against tension", fontsize=10)
    ax2.legend(fontsize=8)
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def gallery(a):
    """The default study behind README's gallery: each part on the scene that shows it."""
    def part(fn, **kw):
        b = argparse.Namespace(**vars(a))
        for k, v in kw.items():
            setattr(b, k, v)
        return fn(b)
    part(precision, scene_opts=DEFAULT_SCENE, t_end=16.0, method=None, tol=None)
    part(precision, scene_opts=f"-options_file {os.path.join(REPO, 'options', 'planewave.opts')} -ts_max_time 72",
         t_end=72.0, method=None, tol=None, out=os.path.join(a.out, "planewave"))
    part(stability, scene_opts=None, scene=None, method=None, steps=1000)
    part(controller, scene_opts="-expansion_n 24 -h 3 -ts_max_time 240", method=None)
    part(entropy, n=[32, 48, 64], h=7.0)
    part(tensile, method=None, sigma0=None)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["precision", "stability", "controller", "entropy", "tensile", "gallery"])
    p.add_argument("--out", required=True)
    p.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    p.add_argument("--scene-opts", help=f"scene options (default '{DEFAULT_SCENE}'; stability: the presets of --scene)")
    p.add_argument("--scene", action="append", choices=list(STABILITY_SCENES),
                   help="stability: preset scene (repeatable; default all: " + ", ".join(STABILITY_SCENES) + ")")
    p.add_argument("--t-end", type=float, default=16.0, help="end time (must match -ts_max_time in --scene-opts)")
    p.add_argument("--method", action="append", help="LABEL=OPTIONS (stability: LABEL=OPTIONS:FORCE_EVALS_PER_STEP)")
    p.add_argument("--tol", action="append", type=float)
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
    os.makedirs(a.out, exist_ok=True)
    if not os.access(a.spam_ark, os.X_OK):
        sys.exit(f"study.py: no spam-ark at {a.spam_ark} (build it, or pass --spam-ark)")
    if a.what in ("precision", "controller"):
        a.scene_opts = a.scene_opts or DEFAULT_SCENE
    if a.what == "gallery":
        gallery(a)
    else:
        a.n = a.n or [32, 48, 64]
        {"precision": precision, "stability": stability, "controller": controller, "entropy": entropy,
         "tensile": tensile}[a.what](a)
    print(f"study.py: results in {a.out}")


if __name__ == "__main__":
    main()
