#!/usr/bin/env python3
"""Benchmark spam-ark against LAMMPS on the same initial particles.

Why LAMMPS is a fair peer: 2D SPAM with pressure P = rho^2/2 and particle
mass m = 1 has P_i/rho_i^2 = 1/2 for every particle, so the SPAM equation of
motion

    dv_i/dt = -sum_j m (P_i/rho_i^2 + P_j/rho_j^2) grad_i w(r_ij)
            = -sum_j grad_i w(r_ij)

is exactly molecular dynamics with Lucy's kernel w(r) as the pair potential.
LAMMPS runs that potential through `pair_style table`, with a table this
script writes.

This is a measurement, not a test: it prints a table and writes
bench/results/bench_<date>.json.  See bench/README.md.

Only the standard library and numpy are used.
"""

import argparse
import datetime
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def _ensure_numpy():
    """Import numpy; if this interpreter lacks it, re-run under the system one."""
    import importlib.util
    if importlib.util.find_spec("numpy") is not None:
        return
    if not os.environ.get("SPAM_BENCH_REEXEC"):
        for cand in ("/usr/bin/python3", "/usr/local/bin/python3"):
            if (os.path.exists(cand)
                    and os.path.realpath(cand) != os.path.realpath(sys.executable)):
                env = dict(os.environ, SPAM_BENCH_REEXEC="1")
                os.execve(cand, [cand, os.path.abspath(__file__)] + sys.argv[1:], env)
    sys.exit("run_bench.py needs numpy (Debian: apt-get install python3-numpy, "
             "then run it with /usr/bin/python3)")


_ensure_numpy()
import numpy as np  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
BENCH_DIR = Path(__file__).resolve().parent
DT = 0.05
DEFAULT_STEPS = {4096: 100, 16384: 1000, 65536: 400}
RUN_TIMEOUT_S = 3600


# --------------------------------------------------------------------------
# Lucy's 2D kernel and its derivative
# --------------------------------------------------------------------------

def lucy_w(r, h):
    """w(r) = 5/(pi h^2) (1+3s)(1-s)^3 for s = r/h < 1, else 0."""
    s = np.asarray(r, dtype=float) / h
    c = 5.0 / (math.pi * h * h)
    return np.where(s < 1.0, c * (1.0 + 3.0 * s) * (1.0 - s) ** 3, 0.0)


def lucy_force(r, h):
    """F(r) = -dw/dr = 60/(pi h^3) s (1-s)^2 for s < 1, else 0 (repulsive > 0).

    d/ds[(1+3s)(1-s)^3] = 3(1-s)^3 - 3(1+3s)(1-s)^2 = -12 s (1-s)^2, and
    ds/dr = 1/h, so dw/dr = -(5/(pi h^2)) 12 s (1-s)^2 / h.
    """
    s = np.asarray(r, dtype=float) / h
    return np.where(s < 1.0, 60.0 / (math.pi * h ** 3) * s * (1.0 - s) ** 2, 0.0)


def write_table(path, h, npts, rlo, scale=1.0):
    """Write a LAMMPS pair_style table file (keyword SPAM) and check it.

    Columns: index r E F with E = scale*w(r), F = -dE/dr, r evenly spaced from
    rlo to h (declared with `N npts R rlo h`).  Returns finite-difference
    checks of F against E.
    """
    r = np.linspace(rlo, h, npts)
    e = scale * lucy_w(r, h)
    f = scale * lucy_force(r, h)
    with open(path, "w") as fh:
        fh.write("# Lucy 2D kernel as a pair potential, E = %.17g * w(r), "
                 "F = -dE/dr, h = %.17g\n\n" % (scale, h))
        fh.write("SPAM\nN %d R %.17g %.17g\n\n" % (npts, rlo, h))
        for i in range(npts):
            fh.write("%d %.17g %.17g %.17g\n" % (i + 1, r[i], e[i], f[i]))
    # (1) analytic F against a central difference of the analytic E.
    rr = np.linspace(rlo + 1e-3 * h, h * (1 - 1e-3), 4001)
    d = 1e-6 * h
    fd = -(scale * lucy_w(rr + d, h) - scale * lucy_w(rr - d, h)) / (2 * d)
    fa = scale * lucy_force(rr, h)
    fmax = float(np.max(np.abs(fa)))
    err_analytic = float(np.max(np.abs(fd - fa)) / fmax)
    # (2) the tabulated F column against a central difference of the
    #     tabulated E column (what LAMMPS itself interpolates).
    fd_tab = -(e[2:] - e[:-2]) / (r[2:] - r[:-2])
    err_table = float(np.max(np.abs(fd_tab - f[1:-1])) / fmax)
    return {"max_rel_err_F_vs_fd_analytic": err_analytic,
            "max_rel_err_F_vs_fd_table_columns": err_table,
            "F_max": fmax, "npts": npts, "rlo": rlo, "rhi": h}


# --------------------------------------------------------------------------
# Pair counting (minimum image, periodic box with lower corner 0)
# --------------------------------------------------------------------------

