#!/usr/bin/python3
"""HDF5 outputs are written race-free, and a failed write ends cleanly.

1. A full disk during a checkpoint write (one rank): exit 1 with the one line naming
   checkpoint.h5 and the system's reason, no crash at exit (HDF5 once kept the failed file
   open and closed it again at its shutdown, after MPI: SIGSEGV), no temporary, no lock.
   Two ways: a 1 MiB tmpfs filled to several levels (needs mount: root in CI; skipped with
   the reason otherwise), and a file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored: write()
   fails with EFBIG), which needs no privilege and always runs; and on two ranks (tmpfs).
2. The symlink race: while the writer is paused right after creating NAME.PID.tmp (the test
   hook SPAM_TEST_PAUSE_TEMP=NAME:GOFILE), the temporary is replaced by a symlink to a
   victim file. HDF5 never opens the temporary by name, so the victim is untouched; the
   writer then sees its temporary was replaced and refuses in one line (exit 1), leaving no
   temporary and no link. For an HDF5 snapshot, a grid file and a checkpoint on one rank,
   and a snapshot and a checkpoint on two ranks (rank 0 writes the file for all); and the
   text series timeseries.csv, which each checkpoint reads back: no file of the run may
   hold the target's bytes."""
import os
import resource
import shutil
import signal
import subprocess
import time
from spamrun import Checks, arguments, brief, one_line

a = arguments()
c = Checks()
w = a.workdir
CK = ["-expansion_n", 64, "-h", 3, "-ts_max_time", 4, "-diag_entropy", 0, "-snapshot_interval", 0, "-checkpoint_interval", 1]


def listing(d):
    return sorted(os.listdir(d)) if os.path.isdir(d) else []


def clean(d):
    """No temporary and no lock left in d."""
    left = listing(d)
    return not [n for n in left if n.endswith(".tmp")] and "spam-ark.lock" not in left


def full_disk_case(label, p, d, reason):
    line = one_line(p.stderr)
    c.check(p.returncode == 1 and line and line.startswith("spam-ark: error: cannot write") and "checkpoint.h5" in line and reason in line,
            f"{label}: exit {p.returncode} (a crash is negative), one line naming checkpoint.h5 and '{reason}': {brief(p.stderr)}")
    c.check(clean(d) and "checkpoint.h5" not in listing(d), f"{label}: no partial checkpoint, no temporary, no lock ({listing(d)})")


def mpiexec_env():
    mpiexec = shutil.which("mpiexec")
    # unbound ranks, as spamrun.mpiexec_env says why
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_pml="ob1",
               OMPI_MCA_hwloc_base_binding_policy="none")
    env.pop("OMPI_MCA_ess_singleton_isolated", None)
    return mpiexec, env


# 1. Full disk during a checkpoint write.
mnt = os.path.join(w, "tmpfs")
os.makedirs(mnt)
mount = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", mnt], capture_output=True, text=True)
if mount.returncode != 0:
    print(f"SKIP: the full-disk case on a tmpfs needs mount (root): {mount.stderr.strip()[:200]}")
else:
    try:
        # A checkpoint of 4096 particles is about 330 kB: filled to these levels, the first
        # checkpoint fails at its first or a later write (measured: all of them crashed before).
        for kib in (700, 800, 850, 900):
            d = os.path.join(mnt, "out")
            shutil.rmtree(d, ignore_errors=True)
            with open(os.path.join(mnt, "filler"), "wb") as f:
                f.write(b"\0" * (kib * 1024))
            p = subprocess.run([a.spam_ark] + [str(x) for x in CK] + ["-output_dir", d], capture_output=True, text=True, timeout=120)
            full_disk_case(f"tmpfs filled to {kib} KiB of 1024", p, d, "No space left on device")
            os.remove(os.path.join(mnt, "filler"))
        # Two ranks: rank 0 writes the whole checkpoint; every rank ends, one line in all.
        mpiexec, menv = mpiexec_env()
        if mpiexec:
            d = os.path.join(mnt, "out2")
            with open(os.path.join(mnt, "filler"), "wb") as f:
                f.write(b"\0" * (800 * 1024))
            p = subprocess.run([mpiexec, "--oversubscribe", "-n", "2", a.spam_ark] + [str(x) for x in CK] + ["-output_dir", d], capture_output=True, text=True, timeout=120, env=menv)
            p.stderr = "\n".join(x for x in p.stderr.splitlines() if x.startswith("spam-ark:"))  # without mpiexec's own lines
            full_disk_case("tmpfs filled to 800 KiB, 2 ranks", p, d, "No space left on device")
            os.remove(os.path.join(mnt, "filler"))
    finally:
        subprocess.run(["umount", mnt])


