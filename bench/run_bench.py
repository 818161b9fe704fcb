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

Cases: the 2D isentropic expansion at h = 3 and h = 6 (spam-ark against
LAMMPS, same particles, steps and dt), and the elastic solid on spam-ark's
full tensor path (plane-wave scene, continuity density, R2 coordinates),
which LAMMPS cannot run; its cost is set against the LAMMPS gas only as a
reference.  Sizes N = 16384 ... 1048576.  At the end the script reports the
targets T1-T3 as "met" or "falls short".

This is a measurement, not a test: it prints a table and writes
bench/results/bench_<date>.json; the exit code is non-zero only when a run
fails.  See bench/README.md.

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
    """Import numpy; if this interpreter lacks it, re-run under the system one.

    What is re-run is the program that was started (this script, or a script
    that imports it, such as run_verlet.py), never this module on its own: an
    import must not turn into a benchmark run.  Without a main script (python3
    -c, an interactive session) there is nothing to re-run, so it just exits.
    """
    import importlib.util
    if importlib.util.find_spec("numpy") is not None:
        return
    main_file = getattr(sys.modules.get("__main__"), "__file__", None)
    if main_file and not os.environ.get("SPAM_BENCH_REEXEC"):
        for cand in ("/usr/bin/python3", "/usr/local/bin/python3"):
            if (os.path.exists(cand)
                    and os.path.realpath(cand) != os.path.realpath(sys.executable)):
                env = dict(os.environ, SPAM_BENCH_REEXEC="1")
                os.execve(cand, [cand, os.path.abspath(main_file)] + sys.argv[1:], env)
    sys.exit("run_bench.py needs numpy (Debian: apt-get install python3-numpy, "
             "then run it with /usr/bin/python3)")


_ensure_numpy()
import numpy as np  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
BENCH_DIR = Path(__file__).resolve().parent
DT = 0.05
DP_TABLE = "ARKODE_DORMAND_PRINCE_7_4_5"
DEFAULT_SIZES = "16384,65536,262144,1048576"
DEFAULT_CASES = "gas-h3,gas-h6,solid-h3"
QUICK_SIZES = "4096"
QUICK_STEPS = 20
# Default step counts: STEPS_AT_16384[kind] * (3/h) * 16384/N, clamped to
# [MIN_STEPS, MAX_STEPS]; chosen so that one timed spam-ark run takes a few
# seconds on this machine (1-4 s up to N = 262144, longer at 1048576, where
# MIN_STEPS decides).  The gas does not get more steps: the longer the run,
# the more pairs the expanding gas loses, and the less the cost per particle
# at different N measures the same thing (T2).
STEPS_AT_16384 = {"gas": 160, "solid": 64}
MIN_STEPS = 4
MAX_STEPS = 2000
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


_INITIAL_CACHE = {}


