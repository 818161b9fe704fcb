#!/usr/bin/python3
"""Checks for examples/plot_expansion.py on synthetic run directories.

Plain script: prints each check, ends with 'N passed, M failed', and exits 0 only
if every check passed.  Needs only the standard library itself; the plot script
needs numpy and matplotlib (it re-runs itself with /usr/bin/python3 if the
python3 running this lacks them).

    python3 tests/test_plot_expansion.py
"""

import json
import math
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(os.path.dirname(HERE), "examples", "plot_expansion.py")

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

# timeseries columns as the engine writes them, plus one added column ("note",
# non-numeric) in the middle, to check that columns are read by name
TS_COLUMNS = ["t", "step", "rejected", "rhs_evals", "dt", "mass", "px", "py", "pz",
              "lx", "ly", "lz", "kinetic", "internal", "note", "total",
              "entropy_sum", "entropy_grid", "dS_sum_ratio", "dS_grid_ratio", "wall_s"]

FINAL_SUM = 0.9876543210987654
FINAL_GRID = 1.0123456789012345

passed = 0
failed = 0


def check(name, ok, detail=""):
    global passed, failed
    if ok:
        passed += 1
        print("PASS  %s" % name)
    else:
        failed += 1
        print("FAIL  %s%s" % (name, ("  -- " + detail) if detail else ""))
    return ok


# --------------------------------------------------------------------------
# synthetic run directories
# --------------------------------------------------------------------------

def smoothstep(u):
    u = min(1.0, max(0.0, u))
    return u * u * (3 - 2 * u)


def write_manifest(run_dir, snapshots, status="ok"):
    """manifest.json as spam-ark writes it: the run's status and its files."""
    files = [{"name": name, "kind": "snapshot_csv", "t": t} for name, t in snapshots]
    files += [{"name": "summary.json", "kind": "summary"},
              {"name": "timeseries.csv", "kind": "timeseries"}]
    with open(os.path.join(run_dir, "manifest.json"), "w") as fh:
        json.dump({"program": "spam-ark", "version": "test", "status": status,
                   "options": "", "files": files}, fh, indent=2)


