#!/usr/bin/python3
"""The run owns its output directory and loses nothing silently.

1. Stale snapshots: a shorter rerun into a directory holding an earlier run is refused
   (exit 2, one line naming a file of that run and -output_overwrite, nothing touched);
   with -output_overwrite every file of the earlier run goes first, so no snapshot of it
   survives and manifest.json lists exactly the files present. Files spam-ark never
   writes are left alone. A snapshot interval that would pass -snapshot_max is refused.
2. Two runs into one directory: the second is refused (exit 2, one line naming the
   holder's pid) while the first completes intact.
3. A symlink left at a temporary's name (timeseries.csv.tmp -> a victim file, or
   /dev/full) is never followed: the victim is untouched and the run succeeds; a symlink
   at the lock's name is refused with one line.
4. A failed write stops the run: exit 1, one stderr line naming the file and the system's
   reason, the partial file and every temporary removed, summary.json and manifest.json
   saying "failed" (or no summary at all), never exit 0. Injected (SPAM_TEST_FAIL_WRITE,
   test only) into the timeseries, steps, an HDF5 and a CSV snapshot and the summary; and
   for real: a 1 MiB tmpfs filled while the run writes (needs root for mount).
5. Verdicts and formats: summary.json is strict JSON (no NaN or Infinity; a null is listed
   in null_fields, with a note saying why) also after a blow-up to overflow; a solid at
   rest with no kick (-tensile_kick 0) is not "unstable": round-off kinetic energy is
   measured against max(|E0|, KE0, M (c0/1000)^2 / 2), not against a 1e-300 floor."""
import json
import math
import os
import shutil
import signal
import subprocess
import time
from spamrun import Checks, arguments, brief, manifest, one_line, run, summary

a = arguments()
c = Checks()
w = a.workdir
SMALL = ["-expansion_n", 16, "-h", 3, "-output_interval", 1, "-snapshot_interval", 4, "-diag_entropy", 0]


def listing(d):
    return sorted(os.listdir(d)) if os.path.isdir(d) else []


def temporaries(d):
    return [n for n in listing(d) if n.endswith(".tmp")]


def listed(d):
    """Names manifest.json lists (files inside the directory)."""
    return sorted(e["name"] for e in manifest(d)["files"] if "name" in e)


# 1. Stale snapshots.
d = os.path.join(w, "stale")
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 32], d)
first = listing(d)
c.check(code == 0 and "particles_00008.csv" in first and "snap_00008.h5" in first, f"first run: exit {code}, 9 snapshots {err.strip()}")
c.check(listed(d) == sorted(n for n in first if n != "manifest.json"), f"manifest lists exactly the {len(first) - 1} other files")
mtimes = {n: os.stat(os.path.join(d, n)).st_mtime_ns for n in first}
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 8], d)
line = one_line(err)
c.check(code == 2 and line and line.startswith("spam-ark: error: -output_dir") and "manifest.json" in line and "-output_overwrite" in line,
        f"rerun without -output_overwrite: exit {code}, {brief(err)}")
c.check({n: os.stat(os.path.join(d, n)).st_mtime_ns for n in listing(d)} == mtimes, "the refused rerun touched nothing")
with open(os.path.join(d, "notes.txt"), "w") as f:
    f.write("mine\n")
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 8, "-output_overwrite"], d)
now = listing(d)
snaps = [n for n in now if n.startswith(("particles_", "snap_"))]
c.check(code == 0 and snaps == ["particles_00000.csv", "particles_00001.csv", "particles_00002.csv", "snap_00000.h5", "snap_00001.h5", "snap_00002.h5"],
        f"rerun with -output_overwrite to t = 8: exit {code}, snapshots {snaps} (none of the first run's 9)")
man = manifest(d)
times = [e["t"] for e in man["files"] if e["kind"] == "snapshot_csv"]
c.check(man["status"] == "ok" and times == [0, 4, 8] and listed(d) == sorted(n for n in now if n not in ("manifest.json", "notes.txt")),
        f"manifest: status {man['status']}, snapshot times {times}, lists exactly the new run's files")
