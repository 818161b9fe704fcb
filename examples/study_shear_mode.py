#!/usr/bin/python3
"""The shear mode of the viscous SPAM gas against c h / nu: does a transverse velocity mode
decay at the Navier-Stokes rate nu k^2 where pressure dominates viscosity?

    study_shear_mode.py [--quick] [--kernel K ...] [--ratio X ...] [--lattice ordered|disordered ...]
                        [--variant NAME="OPTIONS" ...] [--efolds F] [--out DIR] [--chart PNG] [--doc MD]

The scene (the file scene, written by this script): a 32 x 32 unit square lattice in the
periodic box 32 x 32, particles at (i + 0.5, j + 0.5), m = 1, gas with gamma = 2 and e = 1
per particle (P ~ 1, c = sqrt(gamma (gamma - 1) e) = sqrt 2), vx = U sin(k y) with U = 0.01,
k = 2 pi / 32, h = 3. The continuum answer is A(t) = U exp(-nu k^2 t), nu = eta / rho with
rho the mean summed density (1.003 for Lucy's kernel on the lattice). The sweep is over
X = c h / nu: e and so c (Mach U/c = 0.007) stay fixed and nu = c h / X, so that viscous
heating (U^2/4 against e = 1) never changes the sound speed, and the conductivity is 2 eta
(the ratio of the scene this study reproduces). Each run lasts --efolds e-foldings
1/(nu k^2) of the exact decay; the explicit step is bounded by about h/c and h^2/nu, so a
run takes about max(X, 1) * 26/h^2 / C steps: X = 1e3 is the long one.

Lattices: "ordered" is the square lattice itself; "disordered" is the lattice displaced by
a seeded Gaussian jitter of 0.1 spacing per axis (seed 1, rms displacement 0.14 spacing),
then relaxed for each kernel by --relax-cycles runs of 30 time units with eta = 1, bulk
viscosity 1 and conductivity 2, velocities zeroed and e reset to 1 between runs (cached in
DIR/glass_<kernel>.csv). The relaxed glass is still not at rest under every kernel: its
residual motion is the noise the projection must tolerate (its rms velocity is in the table).

Measurement. At every CSV snapshot vx is fitted by least squares to a sin(k y) + b cos(k y)
+ c at the particles' current y (a least-squares projection, not 2 <vx sin ky>, because on
the glass sum sin^2(k y_i) != N/2); A(t) = a(t). From A(t):
- decay rate s: minus the slope of a least-squares line through ln|A| at the envelope
  points, t = 0 and every local maximum of |A| (every sample when |A| has no interior
  maximum: a monotone decay). A damped ringing A = e^{-st}(cos wt + ...) has its |A| peaks on
  e^{-st}, so ringing does not bias s, and near-zero samples at the zero crossings (whose
  logarithm would dominate a fit of all samples) are never used. A nonlinear fit of
  e^{-st}(a cos wt + b sin wt) was rejected: on the runs that disorder or crash A(t) is not
  of that form and the fit wanders, while the envelope still says how fast the mode is lost.
- ringing frequency w: from the zero crossings of A(t) (linear interpolation between
  samples), w = pi (n - 1) / (t_n - t_1) for n >= 2 crossings, else 0: an overdamped mode
  started at full speed crosses zero once, so one crossing is not ringing.
- flags: "failed" (spam-ark exit != 0, e.g. 3 unstable), "grew" (|A| above 1.05 U at some
  time, or s <= 0), "disordered" (rms transverse displacement |y_i(t) - y_i(0)| above 0.2
  spacing at some snapshot: an ideal shear flow moves no particle across the layers).
The same fit is applied to the ordered lattice's linear theory (v'' + a v' + w2 v = 0, a =
nu |K|^2, w2 = 2 (gamma - 1) e D_ee / rho from the lattice sums of tests/lattice_modes.py,
here for every kernel), drawn as thin lines: where a run leaves them the cause is not the
linearised lattice.

Outputs in DIR (default build/shear_mode): shear_mode.csv and shear_mode.json (every case),
shear_mode.md (the tables and readings), runs/<case>/ (each run's diagnostics and mode.json,
its amplitude series; the CSV snapshots are deleted once read unless --keep-snapshots); the
chart (default DIR/shear_mode.png); with --doc PATH, the part of PATH between the markers
<!-- shear_mode:generated --> and <!-- /shear_mode:generated --> is replaced by shear_mode.md.
A case whose mode.json was made by the same spam-ark build with the same options is not run
again (an interrupted study resumes). Runs one spam-ark at a time (-threads 1).

Needs numpy and matplotlib (/usr/bin/python3 on Debian).
"""
import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import textwrap
import time

