"""run_bench.py --memory: spam-ark's bytes per particle, the whole process and by owner.

Two measures, both independent of the machine's load:
  - (peak RSS - the 64-particle run's) / N at several N, for the gas-h3 case (the file
    scene on the expansion lattice, Dormand-Prince at a fixed step) and the default 2D
    expansion (options/expansion.opts at h = 3, its adaptive Dormand-Prince);
  - the resident bytes by owner of the gas-h3 run at two N: memory_owners.c, preloaded,
    records every heap block of 64 KiB or more with its call stack and counts its
    resident pages at the peak (a page only read, the kernel's zero page, does not
    count); each block goes to the owner of OWNERS that its call stack names first. The
    bytes per particle are the difference between the two N over the difference of N, so
    that what does not grow with N drops out; the peak RSS's own difference, over the
    same, is the check: what the owners do not account for (small blocks, libraries) is
    its last row.
"""

import os
import re
import subprocess
from collections import defaultdict
from pathlib import Path

from bench_common import REPO_ROOT, run_measured
from spam_driver import spam_cmd, spam_make_initial

MEMORY_SIZES = (16384, 65536, 262144)
BASELINE_NX = 8
MEMORY_STEPS = 4

OWNER_SIZES = (65536, 262144)
OWNER_STEPS = 4

# (owner, pattern on the functions of a block's call stack, innermost first): the first
# owner whose pattern one of the frames matches, frame by frame from the allocation
# outwards, owns the block. Function names only (the Release build has no line tables).
OWNERS = [
    ("integrator: Dormand-Prince stage derivatives (ERKStep, 7)", r"^erkStep_Init$"),
    ("integrator: interpolant (Hermite: y and f at the step's start)", r"^arkInterpInit"),
    ("integrator: work vectors (yn, fn; the error weights)", r"^(arkAllocVectors|arkResize)"),
    ("run loop: last good state (the last_good snapshot's)", r"^(SpamRun|SpamLoopRemakeVectors)$#VecDuplicate"),
    ("outputs: interpolated state, list kept over outputs", r"^(SpamRun|InterpolatedOutputs|SpamLoopRemakeVectors)$"),
    ("neighbour list: pair rows", r"^(Reserve|BuildRows|BuildRowsThreaded|SpamNeighboursPadList)$"),
    ("ghosts (images, halo)", r"Ghost|^GrowSlots$|[Hh]alo"),
    ("neighbour list: positions, references, shifts, cells, row starts", r"^SpamNeighbours"),
    ("pair fields (m, rho, P/rho^2, acc)", r"^SpamFields"),
    ("outputs: row order of the particles", r"^SpamSwarmIndexRows$"),
    ("swarm: state vector X (DMSwarm's state field)", r"^DMSwarm#state"),
    ("swarm: gid (pid, rank: zeros given back)", r"^DMSwarm"),
    ("outputs", r"Output|Summary|Snapshot|Diagnostic|Timeseries|Manifest|Csv|Json"),
]
UNTRACKED = "not in the owners (blocks under 64 KiB, libraries, stack): RSS minus the above"

# What the default method needs at minimum, bytes a particle by owner (2D: 32 bytes a
# state vector): Dormand-Prince at a fixed step needs the state (where the stages are
# summed), the step's start, its 7 stage derivatives (the 7th is the next step's first:
# FSAL) and, for a last_good snapshot after a failed step, the state before the step;
# no error weights. 10 state vectors; with error control also the weights and the error
# estimate.
MINIMUM = {
    "swarm: state vector X (DMSwarm's state field)": "32 (the state)",
    "integrator: Dormand-Prince stage derivatives (ERKStep, 7)": "224 (7 stages)",
    "integrator: work vectors (yn, fn; the error weights)": "32 (the step's start)",
    "integrator: interpolant (Hermite: y and f at the step's start)": "32 (y at the step's start)",
    "run loop: last good state (the last_good snapshot's)": "0 (the interpolant's y)",
    "neighbour list: pair rows": "4 a listed pair",
    "neighbour list: positions, references, shifts, cells, row starts": "48 (u, references; cells and starts)",
    "pair fields (m, rho, P/rho^2, acc)": "16 (acc; m, P/rho^2 one value each)",
    "swarm: gid (pid, rank: zeros given back)": "8 (gid)",
    "outputs: row order of the particles": "4",
}


def _owner_of(frames, is_state):
    """The owner of a block from its frames (function names, innermost first); is_state:
    the block holds a state vector's bytes a particle."""
    for name, pat in OWNERS:
        pat, _, cond = pat.partition("#")
        for k, f in enumerate(frames):
            if not re.search(pat, f):
                continue
            if cond == "VecDuplicate" and not any(g == "VecDuplicate" for g in frames[:k]):
                break
            if cond == "state" and not is_state:
                break
            return name
    return None


def _memory_owners_so(workdir):
    """bench/memory_owners.c built into workdir; None without a C compiler."""
    so = Path(workdir) / "memory_owners.so"
    src = Path(__file__).resolve().parent / "memory_owners.c"
    cc = os.environ.get("CC", "cc")
    p = subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", str(so), str(src), "-ldl", "-lpthread"],
                       capture_output=True, text=True)
    return so if p.returncode == 0 and so.exists() else None