c.check("notes.txt" in now and summary(d)["t_final"] == 8, "a file spam-ark never writes is kept; summary.json is the new run's")
c.check("spam-ark.lock" not in now and not temporaries(d), "no lock file and no temporary after a clean end")
d = os.path.join(w, "foreign")
os.makedirs(d)
open(os.path.join(d, "particles_00042.csv"), "w").close()
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 4], d)
c.check(code == 2 and one_line(err) and "particles_00042.csv" in err and listing(d) == ["particles_00042.csv"],
        f"a lone snapshot of an earlier run (no manifest) is refused too: exit {code}, {brief(err)}")

d = os.path.join(w, "capped")
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 16, "-snapshot_max", 5], d)
line = one_line(err)
c.check(code == 2 and line and "-snapshot_interval" in line and "-snapshot_max = 5" in line and not os.path.exists(d),
        f"more snapshots than -snapshot_max (6 > 5): exit {code}, {brief(err)}, nothing written")
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 16, "-snapshot_max", 6], d)
c.check(code == 0 and len(manifest(d)["files"]) == 2 * 5 + 4, f"6 allowed, 5 written: exit {code} {brief(err)}")

# 2. Two runs into one directory.
d = os.path.join(w, "shared")
# About 3 s of work, so the second run (a start of about 0.5 s) meets it running.
long_run = ["-expansion_n", 48, "-h", 3, "-ts_max_time", 384, "-output_interval", 4, "-snapshot_interval", 128, "-diag_entropy", 0]
first = subprocess.Popen([a.spam_ark] + [str(x) for x in long_run] + ["-output_dir", d], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
deadline = time.time() + 30
while time.time() < deadline and not any(n.startswith("timeseries.csv.") for n in listing(d)) and first.poll() is None:
    time.sleep(0.02)
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 4], d)
second_running = first.poll() is None
out1, err1 = first.communicate(timeout=120)
line = one_line(err)
c.check(second_running, "the first run was still running when the second one was refused")
c.check(code == 2 and line and "in use by another run" in line and f"pid {first.pid} " in line,
        f"second run into the same directory: exit {code}, {brief(err)}")
s = summary(d)
rows = open(os.path.join(d, "timeseries.csv")).read().splitlines()
c.check(first.returncode == 0 and s["status"] == "ok" and s["n_particles"] == 48 * 48 and len(rows) == 1 + 97
        and all(r.count(",") == rows[0].count(",") for r in rows),
        f"the first run completed intact: exit {first.returncode}, {len(rows) - 1} rows of 97, N = {s['n_particles']} {err1.strip()}")
c.check(listed(d) == sorted(n for n in listing(d) if n != "manifest.json"), "its manifest lists exactly the files present")

# 3. Symlinks at a temporary's name and at the lock's name.
d = os.path.join(w, "symlinks")
os.makedirs(d)
victim = os.path.join(w, "victim.txt")
with open(victim, "w") as f:
    f.write("untouched\n")
for name in ("timeseries.csv.tmp", "steps.csv.tmp", "summary.json.tmp", "manifest.json.tmp"):
    os.symlink(victim, os.path.join(d, name))
os.symlink("/dev/full", os.path.join(d, "particles_00000.csv.tmp"))
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 4], d)
rows = open(os.path.join(d, "timeseries.csv")).read().splitlines() if code == 0 else []
c.check(code == 0 and len(rows) == 6 and open(victim).read() == "untouched\n",
        f"symlinked temporaries are not followed: exit {code}, {len(rows) - 1} rows, victim {open(victim).read()!r} {err.strip()}")
