#!/usr/bin/python3
"""What the benchmark scripts share: numpy, the repository paths, Lucy's kernel, the pair
count, running a program alone with its peak RSS, particle CSV files and small helpers."""

import math
import os
import shutil
import statistics
import subprocess
import sys
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
    sys.exit("the benchmark scripts need numpy (Debian: apt-get install python3-numpy, "
             "then run them with /usr/bin/python3)")


_ensure_numpy()
import numpy as np  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
BENCH_DIR = Path(__file__).resolve().parent
DT = 0.05
RUN_TIMEOUT_S = 3600


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
    fh.write("%d %d %.6f\n" % (os.waitstatus_to_exitcode(status), ru.ru_maxrss,
                               ru.ru_utime + ru.ru_stime))
"""


def run_measured(cmd, cwd, log_path, timeout=RUN_TIMEOUT_S):
    """Run cmd alone, output to log_path; return (rc, wall_s, peak_rss_bytes).

    Peak RSS is ru_maxrss (KiB) from os.wait4 on the program itself, taken by
    the launcher above (taskset execs the program in place, so that pid is
    the program's).
    """
    return run_measured_cpu(cmd, cwd, log_path, timeout)[:3]


def run_measured_cpu(cmd, cwd, log_path, timeout=RUN_TIMEOUT_S):
    """As run_measured, with the program's CPU time (user + system, from the
    same os.wait4) as a fourth value, None if unknown.  On a machine shared
    with other work a process waits for a core; its CPU time does not count
    the waiting, its wall time does."""
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
        fields = rss_file.read_text().split()
        rc, maxrss_kib, cpu = int(fields[0]), int(fields[1]), float(fields[2])
    except (OSError, ValueError, IndexError):
        return (p.returncode or -1), wall, 0, None
    return rc, wall, maxrss_kib * 1024, cpu


def tail(path, n=25):
    try:
        lines = Path(path).read_text(errors="replace").splitlines()
    except OSError:
        return ""
    return "\n".join(lines[-n:])


_FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


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


def page_readings(path, readings):
    """Writes the readings bench/README.md quotes to path (with the command, commit and load,
    examples/chart_readings.py); a script does so when given --readings PATH."""
    sys.path.insert(0, str(REPO_ROOT / "examples"))
    import chart_readings
    return chart_readings.write_json(str(path), readings)
