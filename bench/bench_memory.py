"""run_bench.py --memory: spam-ark's bytes per particle, the whole process and by owner.

Two measures, both independent of the machine's load:
  - (peak RSS - the 64-particle run's) / N at several N, for the gas-h3 case (the file
    scene on the expansion lattice, Dormand-Prince at a fixed step) and the default 2D
    expansion (options/expansion.opts at h = 3, its adaptive Dormand-Prince);
  - with valgrind, the heap at massif's peak of one gas-h3 run, each allocation given to
    the owner named by the first frame of its stack that matches OWNERS below.  Massif
    counts what is allocated; RSS counts the pages written, so an array allocated and
    never written (a capacity, an unused direction) shows in the first only.
"""

import re
import shutil
import subprocess
from pathlib import Path

from bench_common import REPO_ROOT, run_measured
from spam_driver import spam_cmd, spam_make_initial

MEMORY_SIZES = (16384, 65536, 262144)
BASELINE_NX = 8
MEMORY_STEPS = 4

# (owner, pattern on a stack frame "function (file:line)", or "function (in binary)" in a
# build without debug information): the frame nearest the allocation that matches some
# pattern names the owner (the first such pattern).
OWNERS = [
    ("DP5 stage vectors (ERKStep, 7)", r"erkStep_Init"),
    ("ARKODE interpolant (Hermite)", r"arkInterpInit"),
    ("ARKODE work vectors (arkAllocVectors: yn, ewt, tempv...)", r"arkAllocVectors|arkResize"),
    ("PETSc TS vectors (tolerances, work)", r"Tolerances \(ts_create|TSSetUp|TSStep\b"),
    ("state vector X (PETSc Vec on the swarm field)", r"DMSwarmCreate(Global|Local)VectorFromField|SpamSwarmOpenState"),
    ("DMSwarm fields (state, gid, pid, rank; mass, body, xref on several ranks)", r"DMSwarm"),
    ("run loop: last good state, list keep, output state", r"SpamRun \((time_loop|in )|Loop \((time_loop|in )|InterpolatedOutputs"),
    ("pair fields (m, 1/m, rho, P/rho^2, acc)", r"SpamFields(Create|Reserve)"),
    ("neighbour list: pair rows", r"Reserve \((neighbours\.c|in )|BuildRows|SpamNeighboursPadList"),
    ("neighbour list: ghosts", r"neighbours_ghost\.c|ghosts\.c|halo|SpamGhosts|GrowSlots|AppendGhost"),
    ("neighbour list: positions (u, xref, off), cells, build scratch", r"neighbours\.c|SpamNeighboursCreate"),
    ("input particles (freed after set-up)", r"ReadCsv|SpamParticles|scene_file\.c"),
    ("outputs", r"Output|Summary|Snapshot|Diagnostic|Timeseries|Manifest|Csv|Json"),
    ("start-up (MPI, PETSc, libraries)", r"StartMpi|PetscInitialize|MPI_Init"),
]


def _gas_cmd(binary, workdir, n, steps, outdir):
    nx = int(round(n ** 0.5))
    csv, _ = spam_make_initial(binary, nx, 3.0, workdir)
    return spam_cmd(binary, csv, (2.0 * nx, 2.0 * nx), 3.0, steps, outdir)


def _expansion_cmd(binary, n, steps, outdir):
    nx = int(round(n ** 0.5))
    return [binary, "-options_file", REPO_ROOT / "options" / "expansion.opts",
            "-expansion_n", nx, "-h", 3, "-ts_max_steps", steps,
            "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0,
            "-output_dir", outdir]


def _rss(cmd, workdir, tag):
    rc, _, rss = run_measured(cmd, REPO_ROOT, workdir / ("mem_%s.log" % tag))
    if rc != 0 or not rss:
        raise RuntimeError("spam-ark memory run failed (rc=%d): %s" % (rc, " ".join(map(str, cmd))))
    return rss


def rss_table(binary, workdir, sizes, steps):
    """{case: [(N, peak RSS, (RSS - baseline) / N)]} for the gas-h3 case and the expansion."""
    makers = {"gas-h3": ("gas", lambda n, d: _gas_cmd(binary, workdir, n, steps, d)),
              "expansion h=3 (options/expansion.opts)": ("exp", lambda n, d: _expansion_cmd(binary, n, steps, d))}
    rows = {}
    for case, (tag, make) in makers.items():
        def rss(n):
            t = "%s_%d" % (tag, n)
            return _rss(make(n, workdir / ("mem_" + t)), workdir, t)
        base = rss(BASELINE_NX ** 2)
        rows[case] = [(n, r, (r - base) / n) for n, r in ((n, rss(n)) for n in sizes)]
    return rows


