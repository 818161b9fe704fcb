#!/usr/bin/python3
"""The tools for one's own problem work on any run: examples/plot_run.py draws short runs of
two different scenes (the periodic expansion, and a Couette channel, whose walls add their
own columns to timeseries.csv) and of the sample particle file examples/particles/two_drops.csv;
each PNG is written, and examples/spamread.py reads the same runs back: the time series has
a row per output time (t from 0 to the end time), the steps file every accepted step of
summary.json, the snapshots the run's particle count, each in id order. A particle file
written by spamread.write_particles is read by -scene file and a run of it comes back with
the same positions at t = 0 (the file is written with repr, so exactly). Controls: plot_run.py
refuses a directory that is not a run (exit 2, one line), and spamread refuses it too."""
import os
import subprocess
import sys

from spamrun import Checks, arguments, run

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "examples")
sys.path.insert(0, EXAMPLES)
import spamread  # noqa: E402

import numpy as np  # noqa: E402

a = arguments()
c = Checks()
opts = os.path.join(HERE, "..", "options")
runs = {
    "expansion": ["-options_file", os.path.join(opts, "expansion.opts"), "-expansion_n", "16", "-ts_max_time", "8"],
    "couette": ["-options_file", os.path.join(opts, "couette.opts"), "-couette_n", "8", "-ts_max_time", "4"],
    "two_drops": ["-scene", "file", "-file_path", os.path.join(EXAMPLES, "particles", "two_drops.csv"),
                  "-box_len", "64,32", "-h", "3", "-ts_max_time", "2"],
}
for name, args in runs.items():
    out = os.path.join(a.workdir, name)
    code, _, err = run(a.spam_ark, args, out)
    if not c.check(code == 0, f"{name}: spam-ark runs (exit {code}) {err.strip()[-200:]}"):
        continue
    png = os.path.join(out, "run.png")
    p = subprocess.run([os.path.join(EXAMPLES, "plot_run.py"), out], capture_output=True, text=True, timeout=300)
    c.check(p.returncode == 0 and os.path.isfile(png) and os.path.getsize(png) > 20000,
            f"{name}: examples/plot_run.py writes run.png (exit {p.returncode}, "
            f"{os.path.getsize(png) if os.path.exists(png) else 0} bytes) {p.stderr.strip()[-200:]}")
    r = spamread.Run(out)
    ts, st = r.timeseries(), r.steps()
    s = r.summary
    c.check(r.status == "ok" and ts["t"][0] == 0 and abs(ts["t"][-1] - s["t_end"]) <= 1e-12 * s["t_end"],
            f"{name}: spamread: status {r.status}, timeseries t from {ts['t'][0]} to {ts['t'][-1]} (t_end {s['t_end']})")
    c.check(len(st["t"]) == s["steps"] and set(st["limit"]) <= {"accuracy", "cfl", "force", "output", "end", "fixed"},
            f"{name}: spamread: steps.csv has the {s['steps']} steps of summary.json ({len(st['t'])}), limits {sorted(set(st['limit']))}")
    snaps = r.snapshots()
    c.check(len(snaps) >= 2 and all(len(p["x"]) == s["n_particles"] and np.all(p["id"] == np.arange(len(p["x"])))
                                    for _, p in snaps) and snaps[0][0] == 0,
            f"{name}: spamread: {len(snaps)} snapshots of {s['n_particles']} particles each, in id order")

# A particle file written from Python is read back as written.
rng = np.random.default_rng(1)
x, y = np.meshgrid(np.arange(12) + 0.5, np.arange(12) + 0.5)
cols = {"x": x.ravel() + 0.1 * rng.random(144), "y": y.ravel(), "vx": 0.01 * rng.standard_normal(144),
        "m": 1 + 0.5 * rng.random(144), "id": np.arange(144)}
path = os.path.join(a.workdir, "lattice.csv")
spamread.write_particles(path, cols)
out = os.path.join(a.workdir, "lattice")
code, _, err = run(a.spam_ark, ["-scene", "file", "-file_path", path, "-box_len", "12", "-h", "3", "-ts_max_time", "1"], out)
if c.check(code == 0, f"a file written by spamread.write_particles runs (exit {code}) {err.strip()[-200:]}"):
    t0, p0 = spamread.Run(out).snapshots()[0]
    c.check(t0 == 0 and np.array_equal(p0["x"], cols["x"]) and np.array_equal(p0["m"], cols["m"]),
            "its first snapshot holds the written positions and (unequal) masses exactly")

# Controls: a directory that is not a run.
empty = os.path.join(a.workdir, "empty")
os.makedirs(empty)
p = subprocess.run([os.path.join(EXAMPLES, "plot_run.py"), empty], capture_output=True, text=True, timeout=60)
c.check(p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and not os.path.exists(os.path.join(empty, "run.png")),
        f"control: plot_run.py on a directory that is not a run: exit {p.returncode}, {p.stderr.strip()!r}")
try:
    spamread.Run(empty)
    c.check(False, "control: spamread.Run refuses a directory that is not a run")
except spamread.RunError as exc:
    c.check(True, f"control: spamread.Run refuses a directory that is not a run ({exc})")
c.finish()