def _symbolize(blocks):
    """Function names of every frame (addr2line, one call per module)."""
    by_module = defaultdict(set)
    for _, _, frames in blocks:
        for mod, addr in frames:
            by_module[mod].add(addr)
    names = {}
    for mod, addrs in by_module.items():
        addrs = sorted(addrs)
        p = subprocess.run(["addr2line", "-f", "-e", mod] + addrs, capture_output=True, text=True)
        out = p.stdout.splitlines()
        for k, a in enumerate(addrs):
            names[(mod, a)] = out[2 * k] if 2 * k < len(out) else "??"
    return [(size, res, [names[f] for f in frames]) for size, res, frames in blocks]


def _read_owners_file(path):
    blocks, peak = [], 0
    for line in Path(path).read_text().splitlines():
        w = line.split()
        if w[0] == "peak":
            peak = int(w[1])
        elif w[0] == "block":
            blocks.append((int(w[1]), int(w[2]), []))
        elif w[0] == "frame" and blocks:
            blocks[-1][2].append((w[1], w[2]))
    return peak, blocks


def _resident_by_owner(binary, workdir, so, n):
    """({owner: resident bytes}, peak RSS) of the gas-h3 run at N = n, under the preload."""
    outdir = workdir / ("mem_owners_%d" % n)
    cmd = _gas_cmd(binary, workdir, n, OWNER_STEPS, outdir)
    prefix = workdir / ("owners_%d" % n)
    for old in workdir.glob(prefix.name + ".*"):
        old.unlink()
    # env sets the preload for spam-ark alone (the launcher measures its peak RSS)
    env_cmd = ["env", "LD_PRELOAD=%s" % so, "SPAM_MEM_OUT=%s" % prefix] + [str(c) for c in cmd]
    rc, _, rss = run_measured(env_cmd, REPO_ROOT, workdir / ("owners_%d.log" % n))
    files = sorted(workdir.glob(prefix.name + ".*"))
    if rc != 0 or not files:
        raise RuntimeError("memory owner run failed (rc=%d): %s" % (rc, " ".join(map(str, cmd))))
    # one file per preloaded process: spam-ark's is the one with the largest peak
    peak, blocks = max((_read_owners_file(f) for f in files), key=lambda pb: pb[0])
    state_bytes = 8 * 2 * 2  # the gas in 2D: x, y, vx, vy
    owners = defaultdict(int)
    for size, res, frames in _symbolize(blocks):
        # the first frames are the preload's own hook and the allocator's entry
        name = _owner_of(frames, size // n == state_bytes and n > 0) or "other blocks of 64 KiB or more"
        owners[name] += res
    return dict(owners), rss


def owner_table(binary, workdir, sizes=OWNER_SIZES):
    """[(owner, bytes a particle)] from the resident bytes at two N, the untracked rest
    from the peak RSS; None without a C compiler or addr2line."""
    so = _memory_owners_so(workdir)
    if so is None or subprocess.run(["addr2line", "--version"], capture_output=True).returncode != 0:
        return None
    (o1, rss1), (o2, rss2) = (_resident_by_owner(binary, workdir, so, n) for n in sizes)
    dn = float(sizes[1] - sizes[0])
    names = sorted(set(o1) | set(o2), key=lambda k: -(o2.get(k, 0) - o1.get(k, 0)))
    rows = [(k, (o2.get(k, 0) - o1.get(k, 0)) / dn) for k in names]
    rows = [r for r in rows if abs(r[1]) >= 0.05]
    rss_per = (rss2 - rss1) / dn
    rows.append((UNTRACKED, rss_per - sum(b for _, b in rows)))
    return {"sizes": list(sizes), "rows": rows, "rss_per_particle": rss_per}


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
    owners = owner_table(args.spam_ark, workdir)
    if owners is None:
        print("memory by owner: no C compiler or addr2line, skipped")
        owner_rows = []
    else:
        n1, n2 = owners["sizes"]
        print("\nresident bytes a particle by owner, gas-h3, %d steps, (N = %d minus N = %d) / %d:" % (OWNER_STEPS, n2, n1, n2 - n1))
        print("| owner | B/particle | needed at least |")
        print("|---|---|---|")
        for name, b in owners["rows"]:
            print("| %s | %.1f | %s |" % (name, b, MINIMUM.get(name, "")))
        print("| peak RSS | %.1f | |" % owners["rss_per_particle"])
        owner_rows = ([[name, "%.1f" % b, MINIMUM.get(name, "")] for name, b in owners["rows"]]
                      + [["peak RSS (the process)", "%.1f" % owners["rss_per_particle"], ""]])
    rss_rows = [[case, str(n_), "%.1f" % (r / 1e6), "%.0f" % p] for case, rr in rows.items() for n_, r, p in rr]
    return {"rss": {c: [{"n": n_, "peak_rss_bytes": r, "bytes_per_particle": p} for n_, r, p in rr]
                    for c, rr in rows.items()},
            "owners": owners, "owners_n": owners["sizes"] if owners else None,
            "owners_rss_per_particle": owners["rss_per_particle"] if owners else None,
            "tables": {"rss": {"columns": ["case", "N", "peak RSS (MB)", "B/particle (RSS − base)"], "rows": rss_rows},
                       "owners": {"columns": ["owner", "B/particle", "needed at least (B/particle)"], "rows": owner_rows}}}
