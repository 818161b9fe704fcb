"""Helpers for the run tests: invoke spam-ark, read its outputs, count checks."""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys


class Checks:
    """Counts checks and prints the closing line 'N passed, N failed'. A test may also record
    the readings a page quotes (reading()); with --readings FILE they are written to FILE
    with the command and commit (examples/chart_readings.py) when the test passes."""

    def __init__(self):
        self.passed = 0
        self.failed = 0
        self.readings = {}

    def reading(self, key, value):
        """Records one reading under a dotted key ("n24.l1")."""
        d = self.readings
        *parents, last = key.split(".")
        for p in parents:
            d = d.setdefault(p, {})
        d[last] = float(value) if hasattr(value, "dtype") else value

    def check(self, ok, message):
        print(("ok  : " if ok else "FAIL: ") + message, flush=True)
        if ok:
            self.passed += 1
        else:
            self.failed += 1
        return ok

    def finish(self, readings_path=None):
        if readings_path and not self.failed:
            sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
            import chart_readings
            chart_readings.write_json(readings_path, self.readings)
        print(f"{self.passed} passed, {self.failed} failed")
        sys.exit(1 if self.failed else 0)


def arguments(add_options=None):
    """The run tests' common options; add_options(parser), when given, adds a test's own."""
    p = argparse.ArgumentParser()
    p.add_argument("--spam-ark", required=True)
    p.add_argument("--workdir", required=True)
    p.add_argument("--readings", help="write the readings a page quotes to this JSON file (when the test passes)")
    if add_options:
        add_options(p)
    a = p.parse_args()
    shutil.rmtree(a.workdir, ignore_errors=True)
    os.makedirs(a.workdir)
    return a


def run(binary, args, outdir=None, timeout=600):
    """Runs spam-ark; returns (exit code, stdout, stderr)."""
    cmd = [binary] + [str(x) for x in args]
    if outdir is not None:
        cmd += ["-output_dir", outdir]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return check_sanitizers(cmd, p.returncode, p.stdout, p.stderr)


class Runner:
    """run() for many short runs of one binary: each in a forked child of the fork server
    (tests/fork_server.py), where the server is built and the run does not depend on the
    executable's own path; else, and with SPAM_FUZZ_EXEC=1, a start of the binary. The same
    results as run(): exit code (negative: the signal), stdout, stderr, the same check for
    sanitizer reports, subprocess.TimeoutExpired after timeout seconds."""

    def __init__(self, binary, workdir):
        import atexit
        import fork_server
        self.binary, self.server, self.forked = binary, None, 0
        self.fork_server = fork_server
        path = fork_server.server_path(binary)
        if path:
            self.files = os.path.join(os.path.abspath(workdir), ".fork_server")
            os.makedirs(self.files, exist_ok=True)
            self.server = fork_server.Server(path, binary, dict(os.environ), self.files)
            atexit.register(self.server.close)

    def run(self, args, outdir=None, timeout=600, cwd=None):
        args = [str(x) for x in args] + (["-output_dir", outdir] if outdir is not None else [])
        if self.server is None or self.fork_server.needs_exec(args):
            if cwd is None:
                return run(self.binary, args, timeout=timeout)
            p = subprocess.run([self.binary] + args, capture_output=True, text=True, timeout=timeout, cwd=cwd)
            return check_sanitizers([self.binary] + args, p.returncode, p.stdout, p.stderr)
        out, err = os.path.join(self.files, "stdout"), os.path.join(self.files, "stderr")
        code = self.server.run(args, os.path.abspath(cwd or os.getcwd()), dict(os.environ), out, err, timeout)
        self.forked += 1
        with open(out, encoding="utf-8") as f:
            stdout = f.read()
        with open(err, encoding="utf-8") as f:
            stderr = f.read()
        if code == "timeout":
            raise subprocess.TimeoutExpired([self.binary] + args, timeout, stdout, stderr)
        return check_sanitizers([self.binary] + args, code, stdout, stderr)


def check_sanitizers(cmd, code, stdout, stderr):
    """Under tools/sanitize.sh a report also sets exit code 86; this catches it where a test
    accepts any code."""
    if any(s in stderr for s in ("ERROR: AddressSanitizer", "LeakSanitizer", "runtime error:")):
        sys.exit(f"sanitizer report from {' '.join(cmd)}:\n{stderr}")
    return code, stdout, stderr


def kernel_names(binary, runner=None):
    """The names -kernel accepts, in the program's order, read from its -help line
    "-kernel  Smoothing kernel ... (one of) lucy wendland_c2 ...  [default lucy]": the one
    list is the program's (src/kernels/kernel_list.h), so a test keeps no copy of it."""
    _, out, _ = runner.run(["-help"]) if runner else run(binary, ["-help"])
    line = next((l for l in out.splitlines() if l.strip().startswith("-kernel ")), "")
    return line.split("(one of)", 1)[1].split("[", 1)[0].split("(", 1)[0].split() if "(one of)" in line else []


