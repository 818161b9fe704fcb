#!/usr/bin/python3
"""SIGINT and SIGTERM in mid-run: the run finishes the step it is in,
writes every output at the time reached (a timeseries row, a snapshot, summary.json with
"status": "interrupted" and that time, the manifest), prints one line and exits 130
(SIGINT) or 143 (SIGTERM). The files are complete: every timeseries row parses, the last
row and the last step are at the time reached, no temporary or lock is left. On two ranks,
the signal one rank other than 0 received is the one every rank reports (before:
SIGINT to rank 1 was reported as SIGTERM, exit 143)."""
import csv
import os
import shutil
import signal
import subprocess
import time
from spamrun import Checks, arguments, manifest, mpiexec_env, summary

a = arguments()
c = Checks()
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The 64 x 64 expansion to t = 4096: minutes of work, interrupted after a few rows.
ARGS = ["-options_file", os.path.join(root, "options", "expansion.opts"), "-expansion_n", 64, "-ts_max_time", 4096,
        "-output_interval", 2, "-snapshot_interval", 64]

for sig, name, want in ((signal.SIGINT, "SIGINT", 130), (signal.SIGTERM, "SIGTERM", 143)):
    d = os.path.join(a.workdir, name)
    p = subprocess.Popen([a.spam_ark] + [str(x) for x in ARGS] + ["-output_dir", d], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline, rows = time.time() + 45, 0
    while time.time() < deadline and p.poll() is None and rows < 4:
        tmp = [n for n in (os.listdir(d) if os.path.isdir(d) else []) if n.startswith("timeseries.csv.")]
        rows = open(os.path.join(d, tmp[0])).read().count("\n") - 1 if tmp else 0
        time.sleep(0.02)
    p.send_signal(sig)
    try:
        out, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
    last = out.strip().splitlines()[-1] if out.strip() else ""
    c.check(p.returncode == want and f"interrupted by {name}" in last and not err.strip(),
            f"{name} after {rows} rows: exit {p.returncode} (want {want}), last line {last!r}, stderr {err.strip()!r}")
    s = summary(d)
    c.check(s["status"] == "interrupted" and s.get("signal") == int(sig) and 0 < s["t_final"] < s["t_end"] and name in s["reason"],
            f"{name}: summary status {s['status']}, signal {s.get('signal')}, t reached {s['t_final']} of {s['t_end']}: {s['reason']}")
    with open(os.path.join(d, "timeseries.csv")) as f:
        table = list(csv.reader(f))
    widths = {len(r) for r in table}
    t = [float(r[0]) for r in table[1:]]
    c.check(len(widths) == 1 and len(t) >= 4 and all(u < v for u, v in zip(t, t[1:])) and abs(t[-1] - s["t_final"]) <= 1e-9 * s["t_final"],
            f"{name}: timeseries.csv has {len(t)} whole rows of {widths}, increasing t, the last at the time reached ({t[-1] if t else None})")
    with open(os.path.join(d, "steps.csv")) as f:
        steps = list(csv.DictReader(f))
    c.check(len(steps) == s["steps"] and abs(float(steps[-1]["t"]) - s["t_final"]) <= 1e-9 * s["t_final"],
            f"{name}: steps.csv has a row per step ({len(steps)} for {s['steps']}), the last at the time reached")
    m = manifest(d)
    snaps = [e for e in m["files"] if e["kind"] == "snapshot_csv"]
    left = os.listdir(d)
    c.check(m["status"] == "interrupted" and snaps and abs(snaps[-1]["t"] - s["t_final"]) <= 1e-9 * s["t_final"]
            and all(e["name"] in left for e in m["files"] if "name" in e),
            f"{name}: manifest status {m['status']}, {len(snaps)} snapshots, the last at the time reached, every listed file present")
    c.check(not [n for n in left if n.endswith(".tmp")] and "spam-ark.lock" not in left, f"{name}: no temporary, no lock left")


def rank_of(pid):
    """The MPI rank of a process started by OpenMPI's mpiexec (its environment says)."""
    try:
        env = open(f"/proc/{pid}/environ", "rb").read().split(b"\0")
    except OSError:
        return None
    ranks = [e.split(b"=", 1)[1] for e in env if e.startswith(b"OMPI_COMM_WORLD_RANK=")]
    return int(ranks[0]) if ranks else None


# A signal to rank 1 alone (a batch system may signal any rank): every rank stops after the
# same step and the run reports that signal, not SIGTERM.
if shutil.which("mpiexec"):
    mpiexec, ENV = mpiexec_env()
    for sig, name, want in ((signal.SIGINT, "SIGINT", 130), (signal.SIGTERM, "SIGTERM", 143)):
        d = os.path.join(a.workdir, f"{name}_rank1")
        log = d + ".log"
        cmd = [mpiexec, "--oversubscribe", "-n", "2", a.spam_ark] + [str(x) for x in ARGS] + ["-expansion_n", "32", "-snapshot_interval", "0", "-output_dir", d]
        with open(log, "w") as f:
            p = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT, env=ENV)
        # Rank 0 prints its first line once every rank has opened the run (and installed
        # its handler); the run would go on for minutes.
        deadline = time.time() + 120
        while time.time() < deadline and p.poll() is None and "spam-ark: scene" not in open(log).read():
            time.sleep(0.1)
        time.sleep(0.5)
        kids = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
        target = [k for k in kids if rank_of(k) == 1]
        if target:
            os.kill(int(target[0]), sig)
        try:
            p.wait(timeout=60)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
        s = summary(d) if os.path.exists(os.path.join(d, "summary.json")) else {}
        c.check(len(target) == 1 and p.returncode == want and s.get("status") == "interrupted" and s.get("signal") == int(sig) and f"interrupted by {name}" in s.get("reason", ""),
                f"{name} to rank 1 of 2: exit {p.returncode} (want {want}), summary signal {s.get('signal')} (want {int(sig)}), reason {s.get('reason')!r}")
else:
    print("mpiexec not found: the two-rank cases skipped")
c.finish()