def _massif_peak_leaves(path):
    """(bytes, [frames from the allocation outwards]) of every leaf of massif's peak tree."""
    lines = Path(path).read_text().splitlines()
    start = next(k for k, l in enumerate(lines) if l.startswith("heap_tree=peak")) + 1
    leaves, stack = [], []
    for line in lines[start:]:
        m = re.match(r"(\s*)n(\d+): (\d+) (.*)", line)
        if not m:
            break
        depth = len(m.group(1))
        stack = stack[:depth] + [m.group(4)]
        if int(m.group(2)) == 0:
            leaves.append((int(m.group(3)), stack[1:][::-1]))
    return leaves


def owner_table(binary, workdir, n, steps):
    """{owner: bytes} of the heap at massif's peak of the gas-h3 run at N = n; None without
    valgrind."""
    if shutil.which("valgrind") is None:
        return None
    out = workdir / ("massif_%d.out" % n)
    cmd = (["valgrind", "--tool=massif", "--depth=40", "--threshold=0.1",
            "--massif-out-file=%s" % out]
           + [str(c) for c in _gas_cmd(binary, workdir, n, steps, workdir / "mem_massif")])
    p = subprocess.run(cmd, cwd=str(REPO_ROOT), capture_output=True, text=True)
    if p.returncode != 0 or not out.exists():
        raise RuntimeError("massif run failed (rc=%d): %s" % (p.returncode, p.stderr[-2000:]))
    owners = {}
    for size, frames in _massif_peak_leaves(out):
        # frames: innermost last in massif's tree; reversed above: the caller chain outwards
        chain = list(reversed(frames))
        name = next((o for f in chain for o, pat in OWNERS if re.search(pat, f)), None)
        if name is None:
            name = "other (below massif's threshold, libraries)"
        owners[name] = owners.get(name, 0) + size
    return owners


def run_memory(args, workdir):
    """Prints the two tables; returns them as a dict for the results file."""
    sizes = sorted(args.memory_sizes)
    print("memory: (peak RSS - the %d-particle run's) / N, %d steps each" % (BASELINE_NX ** 2, MEMORY_STEPS))
    rows = rss_table(args.spam_ark, workdir, sizes, MEMORY_STEPS)
    print("| case | N | peak RSS (MB) | B/particle (RSS - base) |")
    print("|---|---|---|---|")
    for case, rr in rows.items():
        for n, rss, per in rr:
            print("| %s | %d | %.1f | %.0f |" % (case, n, rss / 1e6, per))
    n = args.memory_massif_size
    owners = owner_table(args.spam_ark, workdir, n, 2)
    if owners is None:
        print("memory by owner: valgrind not found (massif), skipped")
    else:
        total = sum(owners.values())
        print("\nheap at massif's peak by owner, gas-h3, N = %d, 2 steps (allocated bytes):" % n)
        state = 8 * 2 * 2  # bytes a particle holds in one state vector: 2D positions and velocities
        print("| owner | B/particle | in state vectors |")
        print("|---|---|---|")
        for name, b in sorted(owners.items(), key=lambda kv: -kv[1]):
            print("| %s | %.1f | %.1f |" % (name, b / n, b / n / state))
        print("| total heap | %.1f | |" % (total / n))
    rss_rows = [[case, str(n_), "%.1f" % (r / 1e6), "%.0f" % p] for case, rr in rows.items() for n_, r, p in rr]
    owner_rows = [] if owners is None else (
        [[name, "%.1f" % (b / n), "%.1f" % (b / n / state)] for name, b in sorted(owners.items(), key=lambda kv: -kv[1])]
        + [["total heap", "%.1f" % (total / n), ""]])
    return {"rss": {c: [{"n": n_, "peak_rss_bytes": r, "bytes_per_particle": p} for n_, r, p in rr]
                    for c, rr in rows.items()},
            "owners_bytes": owners, "owners_n": n,
            "tables": {"rss": {"columns": ["case", "N", "peak RSS (MB)", "B/particle (RSS − base)"], "rows": rss_rows},
                       "owners": {"columns": ["owner", "B/particle", "state vectors"], "rows": owner_rows}}}