def file_size_limit():
    """In the child: files may not grow past 200 kB, and the signal of a write past it is
    ignored, so write() fails with EFBIG (as on a full disk) instead of killing the run."""
    resource.setrlimit(resource.RLIMIT_FSIZE, (200 * 1024, 200 * 1024))
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)


d = os.path.join(w, "fsize")
p = subprocess.run([a.spam_ark] + [str(x) for x in CK] + ["-output_dir", d], capture_output=True, text=True, timeout=120, preexec_fn=file_size_limit)
full_disk_case("a 200 kB file-size limit", p, d, "File too large")


# 2. The symlink race.
def race(label, name, args, ranks=1):
    d = os.path.join(w, "race_" + label.replace(" ", "_"))
    victim = os.path.join(w, "victim_" + label.replace(" ", "_"))
    go = os.path.join(w, "go_" + label.replace(" ", "_"))
    with open(victim, "w") as f:
        f.write("untouched\n")
    env = dict(os.environ, SPAM_TEST_PAUSE_TEMP=f"{name}:{go}")
    cmd = [a.spam_ark] + [str(x) for x in args] + ["-output_dir", d]
    if ranks > 1:
        mpiexec, menv = mpiexec_env()
        if not mpiexec:
            print(f"SKIP: {label}: mpiexec not found")
            return
        env = dict(menv, SPAM_TEST_PAUSE_TEMP=env["SPAM_TEST_PAUSE_TEMP"])
        cmd = [mpiexec, "--oversubscribe", "-n", str(ranks)] + cmd
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    tmp, deadline = None, time.time() + 60
    while time.time() < deadline and p.poll() is None and not tmp:
        tmp = next((n for n in listing(d) if n.startswith(name + ".") and n.endswith(".tmp")), None)
        time.sleep(0.01)
    swapped = False
    if tmp:
        link = os.path.join(d, "link.swap")
        os.symlink(victim, link)
        os.replace(link, os.path.join(d, tmp))  # atomically: the temporary's name is now the link
        swapped = True
    open(go, "w").close()
    try:
        out, err = p.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
    # mpiexec adds its own lines about the rank that exited 1: the program's are counted
    line = one_line("\n".join(x for x in err.splitlines() if x.startswith("spam-ark:")) if ranks > 1 else err)
    c.check(swapped, f"{label}: the run paused with its temporary {tmp} and the test swapped it for a symlink")
    c.check(open(victim).read() == "untouched\n", f"{label}: the symlink's target is untouched")
    leaked = [n for n in listing(d) if os.path.isfile(os.path.join(d, n)) and b"untouched" in open(os.path.join(d, n), "rb").read()]
    c.check(not leaked, f"{label}: no file of the run holds the target's bytes (read back through the link): {leaked}")
    refused = p.returncode == 1 and line and f"cannot write {os.path.join(d, name)}: its temporary" in line and "was replaced during the write" in line
    c.check(refused, f"{label}: the write is refused in one line (exit {p.returncode}): {brief(err)}")
    final = os.path.join(d, name)
    c.check(clean(d) and not os.path.islink(final) and not os.path.lexists(os.path.join(d, tmp or "none")),
            f"{label}: no temporary, link or lock left, {name} is not a link ({listing(d)})")


SNAP = ["-expansion_n", 8, "-h", 1.5, "-ts_max_time", 1, "-snapshot_interval", 0.5, "-diag_entropy", 0]
race("HDF5 snapshot", "snap_00001.h5", SNAP)
race("grid file", "grid_00001.h5", SNAP + ["-grid_interval", 1])
race("checkpoint", "checkpoint.h5", ["-expansion_n", 8, "-h", 1.5, "-ts_max_time", 1, "-checkpoint_interval", 0.5, "-diag_entropy", 0])
# The text series: its temporary is read back into each checkpoint (through its descriptor,
# so the link's target never reaches the checkpoint) and renamed at the end.
race("timeseries", "timeseries.csv", ["-expansion_n", 8, "-h", 1.5, "-ts_max_time", 1, "-checkpoint_interval", 0.25, "-diag_entropy", 0])
race("HDF5 snapshot on 2 ranks", "snap_00001.h5", SNAP, ranks=2)
race("checkpoint on 2 ranks", "checkpoint.h5", ["-expansion_n", 8, "-h", 1.5, "-ts_max_time", 1, "-checkpoint_interval", 0.5, "-diag_entropy", 0], ranks=2)
c.finish()