try:
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
except ImportError:
    if os.path.realpath(sys.executable) != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("study_shear_mode.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402
from chart_style import style, UNSTABLE  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
N, L, H, U, E0, GAMMA = 32, 32.0, 3.0, 0.01, 1.0, 2.0
K = 2 * math.pi / L
C = math.sqrt(GAMMA * (GAMMA - 1) * E0)
KAPPA_PER_ETA = 2.0
KERNELS = ["lucy", "cubic_spline", "quintic_spline", "wendland_c2", "wendland_c4", "wendland_c6"]
DEFAULT_RATIOS = [1e-2, 1e-1, 1.0, 10.0, 31.6227766, 1e2, 316.227766, 1e3]
QUICK = dict(kernels=["wendland_c4"], ratios=[1e-2, 1.0, 1e2], lattices=["ordered"])
GROW, DISORDER = 1.05, 0.2
# Decay ratios at or below zero (a growing mode) are drawn at this floor of the log axis.
FLOOR = 0.03
JITTER, SEED = 0.1, 1


# --- kernels (2D; docs/kernels.md): w = C2 h^-2 F(s), w'/r = cgrad C2 h^-4 G(s), w'' = cgrad C2 h^-4 H(s)

def _p(x):
    return np.maximum(x, 0.0)


KERNEL_SHAPES = {
    "lucy": (5 / math.pi, -12.0,
             lambda s, t: (1 + 3 * s) * t**3, lambda s, t: t**2, lambda s, t: t * (1 - 3 * s)),
    "wendland_c2": (7 / math.pi, -20.0,
                    lambda s, t: (1 + 4 * s) * t**4, lambda s, t: t**3, lambda s, t: t**2 * (1 - 4 * s)),
    "wendland_c4": (9 / math.pi, -56 / 3,
                    lambda s, t: t**6 * (1 + 6 * s + 35 / 3 * s**2), lambda s, t: t**5 * (1 + 5 * s),
                    lambda s, t: t**4 * (1 + 4 * s - 35 * s**2)),
    "wendland_c6": (78 / (7 * math.pi), -22.0,
                    lambda s, t: t**8 * (1 + 8 * s + 25 * s**2 + 32 * s**3),
                    lambda s, t: t**7 * (1 + 7 * s + 16 * s**2),
                    lambda s, t: t**6 * (1 + 6 * s - 15 * s**2 - 160 * s**3)),
    "cubic_spline": (40 / (7 * math.pi), -6.0,
                     lambda s, t: 2 * t**3 - _p(1 - 2 * s)**3,
                     lambda s, t: np.where(s < 0.5, 2 - 3 * s, t**2 / np.maximum(s, 0.5)),
                     lambda s, t: 4 * _p(1 - 2 * s) - 2 * t),
    "quintic_spline": (2079 / (239 * math.pi), -405 / 22,
                       lambda s, t: 81 / 22 * (t**5 - 6 * _p(2 / 3 - s)**5 + 15 * _p(1 / 3 - s)**5),
                       lambda s, t: np.where(s < 1 / 3, 8 / 9 - 8 * s**2 + 10 * s**3,
                                             (t**4 - 6 * _p(2 / 3 - s)**4) / np.maximum(s, 1 / 3)),
                       lambda s, t: -4 * t**3 + 24 * _p(2 / 3 - s)**3 - 60 * _p(1 / 3 - s)**3),
}


def kernel_parts(kernel, r):
    """w, g = w'/r and w'' of a 2D kernel at distances r."""
    c2, cgrad, F, G, Hs = KERNEL_SHAPES[kernel]
    s = np.asarray(r, float) / H
    t = _p(1 - s)
    inside = s < 1
    w = np.where(inside, c2 / H**2 * F(s, t), 0.0)
    g = np.where(inside, cgrad * c2 / H**4 * G(s, t), 0.0)
    d2 = np.where(inside, cgrad * c2 / H**4 * Hs(s, t), 0.0)
    return w, g, d2


def summed_density(kernel, x, y):
    """Summed density (m = 1, self term included) at every particle of the periodic box."""
    dx = x[:, None] - x[None, :]
    dy = y[:, None] - y[None, :]
    dx -= L * np.round(dx / L)
    dy -= L * np.round(dy / L)
    w, _, _ = kernel_parts(kernel, np.hypot(dx, dy))
    return w.sum(1)


def lattice_theory(kernel, eta, e0=E0):
    """The transverse mode (k along y, v along x) on the perfect lattice, linearised as in
    tests/lattice_modes.py: v'' + a v' + w2 v = 0, a = (eta/rho) |K|^2, w2 = 2 (gamma-1) e0
    D_ee / rho. Returns (rho, |K|^2/k^2, a, w2)."""
    n = int(math.floor(H))
    s = np.array(list(itertools.product(range(-n, n + 1), repeat=2)), float)
    r = np.linalg.norm(s, axis=1)
    s, r = s[r < H], r[r < H]
    w, g, d2 = kernel_parts(kernel, r)
    rho = w.sum()
    ks = s[:, 1] * K
    Ky = -(g * s[:, 1] * np.sin(ks)).sum() / rho
    nz = r > 0
    hess = g[nz] + (d2[nz] - g[nz]) / r[nz] ** 2 * s[nz, 0] ** 2
    dee = ((1 - np.cos(ks[nz])) * hess).sum()
    return rho, Ky * Ky / (K * K), eta / rho * Ky * Ky, 2 * (GAMMA - 1) * e0 / rho * dee


def theory_amplitude(a, w2, t):
    """A(t)/U of v'' + a v' + w2 v = 0 with v(0) = U and the displacement 0."""
    lam = np.roots([1.0, a, w2]).astype(complex)
    l1, l2 = lam
    t = np.asarray(t, float)
    if abs(l1 - l2) < 1e-12 * max(abs(l1), 1e-300):
        return np.real((1 + l1 * t) * np.exp(l1 * t))
    return np.real((l1 * np.exp(l1 * t) - l2 * np.exp(l2 * t)) / (l1 - l2))


# --- the measurement

def envelope_rate(t, A):
    """Decay rate from a line through ln|A| at t = 0 and the local maxima of |A| (all samples
    when there is no interior maximum). Returns (s, the envelope points used)."""
    t, m = np.asarray(t, float), np.abs(np.asarray(A, float))
    idx = [0] + [i for i in range(1, len(m) - 1) if m[i] >= m[i - 1] and m[i] >= m[i + 1] and m[i] > 0]
    if len(idx) == 1:
        idx = [i for i in range(len(m)) if m[i] > 0]
    if len(idx) < 2:
        return float("nan"), idx
    slope = np.polyfit(t[idx], np.log(m[idx]), 1)[0]
    return float(-slope), idx


def ringing(t, A):
    """(w, crossings): w = pi (n-1) / (t_n - t_1) over the n zero crossings of A, 0 if n < 2."""
    t, A = np.asarray(t, float), np.asarray(A, float)
    cross = []
    for i in range(len(A) - 1):
        if A[i] == 0 and i > 0:
            cross.append(t[i])
        elif A[i] * A[i + 1] < 0:
            cross.append(t[i] + (t[i + 1] - t[i]) * A[i] / (A[i] - A[i + 1]))
    if len(cross) < 2:
        return 0.0, len(cross)
    return math.pi * (len(cross) - 1) / (cross[-1] - cross[0]), len(cross)


def project(path, y0):
    """(a, b, residual rms, rms vy, rms transverse displacement) of one CSV snapshot, rows in
    id order; y0 the initial y of every particle."""
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    ids = np.array([int(float(r["id"])) for r in rows])
    order = np.argsort(ids)
    y = np.array([float(r["y"]) for r in rows])[order]
    vx = np.array([float(r["vx"]) for r in rows])[order]
    vy = np.array([float(r["vy"]) for r in rows])[order]
    M = np.column_stack([np.sin(K * y), np.cos(K * y), np.ones_like(y)])
    coef, *_ = np.linalg.lstsq(M, vx, rcond=None)
    res = vx - M @ coef
    dy = y - y0
    dy -= L * np.round(dy / L)
    return (float(coef[0]), float(coef[1]), float(np.sqrt(np.mean(res**2))), float(np.sqrt(np.mean(vy**2))),
            float(np.sqrt(np.mean(dy**2))))


# --- scenes

def write_particles(path, x, y, vx, vy=None, e=None):
    vy = np.zeros_like(x) if vy is None else vy
    e = np.full_like(x, E0) if e is None else e
    with open(path + ".tmp", "w") as f:
        f.write("x,y,vx,vy,e\n")
        for row in zip(x, y, vx, vy, e):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    os.replace(path + ".tmp", path)


def read_particles(path):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    if rows and "id" in rows[0]:
        rows.sort(key=lambda r: int(float(r["id"])))
    return np.array([float(r["x"]) for r in rows]), np.array([float(r["y"]) for r in rows])


def lattice():
    i, j = np.meshgrid(np.arange(N), np.arange(N))
    return i.ravel() + 0.5, j.ravel() + 0.5


def base_args(kernel):
    return ["-scene", "file", "-dim", 2, "-box_len", L, "-material", "gas", "-gas_gamma", GAMMA, "-h", H,
            "-kernel", kernel, "-threads", 1]


def spam(binary, args, outdir, timeout=3600):
    os.makedirs(outdir, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1", OMPI_MCA_pml="ob1")
    p = subprocess.run([binary] + [str(a) for a in args] + ["-output_dir", outdir, "-output_overwrite"],
                       capture_output=True, text=True, env=env, timeout=timeout)
    return p.returncode, p.stderr.strip()


def glass(a, kernel):
    """The disordered start for one kernel (cached): the seeded jittered lattice relaxed by
    viscous runs with quenches between them."""
    path = os.path.join(a.out, f"glass_{kernel}_{a.relax_cycles}.csv")
    if os.path.exists(path):
        return read_particles(path)
    rng = np.random.default_rng(SEED)
    x, y = lattice()
    x = (x + rng.normal(0, JITTER, x.size)) % L
    y = (y + rng.normal(0, JITTER, y.size)) % L
    work = os.path.join(a.out, "glass_work")
    os.makedirs(work, exist_ok=True)
    for _ in range(a.relax_cycles):
        write_particles(os.path.join(work, "in.csv"), x, y, 0 * x)
        code, err = spam(a.spam_ark, base_args(kernel) + [
            "-file_path", os.path.join(work, "in.csv"), "-viscosity_shear", 1, "-viscosity_bulk", 1, "-conductivity", 2,
            "-ts_max_time", 30, "-snapshot_interval", 0, "-output_interval", 0,
            "-final_csv", os.path.join(work, "out.csv")], os.path.join(work, "run"))
        if code != 0:
            raise SystemExit(f"relaxing the glass for {kernel} failed (exit {code}): {err}")
        x, y = read_particles(os.path.join(work, "out.csv"))
    write_particles(path, x, y, 0 * x)
    shutil.rmtree(work, ignore_errors=True)
    return x, y


# --- one case

def case_name(lat, kernel, variant, X):
    return f"{lat}_{kernel}_{re.sub(r'[^A-Za-z0-9_.-]', '_', variant)}_X{X:.4g}" + ("" if U == 0.01 else f"_U{U:g}")


def run_key(args, out, binary, x, y):
    """What makes a stored run reusable: its options (the study's directory left out, so a
    moved study is still reused), the spam-ark build and the start's positions."""
    start = hashlib.sha1(np.ascontiguousarray(x).tobytes() + np.ascontiguousarray(y).tobytes()).hexdigest() + repr(U)
    return hashlib.sha1((args.replace(out, "OUT") + spam_manifest.binary_id(binary) + start).encode()).hexdigest()


def run_case(a, lat, kernel, variant, opts, X):
    if lat == "ordered":
        x, y = lattice()
    else:
        x, y = glass(a, kernel)
    rho = summed_density(kernel, x, y)
    rho_mean = float(rho.mean())
    nu = C * H / X
    eta = nu * rho_mean
    rate = nu * K * K
    t_end = a.efolds / rate
    _, K2ratio, ath, w2 = lattice_theory(kernel, eta)
    # Snapshots: at least 40 per run, and about 12 per period of the lattice's ringing.
    per = 2 * math.pi / math.sqrt(w2) if w2 > 0 else float("inf")
    nsnap = int(min(a.max_snapshots, max(40, math.ceil(12 * t_end / per))))
    dt_snap = t_end / nsnap
    name = case_name(lat, kernel, variant, X)
    d = os.path.join(a.out, "runs", name)
    pfile = os.path.join(d, "particles.csv")
    args = base_args(kernel) + ["-file_path", pfile, "-viscosity_shear", repr(eta),
                                "-conductivity", repr(KAPPA_PER_ETA * eta), "-ts_max_time", repr(t_end),
                                "-output_interval", repr(dt_snap), "-snapshot_interval", repr(dt_snap),
                                "-snapshot_hdf5", 0, "-snapshot_csv", 1, "-snapshot_max", nsnap + 5] + opts
    key = run_key(" ".join(map(str, args)), a.out, a.spam_ark, x, y)
    mode_path = os.path.join(d, "mode.json")
    rec = None
    if os.path.exists(mode_path):
        rec = json.load(open(mode_path))
        if rec.get("key") != key:
            rec = None
    skipped = rec is not None
    if rec is None:
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        write_particles(pfile, x, y, U * np.sin(K * y))
        t0 = time.time()
        code, err = spam(a.spam_ark, args, os.path.join(d, "out"))
        wall = time.time() - t0
        out = os.path.join(d, "out")
        ts, A, B, res, vy, dy = [], [], [], [], [], []
        status = spam_manifest.status(out)
        if status is not None:
            for t, p in spam_manifest.files(spam_manifest.read(out), out, "snapshot_csv"):
                if not os.path.exists(p):
                    continue
                pa, pb, pr, pv, pd = project(p, y)
                ts.append(t), A.append(pa), B.append(pb), res.append(pr), vy.append(pv), dy.append(pd)
                if not a.keep_snapshots:
                    os.remove(p)
        rec = {"key": key, "exit_code": code, "status": status, "stderr": err[-2000:], "wall_s": wall,
               "t": ts, "a": A, "b": B, "residual": res, "vy": vy, "dy": dy, "rho_mean": rho_mean,
               "args": " ".join(map(str, args))}
        with open(mode_path + ".tmp", "w") as f:
            json.dump(rec, f)
        os.replace(mode_path + ".tmp", mode_path)
    t, A = np.array(rec["t"]), np.array(rec["a"])
    s, _ = envelope_rate(t, A) if len(t) > 1 else (float("nan"), [])
    w, ncross = ringing(t, A) if len(t) > 1 else (0.0, 0)
    tt = np.linspace(0, t_end, nsnap + 1)
    At = theory_amplitude(ath, w2, tt)
    s_th, _ = envelope_rate(tt, At)
    w_th, _ = ringing(tt, At)
    if lat != "ordered":  # the linear theory is that of the perfect lattice
        s_th = w_th = float("nan")
    failed = rec["exit_code"] != 0 or len(t) < 2
    grew = bool(len(A) and (np.max(np.abs(A)) > GROW * U or not (s > 0)))
    disordered = bool(len(rec["dy"]) and max(rec["dy"]) > DISORDER)
    row = {"lattice": lat, "kernel": kernel, "variant": variant, "options": " ".join(opts), "ch_over_nu": X,
           "e": E0, "c": C, "nu": nu, "eta": eta, "rho_mean": rho_mean, "nu_k2": rate, "t_end": t_end,
           "snapshots": len(t), "decay_ratio": s / rate, "ringing_ratio": w / rate, "crossings": ncross,
           "theory_decay_ratio": s_th / rate, "theory_ringing_ratio": w_th / rate, "laplacian_factor": K2ratio,
           "final_amplitude": float(A[-1] / U) if len(A) else float("nan"),
           "max_dy": max(rec["dy"]) if rec["dy"] else float("nan"),
           "noise_vy_over_U": max(rec["vy"]) / U if rec["vy"] else float("nan"),
           "exit_code": rec["exit_code"], "failed": failed, "grew": grew, "disordered": disordered,
           "flag": ",".join(f for f, on in (("failed", failed), ("grew", grew), ("disordered", disordered)) if on),
           "wall_s": rec["wall_s"]}
    return row, skipped


# --- chart and tables

VARIANT_MARKERS = "osD^v<>ph*"
VARIANT_LINES = ["-", "--", "-.", (0, (6, 2, 1, 2, 1, 2))]  # ":" is the linear theory


def variant_style(i):
    return VARIANT_MARKERS[i % len(VARIANT_MARKERS)], VARIANT_LINES[i % len(VARIANT_LINES)]


def chart(rows, path, readings, lattices, variants, kernels, efolds):
    # One kernel: each variant its own colour (with several, colour is the kernel, marker the variant).
    by_variant = len(kernels) == 1
    width = max(11.0, 6.5 * len(lattices))
    text = [piece for line in readings for piece in textwrap.wrap(line, int(width * 15), subsequent_indent="    ")]
    height = 9.6 + 0.16 * len(text)
    fig, axes = plt.subplots(2, len(lattices), figsize=(width, height), squeeze=False)
    for col, lat in enumerate(lattices):
        axd, axw = axes[0, col], axes[1, col]
        for ax in (axd, axw):
            ax.set_xscale("log")
            ax.grid(True, which="both", alpha=0.3)
        axd.set_yscale("log")
        axw.set_yscale("symlog", linthresh=0.1)
        axd.axhspan(0.95, 1.05, color="green", alpha=0.15, lw=0)
        axd.axhline(1.0, color="green", lw=0.8)
        for kernel in kernels:
            for vi, v in enumerate(variants):
                marker, ls = variant_style(vi)
                colour = f"C{vi}" if by_variant else style(kernel)["color"]
                rs = sorted((r for r in rows if r["lattice"] == lat and r["kernel"] == kernel and r["variant"] == v),
                            key=lambda r: r["ch_over_nu"])
                if not rs:
                    continue
                X = [r["ch_over_nu"] for r in rs]
                for ax, key in ((axd, "decay_ratio"), (axw, "ringing_ratio")):
                    Y = np.array([r[key] for r in rs], float)
                    if key == "decay_ratio":
                        Y = np.clip(np.where(np.isfinite(Y) & (Y > 0), Y, FLOOR), FLOOR, 1e3)
                    ax.plot(X, Y, linestyle=ls, color=colour, lw=1.2)
                    good = [i for i, r in enumerate(rs) if not r["flag"]]
                    bad = [i for i, r in enumerate(rs) if r["flag"]]
                    ax.plot([X[i] for i in good], Y[good], marker, color=colour, ms=6, linestyle="none")
                    ax.plot([X[i] for i in bad], Y[bad], marker, color=colour, mfc="none", ms=6, linestyle="none")
                    ax.plot([X[i] for i in bad], Y[bad], **UNSTABLE)
                    if lat == "ordered" and vi == 0:
                        # Where the theory's mode grows (a negative stiffness: the square
                        # lattice itself is unstable) its rate is drawn at the axis floor.
                        th = np.array([r["theory_" + key] for r in rs], float)
                        if key == "decay_ratio":
                            th = np.clip(np.where(th > 0, th, FLOOR), FLOOR, 1e3)
                        ax.plot(X, th, ":", color="grey" if by_variant else colour, lw=0.9, alpha=0.9)
        finite = [r["decay_ratio"] for r in rows if math.isfinite(r["decay_ratio"])]
        axd.set_ylim(FLOOR * 0.7, max([10.0] + [min(v, 1e3) * 1.4 for v in finite]))
        axd.axhline(FLOOR, color="grey", lw=0.6, ls="--")
        axd.text(0.012, FLOOR * 1.08, "s <= 0 (the mode grew) drawn here", fontsize=7, color="grey")
        wmax = max([1.0] + [r["ringing_ratio"] for r in rows if math.isfinite(r["ringing_ratio"])]
                   + [r["theory_ringing_ratio"] for r in rows if math.isfinite(r["theory_ringing_ratio"])])
        axw.set_ylim(-0.05, wmax * 2)
        axd.set_title(f"{lat} start: decay rate of the shear mode", fontsize=10)
        axw.set_title(f"{lat} start: ringing frequency of the shear mode", fontsize=10)
        axd.set_ylabel("decay rate s / (nu k^2)  (1 = Navier-Stokes)")
        axw.set_ylabel("ringing frequency w / (nu k^2)  (0 = no ringing)")
        for ax in (axd, axw):
            ax.set_xlabel("c h / nu  (sound speed x kernel range / kinematic viscosity; dimensionless)")
    handles = [Line2D([], [], color="black" if by_variant else style(k)["color"], lw=2,
                      label=f"kernel {k}" if by_variant else k) for k in kernels]
    handles += [Line2D([], [], color=f"C{i}" if by_variant else "grey", marker=variant_style(i)[0],
                       linestyle=variant_style(i)[1], label=f"variant {v}") for i, v in enumerate(variants)]
    handles += [Line2D([], [], **UNSTABLE, label="flagged: failed, grew or disordered (kernel marker hollow)"),
                Line2D([], [], color="grey", linestyle=":", lw=0.8, label="linear theory, perfect lattice"),
                matplotlib.patches.Patch(color="green", alpha=0.15, label="goal: within 5 % of nu k^2")]
    fig.legend(handles=handles, loc="upper center", ncol=4, fontsize=8, bbox_to_anchor=(0.5, 1 - 0.5 / height))
    fig.suptitle("Shear mode vx = U sin(k y) of the viscous SPAM gas (file scene): 32 x 32 particles, periodic box 32,\n"
                 f"h = 3, gamma = 2, e = 1, U = {U:g} (Mach {U / C:.2g}), k = 2 pi/32; each run {efolds:g} "
                 "e-folding(s) 1/(nu k^2) of the exact decay",
                 fontsize=10, y=1 - 0.06 / height, va="top")
    fig.text(0.01, 0.08 / height, "\n".join(text), fontsize=7.5, family="monospace", va="bottom")
    fig.subplots_adjust(top=1 - 1.55 / height, bottom=(0.85 + 0.16 * len(text)) / height, left=0.07, right=0.98,
                        hspace=0.32, wspace=0.2)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def fmt(x, digits=3):
    if not isinstance(x, (int, float)) or not math.isfinite(x):
        return "nan"
    return f"{x:.{digits}g}"


def readings_of(rows, variants, lattices):
    out = []
    for v in variants:
        for lat in lattices:
            rs = [r for r in rows if r["variant"] == v and r["lattice"] == lat]
            if not rs:
                continue
            ok = [r for r in rs if not r["flag"] and math.isfinite(r["decay_ratio"])]
            flagged = len(rs) - len(ok)
            worst = max(ok, key=lambda r: abs(math.log(r["decay_ratio"])) if r["decay_ratio"] > 0 else 1e9, default=None)
            within = sum(1 for r in ok if abs(r["decay_ratio"] - 1) <= 0.05)
            w = (f"worst unflagged s/(nu k^2) {fmt(worst['decay_ratio'])} ({worst['kernel']}, c h/nu {fmt(worst['ch_over_nu'])})"
                 if worst else "no unflagged run")
            fastest = max(rs, key=lambda r: r["decay_ratio"] if math.isfinite(r["decay_ratio"]) else -1)
            out.append(f"{v}, {lat}: {within}/{len(rs)} within 5 %; {flagged} flagged; {w}; "
                       f"largest s/(nu k^2) {fmt(fastest['decay_ratio'])} ({fastest['kernel']}, c h/nu {fmt(fastest['ch_over_nu'])})")
    return out


def markdown(rows, variants, lattices, kernels, ratios, readings, made):
    mark = {"failed": "F", "grew": "G", "disordered": "D"}
    lines = [made, ""]
    pick = [X for X in (1e-2, 1.0, 1e2, 1e3) if any(abs(X / r - 1) < 1e-9 for r in ratios)]
    if pick:
        lines += ["**Summary: s / (nu k^2) and, in brackets, w / (nu k^2)** (flags: F failed, G grew, D disordered)", "",
                  "| start | kernel | variant | " + " | ".join(f"c h/nu = {fmt(X)}" for X in pick) + " |",
                  "|---|---|---|" + "---|" * len(pick)]
        for lat in lattices:
            for kernel in kernels:
                for v in variants:
                    cells = []
                    for X in pick:
                        r = next((r for r in rows if r["lattice"] == lat and r["kernel"] == kernel and r["variant"] == v
                                  and abs(r["ch_over_nu"] / X - 1) < 1e-9), None)
                        f = "".join(mark[x] for x in r["flag"].split(",") if x) if r else ""
                        cells.append(f"{fmt(r['decay_ratio'])} ({fmt(r['ringing_ratio'])}){' ' + f if f else ''}" if r else "")
                    lines.append(f"| {lat} | {kernel} | {v} | " + " | ".join(cells) + " |")
        lines.append("")
    for key, title in (("decay_ratio", "Decay rate s / (nu k^2)"), ("ringing_ratio", "Ringing frequency w / (nu k^2)")):
        for lat in lattices:
            lines += [f"**{title}, {lat} start** (flags: F failed, G grew, D disordered; "
                      f"th = linear theory of the perfect lattice)", "",
                      "| kernel | variant | " + " | ".join(f"c h/nu = {fmt(X)}" for X in ratios) + " |",
                      "|---|---|" + "---|" * len(ratios)]
            for kernel in kernels:
                for v in variants:
                    cells = []
                    for X in ratios:
                        r = next((r for r in rows if r["lattice"] == lat and r["kernel"] == kernel and r["variant"] == v
                                  and abs(r["ch_over_nu"] / X - 1) < 1e-9), None)
                        if r is None:
                            cells.append("")
                            continue
                        f = "".join(mark[x] for x in r["flag"].split(",") if x)
                        cells.append(fmt(r[key]) + (f" {f}" if f else ""))
                    lines.append(f"| {kernel} | {v} | " + " | ".join(cells) + " |")
                if lat == "ordered":
                    th = []
                    for X in ratios:
                        r = next((r for r in rows if r["lattice"] == lat and r["kernel"] == kernel
                                  and abs(r["ch_over_nu"] / X - 1) < 1e-9), None)
                        th.append(fmt(r["theory_" + key]) if r else "")
                    lines.append(f"| {kernel} | th | " + " | ".join(th) + " |")
            lines.append("")
    lines += ["Readings:", ""] + [f"- {r}" for r in readings] + [""]
    return "\n".join(lines)


def rows_of_csv(path):
    """The rows of a stored shear_mode.csv, typed as run_case makes them (a redraw of a
    finished study: chart, tables and readings without running anything)."""
    def value(k, v):
        if v in ("True", "False"):
            return v == "True"
        if k in ("lattice", "kernel", "variant", "options", "flag"):
            return v
        try:
            return int(v) if k in ("crossings", "snapshots", "exit_code") else float(v)
        except ValueError:
            return v
    with open(path, newline="") as f:
        return [{k: value(k, v) for k, v in r.items()} for r in csv.DictReader(f)]


def cell_readings(rows):
    """Every run's measures as cells[start][kernel][variant][X] (X = "X" + c h/nu, "." as
    "_"), the range of the decay ratio over the kernels as ranges[variant][start or "any"][X],
    and counts per variant and start: within 5 % of nu k^2 (flagged runs too, and unflagged
    only), runs that ring, runs."""
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    starts = ("ordered", "disordered", "any")
    cells, ranges = {}, {}
    for r in rows:
        X = f"X{r['ch_over_nu']:g}".replace(".", "_")
        cells.setdefault(r["lattice"], {}).setdefault(r["kernel"], {}).setdefault(r["variant"], {})[X] = {
            k: r[k] for k in ("decay_ratio", "ringing_ratio", "theory_decay_ratio", "flag", "noise_vy_over_U", "crossings")}
        for lat in (r["lattice"], "any"):
            rng = ranges.setdefault(r["variant"], {}).setdefault(lat, {}).setdefault(X, {"min": math.inf, "max": -math.inf})
            rng["min"], rng["max"] = min(rng["min"], r["decay_ratio"]), max(rng["max"], r["decay_ratio"])

    def count(v, lat, unflagged):
        return sum(1 for r in rows if r["variant"] == v and lat in (r["lattice"], "any")
                   and abs(r["decay_ratio"] - 1) <= 0.05 and not (unflagged and r["flag"]))
    return {"cells": cells, "ranges": ranges,
            "within_5pct": {v: {lat: count(v, lat, False) for lat in starts} for v in variants},
            "within_5pct_unflagged": {v: {lat: count(v, lat, True) for lat in starts} for v in variants},
            "ringing_runs": {v: sum(1 for r in rows if r["variant"] == v and r["crossings"] > 0) for v in variants},
            "runs": {v: sum(1 for r in rows if r["variant"] == v) for v in variants}}


def made_line(argv):
    rel = [os.path.relpath(w, REPO) if os.path.isabs(w) else w for w in argv]
    words = ["examples/study_shear_mode.py"] + rel
    return "*Made by `" + " ".join(w if not re.search(r"[\s'\"]", w) else "'" + w + "'" for w in words) + \
        "` (run from the repository root).*"


def main():
    global U
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    p.add_argument("--out", default=os.path.join(REPO, "build", "shear_mode"))
    p.add_argument("--chart", help="PNG path (default OUT/shear_mode.png)")
    p.add_argument("--doc", help="a markdown page whose generated section is replaced by the tables")
    p.add_argument("--quick", action="store_true", help="one kernel (wendland_c4), c h/nu = 0.01, 1, 100, ordered")
    p.add_argument("--kernel", action="append", choices=KERNELS)
    p.add_argument("--ratio", action="append", type=float, help="c h / nu values (default 8 from 1e-2 to 1e3)")
    p.add_argument("--lattice", action="append", choices=["ordered", "disordered"])
    p.add_argument("--variant", action="append", help='NAME="OPTIONS" added to every run of that variant '
                                                       '(default one variant "plain" without options)')
    p.add_argument("--efolds", type=float, default=1.0, help="run length in e-foldings 1/(nu k^2) of the exact decay")
    p.add_argument("--max-snapshots", type=int, default=300)
    p.add_argument("--relax-cycles", type=int, default=6, help="viscous relaxation runs of the disordered start")
    p.add_argument("--keep-snapshots", action="store_true")
    p.add_argument("--from-csv", metavar="CSV", help="redraw the chart, tables and readings from a stored "
                   "shear_mode.csv (of the same options) instead of running")
    p.add_argument("--reuse", action="append", default=[], metavar="VARIANT=CSV",
                   help="take the rows of VARIANT from a stored shear_mode.csv instead of running them (a variant "
                        "whose code path a change of the build did not touch; the page says so and how it was checked)")
    p.add_argument("--amplitude", type=float, default=U, help="U (default 0.01): the rows' slide, about "
                   "0.06 (U / 0.01) (c h / nu) spacings over an e-folding, is linear only well under 1/(2 pi)")
    a = p.parse_args()
    U = a.amplitude
    a.out = os.path.abspath(a.out)
    a.spam_ark = os.path.abspath(a.spam_ark)
    kernels = a.kernel or (QUICK["kernels"] if a.quick else KERNELS)
    ratios = sorted(a.ratio or (QUICK["ratios"] if a.quick else DEFAULT_RATIOS))
    lattices = a.lattice or (QUICK["lattices"] if a.quick else ["ordered", "disordered"])
    variants = []
    for spec in a.variant or ["plain="]:
        name, _, opts = spec.partition("=")
        variants.append((name, opts.split()))
    vnames = [v for v, _ in variants]
    os.makedirs(a.out, exist_ok=True)
    cases = [(lat, k, v, o, X) for v, o in variants for lat in lattices for k in kernels for X in ratios]
    rows, t0, ran = [], time.time(), 0
    if a.from_csv and a.reuse:
        raise SystemExit("--from-csv redraws every row from one CSV: --reuse is for a study that runs")
    if a.from_csv:
        rows = [r for r in rows_of_csv(a.from_csv) if (r["lattice"], r["kernel"], r["variant"], r["ch_over_nu"])
                in {(lat, k, v, X) for lat, k, v, _, X in cases}]
        if len(rows) != len(cases):
            raise SystemExit(f"{a.from_csv} holds {len(rows)} of the {len(cases)} cases these options ask for")
        cases = []
    for spec in a.reuse:
        v, _, path = spec.partition("=")
        if v not in vnames or not path:
            raise SystemExit(f"--reuse {spec}: VARIANT=CSV with VARIANT one of {', '.join(vnames)}")
        wanted = {(lat, k, X) for lat, k, cv, _, X in cases if cv == v}
        got = [r for r in rows_of_csv(path) if r["variant"] == v and (r["lattice"], r["kernel"], r["ch_over_nu"]) in wanted]
        if len(got) != len(wanted):
            raise SystemExit(f"{path} holds {len(got)} of the {len(wanted)} cases of variant {v} these options ask for")
        rows += got
        cases = [cs for cs in cases if cs[2] != v]
    for i, (lat, k, v, o, X) in enumerate(cases):
        row, skipped = run_case(a, lat, k, v, o, X)
        rows.append(row)
        ran += not skipped
        el = time.time() - t0
        eta = el / ran * (len(cases) - i - 1) if ran else 0
        print(f"[{i + 1}/{len(cases)}] {lat} {k} {v} c h/nu {X:.4g}: s/(nu k^2) {fmt(row['decay_ratio'], 4)} "
              f"(theory {fmt(row['theory_decay_ratio'], 4)}), w/(nu k^2) {fmt(row['ringing_ratio'], 4)}"
              f"{' [' + row['flag'] + ']' if row['flag'] else ''}  run {row['wall_s']:.1f} s"
              f"{' (done before)' if skipped else ''}  elapsed {el:.0f} s eta {eta:.0f} s", flush=True)
    with open(os.path.join(a.out, "shear_mode.csv") + ".tmp", "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)
    os.replace(os.path.join(a.out, "shear_mode.csv") + ".tmp", os.path.join(a.out, "shear_mode.csv"))
    with open(os.path.join(a.out, "shear_mode.json"), "w") as f:
        json.dump(rows, f, indent=1)
    readings = readings_of(rows, vnames, lattices)
    readings.append(f"runs: {len(rows)}")  # their wall times are in the CSV, without the load they ran under
    chart_path = a.chart or os.path.join(a.out, "shear_mode.png")
    chart(rows, chart_path, readings, lattices, vnames, kernels, a.efolds)
    # Not CHART.json: OUT/shear_mode.json is the rows' file, and the chart defaults to OUT/shear_mode.png.
    chart_readings.write_json(os.path.splitext(chart_path)[0] + "_readings.json", cell_readings(rows),
                              runs=[a.from_csv or a.out] + [spec.partition("=")[2] for spec in a.reuse],
                              chart=os.path.basename(chart_path))
    md = markdown(rows, vnames, lattices, kernels, ratios, readings, made_line(sys.argv[1:]))
    with open(os.path.join(a.out, "shear_mode.md"), "w") as f:
        f.write(md)
    if a.doc:
        text = open(a.doc).read()
        begin, end = "<!-- shear_mode:generated -->\n", "<!-- /shear_mode:generated -->\n"
        if begin not in text or end not in text:
            raise SystemExit(f"{a.doc} has no {begin.strip()} ... {end.strip()} section")
        text = text[:text.index(begin) + len(begin)] + md + "\n" + text[text.index(end):]
        with open(a.doc + ".tmp", "w") as f:
            f.write(text)
        os.replace(a.doc + ".tmp", a.doc)
    print("\n".join(readings))
    print(f"wrote {os.path.join(a.out, 'shear_mode.csv')}, {chart_path}, {os.path.join(a.out, 'shear_mode.md')}"
          f"{', ' + a.doc if a.doc else ''}; total {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