def spam_make_initial(binary, nx, h, workdir):
    """The expansion lattice NX x NX at range h, written by spam-ark -initial_csv.

    Returns (csv_path, command line).  Made once per (workdir, nx, h).
    """
    key = (str(workdir), nx, float(h))
    if key in _INITIAL_CACHE and Path(_INITIAL_CACHE[key][0]).exists():
        return _INITIAL_CACHE[key]
    tag = "%d_h%g" % (nx, h)
    outdir = workdir / ("init_%s" % tag)
    outdir.mkdir(parents=True, exist_ok=True)
    csv = workdir / ("initial_%s.csv" % tag)
    opts = REPO_ROOT / "options" / "expansion.opts"
    if opts.is_file():
        scene = ["-options_file", opts]
    else:
        print("  note: %s is missing; using -scene expansion -dim 2 instead" % opts)
        scene = ["-scene", "expansion", "-dim", 2]
    cmd = [binary] + scene + [
           "-expansion_n", nx, "-h", h, "-initial_csv", csv,
           "-ts_max_steps", 0, "-output_dir", outdir, "-output_overwrite"]
    log = workdir / ("init_%s.log" % tag)
    rc, _, _ = run_measured(cmd, REPO_ROOT, log)
    if rc != 0 or not csv.exists():
        raise RuntimeError("spam-ark initial-state run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    _INITIAL_CACHE[key] = (csv, " ".join(map(str, cmd)))
    return _INITIAL_CACHE[key]


def _run_limits(steps):
    """Options shared by every timed spam-ark run: a fixed Dormand-Prince step,
    a step count, no snapshots and no entropy estimates (not part of the
    benchmark), diagnostics only at the start and the end."""
    return ["-arkode_table", DP_TABLE,
            "-arkode_fixed_step", DT, "-ts_max_steps", steps,
            # The scenes' default end times would stop the run early (t = 10
            # for the file scene); set it past the last step so that
            # -ts_max_steps decides.
            "-ts_max_time", "%.17g" % ((steps + 0.5) * DT),
            "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0]


def spam_cmd(binary, csv, box, h, steps, outdir):
    """The gas run: the file scene on the expansion lattice."""
    return [binary, "-scene", "file", "-file_path", csv, "-dim", 2,
            "-box_lo", "0,0", "-box_len", "%.17g,%.17g" % (box[0], box[1]),
            "-periodic", "1,1", "-h", h] + _run_limits(steps) + ["-output_dir", outdir]


# The elastic solid on the full tensor path (options/planewave.opts, with R2
# coordinates instead of R0): Hooke's law with the stress in the state,
# continuity density, XSPH coordinates, no angular-momentum treatment.
SOLID_PHYSICS = ["-scene", "planewave", "-dim", 2, "-mass", 1,
                 "-planewave_mode", "transverse", "-planewave_amplitude", 0.25,
                 "-material", "elastic", "-density", "continuity",
                 "-density_initial", "ideal", "-coordinates", "R2", "-angmom", "none"]


def solid_cmd(binary, nx, ny, h, steps, outdir):
    return ([binary] + SOLID_PHYSICS
            + ["-planewave_nx", nx, "-planewave_ny", ny, "-h", h]
            + _run_limits(steps) + ["-output_dir", outdir])


def solid_shape(n):
    """Lattice rows NY (even) and row length NX with NX*NY as close to n as
    possible: NX = NY = sqrt(n) when that is an even integer."""
    ny = max(2, 2 * int(round(math.sqrt(n) / 2)))
    nx = max(1, int(round(n / ny)))
    return nx, ny


def read_loop_wall(outdir):
    """wall_s of the last timeseries.csv row: from the start of the run to the
    end of the last step (the initial diagnostics included, the final ones
    not).  None if the file or column is missing."""
    path = Path(outdir) / "timeseries.csv"
    try:
        lines = path.read_text().splitlines()
    except OSError:
        return None
    if len(lines) < 2:
        return None
    cols = lines[0].split(",")
    if "wall_s" not in cols:
        return None
    try:
        return float(lines[-1].split(",")[cols.index("wall_s")])
    except (ValueError, IndexError):
        return None


def spam_run_cmd(cmd_for, workdir, tag, pin, extra=()):
    """Run spam-ark; cmd_for(outdir) builds the command.  Returns a dict with
    the summary, the loop wall time and the process's peak RSS."""
    outdir = workdir / ("spam_%s" % tag)
    if outdir.exists():
        shutil.rmtree(outdir)
    outdir.mkdir(parents=True)
    cmd = pin + cmd_for(outdir) + list(extra)
    log = workdir / ("spam_%s.log" % tag)
    rc, wall, rss = run_measured(cmd, REPO_ROOT, log)
    summ_path = outdir / "summary.json"
    if rc != 0 or not summ_path.exists():
        raise RuntimeError("spam-ark run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    summary = json.loads(summ_path.read_text())
    return {"rc": rc, "process_wall_s": wall, "ru_maxrss_bytes": rss,
            "loop_wall_s": read_loop_wall(outdir),
            "summary": summary, "cmd": " ".join(map(str, cmd))}


def spam_run(binary, csv, box, h, steps, workdir, tag, pin, extra=()):
    return spam_run_cmd(lambda d: spam_cmd(binary, csv, box, h, steps, d),
                        workdir, tag, pin, extra)


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

def validate_lammps(args, workdir, pin, h=3.0):
    """Check the table/potential pipeline and energy conservation in LAMMPS."""
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
# Cases, sizes and step counts
# --------------------------------------------------------------------------

def parse_cases(text):
    """'gas-h3,gas-h6,solid-h3' -> list of case dicts (name, kind, h, label)."""
    cases = []
    for tok in (t.strip() for t in text.split(",")):
        if not tok:
            continue
        m = re.fullmatch(r"(gas|solid)-h(\d+(?:\.\d*)?|\.\d+)", tok)
        if not m:
            raise SystemExit("--cases: %r is not gas-hH or solid-hH (e.g. gas-h3, "
                             "solid-h3)" % tok)
        kind, h = m.group(1), float(m.group(2))
        if h <= 0:
            raise SystemExit("--cases: %r needs h > 0" % tok)
        label = ("gas h=%g (isentrope P = rho^2/2; LAMMPS pair_style table)" % h
                 if kind == "gas" else
                 "solid h=%g (elastic, continuity density, R2; spam-ark only)" % h)
        cases.append({"name": "%s-h%g" % (kind, h), "kind": kind, "h": h,
                      "label": label})
    if not cases:
        raise SystemExit("--cases: no case given")
    # A solid's reference is the LAMMPS gas at the same h: run gases first.
    return sorted(cases, key=lambda c: (c["kind"] != "gas", c["h"]))


def steps_for(case, n, args):
    """(LAMMPS steps, spam-ark steps) for a case and size.

    Default: STEPS_AT_16384[kind] * (3/h) * 16384/N, at least MIN_STEPS and
    at most MAX_STEPS, so that one timed spam-ark run takes a few seconds.
    """
    if args.steps is not None:
        base = args.steps
    else:
        k = STEPS_AT_16384[case["kind"]] * (3.0 / case["h"])
        base = int(min(MAX_STEPS, max(MIN_STEPS, round(k * 16384 / n))))
    ls = args.lammps_steps if args.lammps_steps is not None else base
    ss = args.spam_steps if args.spam_steps is not None else base
    return ls, ss


def per_particle(x, base, n):
    """(x - base) / n, or None when either is unknown."""
    if not x or not base or not n:
        return None
    return (x - base) / n


def summarize_spam(spam, n, pairs_mean, pairs0, baseline_rss):
    """Medians over the spam-ark runs of one case and size."""
    def sget(r, key):
        v = r["summary"].get(key)
        return float(v) if isinstance(v, (int, float)) else None

    S = {}
    per_eval, per_step = [], []
    for r in spam:
        rt, ne, ns = sget(r, "rhs_time_s"), sget(r, "rhs_evals"), sget(r, "steps")
        per_eval.append(rt / ne if rt is not None and ne else None)
        loop = r.get("loop_wall_s")
        if loop is None:
            loop = sget(r, "wall_time_s")
        per_step.append(loop / ns if loop is not None and ns else None)
    S["time_per_eval_s"] = med(per_eval)
    S["time_per_step_s"] = med(per_step)
    S["time_per_eval_s_runs"] = per_eval
    S["time_per_step_s_runs"] = per_step
    S["rhs_evals"] = med([sget(r, "rhs_evals") for r in spam])
    S["steps"] = med([sget(r, "steps") for r in spam])
    S["rhs_evals_per_step"] = (S["rhs_evals"] / S["steps"]
                               if S["rhs_evals"] and S["steps"] else None)
    S["wall_time_s"] = med([sget(r, "wall_time_s") for r in spam])
    S["loop_wall_s"] = med([r.get("loop_wall_s") for r in spam])
    S["rhs_time_s"] = med([sget(r, "rhs_time_s") for r in spam])
    S["ns_per_pair_self_reported"] = med([sget(r, "ns_per_pair") for r in spam])
    S["pair_interactions_per_s"] = med([sget(r, "pair_interactions_per_s") for r in spam])
    S["peak_rss_bytes_self_reported"] = med([sget(r, "peak_rss_bytes") for r in spam])
    S["neighbour_builds"] = med([sget(r, "neighbour_builds") for r in spam])
    S["n_particles"] = med([sget(r, "n_particles") for r in spam])
    S["ru_maxrss_bytes"] = med([r["ru_maxrss_bytes"] for r in spam])
    te, ts = S["time_per_eval_s"], S["time_per_step_s"]
    S["time_per_eval_per_particle_s"] = te / n if te else None
    S["particle_steps_per_s"] = n / ts if ts else None
    S["ns_per_pair_initial"] = te / pairs0 * 1e9 if te and pairs0 else None
    S["ns_per_pair_mean"] = te / pairs_mean * 1e9 if te and pairs_mean else None
    S["rss_per_particle_bytes"] = S["ru_maxrss_bytes"] / n if S["ru_maxrss_bytes"] else None
    S["rss_minus_baseline_per_particle_bytes"] = per_particle(
        S["ru_maxrss_bytes"], baseline_rss, n)
    S["self_rss_per_particle_bytes"] = (S["peak_rss_bytes_self_reported"] / n
                                        if S["peak_rss_bytes_self_reported"] else None)
    missing = [k for k in ("rhs_evals", "steps", "wall_time_s", "rhs_time_s",
                           "pair_interactions_per_s", "ns_per_pair",
                           "peak_rss_bytes", "n_particles", "neighbour_builds")
               if k not in spam[0]["summary"]]
    if missing:
        S["summary_keys_missing"] = missing
    if not all(r.get("loop_wall_s") is not None for r in spam):
        S["loop_wall_note"] = "timeseries.csv wall_s missing; used summary wall_time_s"
    s0 = spam[0]["summary"]
    if isinstance(s0.get("energy_rel_drift_final"), (int, float)):
        S["energy_rel_drift"] = float(s0["energy_rel_drift_final"])
    return S


# --------------------------------------------------------------------------
# One case at one size
# --------------------------------------------------------------------------

def bench_gas(n, case, args, workdir, pin, spam_ok, table_cache, base):
    nx = int(round(math.sqrt(n)))
    if nx * nx != n:
        raise SystemExit("gas size %d is not a perfect square NX^2" % n)
    h = case["h"]
    box = np.array([2.0 * nx, 2.0 * nx])
    lsteps, ssteps = steps_for(case, n, args)
    res = {"case": case["name"], "kind": "gas", "label": case["label"],
           "n": n, "nx": nx, "box": box.tolist(), "h": h, "dt": DT,
           "lammps_steps": lsteps, "spam_steps": ssteps}

    # ---- initial particles -------------------------------------------------
    if spam_ok and not args.numpy_initial:
        csv, res["initial_cmd"] = spam_make_initial(args.spam_ark, nx, h, workdir)
        res["initial_source"] = "spam-ark -initial_csv"
    else:
        csv = workdir / ("initial_%d_numpy.csv" % nx)
        if not csv.exists():
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
    data = workdir / ("lammps_%d_h%g.data" % (nx, h))
    write_lammps_data(data, pos, vel, box, m0)

    t0 = time.perf_counter()
    pairs0 = count_pairs(pos, box, h)
    res["pairs_initial"] = pairs0
    res["pair_count_time_s"] = time.perf_counter() - t0
    del vel

    # ---- pair census along the trajectory (LAMMPS, untimed) ----------------
    horizon = max(lsteps, ssteps)
    every = max(1, min(lsteps, ssteps) // 20)
    horizon = int(math.ceil(horizon / every) * every)
    tag = "%d_h%g" % (nx, h)
    cen = lammps_run(args.lmp, data, table, h, args.skin, horizon, args.table_points,
                     workdir, "census_%s" % tag, [], thermo_every=every, census=True)
    samples = [(int(r["Step"]), r["c_cs"] / 2.0) for r in cen["thermo"]]
    res["pair_census"] = samples
    res["pairs_lammps_step0"] = samples[0][1] if samples else None
    res["pairs_mean_lammps_window"] = window_mean(samples, lsteps)
    res["pairs_mean_spam_window"] = window_mean(samples, ssteps)
    res["pairs_end_lammps_window"] = [v for s, v in samples if s <= lsteps][-1]

    # ---- timed runs, each process alone, alternating -----------------------
    lam = []
    spam = []
    for k in range(args.repeats):
        lam.append(lammps_run(args.lmp, data, table, h, args.skin, lsteps,
                              args.table_points, workdir, "%s_r%d" % (tag, k), pin))
        if spam_ok:
            spam.append(spam_run(args.spam_ark, csv, box, h, ssteps, workdir,
                                 "%s_r%d" % (tag, k), pin))
    res["lammps_runs"] = lam
    res["spam_runs"] = spam
    res["timed_seconds"] = sum(r["process_wall_s"] for r in lam + spam)

    L = {}
    L["time_per_eval_s"] = med([r["loop_time_s"] / r["steps"] for r in lam])
    L["time_per_eval_s_runs"] = [r["loop_time_s"] / r["steps"] for r in lam]
    # velocity Verlet: one force evaluation per step
    L["time_per_step_s"] = L["time_per_eval_s"]
    L["particle_steps_per_s"] = n / L["time_per_step_s"] if L["time_per_step_s"] else None
    L["time_per_eval_per_particle_s"] = L["time_per_eval_s"] / n
    L["pair_time_per_eval_s"] = med([r.get("pair_time_s", float("nan")) / r["steps"]
                                     for r in lam])
    L["pair_neigh_time_per_eval_s"] = med([(r.get("pair_time_s", float("nan"))
                                            + r.get("neigh_time_s", float("nan")))
                                           / r["steps"] for r in lam])
    L["neighbor_builds"] = med([r.get("neighbor_builds") for r in lam])
    L["dangerous_builds"] = max(r.get("dangerous_builds", 0) for r in lam)
    L["ru_maxrss_bytes"] = med([r["ru_maxrss_bytes"] for r in lam])
    L["rss_per_particle_bytes"] = L["ru_maxrss_bytes"] / n if L["ru_maxrss_bytes"] else None
    L["rss_minus_baseline_per_particle_bytes"] = per_particle(
        L["ru_maxrss_bytes"], base.get("lammps_ru_maxrss_bytes"), n)
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
        S = summarize_spam(spam, n, res["pairs_mean_spam_window"], pairs0,
                           base.get("spam_ru_maxrss_bytes"))
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
        res["consistency"] = cons
        if S["time_per_eval_s"] and L["time_per_eval_s"]:
            res["ratio_time_per_eval"] = S["time_per_eval_s"] / L["time_per_eval_s"]
        if S["time_per_step_s"] and L["time_per_step_s"]:
            res["ratio_time_per_step"] = S["time_per_step_s"] / L["time_per_step_s"]
    res["spam"] = S
    return res


def bench_solid(n, case, args, workdir, pin, base):
    h = case["h"]
    nx, ny = solid_shape(n)
    ns = nx * ny
    _, steps = steps_for(case, n, args)
    res = {"case": case["name"], "kind": "solid", "label": case["label"],
           "n_requested": n, "n": ns, "nx": nx, "ny": ny, "h": h, "dt": DT,
           "spam_steps": steps}
    if ns != n:
        print("  note: solid lattice %dx%d has N = %d (requested %d)" % (nx, ny, ns, n))

    # ---- initial particles (for the pair count and the box) ----------------
    tag = "solid_%dx%d_h%g" % (nx, ny, h)
    init_dir = workdir / ("init_%s" % tag)
    init_dir.mkdir(parents=True, exist_ok=True)
    csv0 = workdir / ("initial_%s.csv" % tag)
    cmd = ([args.spam_ark] + SOLID_PHYSICS
           + ["-planewave_nx", nx, "-planewave_ny", ny, "-h", h,
              "-initial_csv", csv0, "-ts_max_steps", 0, "-output_dir", init_dir, "-output_overwrite"])
    log = workdir / ("init_%s.log" % tag)
    rc, _, _ = run_measured(cmd, REPO_ROOT, log)
    if rc != 0 or not csv0.exists() or not (init_dir / "summary.json").exists():
        raise RuntimeError("spam-ark solid initial-state run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    res["initial_cmd"] = " ".join(map(str, cmd))
    s_init = json.loads((init_dir / "summary.json").read_text())
    box = np.array([float(v) for v in s_init.get("box_len", [0, 0])[:2]])
    lo = np.array([float(v) for v in s_init.get("box_lo", [0, 0])[:2]])
    res["box"] = box.tolist()
    pos = read_particles_csv(csv0)[0] - lo
    t0 = time.perf_counter()
    pairs0 = count_pairs(pos, box, h)
    res["pair_count_time_s"] = time.perf_counter() - t0
    res["pairs_initial"] = pairs0
    del pos
    csv0.unlink()

    # ---- timed runs (the first also writes the final particles) ------------
    spam = []
    csv1 = workdir / ("final_%s.csv" % tag)
    for k in range(args.repeats):
        extra = ["-final_csv", csv1] if k == 0 else []
        spam.append(spam_run_cmd(lambda d: solid_cmd(args.spam_ark, nx, ny, h, steps, d),
                                 workdir, "%s_r%d" % (tag, k), pin, extra))
    res["spam_runs"] = spam
    res["timed_seconds"] = sum(r["process_wall_s"] for r in spam)
    pairs1 = None
    if csv1.exists():
        pos1 = read_particles_csv(csv1)[0] - lo
        pairs1 = count_pairs(pos1, box, h)
        del pos1
        csv1.unlink()
    res["pairs_final"] = pairs1
    # The solid barely moves: the mean of the two counts is the time-mean.
    pm = 0.5 * (pairs0 + pairs1) if pairs1 is not None else pairs0
    res["pairs_mean_spam_window"] = pm
    res["spam"] = summarize_spam(spam, ns, pm, pairs0, base.get("spam_ru_maxrss_bytes"))
    return res


def solid_reference(res, results):
    """The solid's cost against the LAMMPS gas at the nearest N and the same h
    (a reference cost, not the same dynamics)."""
    gases = [r for r in results if r.get("kind") == "gas" and r.get("h") == res["h"]
             and r.get("lammps", {}).get("time_per_step_s")]
    if not gases:
        return None
    g = min(gases, key=lambda r: (abs(math.log(r["n"] / res["n"])), -r["n"]))
    S = res["spam"]
    ref = {"gas_case": g["case"], "gas_n": g["n"],
           "lammps_gas_time_per_step_s": g["lammps"]["time_per_step_s"],
           "lammps_gas_time_per_step_per_particle_s": g["lammps"]["time_per_step_s"] / g["n"]}
    te = S.get("time_per_eval_s")
    if te:
        ref["ratio_time_per_eval"] = te / g["lammps"]["time_per_step_s"]
        # per particle, in case the two N differ
        ref["ratio_time_per_eval_per_particle"] = ((te / res["n"])
                                                   / ref["lammps_gas_time_per_step_per_particle_s"])
        gs = g.get("spam", {}).get("time_per_eval_s")
        if gs:
            ref["spam_gas_time_per_eval_s"] = gs
            ref["ratio_to_spam_gas_per_particle"] = (te / res["n"]) / (gs / g["n"])
    return ref


# --------------------------------------------------------------------------
# Memory baselines
# --------------------------------------------------------------------------

def baselines(args, workdir, pin, spam_ok, case):
    """Peak RSS of each program on a 64-particle problem of this case (the
    runtime baseline: libraries, MPI, PETSc, ...)."""
    h = case["h"]
    out = {}
    if case["kind"] == "solid":
        if not spam_ok:
            return out
        # 8 x 8 unless the box (NX by NY sqrt(3)/2) must be wider than 2.2 h.
        nx = max(8, int(math.ceil(2.2 * h)))
        ny = max(8, 2 * int(math.ceil(2.2 * h / math.sqrt(3))))
        out["n"] = nx * ny
        try:
            r = spam_run_cmd(lambda d: solid_cmd(args.spam_ark, nx, ny, h, 1, d),
                             workdir, "baseline_%s" % case["name"], pin)
            out["spam_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
        except RuntimeError as exc:
            print("  (spam-ark solid baseline failed: %s)" % str(exc).splitlines()[0])
        return out
    nx = 8
    side = max(2.0 * nx, 2.0 * math.ceil(1.1 * h + 1.0))
    box = np.array([side, side])
    pos, vel, mass = numpy_lattice(nx)
    out["n"] = len(pos)
    table = workdir / ("table_baseline_h%g.dat" % h)
    write_table(table, h, args.table_points, args.table_rlo)
    data = workdir / ("baseline_h%g.data" % h)
    write_lammps_data(data, pos, vel, box, 1.0)
    try:
        r = lammps_run(args.lmp, data, table, h, args.skin, 1, args.table_points,
                       workdir, "baseline_%s" % case["name"], pin)
        out["lammps_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
    except RuntimeError as exc:
        print("  (LAMMPS baseline failed: %s)" % str(exc).splitlines()[0])
    if spam_ok:
        csv = workdir / ("baseline_h%g.csv" % h)
        write_particles_csv(csv, pos, vel, mass)
        try:
            r = spam_run(args.spam_ark, csv, box, h, 1, workdir,
                         "baseline_%s" % case["name"], pin)
            out["spam_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
        except RuntimeError as exc:
            print("  (spam-ark baseline failed: %s)" % str(exc).splitlines()[0])
    return out


# --------------------------------------------------------------------------
# Printing
# --------------------------------------------------------------------------

NA = object()  # a row that does not apply to that program


def _ms(x):
    return x * 1e3 if x else None


def _mega(x):
    return x / 1e6 if x else None


def _row(label, sv, lv, fmt="%.3f", ratio=False, have_s=True, width=50):
    s = "" if sv is NA else (fnum(sv, fmt) if have_s else "n/a")
    ls = "" if lv is NA else fnum(lv, fmt)
    rr = ""
    if (ratio and sv is not NA and lv is not NA and sv and lv
            and not (isinstance(lv, float) and math.isnan(lv))):
        rr = "%.3f" % (sv / lv)
    print("  %-*s %14s %14s %9s" % (width, label, s, ls, rr))


def print_gas(res, base):
    n = res["n"]
    L, S = res["lammps"], res["spam"]
    have_s = bool(S)
    print()
    print("== %s, N = %d  (%dx%d lattice in a periodic %gx%g box, dt = %g, %d steps)"
          % (res["label"], n, res["nx"], res["nx"], res["box"][0], res["box"][1],
             res["dt"], res["spam_steps"]))
    print("  initial particles: %s" % res["initial_source"])
    print("  pairs i<j with r < h: initial %d (numpy), %d (LAMMPS coord/atom at step 0);"
          % (res["pairs_initial"], res["pairs_lammps_step0"] or -1))
    print("    the gas expands, so the count falls: %d after %d steps; time-mean %.0f "
          "over the LAMMPS window, %.0f over the spam-ark window"
          % (res["pairs_end_lammps_window"], res["lammps_steps"],
             res["pairs_mean_lammps_window"] or float("nan"),
             res["pairs_mean_spam_window"] or float("nan")))

    def row(label, sv, lv, fmt="%.3f", ratio=False):
        _row(label, sv, lv, fmt, ratio, have_s)

    print("  %-50s %14s %14s %9s" % ("", "spam-ark", "LAMMPS", "ratio"))
    row("steps", S.get("steps"), res["lammps_steps"], "%.0f")
    row("force (RHS) evaluations", S.get("rhs_evals"), res["lammps_steps"], "%.0f")
    row("time per force (RHS) evaluation (ms)", _ms(S.get("time_per_eval_s")),
        _ms(L["time_per_eval_s"]), "%.3f", ratio=True)
    row("  LAMMPS Pair section only (ms)", NA, _ms(L["pair_time_per_eval_s"]))
    row("  same, LAMMPS Pair + Neigh sections only", _ms(S.get("time_per_eval_s")),
        _ms(L["pair_neigh_time_per_eval_s"]), "%.3f", ratio=True)
    row("time per step (ms)", _ms(S.get("time_per_step_s")), _ms(L["time_per_step_s"]),
        "%.3f", ratio=True)
    row("particle-steps per second per core (millions)",
        _mega(S.get("particle_steps_per_s")), _mega(L["particle_steps_per_s"]), "%.3f",
        ratio=True)
    row("time per force evaluation / N (ns)",
        S.get("time_per_eval_per_particle_s") and S["time_per_eval_per_particle_s"] * 1e9,
        L["time_per_eval_per_particle_s"] * 1e9, "%.2f", ratio=True)
    row("ns per pair, initial pair count", S.get("ns_per_pair_initial"),
        L["ns_per_pair_initial"], "%.2f", ratio=True)
    row("ns per pair, time-mean pair count", S.get("ns_per_pair_mean"),
        L["ns_per_pair_mean"], "%.2f", ratio=True)
    row("ns per pair, spam-ark's own count", S.get("ns_per_pair_self_reported"), NA, "%.2f")
    row("neighbour list builds", S.get("neighbour_builds"), L["neighbor_builds"], "%.0f")
    row("peak RSS (MiB, ru_maxrss)",
        S.get("ru_maxrss_bytes") and S["ru_maxrss_bytes"] / 2 ** 20,
        L["ru_maxrss_bytes"] / 2 ** 20, "%.1f")
    row("peak RSS / N (bytes, incl. runtime baseline)",
        S.get("rss_per_particle_bytes"), L["rss_per_particle_bytes"], "%.0f")
    row("(peak RSS - 64-particle run) / N (bytes)",
        S.get("rss_minus_baseline_per_particle_bytes"),
        L["rss_minus_baseline_per_particle_bytes"], "%.0f")
    row("  spam-ark peak_rss_bytes / N (self-reported)",
        S.get("self_rss_per_particle_bytes"), NA, "%.0f")
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
    if S.get("loop_wall_note"):
        print("  note: %s" % S["loop_wall_note"])
    if "ratio_time_per_eval" in res:
        print("  spam-ark time per RHS evaluation / LAMMPS time per step = %.3f"
              % res["ratio_time_per_eval"])
    else:
        print("  spam-ark / LAMMPS: not measured (spam-ark not run)")


def print_solid(res, results):
    n = res["n"]
    S = res["spam"]
    print()
    print("== %s, N = %d  (%dx%d triangular lattice in a periodic %.6gx%.6g box, "
          "dt = %g, %d steps)" % (res["label"], n, res["nx"], res["ny"], res["box"][0],
                                  res["box"][1], res["dt"], res["spam_steps"]))
    print("  pairs i<j with r < h: initial %d, after the run %s (numpy); mean %.0f"
          % (res["pairs_initial"], fnum(res.get("pairs_final"), "%d"),
             res["pairs_mean_spam_window"]))

    def row(label, sv, fmt="%.3f"):
        print("  %-50s %14s" % (label, fnum(sv, fmt)))

    print("  %-50s %14s" % ("", "spam-ark"))
    row("steps", S.get("steps"), "%.0f")
    row("force (RHS) evaluations", S.get("rhs_evals"), "%.0f")
    row("time per force (RHS) evaluation (ms)", _ms(S.get("time_per_eval_s")))
    row("time per step (ms)", _ms(S.get("time_per_step_s")))
    row("particle-steps per second per core (millions)",
        _mega(S.get("particle_steps_per_s")))
    row("time per force evaluation / N (ns)",
        S.get("time_per_eval_per_particle_s") and S["time_per_eval_per_particle_s"] * 1e9,
        "%.2f")
    row("ns per pair, time-mean pair count", S.get("ns_per_pair_mean"), "%.2f")
    row("ns per pair, spam-ark's own count", S.get("ns_per_pair_self_reported"), "%.2f")
    row("neighbour list builds", S.get("neighbour_builds"), "%.0f")
    row("peak RSS (MiB, ru_maxrss)",
        S.get("ru_maxrss_bytes") and S["ru_maxrss_bytes"] / 2 ** 20, "%.1f")
    row("peak RSS / N (bytes, incl. runtime baseline)", S.get("rss_per_particle_bytes"),
        "%.0f")
    row("(peak RSS - 64-particle run) / N (bytes)",
        S.get("rss_minus_baseline_per_particle_bytes"), "%.0f")
    row("  spam-ark peak_rss_bytes / N (self-reported)",
        S.get("self_rss_per_particle_bytes"), "%.0f")
    print("  relative energy (KE + IE) change over the run: %s"
          % fnum(S.get("energy_rel_drift"), "%.2e"))
    ref = solid_reference(res, results)
    res["reference"] = ref
    if ref and ref.get("ratio_time_per_eval"):
        print("  reference cost, not the same dynamics: solid time per RHS evaluation / "
              "LAMMPS gas (%s, N = %d) time per step = %.3f%s"
              % (ref["gas_case"], ref["gas_n"], ref["ratio_time_per_eval"],
                 "" if ref["gas_n"] == n else
                 " (per particle: %.3f)" % ref["ratio_time_per_eval_per_particle"]))
        if ref.get("ratio_to_spam_gas_per_particle"):
            print("    (and per particle against spam-ark's own gas at that N: %.2fx)"
                  % ref["ratio_to_spam_gas_per_particle"])
    else:
        print("  reference cost: no LAMMPS gas run at h = %g to compare with" % res["h"])


def print_summary(results):
    print()
    print("Summary (medians; one core per program; 'B/part' = bytes per particle; "
          "ratio = spam-ark time per RHS evaluation / LAMMPS time per step)")
    hdr = ("%-9s %8s %5s %-8s %8s %9s %9s %10s %8s %8s %8s"
           % ("case", "N", "steps", "program", "ns/pair", "ms/force", "ms/step",
              "Mpart-st/s", "B/part", "B/part", "ratio"))
    print("  " + hdr)
    print("  " + ("%-9s %8s %5s %-8s %8s %9s %9s %10s %8s %8s %8s"
                  % ("", "", "", "", "(mean)", "eval", "", "per core", "RSS-base",
                     "self", "")))
    for r in results:
        S = r.get("spam") or {}
        ratio = r.get("ratio_time_per_eval")
        if r.get("kind") == "solid" and r.get("reference"):
            ratio = r["reference"].get("ratio_time_per_eval")
        if S:
            print("  %-9s %8d %5s %-8s %8s %9s %9s %10s %8s %8s %8s%s"
                  % (r["case"], r["n"], fnum(S.get("steps"), "%.0f"), "spam-ark",
                     fnum(S.get("ns_per_pair_mean"), "%.2f"),
                     fnum(_ms(S.get("time_per_eval_s")), "%.3f"),
                     fnum(_ms(S.get("time_per_step_s")), "%.2f"),
                     fnum(_mega(S.get("particle_steps_per_s")), "%.3f"),
                     fnum(S.get("rss_minus_baseline_per_particle_bytes"), "%.0f"),
                     fnum(S.get("self_rss_per_particle_bytes"), "%.0f"),
                     fnum(ratio, "%.3f"),
                     "  (reference cost vs the LAMMPS gas, not the same dynamics)"
                     if r.get("kind") == "solid" and ratio else ""))
        L = r.get("lammps")
        if L:
            print("  %-9s %8d %5d %-8s %8s %9s %9s %10s %8s %8s"
                  % ("" if S else r["case"], r["n"], r["lammps_steps"], "LAMMPS",
                     fnum(L.get("ns_per_pair_mean"), "%.2f"),
                     fnum(_ms(L.get("time_per_eval_s")), "%.3f"),
                     fnum(_ms(L.get("time_per_step_s")), "%.2f"),
                     fnum(_mega(L.get("particle_steps_per_s")), "%.3f"),
                     fnum(L.get("rss_minus_baseline_per_particle_bytes"), "%.0f"), "-"))


# --------------------------------------------------------------------------
# Targets
# --------------------------------------------------------------------------

T1_N, T1_H, T1_MAX = 65536, 3.0, 0.5
T2_N0, T2_N1, T2_H, T2_MAX = 16384, 1048576, 3.0, 0.20
T3_H, T3_MAX = 3.0, 1024.0


def _verdict(ok):
    return "met" if ok else "falls short"


def evaluate_targets(results):
    gas = sorted([r for r in results if r.get("kind") == "gas" and r.get("h") == T1_H
                  and r.get("spam", {}).get("time_per_eval_s")], key=lambda r: r["n"])
    t = {}
    lines = []

    # T1: spam-ark time per force evaluation <= 0.5 x LAMMPS time per step.
    rec = {"target": "spam-ark time per force evaluation <= %.1f x LAMMPS time per "
                     "step at N = %d, h = %g" % (T1_MAX, T1_N, T1_H),
           "n_wanted": T1_N}
    cands = [r for r in gas if r.get("lammps", {}).get("time_per_step_s")]
    if cands:
        r = min(cands, key=lambda r: abs(math.log(r["n"] / T1_N)))
        s_ev, l_st = r["spam"]["time_per_eval_s"], r["lammps"]["time_per_step_s"]
        ratio = s_ev / l_st
        rec.update({"n": r["n"], "spam_time_per_eval_s": s_ev,
                    "lammps_time_per_step_s": l_st, "ratio": ratio,
                    "met": ratio <= T1_MAX, "at_wanted_n": r["n"] == T1_N})
        lines.append("T1  %s: spam-ark %.3f ms per force evaluation, LAMMPS %.3f ms per "
                     "step, ratio %.3f (target <= %.1f): %s%s"
                     % ("N = %d, h = %g" % (r["n"], T1_H), s_ev * 1e3, l_st * 1e3, ratio,
                        T1_MAX, _verdict(rec["met"]),
                        "" if rec["at_wanted_n"] else
                        "  [measured at N = %d, not %d]" % (r["n"], T1_N)))
    else:
        rec["met"] = None
        lines.append("T1  not measured (no gas run at h = %g with both programs)" % T1_H)
    t["T1"] = rec

    # T2: cost per particle-step grows by < 20 % from N = 16384 to N = 1048576.
    rec = {"target": "spam-ark time per RHS evaluation / N grows by less than %d%% "
                     "from N = %d to N = %d, gas h = %g"
                     % (round(T2_MAX * 100), T2_N0, T2_N1, T2_H)}
    if len(gas) >= 2:
        hi = gas[-1]
        lo = next((r for r in gas if r["n"] == T2_N0 and r["n"] < hi["n"]), gas[0])
        if hi["n"] > lo["n"]:
            c0 = lo["spam"]["time_per_eval_s"] / lo["n"]
            c1 = hi["spam"]["time_per_eval_s"] / hi["n"]
            g = c1 / c0 - 1.0
            p0, p1 = lo["spam"].get("ns_per_pair_mean"), hi["spam"].get("ns_per_pair_mean")
            rec.update({"n_from": lo["n"], "n_to": hi["n"],
                        "ns_per_particle_eval_from": c0 * 1e9,
                        "ns_per_particle_eval_to": c1 * 1e9, "growth": g,
                        "met": g < T2_MAX, "to_wanted_n": hi["n"] == T2_N1,
                        "ns_per_pair_from": p0, "ns_per_pair_to": p1,
                        "ns_per_pair_growth": (p1 / p0 - 1.0) if p0 and p1 else None})
            note = []
            if lo["n"] != T2_N0:
                note.append("from N = %d, the smallest size run" % lo["n"])
            if hi["n"] != T2_N1:
                note.append("to N = %d, the largest size run, not %d" % (hi["n"], T2_N1))
            lines.append("T2  gas h = %g: time per RHS evaluation / N = %.2f ns at N = %d, "
                         "%.2f ns at N = %d: growth %+.1f%% (target < %d%%): %s%s"
                         % (T2_H, c0 * 1e9, lo["n"], c1 * 1e9, hi["n"], 100 * g,
                            round(T2_MAX * 100), _verdict(rec["met"]),
                            "  [%s]" % "; ".join(note) if note else ""))
            if rec["ns_per_pair_growth"] is not None:
                lines.append("      (per pair within h, time-mean: %.2f -> %.2f ns, %+.1f%%%s)"
                             % (p0, p1, 100 * rec["ns_per_pair_growth"],
                                "; the runs cover different physical times (%d and %d "
                                "steps), so the pairs per particle differ"
                                % (lo["spam_steps"], hi["spam_steps"])
                                if lo["spam_steps"] != hi["spam_steps"] else ""))
        else:
            rec["met"] = None
    if "growth" not in rec:
        rec["met"] = None
        lines.append("T2  not measured (needs the gas at h = %g at two sizes)" % T2_H)
    t["T2"] = rec

    # T3: (peak RSS - baseline) / N <= 1 KiB for the gas, at the largest size run.
    rec = {"target": "(peak RSS - 64-particle baseline) / N <= %d bytes for the "
                     "isentropic gas with Dormand-Prince, at the largest size run"
                     % T3_MAX}
    mem = [r for r in gas if r["spam"].get("rss_minus_baseline_per_particle_bytes")]
    if mem:
        r = mem[-1]
        b = r["spam"]["rss_minus_baseline_per_particle_bytes"]
        selfb = r["spam"].get("self_rss_per_particle_bytes")
        rec.update({"n": r["n"], "h": r["h"], "bytes_per_particle": b,
                    "self_reported_bytes_per_particle": selfb, "met": b <= T3_MAX,
                    "lammps_bytes_per_particle":
                        r["lammps"].get("rss_minus_baseline_per_particle_bytes")})
        lines.append("T3  gas h = %g, N = %d: (peak RSS - baseline) / N = %.0f bytes "
                     "(target <= %d): %s   [self-reported peak_rss_bytes / N = %s, "
                     "LAMMPS %s]"
                     % (T3_H, r["n"], b, T3_MAX, _verdict(rec["met"]),
                        fnum(selfb, "%.0f"),
                        fnum(rec["lammps_bytes_per_particle"], "%.0f")))
    else:
        rec["met"] = None
        lines.append("T3  not measured (no gas run at h = %g with a memory baseline)" % T3_H)
    t["T3"] = rec
    return t, lines


# --------------------------------------------------------------------------
# -log_view
# --------------------------------------------------------------------------

LOG_VIEW_SUBSTRINGS = ("Spam", "Vec", "TSStep")


def parse_log_view(text, substrings=LOG_VIEW_SUBSTRINGS):
    """Rows of PETSc's -log_view event table whose name contains one of the
    substrings: name, count, time (max over ranks), %T, Mflop/s, stage."""
    lines = text.splitlines()
    start = next((k for k, l in enumerate(lines)
                  if l.startswith("Event") and "Count" in l), None)
    rows = []
    total = None
    m = re.search(r"^Time \(sec\):\s+(%s)" % _FLOAT, text, re.M)
    if m:
        total = float(m.group(1))
    if start is None:
        return rows, total
    stage = None
    k = start + 1
    while k < len(lines) and (lines[k].startswith(" ") or lines[k].startswith("---")):
        k += 1  # the second header line and the dashes under it
    for line in lines[k:]:
        if line.startswith("-----"):
            break  # end of the event table
        if line.startswith("--- Event Stage"):
            stage = line.strip("- ").strip()
            continue
        parts = line.split()
        if len(parts) < 21:
            continue
        name, nums = " ".join(parts[:-20]), parts[-20:]
        if not any(s in name for s in substrings):
            continue
        try:
            rows.append({"event": name, "count": int(float(nums[0])),
                         "time_s": float(nums[2]), "flop": float(nums[4]),
                         "pct_time": float(nums[9]), "mflops": float(nums[19]),
                         "stage": stage, "line": line})
        except ValueError:
            continue
    return rows, total


def log_view_run(args, workdir, pin, path, spam_ok):
    n, h = args.log_view_size, 3.0
    nx = int(round(math.sqrt(n)))
    if nx * nx != n:
        raise SystemExit("--log-view-size %d is not a perfect square" % n)
    case = {"name": "gas-h3", "kind": "gas", "h": h}
    _, steps = steps_for(case, n, args)
    rec = {"n": n, "h": h, "steps": steps, "file": str(path)}
    if not spam_ok:
        rec["error"] = "spam-ark not usable"
        return rec
    csv, _ = spam_make_initial(args.spam_ark, nx, h, workdir)
    box = np.array([2.0 * nx, 2.0 * nx])
    r = spam_run(args.spam_ark, csv, box, h, steps, workdir, "logview_%d" % nx, pin,
                 extra=["-log_view", ":%s" % path])
    rec["cmd"] = r["cmd"]
    rec["rhs_evals"] = r["summary"].get("rhs_evals")
    rec["rhs_time_s"] = r["summary"].get("rhs_time_s")
    try:
        text = Path(path).read_text(errors="replace")
    except OSError as exc:
        rec["error"] = "no -log_view output: %s" % exc
        return rec
    rows, total = parse_log_view(text)
    rec["total_time_s"] = total
    rec["events"] = rows
    return rec


def print_log_view(rec):
    print()
    print("PETSc -log_view (untimed spam-ark run, gas h = %g, N = %d, %d steps): %s"
          % (rec["h"], rec["n"], rec["steps"], rec["file"]))
    if rec.get("error"):
        print("  %s" % rec["error"])
        return
    print("  events whose name contains %s; total time %s s, spam-ark RHS time %s s "
          "over %s evaluations"
          % (" or ".join('"%s"' % s for s in LOG_VIEW_SUBSTRINGS),
             fnum(rec.get("total_time_s"), "%.3f"), fnum(rec.get("rhs_time_s"), "%.3f"),
             rec.get("rhs_evals")))
    print("  %-24s %9s %11s %13s %6s %9s" % ("event", "count", "time (s)", "ms per call",
                                             "%T", "Mflop/s"))
    for e in rec.get("events", []):
        print("  %-24s %9d %11.4e %13.4f %6.0f %9.0f"
              % (e["event"], e["count"], e["time_s"],
                 1e3 * e["time_s"] / e["count"] if e["count"] else float("nan"),
                 e["pct_time"], e["mflops"]))
    if not rec.get("events"):
        print("  (no matching events in the table)")


# --------------------------------------------------------------------------
# Main
# --------------------------------------------------------------------------

def parse_args(argv):
    ap = argparse.ArgumentParser(
        description="Benchmark spam-ark against LAMMPS (pair_style table with "
                    "Lucy's kernel) on the same initial particles, and the "
                    "spam-ark elastic solid on its own.")
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"),
                    help="spam-ark binary (default: <repo>/build/spam-ark)")
    ap.add_argument("--lmp", default="lmp", help="LAMMPS binary (default: lmp)")
    ap.add_argument("--sizes", default=None,
                    help="comma-separated particle counts, each a perfect square "
                         "(default %s; %s with --quick)" % (DEFAULT_SIZES, QUICK_SIZES))
    ap.add_argument("--cases", default=DEFAULT_CASES,
                    help="comma-separated cases gas-hH and solid-hH (default %s)"
                         % DEFAULT_CASES)
    ap.add_argument("--steps", type=int, default=None,
                    help="steps for every case and size (default: per case and size, "
                         "a few seconds of spam-ark per run; see bench/README.md)")
    ap.add_argument("--lammps-steps", type=int, default=None,
                    help="override LAMMPS steps only")
    ap.add_argument("--spam-steps", type=int, default=None,
                    help="override spam-ark steps only")
    ap.add_argument("--repeats", type=int, default=None,
                    help="timed runs per program, case and size; the median is "
                         "reported (default 5, 1 with --quick)")
    ap.add_argument("--quick", action="store_true",
                    help="smoke run: N = %s, %d steps, 1 repeat" % (QUICK_SIZES, QUICK_STEPS))
    ap.add_argument("--max-seconds", type=float, default=600.0,
                    help="skip a size (and all larger ones) when its runs are predicted, "
                         "from the previous size, to take longer than this "
                         "(default 600; 0: no limit)")
    ap.add_argument("--log-view", action="store_true",
                    help="one extra untimed spam-ark run (gas h = 3, N = --log-view-size) "
                         "with PETSc's -log_view; the file goes next to the JSON")
    ap.add_argument("--log-view-size", type=int, default=65536,
                    help="N of the --log-view run (default 65536)")
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
                    help="skip spam-ark (and so the solid); the initial lattice is "
                         "made with numpy")
    ap.add_argument("--numpy-initial", action="store_true",
                    help="make the initial gas lattice with numpy (unperturbed, sites "
                         "at i+0.5) instead of spam-ark -initial_csv")
    ap.add_argument("--validate-lammps", action="store_true",
                    help="also check the LAMMPS table, forces and energy drift (h = 3)")
    ap.add_argument("--workdir", default=None,
                    help="scratch directory (default: a fresh temporary one)")
    ap.add_argument("--keep", action="store_true", help="keep the scratch directory")
    ap.add_argument("--out", default=None,
                    help="JSON output (default bench/results/bench_<date>.json)")
    args = ap.parse_args(argv)
    if args.quick:
        if args.sizes is None:
            args.sizes = QUICK_SIZES
        if args.steps is None:
            args.steps = QUICK_STEPS
        if args.repeats is None:
            args.repeats = 1
    if args.sizes is None:
        args.sizes = DEFAULT_SIZES
    if args.repeats is None:
        args.repeats = 5
    if args.repeats < 1:
        raise SystemExit("--repeats must be at least 1")
    return args


def predict_seconds(prev, n_next, cases, args):
    """Seconds the next size will take, scaled from the previous size's
    blocks: timed runs by N x steps, the rest (initial state, pair counts,
    data files, census) by N."""
    total = 0.0
    for case in cases:
        p = prev.get(case["name"])
        if not p:
            continue
        _, s_next = steps_for(case, n_next, args)
        timed = p["timed"] * (n_next * s_next) / (p["n"] * p["steps"])
        other = p["other"] * n_next / p["n"]
        total += timed + other
    return total


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        sizes = sorted({int(s) for s in args.sizes.split(",") if s.strip()})
    except ValueError:
        raise SystemExit("--sizes: %r is not a list of integers" % args.sizes)
    cases = parse_cases(args.cases)
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
    if not spam_ok and any(c["kind"] == "solid" for c in cases):
        print("note: the solid cases need spam-ark; skipping them")
        cases = [c for c in cases if c["kind"] != "solid"]

    stamp = datetime.datetime.now().strftime("%Y-%m-%dT%H%M%S")
    if args.out:
        out_path = Path(args.out).resolve()
    else:
        out_path = BENCH_DIR / "results" / ("bench_%s.json" % stamp)
    log_view_path = out_path.with_name(out_path.stem + "_log_view.txt")

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
    print("cases: %s" % "; ".join(c["label"] for c in cases))
    print("steps (both programs, dt = %g, Dormand-Prince for spam-ark, velocity Verlet "
          "for LAMMPS):" % DT)
    for c in cases:
        print("  %-9s %s" % (c["name"], ", ".join("N=%d: %d" % (n, steps_for(c, n, args)[1])
                                                 for n in sizes)))
    if args.max_seconds > 0:
        print("size guard: a size predicted to take more than %.0f s is skipped, with "
              "all larger ones (--max-seconds)" % args.max_seconds)

    t_start = time.perf_counter()
    out = {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "host": platform.node(), "machine": platform.machine(),
        "cpu_count": os.cpu_count(), "python": sys.version.split()[0],
        "numpy": np.__version__, "spam_ark": args.spam_ark, "spam_ark_status": spam_note,
        "lammps": args.lmp, "pin": pin, "repeats": args.repeats, "dt": DT,
        "integrator_spam_ark": DP_TABLE, "integrator_lammps": "fix nve (velocity Verlet)",
        "cases": cases, "lammps_skin": args.skin, "table_points": args.table_points,
        "table_rlo": args.table_rlo, "sizes": sizes, "max_seconds": args.max_seconds,
        "quick": args.quick, "results": [], "skipped": [], "failures": [],
        "argv": sys.argv[1:] if argv is None else list(argv),
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
            gas_h = [c["h"] for c in cases if c["kind"] == "gas"]
            out["lammps_validation"] = validate_lammps(args, workdir, pin,
                                                       gas_h[0] if gas_h else 3.0)
        base = {}
        for c in cases:
            base[c["name"]] = baselines(args, workdir, pin, spam_ok, c)
        out["baseline"] = base
        table_cache = {}
        prev = {}
        for i, n in enumerate(sizes):
            if prev and args.max_seconds > 0:
                pred = predict_seconds(prev, n, cases, args)
                if pred > args.max_seconds:
                    for m_ in sizes[i:]:
                        out["skipped"].append({"n": m_, "predicted_s_first": pred,
                                               "reason": "--max-seconds %.0f" % args.max_seconds})
                    print("\nskipping N = %s: N = %d is predicted to take %.0f s "
                          "(> --max-seconds %.0f)"
                          % (", ".join(str(m_) for m_ in sizes[i:]), n, pred,
                             args.max_seconds))
                    break
                print("\nN = %d: predicted %.0f s" % (n, pred))
            t_size = time.perf_counter()
            # prev keeps each case's latest completed size, so a case that
            # failed at this size is still predicted from an earlier one.
            for c in cases:
                t_case = time.perf_counter()
                try:
                    if c["kind"] == "gas":
                        res = bench_gas(n, c, args, workdir, pin, spam_ok, table_cache,
                                        base[c["name"]])
                    else:
                        res = bench_solid(n, c, args, workdir, pin, base[c["name"]])
                except RuntimeError as exc:
                    print("\n== %s, N = %d: FAILED\n%s" % (c["label"], n, exc))
                    out["failures"].append({"case": c["name"], "n": n, "error": str(exc)})
                    continue
                res["block_seconds"] = time.perf_counter() - t_case
                out["results"].append(res)
                if c["kind"] == "gas":
                    print_gas(res, base[c["name"]])
                else:
                    print_solid(res, out["results"])
                print("  (this block took %.0f s, of which %.0f s in timed runs)"
                      % (res["block_seconds"], res["timed_seconds"]))
                prev[c["name"]] = {"n": n, "steps": res["spam_steps"],
                                   "timed": res["timed_seconds"],
                                   "other": res["block_seconds"] - res["timed_seconds"]}
            print("\nN = %d took %.0f s" % (n, time.perf_counter() - t_size))
        # A solid's nearest gas may have been run after it: recompute.
        for r in out["results"]:
            if r.get("kind") == "solid":
                r["reference"] = solid_reference(r, out["results"])
        if args.log_view:
            log_view_path.parent.mkdir(parents=True, exist_ok=True)
            try:
                out["log_view"] = log_view_run(args, workdir, pin, log_view_path, spam_ok)
            except RuntimeError as exc:
                out["log_view"] = {"error": str(exc)}
                out["failures"].append({"case": "log_view", "error": str(exc)})
                print("\n--log-view run FAILED\n%s" % exc)
    finally:
        if own_workdir and not args.keep:
            shutil.rmtree(workdir, ignore_errors=True)
        elif own_workdir:
            print("kept scratch directory %s" % workdir)

    if out["results"]:
        print_summary(out["results"])
    if out.get("log_view") and "n" in out["log_view"]:
        print_log_view(out["log_view"])
    targets, lines = evaluate_targets(out["results"])
    out["targets"] = targets
    print()
    print("Targets (a measurement: the exit code does not depend on them)")
    for line in lines:
        print("  " + line)
    if out["skipped"]:
        print("  sizes skipped by --max-seconds: %s"
              % ", ".join(str(s["n"]) for s in out["skipped"]))
    out["total_seconds"] = time.perf_counter() - t_start

    out_path.parent.mkdir(parents=True, exist_ok=True)
    out_path.write_text(json.dumps(out, indent=1, default=str) + "\n")
    print("\nwrote %s (total %.0f s)" % (out_path, out["total_seconds"]))
    if out["failures"]:
        print("%d run(s) failed: %s" % (len(out["failures"]),
                                        ", ".join("%s N=%s" % (f["case"], f.get("n", "-"))
                                                  for f in out["failures"])))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
