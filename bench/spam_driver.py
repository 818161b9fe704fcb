"""spam-ark as the benchmark runs it: the initial lattice, the gas and solid command lines,
one run with its summary, and the -log_view event table."""

import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path

from bench_common import DT, REPO_ROOT, _FLOAT, run_measured, tail


DP_TABLE = "ARKODE_DORMAND_PRINCE_7_4_5"


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