def one_line(err):
    """The only line of stderr, or None when it has none or several."""
    lines = err.strip().splitlines()
    return lines[0] if len(lines) == 1 else None


def brief(err):
    """stderr as shown in a check's message: at most 300 characters."""
    err = err.strip()
    return repr(err if len(err) <= 300 else err[:300] + "...")


def summary(outdir):
    with open(os.path.join(outdir, "summary.json")) as f:
        return json.load(f)


def table(path):
    """A CSV file as a dict of column name -> list of floats (or strings for text columns)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))

    def value(v):
        try:
            return float(v)
        except ValueError:
            return v
    return {k: [value(r[k]) for r in rows] for k in rows[0]}


def final_state(path):
    """Rows of a particles CSV (file-scene format) as lists of floats."""
    with open(path) as f:
        next(f)
        return [[float(v) for v in line.split(",")] for line in f if line.strip()]


def manifest(outdir):
    """The run's manifest.json (status and the files it wrote)."""
    with open(os.path.join(outdir, "manifest.json")) as f:
        return json.load(f)


def manifest_files(outdir, kind):
    """Paths of the files of one kind the manifest lists (snapshot_csv, snapshot_h5,
    snapshot_csv_last_good, summary, ...): what the run wrote, never a glob."""
    return [os.path.join(outdir, e["name"]) for e in manifest(outdir)["files"] if e.get("kind") == kind and "name" in e]


def mpiexec_env():
    """mpiexec and the environment to start spam-ark on several ranks as root (exit 77,
    ctest's skip, when OpenMPI's launcher is missing)."""
    import shutil
    mpiexec = shutil.which("mpiexec")
    if not mpiexec:
        print("mpiexec not found (apt-get install openmpi-bin)")
        sys.exit(77)
    # Ranks not bound to cores (mpiexec --bind-to none): mpiexec binds up to as many ranks as
    # cores, one to each, and a bound rank cannot leave a core that another test's process
    # shares: in CI (ctest -j2 on 2 cores) the 2-rank runs took 10-40 times as long as the
    # same runs on 3 ranks, which mpiexec leaves unbound once they outnumber the cores
    # (run_ranks: planewave 15.4 s against 1.1 s, Couette 10.9 s against 0.28 s). Where a
    # rank runs changes no result.
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_pml="ob1",
               OMPI_MCA_hwloc_base_binding_policy="none")
    env.pop("OMPI_MCA_ess_singleton_isolated", None)  # set by ctest for one-rank starts
    return mpiexec, env


def rank_command(mpiexec, env, ranks, binary, args):
    """The command and environment that start binary with args on `ranks` ranks: mpiexec for
    several; for one a plain start, MPI's singleton (OpenMPI's isolated start, as ctest sets for
    the one-rank tests), which is the run mpiexec -n 1 makes without mpiexec's launch (about
    0.5 s and 0.12 CPU-s a start here)."""
    args = [str(x) for x in args]
    if ranks == 1:
        return [binary] + args, dict(env, OMPI_MCA_ess_singleton_isolated="1")
    return [mpiexec, "--oversubscribe", "-n", str(ranks), binary] + args, env


# Comparing two run directories (the restart tests: a restarted run against the
# uninterrupted one).
TIMING = ("rhs_s", "wall_s")


def outputs(d):
    """The files a run leaves, by name, minus the run's own bookkeeping."""
    skip = {"manifest.json", "summary.json", "checkpoint.h5", "spam-ark.lock"}
    return sorted(n for n in os.listdir(d) if n not in skip)


def timeseries_without_timing(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    keep = [k for k, name in enumerate(rows[0]) if name not in TIMING]
    return [[r[k] for k in keep] for r in rows]


def same_outputs(ref, got):
    """The first difference between two run directories' outputs, or ''."""
    names = outputs(ref)
    if names != outputs(got):
        return f"files differ: {sorted(set(names) ^ set(outputs(got)))}"
    for n in names:
        p, q = os.path.join(ref, n), os.path.join(got, n)
        if n == "timeseries.csv":
            if timeseries_without_timing(p) != timeseries_without_timing(q):
                return "timeseries.csv differs (timing columns aside)"
        elif open(p, "rb").read() != open(q, "rb").read():
            return f"{n} differs"
    return ""


def steps_table(d):
    with open(os.path.join(d, "steps.csv")) as f:
        return list(csv.DictReader(f))