def _count_pairs_brute(pos, box, h):
    n = len(pos)
    total = 0
    chunk = max(1, 4_000_000 // max(n, 1))
    for a in range(0, n, chunk):
        d = pos[a:a + chunk, None, :] - pos[None, :, :]
        d -= box * np.round(d / box)
        r2 = np.einsum("ijk,ijk->ij", d, d)
        idx_i = np.arange(a, min(a + chunk, n))[:, None]
        idx_j = np.arange(n)[None, :]
        total += int(np.count_nonzero((r2 < h * h) & (idx_j > idx_i)))
    return total


def count_pairs(pos, box, h):
    """Number of pairs i<j with minimum-image distance < h."""
    pos = np.asarray(pos, dtype=float)
    box = np.asarray(box, dtype=float)
    pos = pos - box * np.floor(pos / box)
    nc = np.floor(box / h).astype(int)
    if np.any(nc < 3) or len(pos) < 2000:
        return _count_pairs_brute(pos, box, h)
    csize = box / nc
    cell = np.minimum((pos / csize).astype(int), nc - 1)
    cid = cell[:, 0] * nc[1] + cell[:, 1]
    order = np.argsort(cid, kind="stable")
    cid_s = cid[order]
    counts = np.bincount(cid_s, minlength=nc[0] * nc[1])
    maxocc = int(counts.max())
    starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
    slot = np.arange(len(pos)) - starts[cid_s]
    grid = np.full((nc[0] * nc[1], maxocc, 2), np.nan)
    grid[cid_s, slot] = pos[order]
    grid = grid.reshape(nc[0], nc[1], maxocc, 2)
    ordered = 0  # ordered pairs (i, j), i != j, plus self terms removed below
    rows = max(1, int(2_000_000 // max(1, nc[1] * maxocc * maxocc)))
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            other = np.roll(grid, shift=(-dx, -dy), axis=(0, 1))
            for a in range(0, nc[0], rows):
                p = grid[a:a + rows]
                q = other[a:a + rows]
                d = p[:, :, :, None, :] - q[:, :, None, :, :]
                d -= box * np.round(d / box)
                r2 = d[..., 0] ** 2 + d[..., 1] ** 2
                ordered += int(np.count_nonzero(r2 < h * h))  # NaN -> False
    ordered -= len(pos)  # each particle with itself (offset 0,0)
    return ordered // 2


# --------------------------------------------------------------------------
# Processes
# --------------------------------------------------------------------------

def pin_prefix(cpu, enabled):
    if not enabled or shutil.which("taskset") is None:
        return []
    try:
        ok = subprocess.run(["taskset", "-c", str(cpu), "true"],
                            capture_output=True).returncode == 0
    except OSError:
        ok = False
    return ["taskset", "-c", str(cpu)] if ok else []


def bench_env():
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    return env


# A small launcher between this (large, numpy-laden) Python process and the
# measured program.  Linux carries a process's peak RSS across exec, so a
# program forked straight from here would report at least this interpreter's
# peak RSS.  The launcher, a bare `python3 -S`, forks the program from a small
# image, waits for it with os.wait4 and writes "exit_code ru_maxrss_kib".
_LAUNCHER = r"""
import os, sys
out, cmd = sys.argv[1], sys.argv[2:]
pid = os.fork()
if pid == 0:
    try:
        os.execvp(cmd[0], cmd)
    except BaseException as exc:
        sys.stderr.write("launcher: cannot run %s: %s\n" % (cmd[0], exc))
    finally:
        os._exit(127)
_, status, ru = os.wait4(pid, 0)
with open(out, "w") as fh:
    fh.write("%d %d\n" % (os.waitstatus_to_exitcode(status), ru.ru_maxrss))
"""


def run_measured(cmd, cwd, log_path, timeout=RUN_TIMEOUT_S):
    """Run cmd alone, output to log_path; return (rc, wall_s, peak_rss_bytes).

    Peak RSS is ru_maxrss (KiB) from os.wait4 on the program itself, taken by
    the launcher above (taskset execs the program in place, so that pid is
    the program's).
    """
    rss_file = Path(str(log_path) + ".rusage")
    launcher = [sys.executable, "-S", "-c", _LAUNCHER, str(rss_file)]
    with open(log_path, "wb") as out:
        t0 = time.perf_counter()
        p = subprocess.Popen(launcher + [str(c) for c in cmd], cwd=str(cwd),
                             env=bench_env(), stdout=out, stderr=subprocess.STDOUT,
                             start_new_session=True)
        try:
            p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, 9)  # the launcher's own session: it and the program
            p.wait()
        wall = time.perf_counter() - t0
    try:
        rc, maxrss_kib = (int(v) for v in rss_file.read_text().split())
    except (OSError, ValueError):
        return (p.returncode or -1), wall, 0
    return rc, wall, maxrss_kib * 1024


def tail(path, n=25):
    try:
        lines = Path(path).read_text(errors="replace").splitlines()
    except OSError:
        return ""
    return "\n".join(lines[-n:])


# --------------------------------------------------------------------------
# LAMMPS
# --------------------------------------------------------------------------

def write_lammps_data(path, pos, vel, box, mass):
    n = len(pos)
    with open(path, "w") as fh:
        fh.write("spam-ark bench particles\n\n%d atoms\n1 atom types\n\n" % n)
        fh.write("0 %.17g xlo xhi\n0 %.17g ylo yhi\n-0.5 0.5 zlo zhi\n\n"
                 % (box[0], box[1]))
        fh.write("Masses\n\n1 %.17g\n\nAtoms # atomic\n\n" % mass)
        fh.writelines("%d 1 %.17g %.17g 0\n" % (i + 1, pos[i, 0], pos[i, 1])
                      for i in range(n))
        fh.write("\nVelocities\n\n")
        fh.writelines("%d %.17g %.17g 0\n" % (i + 1, vel[i, 0], vel[i, 1])
                      for i in range(n))


def lammps_input(data, table, h, skin, steps, table_n, dt=DT,
                 thermo_every=0, census=False, after_run=""):
    lines = [
        "units lj",
        "dimension 2",
        "atom_style atomic",
        "boundary p p p",
        "read_data %s" % data,
        "pair_style table linear %d" % table_n,
        "pair_coeff 1 1 %s SPAM %.17g" % (table, h),
        "neighbor %.17g bin" % skin,
        "neigh_modify every 1 delay 0 check yes",
        "fix 1 all nve",
        "fix 2 all enforce2d",
        "timestep %.17g" % dt,
    ]
    if census:
        lines += [
            "compute cn all coord/atom cutoff %.17g" % h,
            "compute cs all reduce sum c_cn",
            "thermo_style custom step c_cs pe ke etotal",
        ]
    else:
        lines.append("thermo_style custom step pe ke etotal")
    lines += [
        "thermo_modify norm no",
        "thermo %d" % thermo_every,
    ]
    lines.append("run %d" % steps)
    if after_run:
        lines.append(after_run)
    return "\n".join(lines) + "\n"


_FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def parse_lammps_log(text):
    out = {}
    m = re.search(r"Loop time of (%s) on (\d+) procs for (\d+) steps with (\d+) atoms"
                  % _FLOAT, text)
    if m:
        out["loop_time_s"] = float(m.group(1))
        out["procs"] = int(m.group(2))
        out["steps"] = int(m.group(3))
        out["atoms"] = int(m.group(4))
    for sec in ("Pair", "Neigh", "Comm", "Output", "Modify"):
        m = re.search(r"^%s\s*\|\s*(%s)\s*\|\s*(%s)\s*\|\s*(%s)"
                      % (sec, _FLOAT, _FLOAT, _FLOAT), text, re.M)
        if m:
            out["%s_time_s" % sec.lower()] = float(m.group(2))  # avg column
    m = re.search(r"Neighbor list builds = (\d+)", text)
    if m:
        out["neighbor_builds"] = int(m.group(1))
    m = re.search(r"Dangerous builds = (\d+)", text)
    if m:
        out["dangerous_builds"] = int(m.group(1))
    m = re.search(r"Total # of neighbors = (\d+)", text)
    if m:
        out["total_neighbors_end"] = int(m.group(1))
    m = re.search(r"Per MPI rank memory allocation \(min/avg/max\) = (%s) \| (%s) \| (%s) Mbytes"
                  % (_FLOAT, _FLOAT, _FLOAT), text)
    if m:
        out["lammps_memory_mbytes"] = float(m.group(3))
    out["thermo"] = parse_thermo(text)
    m = re.search(r"^(ERROR.*)$", text, re.M)
    if m:
        out["error"] = m.group(1)
    out["warnings"] = sorted(set(re.findall(r"^WARNING: (.*)$", text, re.M)))
    return out


def parse_thermo(text):
    """Rows of the (last) thermo block: list of dicts keyed by column name."""
    rows = []
    lines = text.splitlines()
    for k, line in enumerate(lines):
        if line.split()[:1] == ["Step"]:
            cols = line.split()
            rows = []
            for l2 in lines[k + 1:]:
                parts = l2.split()
                if len(parts) != len(cols):
                    break
                try:
                    rows.append(dict(zip(cols, map(float, parts))))
                except ValueError:
                    break
    return rows


# --------------------------------------------------------------------------
# spam-ark
# --------------------------------------------------------------------------

def read_particles_csv(path):
    with open(path) as fh:
        header = fh.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    col = {name.strip(): k for k, name in enumerate(header)}
    missing = [c for c in ("x", "y", "vx", "vy", "m") if c not in col]
    if missing:
        raise RuntimeError("%s: header %r lacks columns %r" % (path, header, missing))
    pos = data[:, [col["x"], col["y"]]]
    vel = data[:, [col["vx"], col["vy"]]]
    mass = data[:, col["m"]]
    return pos, vel, mass, header


def write_particles_csv(path, pos, vel, mass):
    with open(path, "w") as fh:
        fh.write("x,y,vx,vy,m\n")
        fh.writelines("%.17g,%.17g,%.17g,%.17g,%.17g\n"
                      % (pos[i, 0], pos[i, 1], vel[i, 0], vel[i, 1], mass[i])
                      for i in range(len(pos)))


def numpy_lattice(nx):
    """Stand-in for the spam-ark initial state (used only with --lammps-only
    or when the binary is missing): NX x NX lattice, spacing 1, at rest, in the
    lower-left quarter of a 2NX x 2NX box."""
    g = np.arange(nx) + 0.5
    x, y = np.meshgrid(g, g, indexing="ij")
    pos = np.column_stack([x.ravel(), y.ravel()])
    return pos, np.zeros_like(pos), np.ones(len(pos))


def spam_ark_works(binary):
    if not binary or not Path(binary).is_file() or not os.access(binary, os.X_OK):
        return False, "not found or not executable: %s" % binary
    try:
        p = subprocess.run([str(binary), "-help"], capture_output=True, timeout=60,
                           cwd=str(REPO_ROOT))
    except (OSError, subprocess.TimeoutExpired) as exc:
        return False, "could not run %s -help: %s" % (binary, exc)
    if p.returncode not in (0,):
        return False, "%s -help exited %d" % (binary, p.returncode)
    return True, ""


def spam_make_initial(binary, nx, h, workdir):
    outdir = workdir / ("init_%d" % nx)
    outdir.mkdir(parents=True, exist_ok=True)
    csv = workdir / ("initial_%d.csv" % nx)
    opts = REPO_ROOT / "options" / "expansion.opts"
    if opts.is_file():
        scene = ["-options_file", opts]
    else:
        print("  note: %s is missing; using -scene expansion -dim 2 instead" % opts)
        scene = ["-scene", "expansion", "-dim", 2]
    cmd = [binary] + scene + [
           "-expansion_n", nx, "-h", h, "-initial_csv", csv,
           "-ts_max_steps", 0, "-output_dir", outdir]
    log = workdir / ("init_%d.log" % nx)
    rc, _, _ = run_measured(cmd, REPO_ROOT, log)
    if rc != 0 or not csv.exists():
        raise RuntimeError("spam-ark initial-state run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    return csv, " ".join(map(str, cmd))


def spam_cmd(binary, csv, box, h, steps, outdir):
    return [binary, "-scene", "file", "-file_path", csv, "-dim", 2,
            "-box_lo", "0,0", "-box_len", "%.17g,%.17g" % (box[0], box[1]),
            "-periodic", "1,1", "-h", h,
            "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5",
            "-arkode_fixed_step", DT, "-ts_max_steps", steps,
            # The file scene's default end time (t = 10) would stop the run
            # early; set it past the last step so -ts_max_steps decides.
            "-ts_max_time", "%.17g" % ((steps + 0.5) * DT),
            "-output_dir", outdir, "-snapshot_interval", 0, "-output_interval", 0]


def spam_run(binary, csv, box, h, steps, workdir, tag, pin):
    outdir = workdir / ("spam_%s" % tag)
    if outdir.exists():
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    cmd = pin + spam_cmd(binary, csv, box, h, steps, outdir)
    log = workdir / ("spam_%s.log" % tag)
    rc, wall, rss = run_measured(cmd, REPO_ROOT, log)
    summ_path = outdir / "summary.json"
    if rc != 0 or not summ_path.exists():
        raise RuntimeError("spam-ark run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    summary = json.loads(summ_path.read_text())
    return {"rc": rc, "process_wall_s": wall, "ru_maxrss_bytes": rss,
            "summary": summary, "cmd": " ".join(map(str, cmd))}


def lammps_run(lmp, data, table, h, skin, steps, table_n, workdir, tag, pin,
               thermo_every=0, census=False):
    inp = workdir / ("in_%s.lmp" % tag)
    inp.write_text(lammps_input(data.name, table.name, h, skin, steps, table_n,
                                thermo_every=thermo_every, census=census))
    log = workdir / ("lammps_%s.log" % tag)
    cmd = pin + [lmp, "-in", inp.name, "-log", "none", "-nocite"]
    rc, wall, rss = run_measured(cmd, workdir, log)
    res = parse_lammps_log(Path(log).read_text(errors="replace"))
    if rc != 0 or "loop_time_s" not in res:
        raise RuntimeError("LAMMPS run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    res.update({"rc": rc, "process_wall_s": wall, "ru_maxrss_bytes": rss,
                "cmd": " ".join(map(str, cmd))})
    return res


def window_mean(samples, upto):
    """Time-average (trapezoid) of (step, value) samples over [0, upto]."""
    pts = [(s, v) for s, v in samples if s <= upto]
    if not pts:
        return None
    if len(pts) == 1 or pts[-1][0] == 0:
        return pts[0][1]
    s = np.array([p[0] for p in pts], dtype=float)
    v = np.array([p[1] for p in pts], dtype=float)
    return float(np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(s)) / (s[-1] - s[0]))


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fnum(x, fmt="%.3f"):
    if x is None:
        return "-"
    if isinstance(x, float) and (math.isnan(x) or math.isinf(x)):
        return "-"
    return fmt % x


# --------------------------------------------------------------------------
# LAMMPS self-checks (--validate-lammps)
# --------------------------------------------------------------------------

def validate_lammps(args, workdir, pin):
    """Check the table/potential pipeline and energy conservation in LAMMPS."""
    h = args.h
    report = {}
    table = workdir / "val_table.dat"
    report["table_check"] = write_table(table, h, args.table_points, args.table_rlo)
    print("table: max |F - FD(E)|/max F: analytic %.2e, table columns %.2e"
          % (report["table_check"]["max_rel_err_F_vs_fd_analytic"],
             report["table_check"]["max_rel_err_F_vs_fd_table_columns"]))

    # Forces and energy on a perturbed lattice against a direct numpy sum.
    rng = np.random.default_rng(12345)
    nx = 16
    box = np.array([2.0 * nx, 2.0 * nx])
    pos, vel, _ = numpy_lattice(nx)
    pos = pos + rng.uniform(-0.3, 0.3, pos.shape)
    vel = rng.normal(0.0, 0.1, pos.shape)
    data = workdir / "val_forces.data"
    write_lammps_data(data, pos, vel, box, 1.0)
    inp = workdir / "in_val_forces.lmp"
    inp.write_text(lammps_input(
        data.name, table.name, h, args.skin, 0, args.table_points,
        after_run="write_dump all custom val_forces.dump id x y fx fy "
                  "modify sort id format float %.17g"))
    log = workdir / "lammps_val_forces.log"
    rc, _, _ = run_measured(pin + [args.lmp, "-in", inp.name, "-log", "none", "-nocite"],
                            workdir, log)
    if rc != 0:
        raise RuntimeError("LAMMPS force check failed:\n" + tail(log))
    dump = np.loadtxt(workdir / "val_forces.dump", skiprows=9)
    f_lmp = dump[:, 3:5]
    n = len(pos)
    d = pos[:, None, :] - pos[None, :, :]
    d -= box * np.round(d / box)
    r = np.sqrt(np.einsum("ijk,ijk->ij", d, d))
    np.fill_diagonal(r, np.inf)
    fr = lucy_force(r, h)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(np.isfinite(r)[..., None], d / r[..., None], 0.0)
    f_np = np.sum(fr[..., None] * unit, axis=1)
    pe_np = 0.5 * float(np.sum(lucy_w(np.where(np.isfinite(r), r, 10 * h), h)))
    pe_lmp = parse_thermo(log.read_text())[0]["PotEng"]
    ferr = float(np.max(np.abs(f_lmp - f_np)) / np.max(np.abs(f_np)))
    report["force_check"] = {"n": n, "max_rel_force_err": ferr,
                             "pe_lammps": pe_lmp, "pe_numpy": pe_np,
                             "pe_rel_err": abs(pe_lmp - pe_np) / abs(pe_np)}
    print("forces on a perturbed %d-particle lattice: max |F_lammps - F_numpy|/max|F| = %.2e;"
          " pair energy %.10g (LAMMPS) vs %.10g (numpy), rel err %.2e"
          % (n, ferr, pe_lmp, pe_np, report["force_check"]["pe_rel_err"]))

    # Energy conservation for the expansion itself on a small lattice.
    nx = 32
    box = np.array([2.0 * nx, 2.0 * nx])
    pos, vel, _ = numpy_lattice(nx)
    data = workdir / "val_drift.data"
    write_lammps_data(data, pos, vel, box, 1.0)
    report["energy_drift"] = []
    for dt, steps in ((DT, 400), (DT / 2, 800)):
        inp = workdir / "in_val_drift.lmp"
        inp.write_text(lammps_input(data.name, table.name, h, args.skin, steps,
                                    args.table_points, dt=dt,
                                    thermo_every=max(1, steps // 40)))
        log = workdir / "lammps_val_drift.log"
        rc, _, _ = run_measured(pin + [args.lmp, "-in", inp.name, "-log", "none",
                                       "-nocite"], workdir, log)
        if rc != 0:
            raise RuntimeError("LAMMPS drift check failed:\n" + tail(log))
        rows = parse_thermo(log.read_text())
        e = np.array([row["TotEng"] for row in rows])
        ke = np.array([row["KinEng"] for row in rows])
        rec = {"dt": dt, "steps": steps, "t_end": dt * steps, "n": len(pos),
               "E0": float(e[0]), "E_end": float(e[-1]),
               "rel_drift_end": float((e[-1] - e[0]) / abs(e[0])),
               "max_rel_dev": float(np.max(np.abs(e - e[0])) / abs(e[0])),
               "ke_end_over_E0": float(ke[-1] / abs(e[0]))}
        report["energy_drift"].append(rec)
        print("energy, %d particles, dt %.4g, %d steps (t=%.4g): E0 %.8g, E_end %.8g, "
              "rel drift %.2e, max rel deviation %.2e (KE reaches %.0f%% of E0)"
              % (len(pos), dt, steps, dt * steps, rec["E0"], rec["E_end"],
                 rec["rel_drift_end"], rec["max_rel_dev"], 100 * rec["ke_end_over_E0"]))
    return report


# --------------------------------------------------------------------------
# Main benchmark
# --------------------------------------------------------------------------

def parse_args(argv):
    ap = argparse.ArgumentParser(
        description="Benchmark spam-ark against LAMMPS (pair_style table with "
                    "Lucy's kernel) on the same initial particles.")
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"),
                    help="spam-ark binary (default: <repo>/build/spam-ark)")
    ap.add_argument("--lmp", default="lmp", help="LAMMPS binary (default: lmp)")
    ap.add_argument("--sizes", default="16384,65536",
                    help="comma-separated particle counts, each a perfect square")
    ap.add_argument("--h", type=float, default=3.0, help="smoothing length (default 3)")
    ap.add_argument("--steps", type=int, default=None,
                    help="steps for both programs (default per size: "
                         "16384 -> 1000, 65536 -> 400)")
    ap.add_argument("--lammps-steps", type=int, default=None,
                    help="override LAMMPS steps only")
    ap.add_argument("--spam-steps", type=int, default=None,
                    help="override spam-ark steps only")
    ap.add_argument("--repeats", type=int, default=None,
                    help="timed runs per program and size; the median is "
                         "reported (default 3, 1 with --quick)")
    ap.add_argument("--quick", action="store_true",
                    help="smoke run: N=4096 only, 100 steps, 1 repeat")
    ap.add_argument("--skin", type=float, default=1.0,
                    help="LAMMPS neighbour skin (default 1.0, the fastest of "
                         "0.3/0.5/0.8/1.0/1.5 measured here on this problem)")
    ap.add_argument("--table-points", type=int, default=20000,
                    help="points in the LAMMPS table (default 20000)")
    ap.add_argument("--table-rlo", type=float, default=1e-10,
                    help="inner radius of the LAMMPS table (default 1e-10; the Lucy "
                         "potential is soft, so streams interpenetrate and pairs "
                         "can come very close)")
    ap.add_argument("--cpu", type=int, default=0, help="core to pin to (default 0)")
    ap.add_argument("--no-pin", action="store_true", help="do not use taskset")
    ap.add_argument("--lammps-only", action="store_true",
                    help="skip spam-ark; the initial lattice is made with numpy")
    ap.add_argument("--numpy-initial", action="store_true",
                    help="make the initial lattice with numpy (unperturbed, sites "
                         "at i+0.5) instead of spam-ark -initial_csv")
    ap.add_argument("--validate-lammps", action="store_true",
                    help="also check the LAMMPS table, forces and energy drift")
    ap.add_argument("--workdir", default=None,
                    help="scratch directory (default: a fresh temporary one)")
    ap.add_argument("--keep", action="store_true", help="keep the scratch directory")
    ap.add_argument("--out", default=None,
                    help="JSON output (default bench/results/bench_<date>.json)")
    args = ap.parse_args(argv)
    if args.quick:
        if args.sizes == "16384,65536":
            args.sizes = "4096"
        if args.steps is None:
            args.steps = 100
        if args.repeats is None:
            args.repeats = 1
    if args.repeats is None:
        args.repeats = 3
    return args


def steps_for(n, args):
    base = args.steps if args.steps is not None else DEFAULT_STEPS.get(
        n, max(50, min(2000, int(round(16384 * 1000 / n)))))
    ls = args.lammps_steps if args.lammps_steps is not None else base
    ss = args.spam_steps if args.spam_steps is not None else base
    return ls, ss


def bench_size(n, args, workdir, pin, spam_ok, table_cache):
    nx = int(round(math.sqrt(n)))
    if nx * nx != n:
        raise SystemExit("size %d is not a perfect square" % n)
    h = args.h
    box = np.array([2.0 * nx, 2.0 * nx])
    lsteps, ssteps = steps_for(n, args)
    res = {"n": n, "nx": nx, "box": box.tolist(), "h": h, "dt": DT,
           "lammps_steps": lsteps, "spam_steps": ssteps}

    # ---- initial particles -------------------------------------------------
    if spam_ok and not args.numpy_initial:
        csv, res["initial_cmd"] = spam_make_initial(args.spam_ark, nx, h, workdir)
        res["initial_source"] = "spam-ark -initial_csv"
    else:
        csv = workdir / ("initial_%d.csv" % nx)
        write_particles_csv(csv, *numpy_lattice(nx))
        res["initial_source"] = "numpy lattice (not spam-ark's -initial_csv)"
    pos, vel, mass, header = read_particles_csv(csv)
    res["csv_header"] = header
    if len(pos) != n:
        print("  note: initial CSV has %d particles, expected %d" % (len(pos), n))
    inside = bool(np.all((pos >= 0) & (pos <= box)))
    res["initial_inside_box"] = inside
    lo, hi = pos.min(axis=0), pos.max(axis=0)
    res["initial_extent"] = [lo.tolist(), hi.tolist()]
    if not inside or np.any(hi - lo < nx - 2) or np.any(hi - lo > nx + 1):
        print("  WARNING: the initial particles do not look like a %dx%d lattice of "
              "spacing 1 inside the box: x in [%g, %g], y in [%g, %g]"
              % (nx, nx, lo[0], hi[0], lo[1], hi[1]))
        res["initial_looks_wrong"] = True
    m0 = float(mass[0])
    if not np.allclose(mass, m0):
        print("  note: masses differ (min %g max %g); LAMMPS uses their mean"
              % (mass.min(), mass.max()))
        m0 = float(mass.mean())
    res["mass"] = m0
    # With mass m the SPAM force is m^2 * (-grad w) and the acceleration
    # m * (-grad w): pair potential m^2 w with atom mass m.
    scale = m0 * m0
    key = (h, scale)
    if key not in table_cache:
        table = workdir / ("table_h%g_m%g.dat" % (h, m0))
        table_cache[key] = (table, write_table(table, h, args.table_points,
                                               args.table_rlo, scale))
    table, tcheck = table_cache[key]
    res["table_check"] = tcheck
    data = workdir / ("lammps_%d.data" % nx)
    write_lammps_data(data, pos, vel, box, m0)

    t0 = time.perf_counter()
    pairs0 = count_pairs(pos, box, h)
    res["pairs_initial"] = pairs0
    res["pair_count_time_s"] = time.perf_counter() - t0

    # ---- pair census along the trajectory (LAMMPS, untimed) ----------------
    horizon = max(lsteps, ssteps)
    every = max(1, min(lsteps, ssteps) // 20)
    horizon = int(math.ceil(horizon / every) * every)
    cen = lammps_run(args.lmp, data, table, h, args.skin, horizon, args.table_points,
                     workdir, "census_%d" % nx, [], thermo_every=every, census=True)
    samples = [(int(r["Step"]), r["c_cs"] / 2.0) for r in cen["thermo"]]
    res["pair_census"] = samples
    res["pairs_lammps_step0"] = samples[0][1] if samples else None
    res["pairs_mean_lammps_window"] = window_mean(samples, lsteps)
    res["pairs_mean_spam_window"] = window_mean(samples, ssteps)
    res["pairs_end_lammps_window"] = [v for s, v in samples if s <= lsteps][-1]

    # ---- timed runs, each process alone ------------------------------------
    lam = []
    spam = []
    for k in range(args.repeats):
        lam.append(lammps_run(args.lmp, data, table, h, args.skin, lsteps,
                              args.table_points, workdir, "%d_r%d" % (nx, k), pin))
        if spam_ok:
            spam.append(spam_run(args.spam_ark, csv, box, h, ssteps, workdir,
                                 "%d_r%d" % (nx, k), pin))
    res["lammps_runs"] = lam
    res["spam_runs"] = spam

    L = {}
    L["time_per_eval_s"] = med([r["loop_time_s"] / r["steps"] for r in lam])
    L["pair_time_per_eval_s"] = med([r.get("pair_time_s", float("nan")) / r["steps"]
                                     for r in lam])
    L["pair_neigh_time_per_eval_s"] = med([(r.get("pair_time_s", float("nan"))
                                            + r.get("neigh_time_s", float("nan")))
                                           / r["steps"] for r in lam])
    L["neighbor_builds"] = med([r.get("neighbor_builds") for r in lam])
    L["dangerous_builds"] = max(r.get("dangerous_builds", 0) for r in lam)
    L["ru_maxrss_bytes"] = med([r["ru_maxrss_bytes"] for r in lam])
    L["lammps_memory_mbytes"] = med([r.get("lammps_memory_mbytes") for r in lam])
    th = lam[0]["thermo"]
    if len(th) >= 2 and th[0].get("TotEng"):
        L["energy_rel_drift"] = (th[-1]["TotEng"] - th[0]["TotEng"]) / abs(th[0]["TotEng"])
    L["ns_per_pair_initial"] = L["time_per_eval_s"] / pairs0 * 1e9 if pairs0 else None
    pm = res["pairs_mean_lammps_window"]
    L["ns_per_pair_mean"] = L["time_per_eval_s"] / pm * 1e9 if pm else None
    L["pair_only_ns_per_pair_mean"] = (L["pair_time_per_eval_s"] / pm * 1e9
                                       if pm and L["pair_time_per_eval_s"] else None)
    res["lammps"] = L

    S = {}
    if spam:
        def sget(r, key):
            v = r["summary"].get(key)
            return float(v) if isinstance(v, (int, float)) else None
        per_eval = []
        for r in spam:
            rt, ne = sget(r, "rhs_time_s"), sget(r, "rhs_evals")
            per_eval.append(rt / ne if rt is not None and ne else None)
        S["time_per_eval_s"] = med(per_eval)
        S["rhs_evals"] = med([sget(r, "rhs_evals") for r in spam])
        S["steps"] = med([sget(r, "steps") for r in spam])
        S["wall_time_s"] = med([sget(r, "wall_time_s") for r in spam])
        S["rhs_time_s"] = med([sget(r, "rhs_time_s") for r in spam])
        S["ns_per_pair_self_reported"] = med([sget(r, "ns_per_pair") for r in spam])
        S["pair_interactions_per_s"] = med([sget(r, "pair_interactions_per_s")
                                            for r in spam])
        S["peak_rss_bytes_self_reported"] = med([sget(r, "peak_rss_bytes") for r in spam])
        S["neighbour_builds"] = med([sget(r, "neighbour_builds") for r in spam])
        S["n_particles"] = med([sget(r, "n_particles") for r in spam])
        S["ru_maxrss_bytes"] = med([r["ru_maxrss_bytes"] for r in spam])
        te = S["time_per_eval_s"]
        S["ns_per_pair_initial"] = te / pairs0 * 1e9 if te and pairs0 else None
        pms = res["pairs_mean_spam_window"]
        S["ns_per_pair_mean"] = te / pms * 1e9 if te and pms else None
        missing = [k for k in ("rhs_evals", "steps", "wall_time_s", "rhs_time_s",
                               "pair_interactions_per_s", "ns_per_pair",
                               "peak_rss_bytes", "n_particles", "neighbour_builds")
                   if k not in spam[0]["summary"]]
        if missing:
            S["summary_keys_missing"] = missing
        # Same physics?  SPAM energy = KE + sum_i m rho_i / 2 (P = rho^2/2)
        # = LAMMPS (KE + PE) + N m^2 w(0) / 2; KE at the end should agree to
        # integrator accuracy when both ran the same steps.
        th0 = lam[0]["thermo"]
        s0 = spam[0]["summary"]
        cons = {}
        if th0 and isinstance(s0.get("energy_initial"), (int, float)):
            e_l = th0[0]["TotEng"] + len(pos) * scale * float(lucy_w(0.0, h)) / 2
            cons["energy_initial_spam"] = float(s0["energy_initial"])
            cons["energy_initial_lammps_plus_self"] = e_l
            cons["energy_initial_rel_diff"] = (float(s0["energy_initial"]) - e_l) / abs(e_l)
        if (th0 and lsteps == ssteps and len(th0) >= 2
                and isinstance(s0.get("kinetic_final"), (int, float))):
            ke_l = th0[-1]["KinEng"]
            cons["kinetic_final_spam"] = float(s0["kinetic_final"])
            cons["kinetic_final_lammps"] = ke_l
            cons["kinetic_final_rel_diff"] = ((float(s0["kinetic_final"]) - ke_l)
                                              / abs(ke_l) if ke_l else None)
        eos = (s0.get("eos_gamma"), s0.get("eos_kappa"))
        cons["eos_gamma_kappa"] = eos
        if eos != (None, None) and eos != (2, 0.5):
            print("  WARNING: spam-ark ran with eos gamma %s kappa %s; the LAMMPS "
                  "equivalence needs P = rho^2/2 (gamma 2, kappa 0.5)" % eos)
        if isinstance(s0.get("energy_rel_drift_final"), (int, float)):
            S["energy_rel_drift"] = float(s0["energy_rel_drift_final"])
        res["consistency"] = cons
        if S["time_per_eval_s"] and L["time_per_eval_s"]:
            res["ratio_time_per_eval"] = S["time_per_eval_s"] / L["time_per_eval_s"]
            res["target_met"] = res["ratio_time_per_eval"] <= 1.0
    res["spam"] = S
    return res


def baselines(args, workdir, pin, spam_ok):
    """Peak RSS of each program on a 64-particle problem (runtime baseline)."""
    nx = 8
    box = np.array([2.0 * nx, 2.0 * nx])
    pos, vel, mass = numpy_lattice(nx)
    out = {"n": len(pos)}
    table = workdir / "table_baseline.dat"
    write_table(table, args.h, args.table_points, args.table_rlo)
    data = workdir / "baseline.data"
    write_lammps_data(data, pos, vel, box, 1.0)
    try:
        r = lammps_run(args.lmp, data, table, args.h, args.skin, 1, args.table_points,
                       workdir, "baseline", pin)
        out["lammps_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
    except RuntimeError as exc:
        print("  (LAMMPS baseline failed: %s)" % str(exc).splitlines()[0])
    if spam_ok:
        csv = workdir / "baseline.csv"
        write_particles_csv(csv, pos, vel, mass)
        try:
            r = spam_run(args.spam_ark, csv, box, args.h, 1, workdir, "baseline", pin)
            out["spam_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
        except RuntimeError as exc:
            print("  (spam-ark baseline failed: %s)" % str(exc).splitlines()[0])
    return out


def print_size(res, base):
    n = res["n"]
    L, S = res["lammps"], res["spam"]
    print()
    print("N = %d  (%dx%d lattice in a periodic %gx%g box, h = %g, dt = %g)"
          % (n, res["nx"], res["nx"], res["box"][0], res["box"][1], res["h"], res["dt"]))
    print("  initial particles: %s" % res["initial_source"])
    print("  pairs i<j with r < h: initial %d (numpy), %d (LAMMPS coord/atom at step 0);"
          % (res["pairs_initial"], res["pairs_lammps_step0"] or -1))
    print("    the gas expands, so the count falls: %d after %d steps; time-mean %.0f "
          "over the LAMMPS window, %.0f over the spam-ark window"
          % (res["pairs_end_lammps_window"], res["lammps_steps"],
             res["pairs_mean_lammps_window"] or float("nan"),
             res["pairs_mean_spam_window"] or float("nan")))
    bl_s = base.get("spam_ru_maxrss_bytes")
    bl_l = base.get("lammps_ru_maxrss_bytes")
    have_s = bool(S)

    NA = object()  # row does not apply to that program

    def row(label, sv, lv, fmt="%.3f", ratio=False):
        s = "" if sv is NA else (fnum(sv, fmt) if have_s else "n/a")
        ls = "" if lv is NA else fnum(lv, fmt)
        rr = ""
        if ratio and sv and lv and sv is not NA and lv is not NA:
            rr = "%.3f" % (sv / lv)
        print("  %-46s %14s %14s %9s" % (label, s, ls, rr))

    print("  %-46s %14s %14s %9s" % ("", "spam-ark", "LAMMPS", "ratio"))
    row("steps", S.get("steps"), res["lammps_steps"], "%.0f")
    row("force (RHS) evaluations", S.get("rhs_evals"), res["lammps_steps"], "%.0f")
    row("time per force evaluation (ms)",
        S.get("time_per_eval_s") and S["time_per_eval_s"] * 1e3,
        L["time_per_eval_s"] * 1e3, "%.3f", ratio=True)
    row("  LAMMPS Pair section only (ms)", NA, L["pair_time_per_eval_s"] * 1e3)
    row("  same, LAMMPS Pair + Neigh sections only",
        S.get("time_per_eval_s") and S["time_per_eval_s"] * 1e3,
        L["pair_neigh_time_per_eval_s"] * 1e3, "%.3f", ratio=True)
    row("ns per pair, initial pair count", S.get("ns_per_pair_initial"),
        L["ns_per_pair_initial"], "%.2f", ratio=True)
    row("ns per pair, time-mean pair count", S.get("ns_per_pair_mean"),
        L["ns_per_pair_mean"], "%.2f", ratio=True)
    row("ns per pair, spam-ark's own count", S.get("ns_per_pair_self_reported"), NA,
        "%.2f")
    row("neighbour list builds", S.get("neighbour_builds"), L["neighbor_builds"], "%.0f")
    row("peak RSS (MiB, ru_maxrss)",
        S.get("ru_maxrss_bytes") and S["ru_maxrss_bytes"] / 2 ** 20,
        L["ru_maxrss_bytes"] / 2 ** 20, "%.1f")
    row("peak RSS / N (bytes, incl. runtime baseline)",
        S.get("ru_maxrss_bytes") and S["ru_maxrss_bytes"] / n,
        L["ru_maxrss_bytes"] / n, "%.0f")
    row("(peak RSS - 64-particle run) / N (bytes)",
        S.get("ru_maxrss_bytes") and bl_s and (S["ru_maxrss_bytes"] - bl_s) / n,
        bl_l and (L["ru_maxrss_bytes"] - bl_l) / n, "%.0f")
    row("  spam-ark peak_rss_bytes / N (self-reported)",
        S.get("peak_rss_bytes_self_reported") and S["peak_rss_bytes_self_reported"] / n,
        NA, "%.0f")
    row("  LAMMPS 'memory allocation' (MiB)", NA, L["lammps_memory_mbytes"], "%.2f")
    if "energy_rel_drift" in L:
        print("  relative energy change over the run: spam-ark %s, LAMMPS %.2e"
              % (fnum(S.get("energy_rel_drift"), "%.2e"), L["energy_rel_drift"]))
    cons = res.get("consistency") or {}
    if "energy_initial_rel_diff" in cons:
        print("  same physics? E(0): spam-ark %.10g, LAMMPS KE+PE+N m^2 w(0)/2 %.10g "
              "(rel diff %.1e)" % (cons["energy_initial_spam"],
                                   cons["energy_initial_lammps_plus_self"],
                                   cons["energy_initial_rel_diff"]))
    if cons.get("kinetic_final_rel_diff") is not None:
        print("                KE at the last step: spam-ark %.10g, LAMMPS %.10g "
              "(rel diff %.1e)" % (cons["kinetic_final_spam"], cons["kinetic_final_lammps"],
                                   cons["kinetic_final_rel_diff"]))
    if S.get("summary_keys_missing"):
        print("  note: spam-ark summary.json lacks %s" % ", ".join(S["summary_keys_missing"]))
    if "ratio_time_per_eval" in res:
        print("  spam-ark / LAMMPS time per force evaluation = %.3f   target <= 1.0: %s"
              % (res["ratio_time_per_eval"], "met" if res["target_met"] else "not met"))
    else:
        print("  spam-ark / LAMMPS: not measured (spam-ark not run)")


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    if shutil.which(args.lmp) is None and not Path(args.lmp).is_file():
        sys.exit("LAMMPS binary %r not found (Debian: apt-get install lammps)" % args.lmp)
    args.lmp = shutil.which(args.lmp) or str(Path(args.lmp).resolve())
    args.spam_ark = str(Path(args.spam_ark).resolve())
    pin = pin_prefix(args.cpu, not args.no_pin)

    spam_ok = False
    spam_note = "skipped (--lammps-only)"
    if not args.lammps_only:
        spam_ok, why = spam_ark_works(args.spam_ark)
        spam_note = "ok" if spam_ok else why
        if not spam_ok:
            print("warning: spam-ark unusable (%s); running the LAMMPS half only, "
                  "on a numpy-made lattice" % why)

    if args.workdir:
        workdir = Path(args.workdir).resolve()
        workdir.mkdir(parents=True, exist_ok=True)
        own_workdir = False
    else:
        workdir = Path(tempfile.mkdtemp(prefix="spam-ark-bench-"))
        own_workdir = True

    print("spam-ark bench: spam-ark %s [%s]; LAMMPS %s; pinning: %s; OMP_NUM_THREADS=1; "
          "repeats %d (median); LAMMPS skin %g, table %d points"
          % (args.spam_ark, spam_note, args.lmp, " ".join(pin) or "none",
             args.repeats, args.skin, args.table_points))
    print("scratch: %s" % workdir)

    out = {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "host": platform.node(), "machine": platform.machine(),
        "cpu_count": os.cpu_count(), "python": sys.version.split()[0],
        "numpy": np.__version__, "spam_ark": args.spam_ark, "spam_ark_status": spam_note,
        "lammps": args.lmp, "pin": pin, "repeats": args.repeats, "h": args.h, "dt": DT,
        "lammps_skin": args.skin, "table_points": args.table_points,
        "table_rlo": args.table_rlo, "sizes": sizes, "results": [],
    }
    try:
        lv = subprocess.run([args.lmp, "-h"], capture_output=True, text=True, timeout=60)
        m = re.search(r"LAMMPS.*?- (.+)", lv.stdout)
        out["lammps_version"] = m.group(1).strip() if m else None
    except (OSError, subprocess.TimeoutExpired):
        out["lammps_version"] = None
    try:
        out["git_head"] = subprocess.run(["git", "-C", str(REPO_ROOT), "rev-parse", "HEAD"],
                                         capture_output=True, text=True).stdout.strip()
    except OSError:
        out["git_head"] = None

    try:
        if args.validate_lammps:
            print("\nLAMMPS checks")
            out["lammps_validation"] = validate_lammps(args, workdir, pin)
        base = baselines(args, workdir, pin, spam_ok)
        out["baseline"] = base
        table_cache = {}
        for n in sizes:
            res = bench_size(n, args, workdir, pin, spam_ok, table_cache)
            out["results"].append(res)
            print_size(res, base)
    finally:
        if own_workdir and not args.keep:
            shutil.rmtree(workdir, ignore_errors=True)
        elif own_workdir:
            print("kept scratch directory %s" % workdir)

    if args.out:
        path = Path(args.out)
    else:
        results = BENCH_DIR / "results"
        results.mkdir(parents=True, exist_ok=True)
        path = results / ("bench_%s.json"
                          % datetime.datetime.now().strftime("%Y-%m-%dT%H%M%S"))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=1, default=str) + "\n")
    print("\nwrote %s" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