c.check(not temporaries(d) and os.path.exists(victim), "the stale links are removed (the links, not their target)")
d = os.path.join(w, "symlink_lock")
os.makedirs(d)
os.symlink(victim, os.path.join(d, "spam-ark.lock"))
code, _, err = run(a.spam_ark, SMALL + ["-ts_max_time", 4], d)
c.check(code in (1, 2) and one_line(err) and "spam-ark.lock" in err and open(victim).read() == "untouched\n" and listing(d) == ["spam-ark.lock"],
        f"a symlink at the lock's name is refused: exit {code}, {brief(err)}, victim untouched, nothing written")


# 4. Failed writes.
def failed_run(label, d, args, env_value, name, expect_summary=True):
    env = dict(os.environ, SPAM_TEST_FAIL_WRITE=env_value) if env_value else None
    p = subprocess.run([a.spam_ark] + [str(x) for x in args] + ["-output_dir", d], capture_output=True, text=True, env=env, timeout=120)
    line = one_line(p.stderr)
    c.check(p.returncode == 1 and line and line.startswith("spam-ark: error: cannot write") and name in line and "No space left on device" in line,
            f"{label}: exit {p.returncode}, one line naming {name}: {brief(p.stderr)}")
    left = listing(d)
    c.check(not temporaries(d) and "spam-ark.lock" not in left and (name not in left or name == "summary.json"),
            f"{label}: the partial file, every temporary and the lock are gone ({len(left)} files left)")
    s = summary(d) if "summary.json" in left else None
    status = manifest(d)["status"] if "manifest.json" in left else None
    ok = (s is None or (s["status"] == "failed" and name in s["reason"])) and status in ("failed", None) and (s is not None or not expect_summary)
    c.check(ok, f"{label}: summary {'status ' + s['status'] + ', reason ' + repr(s['reason']) if s else 'absent'}; manifest status {status}")


failed_run("timeseries row 6", os.path.join(w, "fail_ts"), SMALL + ["-ts_max_time", 8], "timeseries.csv:6", "timeseries.csv")
failed_run("steps row 20", os.path.join(w, "fail_steps"), SMALL + ["-ts_max_time", 8], "steps.csv:20", "steps.csv")
failed_run("HDF5 snapshot 1", os.path.join(w, "fail_h5"), SMALL + ["-ts_max_time", 8], "snap_00001.h5:2", "snap_00001.h5")
failed_run("CSV snapshot 2", os.path.join(w, "fail_csv"), SMALL + ["-ts_max_time", 8], "particles_00002.csv:50", "particles_00002.csv")
failed_run("summary.json", os.path.join(w, "fail_summary"), SMALL + ["-ts_max_time", 8], "summary.json:3", "summary.json", expect_summary=False)

# For real: a 1 MiB tmpfs, filled to the last byte while the run writes its rows.
mnt = os.path.join(w, "tmpfs")
os.makedirs(mnt)
mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", mnt], capture_output=True, text=True).returncode == 0
if not mounted and os.geteuid() != 0:
    print("SKIP: disk full on a tmpfs needs root (mount)")
else:
    c.check(mounted, "a 1 MiB tmpfs is mounted for the disk-full case")