def write_run(run_dir, dim, nx, volume_ratio, n_snapshots=3, n_rows=41, seed=1):
    """Write summary.json, timeseries.csv, particle snapshots and manifest.json.

    Returns the expected (final dS_sum_ratio, final dS_grid_ratio, max drift),
    computed from the exact values written to the CSV.
    """
    rng = random.Random(seed)
    os.makedirs(run_dir, exist_ok=True)
    n = nx ** dim
    tau = float(nx)                      # sound speed 1: tau = nx / c
    t_end = 2.0 * tau
    with open(os.path.join(run_dir, "summary.json"), "w") as fh:
        json.dump({"scene": "expansion", "dim": dim, "n_particles": n,
                   "volume_ratio": volume_ratio, "sound_traversal_time": tau,
                   "method": "rk45", "rtol": 1e-6, "atol": 1e-9, "steps": 812,
                   "rejected_steps": 7, "rhs_evals": 4919, "status": "ok",
                   "extra_key_ignored": [1, 2, 3]}, fh, indent=2)

    # time series: entropy ratio rises between 0.4 tau and 1.4 tau
    e0 = 0.5 * n
    rows = []
    totals = []
    for k in range(n_rows):
        t = t_end * k / (n_rows - 1)
        s = smoothstep((t / tau - 0.4) / 1.0)
        ds_sum = s * (1.0 + 0.03 * math.sin(5 * t / tau))
        ds_grid = s * (1.0 - 0.02 * math.cos(4 * t / tau))
        if k == n_rows - 1:
            ds_sum, ds_grid = FINAL_SUM, FINAL_GRID
        kinetic = e0 * 0.6 * math.sin(math.pi * min(1.0, t / (1.5 * tau))) ** 2 * (1 - 0.5 * s)
        drift = 2.5e-7 * math.sin(3.0 * t / tau) + 1e-7 * t / tau
        total = e0 * (1.0 + drift)
        internal = total - kinetic
        totals.append(float(repr(total)))
        ln_v = math.log(volume_ratio)
        rows.append([repr(t), str(k * 20), str(k // 10), str(k * 120), repr(0.05),
                     repr(float(n)), "0", "0", "0", "0", "0", "0",
                     repr(kinetic), repr(internal), "synthetic", repr(total),
                     repr(-n * 0.1 + n * ln_v * ds_sum), repr(-n * 0.1 + n * ln_v * ds_grid),
                     repr(ds_sum), repr(ds_grid), repr(0.01 * k)])
    with open(os.path.join(run_dir, "timeseries.csv"), "w") as fh:
        fh.write(",".join(TS_COLUMNS) + "\n")
        for r in rows:
            fh.write(",".join(r) + "\n")
    max_drift = max(abs(e - totals[0]) / abs(totals[0]) for e in totals)

    # snapshots: lattice in the lower-left part of the box spreading out
    box = nx * volume_ratio ** (1.0 / dim)
    listed = []
    for j in range(n_snapshots):
        t = t_end * j / (n_snapshots - 1)
        grow = 1.0 + (box / nx - 1.0) * smoothstep(t / tau)
        lines = ["# t=%r" % t, "x,y,z,vx,vy,vz,rho"]
        for idx in range(n):
            i0 = idx % nx
            i1 = (idx // nx) % nx if dim >= 2 else 0
            i2 = idx // (nx * nx) if dim == 3 else 0
            x = (i0 + 0.5 + 0.05 * rng.uniform(-1, 1)) * grow
            y = (i1 + 0.5 + 0.05 * rng.uniform(-1, 1)) * grow if dim >= 2 else 0.0
            z = (i2 + 0.5) * grow if dim == 3 else 0.0
            vx = 0.3 * (x / box) * math.exp(-t / tau) + 0.02 * rng.uniform(-1, 1)
            vy = 0.3 * (y / box) * math.exp(-t / tau) if dim >= 2 else 0.0
            rho = (1.0 / grow ** dim) * (1.0 + 0.1 * rng.uniform(-1, 1))
            lines.append("%r,%r,%r,%r,%r,0,%r" % (x, y, z, vx, vy, rho))
        with open(os.path.join(run_dir, "particles_%05d.csv" % j), "w") as fh:
            fh.write("\n".join(lines) + "\n")
        listed.append(("particles_%05d.csv" % j, t))
    write_manifest(run_dir, listed)
    return FINAL_SUM, FINAL_GRID, max_drift


# --------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------

def run_plot(*args):
    proc = subprocess.run([sys.executable, SCRIPT] + list(args),
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=300)
    return proc.returncode, proc.stdout, proc.stderr


def png_size(path):
    """(width, height) from the IHDR chunk, or None if not a PNG."""
    with open(path, "rb") as fh:
        head = fh.read(33)
    if len(head) < 33 or head[:8] != PNG_MAGIC or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def parse_result_line(stdout):
    """{key: value} from 'final dS_sum_ratio=.. dS_grid_ratio=.. max_rel_energy_drift=.. png=..'."""
    lines = [ln for ln in stdout.splitlines() if ln.startswith("final ")]
    if len(lines) != 1:
        return None
    line = lines[0]
    head, sep, png = line.partition(" png=")
    if not sep:
        return None
    out = {"png": png}
    for tok in head.split()[1:]:
        key, _, val = tok.partition("=")
        out[key] = val
    return out


def check_good_run(label, run_dir, expected, out_png=None):
    exp_sum, exp_grid, exp_drift = expected
    args = [run_dir] + (["-o", out_png] if out_png else [])
    png = out_png or os.path.join(run_dir, "expansion.png")
    rc, out, err = run_plot(*args)
    check("%s: exit code 0" % label, rc == 0, "rc=%d stderr=%s" % (rc, err.strip()))
    check("%s: PNG written at %s" % (label, os.path.basename(png)), os.path.isfile(png))
    size = png_size(png) if os.path.isfile(png) else None
    check("%s: valid PNG (magic bytes, IHDR)" % label, size is not None)
    if size:
        check("%s: PNG %dx%d px, both > 500" % (label, size[0], size[1]),
              size[0] > 500 and size[1] > 500)
    res = parse_result_line(out)
    check("%s: one 'final ... png=...' line on stdout" % label, res is not None, repr(out))
    if not res:
        return
    try:
        got = (float(res["dS_sum_ratio"]), float(res["dS_grid_ratio"]),
               float(res["max_rel_energy_drift"]))
    except (KeyError, ValueError) as exc:
        check("%s: result line has numeric fields" % label, False, "%s in %r" % (exc, out))
        return
    check("%s: final dS_sum_ratio %r == %r (1e-12)" % (label, got[0], exp_sum),
          abs(got[0] - exp_sum) <= 1e-12)
    check("%s: final dS_grid_ratio %r == %r (1e-12)" % (label, got[1], exp_grid),
          abs(got[1] - exp_grid) <= 1e-12)
    check("%s: max energy drift %.6g == %.6g (1e-12)" % (label, got[2], exp_drift),
          abs(got[2] - exp_drift) <= 1e-12)
    check("%s: printed PNG path is the written file" % label,
          os.path.abspath(res["png"]) == os.path.abspath(png), res["png"])


def check_error(label, args, must_name):
    rc, out, err = run_plot(*args)
    lines = err.strip().splitlines()
    check("%s: exit code 2" % label, rc == 2, "rc=%d stdout=%r stderr=%r" % (rc, out, err))
    check("%s: one line on stderr naming %s" % (label, must_name),
          len(lines) == 1 and must_name in lines[0], repr(err))


# --------------------------------------------------------------------------

def main():
    check("plot script exists", os.path.isfile(SCRIPT), SCRIPT)
    tmp = tempfile.mkdtemp(prefix="spam_ark_plot_test_")
    try:
        # 2D, 3 snapshots, default output path
        run2 = os.path.join(tmp, "run2d")
        exp2 = write_run(run2, dim=2, nx=12, volume_ratio=4)
        check_good_run("2D", run2, exp2)

        # 2D again with -o to another directory
        out_png = os.path.join(tmp, "elsewhere", "chart.png")
        os.makedirs(os.path.dirname(out_png))
        check_good_run("2D -o", run2, exp2, out_png=out_png)

        # 2D with more snapshots than panels (4 chosen of 9)
        run9 = os.path.join(tmp, "run2d_9snap")
        exp9 = write_run(run9, dim=2, nx=8, volume_ratio=4, n_snapshots=9, seed=3)
        check_good_run("2D 9 snapshots", run9, exp9)

        # 1D, twofold expansion
        run1 = os.path.join(tmp, "run1d")
        exp1 = write_run(run1, dim=1, nx=64, volume_ratio=2, seed=2)
        check_good_run("1D", run1, exp1)

        # missing timeseries.csv
        bad = os.path.join(tmp, "no_timeseries")
        shutil.copytree(run2, bad)
        os.remove(os.path.join(bad, "expansion.png"))    # left by the 2D case
        os.remove(os.path.join(bad, "timeseries.csv"))
        check_error("missing timeseries.csv", [bad], "timeseries.csv")
        check("missing timeseries.csv: no PNG written",
              not os.path.exists(os.path.join(bad, "expansion.png")))

        # missing run directory
        check_error("missing DIR", [os.path.join(tmp, "does_not_exist")], "does_not_exist")

        # missing summary.json
        bad_s = os.path.join(tmp, "no_summary")
        shutil.copytree(run2, bad_s)
        os.remove(os.path.join(bad_s, "summary.json"))
        check_error("missing summary.json", [bad_s], "summary.json")

        # timeseries without a needed column
        bad_c = os.path.join(tmp, "no_column")
        shutil.copytree(run2, bad_c)
        path = os.path.join(bad_c, "timeseries.csv")
        with open(path) as fh:
            text = fh.read()
        with open(path, "w") as fh:
            fh.write(text.replace("dS_grid_ratio", "dS_grid_ratio_renamed", 1))
        check_error("timeseries missing dS_grid_ratio", [bad_c], "dS_grid_ratio")

        # snapshot with a non-numeric value
        bad_p = os.path.join(tmp, "bad_snapshot")
        shutil.copytree(run2, bad_p)
        path = os.path.join(bad_p, "particles_00002.csv")
        with open(path) as fh:
            lines = fh.read().splitlines()
        lines[5] = "oops," + lines[5].split(",", 1)[1]
        with open(path, "w") as fh:
            fh.write("\n".join(lines) + "\n")
        check_error("malformed snapshot", [bad_p], "particles_00002.csv")

        # no snapshots at all
        bad_n = os.path.join(tmp, "no_snapshots")
        shutil.copytree(run2, bad_n)
        for name in os.listdir(bad_n):
            if name.startswith("particles_"):
                os.remove(os.path.join(bad_n, name))
        write_manifest(bad_n, [])
        check_error("no snapshots", [bad_n], "particles_NNNNN.csv")

        # no manifest: refused, not globbed
        bad_m = os.path.join(tmp, "no_manifest")
        shutil.copytree(run2, bad_m)
        os.remove(os.path.join(bad_m, "manifest.json"))
        check_error("missing manifest.json", [bad_m], "manifest.json")

        # a failed run is refused
        bad_f = os.path.join(tmp, "failed_run")
        shutil.copytree(run2, bad_f)
        with open(os.path.join(bad_f, "manifest.json")) as fh:
            man = json.load(fh)
        man["status"] = "failed"
        with open(os.path.join(bad_f, "manifest.json"), "w") as fh:
            json.dump(man, fh)
        check_error("status failed", [bad_f], "failed")

        # a stale snapshot of another run (not in the manifest, malformed) is not read;
        # an interrupted run is drawn with one warning line
        stale = os.path.join(tmp, "stale")
        shutil.copytree(run2, stale)
        os.remove(os.path.join(stale, "expansion.png"))
        with open(os.path.join(stale, "particles_00007.csv"), "w") as fh:
            fh.write("# t=9999\nx,y,z,vx,vy,vz,rho\nnot,a,number,at,all,0,0\n")
        man["status"] = "interrupted"
        with open(os.path.join(stale, "manifest.json"), "w") as fh:
            json.dump(man, fh)
        rc, out, err = run_plot(stale)
        check("stale snapshot not in the manifest: ignored, exit 0", rc == 0, err)
        check("interrupted run: one warning line naming the status",
              len(err.strip().splitlines()) == 1 and "interrupted" in err, repr(err))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    print("%d passed, %d failed" % (passed, failed))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