try:
    if mounted:
        d = os.path.join(mnt, "out")
        args = ["-expansion_n", 32, "-h", 3, "-ts_max_time", 2000, "-output_interval", 0.5, "-snapshot_interval", 0, "-diag_entropy", 0]
        p = subprocess.Popen([a.spam_ark] + [str(x) for x in args] + ["-output_dir", d], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.time() + 30
        tmp = None
        while time.time() < deadline and p.poll() is None:
            tmp = next((n for n in listing(d) if n.startswith("timeseries.csv.")), None)
            if tmp and os.path.getsize(os.path.join(d, tmp)) > 1500:
                break
            time.sleep(0.02)
        filled = 0
        try:
            with open(os.path.join(mnt, "filler"), "wb") as f:
                while True:
                    f.write(b"\0" * 4096)
                    f.flush()
                    filled += 4096
        except OSError:
            pass
        try:
            out, err = p.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGKILL)
            out, err = p.communicate()
        line = one_line(err)
        c.check(p.returncode == 1 and line and "cannot write" in line and d in line and "No space left on device" in line,
                f"disk full mid-run ({filled} bytes of filler): exit {p.returncode}, {brief(err)}")
        os.remove(os.path.join(mnt, "filler"))
        s = summary(d) if os.path.exists(os.path.join(d, "summary.json")) else None
        status = manifest(d)["status"] if os.path.exists(os.path.join(d, "manifest.json")) else None
        c.check((s is None or s["status"] == "failed") and status in ("failed", "running", None) and not temporaries(d) and "spam-ark.lock" not in listing(d),
                f"disk full: summary {s['status'] if s else 'absent'}, manifest {status}, no temporaries, no lock ({listing(d)})")
        # The HDF5 library's own write failing: 100 KiB left, a snapshot of 4096 particles
        # needs about 230 KiB.
        shutil.rmtree(d)
        with open(os.path.join(mnt, "filler"), "wb") as f:
            f.write(b"\0" * (1024 * 1024 - 100 * 1024))
        code, _, err = run(a.spam_ark, ["-expansion_n", 64, "-h", 3, "-ts_max_time", 4, "-diag_entropy", 0], d)
        line = one_line(err)
        c.check(code == 1 and line and "snap_00000.h5" in line and "No space left on device" in line and not temporaries(d),
                f"disk full in an HDF5 write: exit {code}, {brief(err)}, no temporaries")
finally:
    if mounted:
        subprocess.run(["umount", mnt])


# 5. Verdicts and formats.
def strict(path):
    def refuse(name):
        raise ValueError(f"{name} in {path}")
    with open(path) as f:
        return json.load(f, parse_constant=refuse)


d = os.path.join(w, "tensile_rest")
# -step_cfl: a body at rest gives the controller nothing to see, so without a bound it
# grows the step past the lattice's stability limit and round-off grows to KE 3e-7 (the
# output stops once capped the step at 1.5); see options/tensile.opts.
code, out, err = run(a.spam_ark, ["-scene", "tensile", "-tensile_kick", 0, "-ts_max_time", 150, "-step_cfl", 0.5], d)
s = strict(os.path.join(d, "summary.json"))
c.check(code == 0 and s["status"] == "ok" and s["kinetic_final"] < 1e-20 * s["energy_scale"] and s["energy_scale"] > 0,
        f"tensile at rest, no kick: exit {code}, status {s['status']}, KE {s['kinetic_final']:.3g} against the energy scale {s['energy_scale']:.3g}")
c.check(s["energy_rel_drift_max"] is None and "energy_rel_drift_max" in s["null_fields"] and "initial energy of zero" in s["nulls"],
        f"drift relative to a zero initial energy is null and the note says why: {s['null_fields']}")
blow = os.path.join(w, "blow.csv")
with open(blow, "w") as f:
    f.write("x,y,vx,vy\n" + "".join(f"{i + 0.5},{j + 0.5},{1e308 if (i, j) == (3, 4) else 0.0!r},0\n" for j in range(8) for i in range(8)))
d = os.path.join(w, "overflow")
code, out, err = run(a.spam_ark, ["-scene", "file", "-box_len", "8,8", "-file_path", blow, "-arkode_fixed_step", 2, "-ts_max_time", 10], d)
try:
    s, why = strict(os.path.join(d, "summary.json")), ""
except ValueError as e:
    s, why = {}, str(e)
nums = [v for v in s.values() if isinstance(v, float)] + [x for v in s.values() if isinstance(v, list) for x in v if isinstance(x, float)]
c.check(code == 3 and s.get("status") == "unstable" and all(math.isfinite(x) for x in nums) and s.get("null_fields") is not None,
        f"blow-up by overflow: exit {code}, summary.json is strict JSON {why} (nulls: {s.get('null_fields')})")
c.check(strict(os.path.join(d, "manifest.json"))["status"] == "unstable", "its manifest says unstable")
c.finish()
