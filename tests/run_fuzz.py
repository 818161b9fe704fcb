#!/usr/bin/python3
"""Fuzz corpus: hostile option values and particle files, each with its expected exit code.

Every case runs spam-ark in an empty directory of its own (-output_dir out, relative) and must
hold these invariants:
  - no crash: no signal, no exit code outside 0, 1, 2, 3, no sanitizer report on stderr
    ("runtime error:", "ERROR: AddressSanitizer", "LeakSanitizer"; tools/sanitize.sh also makes
    every report exit 86);
  - no hang: done within TIMEOUT seconds;
  - the exit code is one of the case's expected codes;
  - exit 2: exactly one line on stderr, starting "spam-ark: error: " (for an option case it
    names the option), and nothing written: the case directory is still empty;
  - exit 1: exactly one line on stderr;
  - exit 0 of a run: out/summary.json is strict JSON (no NaN/Infinity) with status "ok" (or
    "max_steps": exit 0 covers a run stopped by -ts_max_steps);
    exit 0 of -help/-version: nothing written; exit 3: summary.json strict, status "unstable".
The corpus (see tests/fuzz/cases.txt for the curated part):
  curated  the inputs found by an earlier review, with their codes;
  options  every option printed by `spam-ark -help petsc` (lines ending "(README)") with each value of
           HOSTILE and with no value, in a tiny run of a scene that reads it; of the values that
           PETSc's reader of the option's kind refuses alike for every option (SHARED: "abc" for
           a number, "1e300" for an integer, a name for a flag) and of the empty and the missing
           value, each option runs only its turn's, so each runs on several options of every
           kind (values_of). Expected: 2, except
           the values listed as valid in OPTION_TABLE (0, or a set where the outcome is not
           determined by the input alone: a physical run may also go unstable, exit 3). The
           rule: nan, inf, -inf, text, 7 values, 5000 digits, control bytes and an empty or
           missing value are bad input for every number; a count (int) refuses also -1 and 0
           where it must be positive, and fractions, 1e300 and 2147483648 (beyond PetscInt);
           a flag accepts 0, an empty and a missing value (true); a path accepts any name but
           the empty one (5000 bytes: exit 1 or 2); "0 means off/default" values run;
  files    mutations of a good 8x8 CSV (fixed seed): hostile fields, structure, bytes; the
           expected code comes from a strict reference reader (reference_expect); cases it
           cannot decide accept 0 or 2 and are counted as "open".
  snapshots  an HDF5 snapshot written by a tiny run, used as the file scene's input (fixed
           seed): bit flips anywhere (its checksum refuses each, exit 2), truncations, bytes
           appended, its checksum block zeroed or taken from another snapshot; and forged
           (tests/snapshot_forge.c edits a dataset and stamps the checksum again): ids stored
           as doubles (0.5 is refused, not truncated), as text, duplicated; a NaN position, a
           negative mass, no velocities, positions n x 2. Forged and control cases run at
           every stride.
  checkpoints  a tiny run's checkpoint forged entry by entry with its checksum made to match
           (tests/ck_forge.c; SPAM_CK_FORGE names it): counts, run status, intervals, times,
           steps, positions, missing entries, the list of files, shape and identity, and
           non-finite or negative values drawn into random places (fixed seed); and a
           FIFO, a directory and /dev/zero as -restart. Each runs in a copy of the run's
           directory: exit 2 must leave every file in it byte for byte as it was.
SPAM_FUZZ_STRIDE=k (tools/sanitize.sh: 48) runs every curated case, the forged and control snapshots, every 4th forged
checkpoint (with its control and special files) and every k-th generated case;
SPAM_FUZZ_SANITIZED_STRIDE=k (.ci/run: 48), in a run at stride 1, leaves out the cases that a run
at stride k takes, i.e. those tools/sanitize.sh runs under the sanitizers later in the same CI
run (it reads this stride too), where each is checked for the same verdict and for sanitizer
reports besides; the forged checkpoints' control runs in both. Each case then runs once per
CI run.
SPAM_FUZZ_ONLY=regex only the cases whose name matches it (a development aid).
Each case runs in a forked child of the fork server tests/fuzz_server.c (one per worker),
which calls spam-ark's own entry; SPAM_FUZZ_EXEC=1 starts spam-ark for each instead (as does
a build without the server). SPAM_FUZZ_VERDICTS=file writes each case's exit code and
problems, to compare the two.
"""
import concurrent.futures
import hashlib
import json
import os
import random
import re
import shutil
import subprocess
import sys
import threading
import time
import fork_server
from spamrun import Checks, arguments

a = arguments()
c = Checks()
w = os.path.abspath(a.workdir)
SPAM = os.path.abspath(a.spam_ark)
HERE = os.path.dirname(os.path.abspath(__file__))
TIMEOUT = 20
JOBS = 2
STRIDE = max(1, int(os.environ.get("SPAM_FUZZ_STRIDE", "1")))
# The stride of the sanitized run that takes the rest (docstring); only for a run of them all.
SANITIZED = max(1, int(os.environ.get("SPAM_FUZZ_SANITIZED_STRIDE", "1"))) if STRIDE == 1 else 1
ENV = dict(os.environ)
# OpenMPI's singleton start without its PMIx server: 0.1 s instead of 0.3-0.6 s per start.
ENV.setdefault("OMPI_MCA_ess_singleton_isolated", "1")
ENV.setdefault("OMPI_MCA_pml", "ob1")  # no UCX probe at each start (tests/CMakeLists.txt)
# Under ASan (tools/sanitize.sh) the cases run without LeakSanitizer's scan at exit, which
# was about three quarters of a case's time (0.94 s against 0.21 s for a refused option):
# the corpus looks for crashes, hangs, memory errors and undefined behaviour on hostile
# input; every other test under the sanitizers keeps leak checking on. ASan reads its
# flags left to right, so the last detect_leaks wins. Without the leak scan, the slow
# unwinding of every allocation's stack (tools/sanitize.sh: fast_unwind_on_malloc=0, so that
# the leak suppressions see OpenMPI's libraries) serves only the allocation and free stacks a
# report prints: the frame-pointer unwinder does (full through this project's code, built
# with frame pointers), and a case takes 0.63 CPU-s instead of 0.88 (12 starts, refused
# and tiny runs). What is detected is the same: the shadow memory finds the error, and the
# faulting access's own stack is still unwound in full (fast_unwind_on_fatal=0).
if "ASAN_OPTIONS" in ENV:
    ENV["ASAN_OPTIONS"] += ":detect_leaks=0:fast_unwind_on_malloc=1"
# Address space of one case (normal build): a reader that grows a buffer without bound on
# /dev/zero fails instead of taking the machine's memory. Not under ASan (its shadow memory
# is terabytes of address space).
LIMIT = [] if "ASAN_OPTIONS" in os.environ else [b"/bin/sh", b"-c", b'ulimit -v 4194304 && exec "$0" "$@"']
# The cases run in forked children of the fork server (tests/fuzz_server.c), one server per
# worker, unless SPAM_FUZZ_EXEC=1 or the server is not built: then each starts spam-ark.
# A start of spam-ark refused at option parsing took 0.16-0.19 CPU-s, much of it the dynamic
# loader binding the symbols of the hundred-odd shared libraries PETSc brings in; in the
# server's child, loaded once, 0.09-0.10 (20 of each, loaded machine). The whole corpus at
# CI's stride: 318 CPU-s, 159 through the server (user+sys), the same verdicts case by case.
# The child runs the program's entry (src/app/program.c) with the case's argv, directory,
# environment, address-space limit (the same bytes as LIMIT's) and stdin, and exits with its
# code; the server reports an exit code, a signal or a timeout, which the verdicts below
# read as they read a process's. Those that need spam-ark itself keep starting it (exec_only).
SERVER = os.environ.get("SPAM_FUZZ_SERVER") or os.path.join(os.path.dirname(SPAM), "tests", "fuzz_server")
FORK = os.environ.get("SPAM_FUZZ_EXEC") != "1" and os.access(SERVER, os.X_OK)
if not FORK and os.environ.get("SPAM_FUZZ_EXEC") != "1":
    print(f"note: no fork server at {SERVER}: every case starts spam-ark")
LIMIT_BYTES = 4194304 * 1024 if LIMIT else 0


class Server(fork_server.Server):
    """A fork server (tests/fuzz_server.c, tests/fork_server.py) of one worker thread; run()
    sends it a case."""

    def __init__(self):
        super().__init__(SERVER, SPAM, ENV, w)

    def run(self, args, cwd, env, err_path, timeout=TIMEOUT):
        """The run's exit code (negative: the signal that ended it) or "timeout"."""
        return super().run(args, cwd, env, os.devnull, err_path, timeout, LIMIT_BYTES)


SANITIZER = ("runtime error:", "ERROR: AddressSanitizer", "LeakSanitizer", "ERROR: UndefinedBehaviorSanitizer")
FILES = os.path.join(w, "files")
os.makedirs(FILES)

# ---------------------------------------------------------------- tiny runs (contexts) ----
TINY = [("-ts_max_time", "0.5"), ("-ts_max_steps", "200"), ("-snapshot_interval", "0"), ("-output_interval", "0.25")]
GOOD_ROWS = [(i + 0.5, j + 0.5, 0.0, 0.0) for j in range(8) for i in range(8)]


def fpath(name, data):
    """Writes bytes to a file of the corpus (outside every case directory); returns its path."""
    p = os.path.join(FILES, name)
    with open(p, "wb") as f:
        f.write(data)
    return p


def csv_bytes(rows, header="x,y,vx,vy"):
    return (header + "\n" + "".join(",".join(repr(float(v)) if isinstance(v, float) else str(v) for v in r) + "\n" for r in rows)).encode()


GOOD = csv_bytes(GOOD_ROWS)
GOOD_PATH = fpath("good.csv", GOOD)
CONTEXTS = {
    "E": [("-expansion_n", "4"), ("-h", "1.5")] + TINY,
    "F": [("-scene", "file"), ("-file_path", GOOD_PATH), ("-box_len", "8,8"), ("-h", "1.5")] + TINY,
    "C": [("-scene", "chain"), ("-dim", "1"), ("-chain_n", "8")] + TINY,
    "P": [("-scene", "planewave"), ("-planewave_nx", "6"), ("-planewave_ny", "8")] + TINY,
    "PG": [("-scene", "planewave"), ("-planewave_nx", "6"), ("-planewave_ny", "8"), ("-material", "gas")] + TINY,
    "PR2": [("-scene", "planewave"), ("-planewave_nx", "6"), ("-planewave_ny", "8"), ("-coordinates", "R2")] + TINY,
    "PAV": [("-scene", "planewave"), ("-planewave_nx", "6"), ("-planewave_ny", "8"), ("-viscosity", "monaghan")] + TINY,
    "PTI": [("-scene", "planewave"), ("-planewave_nx", "6"), ("-planewave_ny", "8"), ("-angmom", "Ti")] + TINY,
    "R": [("-scene", "rotor"), ("-rotor_n", "1")] + TINY,
    "RP": [("-scene", "rotor-pair"), ("-rotor_n", "1")] + TINY,
    "RM": [("-scene", "rotor-md"), ("-rotor_n", "1")] + TINY,
    "T": [("-scene", "tensile"), ("-tensile_nx", "6"), ("-tensile_ny", "8")] + TINY,
    "CV": [("-expansion_n", "4"), ("-h", "1.5"), ("-ts_type", "cvode")] + TINY,
    "RK": [("-expansion_n", "4"), ("-h", "1.5"), ("-ts_type", "rk")] + TINY,
    "BS": [("-expansion_n", "4"), ("-h", "1.5"), ("-ts_type", "basicsymplectic")] + TINY,
    "CONV": [("-scene", "convection"), ("-convection_nx", "6"), ("-convection_ny", "4"), ("-h", "1.5")] + TINY,
    "CO": [("-scene", "couette"), ("-couette_n", "4"), ("-h", "1.5")] + TINY,
    "PO": [("-scene", "poiseuille"), ("-poiseuille_n", "4"), ("-h", "1.5")] + TINY,
    "CAV": [("-scene", "cavity"), ("-cavity_n", "4"), ("-h", "1.5")] + TINY,
    # snapshots on (at t = 0 and 0.5): the grid fields are written at the snapshot times
    "EG": [("-expansion_n", "4"), ("-h", "1.5")] + TINY[:2] + [("-snapshot_interval", "0.5"), ("-output_interval", "0.25")],
    "SOD": [("-scene", "sod"), ("-dim", "1"), ("-sod_n", "10")] + TINY,
    "SOD2": [("-scene", "sod"), ("-dim", "2"), ("-sod_n", "8"), ("-sod_width", "4")] + TINY,
    "SED": [("-scene", "sedov"), ("-sedov_n", "16")] + TINY,
    "GR": [("-scene", "gresho"), ("-gresho_n", "8")] + TINY,
    "TG": [("-scene", "taylor-green"), ("-taylorgreen_n", "8")] + TINY,
    "HM": [("-scene", "heat-mode"), ("-heatmode_n", "8"), ("-heatmode_ny", "8")] + TINY,
}


def argv(context, extra):
    """The context's options, those named in extra replaced; extra = [(option, value or None)];
    a None value (the option given without a value) goes last so that nothing follows it."""
    named = {o for o, _ in extra}
    out = [x for o, v in CONTEXTS[context] if o not in named for x in (o, v)]
    out += [x for o, v in extra if v is not None for x in (o, v)]
    out += [o for o, v in extra if v is None]
    return out


class Case:
    def __init__(self, category, name, args, expect, option=None, outdir="out", run=True):
        self.category, self.name, self.args = category, name, args
        self.expect = set(expect)
        self.option = option      # an option case: its refusal must name the option
        self.outdir = outdir      # where summary.json is expected (relative to the case directory)
        self.run = run            # False: -help/-version, exit 0 writes nothing


cases = []

# ----------------------------------------------------------------------- curated (i) ------
# tests/fuzz/cases.txt: "<expected codes> | <context> | <arguments>"; @name stands for a corpus
# file built below (CURATED_FILES), @good for the good 8x8 CSV.
LONG_LINE = b"x,y,vx,vy\n" + b"0.5" + b"0" * 5000 + b",0.5,0,0\n" + GOOD.split(b"\n", 1)[1]
CURATED_FILES = {
    "good": GOOD,
    "bad_number": b"x,y,vx,vy\n1,2,0,0\n1,two,0,0\n",
    "space_field": b"x,y,vx,vy\n0.5,0.5,0,0\n1.5, ,0,0\n",
    "tab_field": b"x,y,vx,vy\n0.5,0.5,0,0\n1.5,\t,0,0\n",
    "empty_field": b"x,y,vx,vy\n0.5,0.5,0,0\n1.5,,0,0\n",
    "long_line": LONG_LINE,
    "long_line_4096": b"x,y,vx,vy\n" + b"0.5" + b"0" * 4093 + b",0.5,0,0\n",
    "long_comment": b"x,y,vx,vy\n# " + b"c" * 4100 + b"1.5,2.5,0,0\n" + GOOD.split(b"\n", 1)[1],
    "nul_in_field": b"x,y,vx,vy\n0.5,0.5,0,0\n1.\x005,2.5,0,0\n",
    "nul_line_start": b"x,y,vx,vy\n0.5,0.5,0,0\n\x001.5,2.5,0,0\n",
    "nul_after_row": b"x,y,vx,vy\n0.5,0.5,0,0\x00\n1.5,2.5,0,0\n",
    "outside_high": csv_bytes(GOOD_ROWS[:-1] + [(9.5, 7.5, 0.0, 0.0)]),
    "outside_low": csv_bytes([(-0.5, 0.5, 0.0, 0.0)] + GOOD_ROWS[1:]),
    "outside_64": csv_bytes([(70.0, 0.5, 0.0, 0.0)] + GOOD_ROWS[1:]),
    "coord_1e15": csv_bytes([(1e15, 0.5, 0.0, 0.0)] + GOOD_ROWS[1:]),
    "coord_m1e15": csv_bytes([(-1e15, 0.5, 0.0, 0.0)] + GOOD_ROWS[1:]),
    "binary_field": b"x,y,vx,vy\n0.5,0.5,0,0\n\x01\xff,2.5,0,0\n",
    "unequal_mass": b"x,y,vx,vy,m\n1,2,0,0,1\n3,2,0,0,2\n",
    "header_only": b"x,y,vx,vy\n",
    "empty": b"",
    "options_garbage": b"garbage here\n",
    "options_binary": b"\xff\xfe-\x01h\n",
    "subnormal_position": csv_bytes([(4.9e-324, 0.5, 0.0, 0.0)] + GOOD_ROWS[1:]),
}
CURATED_PATHS = {k: fpath("curated_" + k, v) for k, v in CURATED_FILES.items()}
FIFO = os.path.join(FILES, "fifo.csv")
os.mkfifo(FIFO)
CURATED_PATHS.update(fifo=FIFO, dir=FILES, missing=os.path.join(FILES, "missing.csv"), devnull="/dev/null", devzero="/dev/zero")


def curated():
    path = os.path.join(HERE, "fuzz", "cases.txt")
    for n, line in enumerate(open(path, encoding="utf-8")):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = [s.strip() for s in line.split("|")]
        codes, context, rest = parts[:3]
        needle = parts[3] if len(parts) > 3 else None
        words = [CURATED_PATHS[x[1:]] if x.startswith("@") else x for x in rest.split()]
        run = not any(x in ("-help", "--help", "-version", "--version") for x in words)
        pairs, k = [], 0
        while k < len(words):
            if k + 1 < len(words) and not re.match(r"^-+[A-Za-z]", words[k + 1]):
                pairs.append((words[k], words[k + 1]))
                k += 2
            else:
                pairs.append((words[k], None))
                k += 1
        if context == "-":
            args = [x for o, v in pairs for x in ((o,) if v is None else (o, v))]
        else:
            args = argv(context, pairs)
        outdir = next((v for o, v in pairs if o == "-output_dir"), "out")
        if run and not any(o == "-output_dir" for o, _ in pairs):
            args += ["-output_dir", "out"]
        cases.append(Case("curated", f"cases.txt:{n + 1} [{context}] {rest}", args,
                          {int(x) for x in codes.split(",")}, needle, outdir, run))


if SANITIZED == 1:
    curated()

# ---------------------------------------------------------------------- options (ii) ------
HOSTILE = ["nan", "inf", "-inf", "-1", "0", "1e-300", "4.9e-324", "1e300", "2147483648", "", "abc",
           "1,2,3,4,5,6,7", "9" * 5000, b"\x01\xff"]
HNAME = {"9" * 5000: "9x5000", b"\x01\xff": "\\x01\\xff", "": "''"}
BOOL = {"0": {0}, "": {0}, None: {0}}          # a flag without a value is true
PATH = {v: {0} for v in HOSTILE if v not in ("", "9" * 5000)}    # "-inf" is a name too
PATH.update({"9" * 5000: {1, 2}})               # a 5000-byte name: ENAMETOOLONG
O023, O02, O0, O03, O23 = {0, 2, 3}, {0, 2}, {0}, {0, 3}, {2, 3}


SAME = object()


def real(m1=None, zero=None, tiny=None, big=None, i31=None, sub=SAME):
    """Valid codes of a real option's numeric values (None: refused, exit 2). A subnormal
    (4.9e-324) counts as tiny unless sub says otherwise: coefficients whose checks refuse
    subnormals as "too small" (run_options.c, solid_options.c CheckRange) have sub=None."""
    t = {"-1": m1, "0": zero, "1e-300": tiny, "4.9e-324": tiny if sub is SAME else sub, "1e300": big, "2147483648": i31}
    return {k: v for k, v in t.items() if v is not None}


# option -> (context, {value: expected codes}); values not listed: exit 2.
OPTION_TABLE = {
    "-dim": ("E", {}), "-threads": ("E", {}), "-expansion_n": ("E", {}), "-chain_n": ("C", {}),
    "-planewave_nx": ("P", {}), "-planewave_ny": ("P", {}), "-tensile_nx": ("T", {}), "-tensile_ny": ("T", {}),
    "-cvode_max_order": ("CV", {}), "-rotor_n": ("R", {"0": O02}),
    "-expansion_seed": ("E", {"-1": O02, "0": O0}),
    "-ts_max_steps": ("E", {"0": O02}),
    "-h": ("E", {}),
    "-mass": ("E", real(tiny=O02, big=O23, i31=O023)),
    "-neighbour_skin": ("E", real(zero=O02, tiny=O02)),
    "-eos_gamma": ("E", real(big=O23, i31=O023)),
    "-eos_kappa": ("E", real(tiny=O02, big=O23, i31=O023)),
    "-scene_translate": ("E", real(m1=O0, zero=O0, tiny=O0, i31=O02)),
    "-expansion_amplitude": ("E", real(m1=O02, zero=O0, tiny=O0)),
    "-box_lo": ("F", real(zero=O0, tiny=O0)),
    "-gravity": ("E", real(m1=O0, zero=O0, tiny=O0, i31=O023)),  # |g| up to 1e100; 2^31 may blow up
    "-kernel": ("E", {}), "-periodic_images": ("E", {}),
    "-wall_ylo": ("E", {}), "-wall_ylo_velocity": ("E", {}), "-wall_ylo_temperature": ("E", {}),
    "-box_len": ("F", real(i31=O02)),
    "-periodic": ("F", {"0": O0}),
    "-file_path": ("F", {}),
    "-chain_amplitude": ("C", real(m1=O02, zero=O0, tiny=O0, big=O23, i31=O023)),
    "-spring_k": ("C", real(zero=O02, tiny=O02, big=O23, i31=O023)),
    "-planewave_amplitude": ("P", real(m1=O023, zero=O0, tiny=O0, big=O23, i31=O023)),
    "-planewave_mode": ("P", {}), "-material": ("P", {}), "-density": ("P", {}), "-density_initial": ("P", {}),
    "-density_mean": ("P", {}), "-coordinates": ("P", {}), "-angmom": ("P", {}), "-angmom_scope": ("PTI", {}),
    "-viscosity": ("P", {}), "-scene": ("E", {}), "-arkode_table": ("E", {}), "-arkode_adapt": ("E", {}),
    "-gas_gamma": ("PG", real(big=O23, i31=O023)),
    "-gas_e0": ("PG", real(zero=O02, tiny=O02, big=O23, i31=O023)),
    "-viscosity_shear": ("PG", real(zero=O0, tiny=O0, big=O23, i31=O023, sub=None)),
    "-viscosity_bulk": ("PG", real(zero=O0, tiny=O0, big=O23, i31=O023, sub=None)),
    # big: the flow scheme (a conducting gas's default) keeps this transverse wave's e exactly
    # uniform, so 1e300 times a zero gradient runs to the end (0); the plain scheme's work
    # term makes a gradient and the run ends unstable (3).
    "-conductivity": ("PG", real(zero=O0, tiny=O0, big=O023, i31=O023, sub=None)),
    "-solid_lambda": ("P", real(m1=O023, zero=O02, tiny=O02, big=O23, i31=O023)),
    "-solid_eta": ("P", real(zero=O02, tiny=O02, big=O23, i31=O023)),
    "-xsph_eps": ("PR2", real(zero=O0, tiny=O0, big=O23, i31=O023, sub=None)),
    "-viscosity_alpha": ("PAV", real(zero=O0, tiny=O0, big=O23, i31=O023, sub=None)),
    "-viscosity_beta": ("PAV", real(zero=O0, tiny=O0, big=O23, i31=O023, sub=None)),
    "-closest_approach": ("P", real(zero=O0, tiny=O0, big=O02, i31=O02, sub=None)),
    "-rotor_speed": ("R", real(m1=O02, zero=O02, big=O23, i31=O023)),  # from 1e-6 to 10
    "-rotor_gap": ("RP", real(big=O02, i31=O02)),
    "-spring_range": ("RM", real(zero=O02, tiny=O02, big=O02, i31=O02)),
    "-tensile_stress": ("T", real(m1=O03, zero=O0, tiny=O0, big=O23, i31=O023)),
    "-tensile_kick": ("T", real(m1=O03, zero=O0, tiny=O0, big=O23, i31=O023)),
    "-ts_max_time": ("E", real(zero=O0, big=O02, i31=O02)),  # 0: the initial state only
    "-ts_dt": ("E", real(zero=O0, tiny=O023, big=O02, i31=O02)),
    "-ts_rtol": ("E", real(tiny=O023, big=O02, i31=O02)),
    "-ts_atol": ("E", real(zero=O02, tiny=O023, big=O02, i31=O02)),
    "-step_cfl": ("E", real(zero=O0, big=O02, i31=O02)),
    "-step_force": ("E", real(zero=O0, big=O02, i31=O02)),
    "-unstable_dt_min": ("E", real(zero=O0, tiny=O0, big=O023, i31=O023, sub=None)),
    "-unstable_energy_growth": ("E", real(zero=O0, tiny=O23, big=O0, i31=O0)),
    "-arkode_fixed_step": ("E", real(zero=O0, tiny=O02, big=O023, i31=O023)),
    "-arkode_safety": ("E", real(zero=O0, tiny=O023, big=O023, i31=O023)),
    "-arkode_max_growth": ("E", real(zero=O0, tiny=O023, big=O023, i31=O023)),
    "-arkode_max_first_growth": ("E", real(zero=O0, tiny=O023, big=O023, i31=O023)),
    "-arkode_max_efail_growth": ("E", real(zero=O0, tiny=O023, big=O023, i31=O023)),
    "-arkode_adapt_params": ("E", {k: O023 for k in ("-1", "0", "1e-300", "4.9e-324", "1e300", "2147483648")}),
    "-output_interval": ("E", real(zero=O0, big=O02, i31=O02)),
    "-snapshot_interval": ("E", real(zero=O0, big=O02, i31=O02)),
    "-diag_grid_spacing": ("E", real(zero=O0, big=O02, i31=O02)),
    "-grid_interval": ("EG", real(zero=O0, big=O0, i31=O0)),  # 1e300: one point per direction
    "-snapshot_max": ("E", {}),
    # the Rayleigh-Benard cell: counts, Ra, Pr and g have finite ranges (every hostile value out)
    "-convection_nx": ("CONV", {}), "-convection_ny": ("CONV", {}), "-convection_ra": ("CONV", {"2147483648": O0}),
    "-convection_prandtl": ("CONV", {}), "-convection_g": ("CONV", {}),
    "-convection_amplitude": ("CONV", real(zero=O0, tiny=O0)),
    "-convection_seed": ("CONV", {"-1": O02, "0": O0}),
    "-sod_n": ("SOD", {}), "-sod_width": ("SOD2", {}), "-sedov_n": ("SED", {}),
    "-sod_length": ("SOD", real()),
    "-sedov_energy": ("SED", real(i31=O03)),  # from 1e-100 to 1e100; 2^31 blows the box apart
    "-output_dir": ("E", PATH), "-initial_csv": ("E", PATH), "-final_csv": ("E", PATH),
    # the smooth flows with exact answers
    "-gresho_n": ("GR", {}), "-taylorgreen_n": ("TG", {}), "-heatmode_n": ("HM", {}), "-heatmode_ny": ("HM", {}),
    "-gresho_p0": ("GR", real(i31=O023)),  # from 1e-100 to 1e100; 2^31 may blow up or hit the step limit
    "-taylorgreen_amplitude": ("TG", real(m1=O0, zero=O0, tiny=O0, i31=O023)),  # |U| up to 1e100
    "-heatmode_eps": ("HM", real(zero=O0, tiny=O0)),  # |eps| < 1
    # the shear channels: n >= max(2, h); nx 0 is automatic; |speed| below the sound speed (1.41)
    "-couette_n": ("CO", {}), "-couette_nx": ("CO", {"0": O0}), "-couette_start": ("CO", {}),
    "-couette_speed": ("CO", real(m1=O0, zero=O0, tiny=O0)),
    "-poiseuille_n": ("PO", {}), "-poiseuille_nx": ("PO", {"0": O0}), "-poiseuille_start": ("PO", {}),
    "-poiseuille_speed": ("PO", real(m1=O0, zero=O0, tiny=O0)),
    # the lid-driven cavity: n >= max(2, h); U from 1e-6 to 1e6, Re from 1e-6 to 1e6, Mach in
    # [1e-3, 1): every hostile value out
    "-cavity_n": ("CAV", {}), "-cavity_lid_velocity": ("CAV", {}), "-cavity_re": ("CAV", {}), "-cavity_mach": ("CAV", {}),
    # -error_norm: rms or max, names only (every hostile value refused)
    "-error_norm": ("E", {}),
    # checkpoints (1e300: none before the end; 1e-300: too many) and
    # restart (no hostile value names a checkpoint: every one refused)
    "-checkpoint_interval": ("E", real(zero=O0, big=O0, i31=O0)),
    "-checkpoint_wall": ("E", real(zero=O0, tiny=O0, big=O0, i31=O0, sub=None)),
    "-restart": ("E", {}),
    # migrations apply to runs on several ranks; the fuzz corpus runs on one, where
    # every value is refused (irrelevant, or not a count); run_ranks covers several ranks
    "-migrate_interval": ("E", {}),
}
for flag in ("-expansion_perturb_velocities", "-arkode_classic_weights", "-snapshot_hdf5", "-snapshot_csv",
             "-monitor", "-quiet", "-diag_entropy", "-sort_particles", "-output_overwrite"):
    OPTION_TABLE[flag] = ("E", BOOL)
# Outputs stop the integrator only when asked; SUNDIALS' statistics table
# (the expansion context runs arkode, for which -sundials_stats is relevant).
for flag in ("-output_stop", "-sundials_stats"):
    OPTION_TABLE[flag] = ("E", BOOL)
# Canonical pair sums for the isentropic gas (the expansion context's model).
OPTION_TABLE["-reproducible"] = ("E", BOOL)


def help_options():
    """The options -help lists, each with the kind of PETSc reader its line shows (PETSc prints
    each reader's line in its own form): bool "-x: <FALSE : FALSE>", int "-x <now 2 : formerly 2>",
    string "-x <now lucy : formerly lucy>", real "-x <2. : 2.>"; anything else (the lists,
    "-x <0.>:") is None."""
    p = subprocess.run([SPAM, "-help", "petsc"], capture_output=True, text=True, env=ENV, timeout=60, cwd=w)
    kinds = {}
    for name, rest in re.findall(r"^ +(-[a-z0-9_]+)([ :].*)\(README\)$", p.stdout, re.M):
        kind = None
        if rest.startswith(": <"):
            kind = "bool"
        elif re.match(r" <now -?\d+ : formerly -?\d+>", rest):
            kind = "int"
        elif re.match(r" <now [^>]* : formerly [^>]*>", rest):
            kind = "string"
        elif re.match(r" <[-+0-9.e]+ : [-+0-9.e]+>", rest):
            kind = "real"
        kinds.setdefault(name, kind)
    return kinds


KINDS = help_options()
OPTIONS = list(KINDS)
c.check(len(OPTIONS) >= 80, f"-help lists {len(OPTIONS)} spam-ark options (lines ending '(README)')")
# A new option missing from OPTION_TABLE is fuzzed in the expansion run, every value refused.
unknown = [o for o in OPTIONS if o not in OPTION_TABLE]
if unknown:
    print(f"note: options not in OPTION_TABLE (expansion context, every value refused): {unknown}")
# The six faces' wall options share one parser (core/walls.c) and one relevance rule
# (option_use.c WallRelevant): the ylo face's three stand for all of them.
SAME_PARSER = {f"-wall_{f}{s}" for f in ("xlo", "xhi", "yhi", "zlo", "zhi") for s in ("", "_velocity", "_temperature")}
# Values that PETSc's reader of the option's kind refuses before the option's own code sees
# them (the syntax of a number, an integer, a flag; a name that is none of a choice's), and the
# empty and the missing value, which SpamOptionsCheckValues refuses for every option alike.
# Each such value takes the same path for every option of the kind, the option's part being
# only that the refusal names it: every option runs KEEP[kind] of them, taken in turn along
# the options of the kind, so that each value still runs on several options of every kind.
# Every other value (the range
# checks, an option's own parsing, the valid ones) runs on every option. The file names
# (-file_path, -restart and the outputs) and the lists keep every value: each value is
# another file, or another list element.
MISSING = ["", None]
SHARED = {"bool": ["nan", "inf", "-inf", "-1", "1e-300", "4.9e-324", "1e300", "2147483648", "abc", "1,2,3,4,5,6,7", "9" * 5000, b"\x01\xff"],
          "int": ["nan", "inf", "-inf", "1e-300", "4.9e-324", "1e300", "abc", "1,2,3,4,5,6,7", b"\x01\xff"],
          "real": ["abc", "1,2,3,4,5,6,7", b"\x01\xff"],
          "string": ["nan", "inf", "-inf", "-1", "0", "1e-300", "4.9e-324", "1e300", "2147483648", "abc", "1,2,3,4,5,6,7", "9" * 5000, b"\x01\xff"]}
KEEP = {"bool": 2, "int": 2, "real": 1, "string": 2}
FILE_NAMES = {"-file_path", "-restart", "-output_dir", "-initial_csv", "-final_csv"}
turn = {}


def values_of(opt, valid):
    """The values option opt runs: every value of HOSTILE and the missing one, but of each
    shared class (SHARED[kind], MISSING) refused alike only its turn's."""
    kind = KINDS.get(opt)
    if kind not in SHARED or opt in FILE_NAMES:
        return HOSTILE + [None]
    k = turn[kind] = turn.get(kind, -1) + 1
    skip = set()
    for group, keep in ((SHARED[kind], KEEP[kind]), (MISSING, 1)):
        refused = [v for v in group if valid.get(v, {2}) == {2}]
        chosen = {refused[(k * keep + j) % len(refused)] for j in range(min(keep, len(refused)))} if refused else set()
        skip |= {v for v in refused if v not in chosen}
    return [v for v in HOSTILE + [None] if v not in skip]


generated = []
for opt in OPTIONS:
    if opt in SAME_PARSER:
        continue
    context, valid = OPTION_TABLE.get(opt, ("E", {}))
    for value in values_of(opt, valid):
        expect = valid.get(value, {2})
        shown = HNAME.get(value, value) if value is not None else "(no value)"
        args = argv(context, [(opt, value)])
        outdir = "out"
        if opt == "-output_dir" and value is not None:
            outdir = os.fsdecode(value)
        elif opt != "-output_dir":
            args += ["-output_dir", "out"]
        generated.append(Case("options", f"{opt} {shown} [{context}]", args, expect, opt, outdir))

# ------------------------------------------------------------------------ files (iii) ------
HEX = re.compile(r"^[+-]?0[xX][0-9a-fA-F]*\.?[0-9a-fA-F]*([pP][+-]?\d+)?$")
NUM = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def reference_expect(data, box=8.0, header="x,y,vx,vy"):
    """Expected codes of a 2D particle file in the box [0, 8)^2 by a strict reader: {2} for a
    malformed or out-of-range line, {0} for a clean file, {0, 2} where the contract leaves it
    open (blank lines, comments, surrounding spaces, an underflow to 0, a position on the edge)."""
    lines = data.split(b"\n")
    if lines and lines[-1] == b"":
        lines.pop()
    # The header is the first line that is not blank or a comment; its names may have
    # spaces or tabs around them (particle_header.c).
    leading = False
    while lines and (lines[0].rstrip(b"\r ") == b"" or lines[0].startswith(b"#")):
        if len(lines[0]) > 4000 or b"\0" in lines[0]:
            return {2}
        lines.pop(0)
        leading = True
    if not lines or b",".join(n.strip(b" \t") for n in lines[0].rstrip(b"\r").split(b",")) != header.encode():
        return {2}
    open_ = leading or lines[0] != header.encode()
    rows, fast = 0, False
    ncol = len(header.split(","))
    for raw in lines[1:]:
        if len(raw) > 4000 or b"\0" in raw:
            return {2}
        if raw.strip() == b"":
            open_ = True
            continue
        if raw.startswith(b"#"):
            open_ = True
            continue
        try:
            line = raw.decode("ascii")
        except UnicodeDecodeError:
            return {2}
        if line.endswith("\r"):
            line, open_ = line[:-1], True
        fields = line.split(",")
        if len(fields) != ncol:
            return {2}
        values = []
        for f in fields:
            s = f.strip()
            if not s:
                return {2}
            if not NUM.match(s):
                if HEX.match(s):
                    open_ = True  # strtod reads C99 hex floats; the contract does not say
                    continue
                if any(ch not in "0123456789+-.eE \t" for ch in f):
                    return {2}
                if s == f:
                    return {2}
                open_ = True
                continue
            if s != f:
                open_ = True
            v = float(s)
            if v in (float("inf"), float("-inf")):
                return {2}
            if v == 0.0 and any(ch in "123456789" for ch in s.split("e")[0].split("E")[0]):
                open_ = True  # a nonzero literal that underflows to 0
            values.append(v)
        if len(values) == ncol:
            x, y = values[0], values[1]
            if not (0.0 <= x <= box and 0.0 <= y <= box):
                return {2}
            if x == box or y == box:
                open_ = True
            if max(abs(values[2]), abs(values[3])) > 1e3:
                fast = True   # a physical blow-up is a result (exit 3), not bad input
        rows += 1
    if rows == 0:
        return {2}
    return ({0, 2} if open_ else {0}) | ({3} if fast else set())


rng = random.Random(13)
file_cases = []


def add_file(name, data, expect=None, extra=()):
    expect = reference_expect(data) if expect is None else set(expect)
    path = fpath(f"m{len(file_cases):04d}.csv", data)
    file_cases.append(Case("files", name, argv("F", [("-file_path", path)] + list(extra)) + ["-output_dir", "out"], expect))


good_lines = GOOD.split(b"\n")[:-1]


def with_field(row, col, token):
    lines = list(good_lines)
    fields = lines[1 + row].split(b",")
    fields[col] = token
    lines[1 + row] = b",".join(fields)
    return b"\n".join(lines) + b"\n"


TOKENS = [b"", b" ", b"\t", b"  \t ", b"nan", b"NaN", b"-nan", b"inf", b"-inf", b"Infinity", b"1e400", b"-1e400",
          b"1e15", b"-1e15", b"1e308", b"0x1p1", b"0x1.8p1", b"1e-400", b"4.9e-324", b"2.2e-308", b"abc", b"1..2",
          b"--1", b"+", b"-", b".", b"1e", b"1e+", b"e5", b"1,5", b"1;5", b"\xd9\xa1", b"\xef\xbb\xbf1", b"1 2",
          b" 1.5", b"1.5 ", b"+1.5", b"1.5e0", b"00001.5", b"\x01", b"\xff", b"1\x7f", b"'1'", b"\"1\"", b"1_0"]
for tok in TOKENS:
    for col in range(4):
        row = rng.randrange(64)
        add_file(f"field {col + 1} of row {row + 2} = {tok!r}", with_field(row, col, tok))
# positions out of the box, on its edges, huge velocities
for x in (8.0, 8.5, -0.5, -1e-300, 70.0, 1e15, -1e15, 1e300, 7.999999999999999, 0.0):
    for col in (0, 1):
        add_file(f"position {col + 1} = {x!r}", with_field(rng.randrange(64), col, repr(x).encode()))
for v in (1e3, 1e10, 1e300, -1e300, 4.9e-324):
    add_file(f"velocity = {v!r}", with_field(rng.randrange(64), 2, repr(v).encode()),
             {0, 2, 3} if abs(v) > 1 else {0})
# structure
body = good_lines[1:]
structural = [
    # A header-less file is the legacy x,y,vx,vy layout; a header names columns in any order.
    ("no header", b"\n".join(body) + b"\n", {0}),
    ("header y,x,vx,vy", b"y,x,vx,vy\n" + b"\n".join(body) + b"\n", {0}),
    ("header X,Y,VX,VY", b"X,Y,VX,VY\n" + b"\n".join(body) + b"\n", {2}),
    ("header with extra column", b"x,y,vx,vy,q\n" + b"\n".join(body) + b"\n", {2}),
    ("header with spaces", b"x, y, vx, vy\n" + b"\n".join(body) + b"\n", {0, 2}),
    ("3D header in 2D", b"x,y,z,vx,vy,vz\n" + b"\n".join(body) + b"\n", {2}),
    ("header only", b"x,y,vx,vy\n", {2}),
    ("empty file", b"", {2}),
    ("only newlines", b"\n\n\n", {2}),
    ("no final newline", GOOD[:-1], {0}),
    ("CRLF", GOOD.replace(b"\n", b"\r\n"), {0, 2}),
    ("CR only", GOOD.replace(b"\n", b"\r"), {2}),
    ("BOM", b"\xef\xbb\xbf" + GOOD, {0, 2}),
    ("UTF-16", GOOD.decode().encode("utf-16"), {2}),
    ("blank line inside", b"\n".join(good_lines[:10] + [b""] + good_lines[10:]) + b"\n", {0, 2}),
    ("comment line inside", b"\n".join(good_lines[:10] + [b"# note"] + good_lines[10:]) + b"\n", {0, 2}),
    ("long comment 5000", b"\n".join(good_lines[:10] + [b"# " + b"c" * 5000] + good_lines[10:]) + b"\n", {2}),
    ("long comment 4094 + row", b"\n".join(good_lines[:10] + [b"# " + b"c" * 4093 + b"0.5,0.5,0,0"] + good_lines[10:]) + b"\n", {2}),
    ("line of 4095 bytes", b"\n".join(good_lines[:10] + [b"0.5" + b"0" * 4084 + b",0.5,0,0"] + good_lines[11:]) + b"\n", {0, 2}),
    ("line of 4096 bytes", b"\n".join(good_lines[:10] + [b"0.5" + b"0" * 4085 + b",0.5,0,0"] + good_lines[11:]) + b"\n", {2}),
    ("line of 5000 bytes", b"\n".join(good_lines[:10] + [b"0.5" + b"0" * 4989 + b",0.5,0,0"] + good_lines[11:]) + b"\n", {2}),
    ("line of 100000 bytes", b"\n".join(good_lines[:10] + [b"0.5" + b"0" * 99989 + b",0.5,0,0"] + good_lines[11:]) + b"\n", {2}),
    ("5000 spaces then a row", b"\n".join(good_lines[:10] + [b" " * 5000 + b"0.5,0.5,0,0"] + good_lines[11:]) + b"\n", {2}),
    ("duplicate row", b"\n".join(good_lines + [good_lines[5]]) + b"\n", {0, 2}),
    ("two particles at one place", with_field(0, 0, b"1.5"), {0, 2}),
    ("all particles at one place", b"x,y,vx,vy\n" + b"4,4,0,0\n" * 64, {0, 2, 3}),
    ("one particle", b"x,y,vx,vy\n4,4,0,0\n", {0, 2}),
    ("trailing comma", b"\n".join(good_lines[:5] + [good_lines[5] + b","] + good_lines[6:]) + b"\n", {2}),
    ("leading comma", b"\n".join(good_lines[:5] + [b"," + good_lines[5]] + good_lines[6:]) + b"\n", {2}),
    ("semicolons", GOOD.replace(b",", b";"), {2}),
    ("tabs as separators", b"x,y,vx,vy\n" + b"\n".join(l.replace(b",", b"\t") for l in body) + b"\n", {2}),
    ("mass column, equal", b"x,y,vx,vy,m\n" + b"\n".join(l + b",1" for l in body) + b"\n", {0}),
    ("mass column, zero", b"x,y,vx,vy,m\n" + b"\n".join(l + b",0" for l in body) + b"\n", {2}),
    ("mass column, negative", b"x,y,vx,vy,m\n" + b"\n".join(l + b",-1" for l in body) + b"\n", {2}),
    ("mass column, nan", b"x,y,vx,vy,m\n" + b"\n".join(l + b",nan" for l in body) + b"\n", {2}),
    ("mass column, 1e-300", b"x,y,vx,vy,m\n" + b"\n".join(l + b",1e-300" for l in body) + b"\n", {0, 2}),
    ("mass column, 1e300", b"x,y,vx,vy,m\n" + b"\n".join(l + b",1e300" for l in body) + b"\n", {2, 3}),
    ("mass column, one missing", b"x,y,vx,vy,m\n" + b"\n".join(l + (b",1" if k else b"") for k, l in enumerate(body)) + b"\n", {2}),
    ("NUL file", b"\0" * 100, {2}),
    ("NUL after header", b"x,y,vx,vy\n\0\n" + b"\n".join(body) + b"\n", {2}),
    ("NUL at end", GOOD + b"\0", {2}),
    ("NUL in header", b"x,y\0,vx,vy\n" + b"\n".join(body) + b"\n", {2}),
    ("truncated mid-row", GOOD[:-7], {2}),
    ("truncated mid-number", GOOD[:-4], {2}),
    ("row of 3 fields", b"\n".join(good_lines[:7] + [b"1.5,2.5,0"] + good_lines[8:]) + b"\n", {2}),
    ("row of 5 fields", b"\n".join(good_lines[:7] + [b"1.5,2.5,0,0,0"] + good_lines[8:]) + b"\n", {2}),
    ("row of 1 field", b"\n".join(good_lines[:7] + [b"1.5"] + good_lines[8:]) + b"\n", {2}),
    ("row of 100 fields", b"\n".join(good_lines[:7] + [b",".join([b"1"] * 100)] + good_lines[8:]) + b"\n", {2}),
    ("hex floats everywhere", b"x,y,vx,vy\n" + b"".join(f"{x.hex()},{y.hex()},0,0\n".encode() for x, y, _, _ in GOOD_ROWS), {0, 2}),
]
for name, data, expect in structural:
    add_file(name, data, expect)
# random byte flips, insertions, deletions (the reference reader decides)
good_body_start = len(good_lines[0]) + 1
for k in range(240):
    data = bytearray(GOOD)
    kind = k % 3
    pos = rng.randrange(len(data))
    if kind == 0:
        data[pos] = rng.randrange(256)
        name = f"byte {pos} set to {data[pos]:#04x}"
    elif kind == 1:
        b = rng.choice([0, 0x2c, 0x0a, 0x2e, 0x2d, 0x65, 0x20, rng.randrange(256)])
        data.insert(pos, b)
        name = f"byte {b:#04x} inserted at {pos}"
    else:
        del data[pos]
        name = f"byte {pos} deleted"
    add_file(name, bytes(data))
# special files
for name, path, expect in (("FIFO", FIFO, {2}), ("a directory", FILES, {2}), ("missing file", os.path.join(FILES, "nope.csv"), {2}),
                           ("/dev/null", "/dev/null", {2}), ("/dev/zero", "/dev/zero", {2}), ("/proc/self/status", "/proc/self/status", {2})):
    file_cases.append(Case("files", name, argv("F", [("-file_path", path)]) + ["-output_dir", "out"], expect))
# the same 2D file in a 3D run and a 1D run
file_cases.append(Case("files", "2D file under -dim 3", argv("F", [("-dim", "3"), ("-box_len", "8,8,8")]) + ["-output_dir", "out"], {2}))
file_cases.append(Case("files", "2D file under -dim 1", argv("F", [("-dim", "1"), ("-box_len", "8")]) + ["-output_dir", "out"], {2}))



# ------------------------------------------------------------------------ snapshots (iv) ----
def snapshot_cases():
    """The snapshot family: (cases run at every stride, generated cases). The source is the
    snapshot at t = 0.5 of a tiny run of the file scene (64 particles, about 9 kB)."""
    src_dir = os.path.join(w, "snapshot_source")
    p = subprocess.run([SPAM] + argv("F", [("-snapshot_interval", "0.5")]) + ["-output_dir", src_dir], capture_output=True, env=ENV, timeout=60)
    src = os.path.join(src_dir, "snap_00001.h5")
    if not c.check(p.returncode == 0 and os.path.exists(src), f"the snapshot family's source run: exit {p.returncode}, {p.stderr.decode(errors='replace')[:200]}"):
        return [], []
    good, other = open(src, "rb").read(), open(os.path.join(src_dir, "snap_00000.h5"), "rb").read()
    block = 512  # the checksum's user block (snapshot_checksum.c)

    def case(name, path, expect):
        return Case("snapshots", "snapshot " + name, argv("F", [("-file_path", path)]) + ["-output_dir", "out"], expect)

    def mutated(k, name, data, expect):
        return case(name, fpath(f"s{k:04d}.h5", data), expect)

    always = [mutated(0, "as written", good, {0}), mutated(1, "without its checksum block (an earlier version's file)", good[block:], {0})]
    srng = random.Random(28)
    more = []
    # One bit flipped: 16 in the checksum's block, 80 in the HDF5 file after it.
    for k in range(96):
        pos = srng.randrange(block) if k < 16 else srng.randrange(block, len(good))
        bit = srng.randrange(8)
        data = bytearray(good)
        data[pos] ^= 1 << bit
        more.append(mutated(10 + k, f"bit {bit} of byte {pos} flipped", bytes(data), {2}))
    for k, n in enumerate((len(good) - 1, len(good) // 2, block + 8, block, block - 1, 8)):
        more.append(mutated(200 + k, f"truncated to {n} bytes", good[:n], {2}))
    more.append(mutated(210, "one byte appended", good + b"\0", {2}))
    more.append(mutated(211, "its checksum block zeroed", bytes(block) + good[block:], {2}))
    more.append(mutated(212, "the checksum block of another snapshot", other[:block] + good[block:], {2}))
    forge = os.environ.get("SPAM_SNAPSHOT_FORGE")
    if not forge or not os.access(forge, os.X_OK):
        print("SKIP: forged snapshots: SPAM_SNAPSHOT_FORGE (the snapshot_forge tool, set by ctest) is not set")
        return always, more
    forged = (("restamp", {0}), ("int32_ids", {0}), ("float_ids_half", {2}), ("float_ids_whole", {2}), ("string_ids", {2}), ("dup_ids", {2}),
              ("nan_position", {2}), ("negative_mass", {2}), ("no_velocities", {2}), ("positions_2col", {2}))
    for k, (op, expect) in enumerate(forged):
        out = os.path.join(FILES, f"forged_{op}.h5")
        f = subprocess.run([forge, src, out, op], capture_output=True, text=True, timeout=60)
        if c.check(f.returncode == 0, f"snapshot_forge {op}: {f.stderr.strip()[:200]}"):
            always.append(case(f"forged: {op}, checksum stamped again", out, expect))
            if op == "float_ids_half":  # the same without the block: no checksum, still refused
                always.append(mutated(300 + k, "forged: float_ids_half, no checksum block", open(out, "rb").read()[block:], expect))
    return always, more


snapshot_always, snapshot_generated = snapshot_cases()
if SANITIZED == 1:
    cases += snapshot_always
generated += snapshot_generated
generated += file_cases
if STRIDE > 1:
    cases += generated[::STRIDE]
else:
    cases += [g for k, g in enumerate(generated) if SANITIZED == 1 or k % SANITIZED]
# ------------------------------------------------------------ forged checkpoints (iv) ------
# A checkpoint written by a tiny run (expansion, a mirror wall at ylo, snapshots on) is
# edited entry by entry and written back by tests/ck_forge (built by CMake, through the
# library's writer), so that its checksum and entry count match the forgery: the restart
# must refuse it by its values. Each forged case runs in a copy of the run's directory and
# must exit 2 with one line naming the checkpoint, leaving every file of the directory byte
# for byte as it was (no file removed, added or rewritten, no "failed" summary).
FORGE = os.environ.get("SPAM_CK_FORGE") or os.path.join(os.path.dirname(SPAM), "tests", "ck_forge")
CK_EXTRA = [("-snapshot_interval", "0.125"), ("-output_interval", "0.0625"), ("-wall_ylo", "freeslip")]
# (name, ck_forge edits, expected codes); the box is [0, 8)^2, the state x, y, vx, vy.
CK_FORGERIES = [
    ("unchanged (control)", [], {0}),
    # counts
    ("out_nsnap -1", ["set", "out_nsnap", "0", "-1"], {2}),
    ("out_nsnap 2^40", ["set", "out_nsnap", "0", str(2 ** 40)], {2}),
    ("out_nsnap beyond its times", ["set", "out_nsnap", "0", "5"], {2}),
    ("out_step -1", ["set", "out_step", "0", "-1"], {2}),
    ("out_snap_times NaN", ["set", "out_snap_times", "0", "nan"], {2}),
    ("out_snap_times after the time", ["set", "out_snap_times", "0", "1e9"], {2}),
    ("out_grid_times NaN", ["real", "out_grid_times", "nan"], {2}),
    ("rank_checksums of 2 ranks", ["int", "rank_checksums", "0,0"], {2}),
    ("migration_loop of 2 values on one rank", ["real", "migration_loop", "0,0"], {2}),
    ("migration_loop NaN on one rank", ["real", "migration_loop", "0,0,nan,0,0,0"], {2}),
    # the run's record
    ("status 5 (past the enum)", ["status", "5"], {2}),
    ("status -1", ["status", "-1"], {2}),
    ("status 1000000", ["status", "1000000"], {2}),
    ("status interrupted", ["status", "3"], {2}),
    ("run_result reason unterminated", ["unterminated", "x"], {2}),
    ("run_result short", ["text", "run_result", "x"], {2}),
    # intervals and schedule
    ("output interval 1e-9", ["set", "loop", "0", "1e-9"], {2}),
    ("output interval 0", ["set", "loop", "0", "0"], {2}),
    ("output interval NaN", ["set", "loop", "0", "nan"], {2}),
    ("output interval -1", ["set", "loop", "0", "-1"], {2}),
    ("output interval inf", ["set", "loop", "0", "inf"], {2}),
    ("snapshot interval 1e-9", ["set", "loop", "1", "1e-9"], {2}),
    ("snapshot interval 0", ["set", "loop", "1", "0"], {2}),
    ("snapshot interval NaN", ["set", "loop", "1", "nan"], {2}),
    ("snapshot interval -0.125", ["set", "loop", "1", "-0.125"], {2}),
    ("next output NaN", ["set", "loop", "2", "nan"], {2}),
    ("next snapshot -5", ["set", "loop", "3", "-5"], {2}),
    ("next output far ahead", ["set", "loop", "2", "0.45"], {2}),
    ("loop time not the time", ["set", "loop", "4", "0.3"], {2}),
    ("last step -1", ["set", "loop", "5", "-1"], {2}),
    ("last row after the time", ["set", "loop", "6", "1e9"], {2}),
    ("wall clock NaN", ["set", "loop", "8", "nan"], {2}),
    ("writer's end NaN", ["set", "loop", "10", "nan"], {2}),
    ("loop of 4 values", ["real", "loop", "0.0625,0.125,0.125,0.125"], {2}),
    ("loop as integers", ["int", "loop", "0,0,0,0,0,0,0,0,0,0,0"], {2}),
    # times and steps
    ("time NaN", ["set", "time", "0", "nan"], {2}),
    ("time -1", ["set", "time", "0", "-1"], {2}),
    ("time 1e300", ["set", "time", "0", "1e300"], {2}),
    ("time -inf", ["set", "time", "0", "-inf"], {2}),
    ("step -1", ["set", "step", "0", "-1"], {2}),
    ("step 2^40", ["set", "step", "0", str(2 ** 40)], {2}),
    ("step 2^63-1", ["set", "step", "0", str(2 ** 63 - 1)], {2}),
    ("step not the progress's", ["set", "step", "0", "7"], {2}),
    ("step as a fraction", ["real", "step", "6.5"], {2}),
    ("progress rejected -1", ["set", "progress", "2", "-1"], {2}),
    ("progress time NaN", ["set", "progress", "0", "nan"], {2}),
    # integrator
    ("h_next NaN", ["set", "h_next", "0", "nan"], {2}),
    ("h_next -1", ["set", "h_next", "0", "-1"], {2}),
    ("velocity_scale 0", ["set", "velocity_scale", "0", "0"], {2}),
    ("velocity_scale NaN", ["set", "velocity_scale", "0", "nan"], {2}),
    ("arkode_history NaN", ["set", "arkode_history", "1", "nan"], {2}),
    ("arkode_accepted -1", ["set", "arkode_accepted", "0", "-1"], {2}),
    ("exact 2", ["set", "exact", "0", "2"], {2}),
    ("step_restart_pending -1", ["set", "step_restart_pending", "0", "-1"], {2}),
    ("kick_cached 7", ["set", "kick_cached", "0", "7"], {2}),
    ("list_builds -1", ["set", "list_builds", "0", "-1"], {2}),
    # particles
    ("y beyond the ylo wall", ["set", "state", "1", "-1000"], {2}),
    ("xref y beyond the ylo wall", ["set", "xref", "1", "-1000"], {2}),
    ("x NaN", ["set", "state", "0", "nan"], {2}),
    ("velocity inf", ["set", "state", "2", "inf"], {2}),
    ("xref x 1e309 (inf)", ["set", "xref", "0", "1e309"], {2}),
    ("acc NaN", ["set", "acc", "3", "nan"], {2}),
    ("rhs_stats -1", ["set", "rhs_stats", "0", "-1"], {2}),
    ("state one value short", ["real", "state", ",".join(["1"] * 63)], {2}),
    ("id out of order", ["set", "id", "0", "5"], {2}),
    ("mass changed", ["set", "mass", "0", "2"], {2}),
    # shape and identity
    ("dim 3", ["set", "dim", "0", "3"], {2}),
    ("nvar 7", ["set", "nvar", "0", "7"], {2}),
    ("nglobal -1", ["set", "nglobal", "0", "-1"], {2}),
    ("options of another kernel", ["text", "options", "-kernel lucy -expansion_n 4"], {2}),
    ("version of another build", ["text", "version", "spam-ark 0.0 (forged)"], {2}),
    # the list of files
    ("out_files garbage", ["text", "out_files", "garbage"], {2}),
    ("out_files a path", ["text", "out_files", "../escape.h5\tsnapshot_h5\t0\t0\n"], {2}),
    ("out_files a hidden name", ["text", "out_files", ".lock\tsnapshot_h5\t0\t0\n"], {2}),
    ("out_files a quoted kind", ["text", "out_files", 'snap_00000.h5\tsnap"\t0\t0\n'], {2}),
    ("out_files a time 'abc'", ["text", "out_files", "snap_00000.h5\tsnapshot_h5\tabc\t0\n"], {2}),
    ("out_files outside 2", ["text", "out_files", "snap_00000.h5\tsnapshot_h5\t0\t2\n"], {2}),
    ("out_files five fields", ["text", "out_files", "snap_00000.h5\tsnapshot_h5\t0\t0\t0\n"], {2}),
    ("out_files a control byte", ["text", "out_files", "snap\x01.h5\tsnapshot_h5\t0\t0\n"], {2}),
]
# every entry a restart reads, missing
CK_FORGERIES += [(f"{e} missing", ["drop", e], {2}) for e in (
    "loop", "time", "step", "progress", "limit", "run_result", "h_next", "velocity_scale", "arkode_history", "exact",
    "step_restart_pending", "kick_cached", "list_builds", "state", "xref", "acc", "rhs_stats", "id", "mass", "dim",
    "options", "version", "out_files", "out_nsnap", "out_step", "out_snap_times", "out_grid_times", "out_timeseries",
    "out_steps")]

# and drawn with a fixed seed: a non-finite value in a random place of a real entry, a
# negative one in an integer entry (each is invalid wherever it lands; loop[9], the next
# checkpoint time, is left out: it may be inf, and a restart sets it anew).
CK_REALS = {"loop": [k for k in range(11) if k != 9], "progress": range(6), "h_next": [0], "velocity_scale": [0],
            "arkode_history": range(5), "state": range(64), "xref": range(32), "acc": range(32), "mass": range(16),
            "rhs_stats": range(3), "out_snap_times": [0], "time": [0]}
CK_INTS = {e: [0] for e in ("nglobal", "nvar", "dim", "step", "exact", "kick_cached", "step_restart_pending", "list_builds",
                            "arkode_accepted", "out_nsnap", "out_step")}
CK_INTS["id"] = range(16)
ck_rng = random.Random(2028)
ck_drawn = {}
while len(ck_drawn) < 24:  # 24 different forgeries
    entry = ck_rng.choice(sorted(CK_REALS) + sorted(CK_INTS))
    table, values = (CK_REALS, ["nan", "inf", "-inf", "-nan"]) if entry in CK_REALS else (CK_INTS, ["-1", str(-2 ** 63)])
    k, value = ck_rng.choice(list(table[entry])), ck_rng.choice(values)
    ck_drawn[f"drawn: {entry}[{k}] = {value}"] = ["set", entry, str(k), value]
CK_FORGERIES += [(name, edits, {2}) for name, edits in ck_drawn.items()]


def digest(root):
    """Every file and directory under root: regular files by content hash, the others by type."""
    out = {}
    for d, ds, fs in os.walk(root):
        for name in ds + fs:
            p = os.path.join(d, name)
            st = os.lstat(p)
            if os.path.isfile(p) and not os.path.islink(p):
                with open(p, "rb") as f:
                    out[os.path.relpath(p, root)] = hashlib.sha256(f.read()).hexdigest()
            else:
                out[os.path.relpath(p, root)] = oct(st.st_mode)
    return out


class RunDirCase(Case):
    """A restart in a copy of a run directory (base); checkpoint (or None: the base's own)
    is copied over out/checkpoint.h5, fifo: a FIFO made at out/fifo.h5. A refusal must
    leave the directory as it was."""

    def __init__(self, name, args, expect, base, checkpoint=None, fifo=False):
        super().__init__("checkpoints", name, args, expect)
        self.base, self.checkpoint, self.fifo = base, checkpoint, fifo

    def prepare(self, cwd):
        out = os.path.join(cwd, "out")
        shutil.copytree(self.base, out)
        if self.checkpoint:
            shutil.copyfile(self.checkpoint, os.path.join(out, "checkpoint.h5"))
        if self.fifo:
            os.mkfifo(os.path.join(out, "fifo.h5"))
        self.before = digest(cwd)

    def refused_cleanly(self, cwd):
        """Problems of a refusal: any change in the directory."""
        after = digest(cwd)
        changed = sorted(k for k in set(self.before) | set(after) if self.before.get(k) != after.get(k))
        return [f"the run directory changed: {changed[:6]}"] if changed else []


def forged_checkpoint_cases():
    base = os.path.join(FILES, "ck_base")
    base_args = argv("E", CK_EXTRA + [("-ts_max_steps", "6"), ("-checkpoint_interval", "1000")]) + ["-output_dir", base]
    if FORK:  # the restarts run in the server's children: a checkpoint continues only in its own build
        srv = Server()
        code = srv.run(base_args, w, ENV, os.path.join(FILES, "ck_base.stderr"), 120)
        srv.close()
    else:
        code = subprocess.run([SPAM] + base_args, capture_output=True, env=ENV, timeout=120).returncode
    if not c.check(code == 0 and os.path.exists(os.path.join(base, "checkpoint.h5")), f"the forged checkpoints' base run wrote its checkpoint (exit {code})"):
        return []
    if not c.check(os.access(FORGE, os.X_OK), f"the checkpoint forger {FORGE} is built"):
        return []
    # the restart gives no intervals: it takes the checkpoint's (restart_load.c TakeIntervals)
    ck_args = [x for o, v in CONTEXTS["E"] + CK_EXTRA if o not in ("-snapshot_interval", "-output_interval") for x in (o, v)]
    restart = ["-output_dir", "out", "-restart", "out/checkpoint.h5"]
    # Every forgery in one start of the forger (a start under the sanitizers takes seconds);
    # with a stride (tools/sanitize.sh) every 4th of them, the control always.
    # Left to the sanitized run (SANITIZED): the 4th ones but the control, and the special files.
    chosen = [f for k, f in enumerate(CK_FORGERIES) if (k % 4 == 0 if STRIDE > 1 else SANITIZED == 1 or k % 4 or k == 0)]
    paths = [os.path.join(FILES, f"ck_forged_{k:03d}.h5") for k in range(len(chosen))]
    groups = [x for k, (name, edits, expect) in enumerate(chosen) for x in (["--"] if k else []) + [paths[k]] + edits]
    p = subprocess.run([FORGE, os.path.join(base, "checkpoint.h5")] + groups, capture_output=True, env=ENV, timeout=300)
    if not c.check(p.returncode == 0, f"ck_forge wrote {len(chosen)} forgeries: {p.stderr.decode(errors='replace').strip()[:300]}"):
        return []
    out = [RunDirCase(f"forged checkpoint: {name}", ck_args + restart, expect, base, path) for (name, edits, expect), path in zip(chosen, paths)]
    if SANITIZED > 1:
        return out
    # special files as the checkpoint: refused before they are opened (a FIFO would block)
    out.append(RunDirCase("checkpoint a FIFO", ck_args + ["-output_dir", "out", "-restart", "out/fifo.h5"], {2}, base, fifo=True))
    out.append(RunDirCase("checkpoint a directory", ck_args + ["-output_dir", "out", "-restart", "out"], {2}, base))
    out.append(RunDirCase("checkpoint /dev/zero", ck_args + ["-output_dir", "out", "-restart", "/dev/zero"], {2}, base))
    return out


cases += forged_checkpoint_cases()
# SPAM_FUZZ_ONLY=regex: only the cases whose name matches (say "^-sod_|^-sedov_" for the
# option cases of two scenes), to try new options without the whole corpus.
ONLY = os.environ.get("SPAM_FUZZ_ONLY")
if ONLY:
    cases = [k for k in cases if re.search(ONLY, k.name)]

# ------------------------------------------------------------------------------ run ------


def strict_json(path):
    def bad(x):
        raise ValueError(f"non-JSON constant {x}")
    with open(path, "rb") as f:
        return json.loads(f.read(), parse_constant=bad)


def tree(path):
    return sorted(os.path.relpath(os.path.join(d, f), path) for d, ds, fs in os.walk(path) for f in fs + ds)


def exec_only(case):
    """A case whose outcome may depend on which executable runs it (fork_server.needs_exec)."""
    return fork_server.needs_exec(case.args)


servers = []
local = threading.local()


def server():
    """This worker thread's fork server, started at its first case."""
    if not hasattr(local, "server"):
        local.server = Server()
        servers.append(local.server)
    return local.server


def execute(k, case):
    cwd = os.path.join(w, "c", f"{k:05d}")
    os.makedirs(cwd)
    if hasattr(case, "prepare"):  # a case that starts from a run directory (forged checkpoints)
        case.prepare(cwd)
    # OpenMPI's session directory goes under TMPDIR: one per case, outside the case directory
    # (concurrent starts sharing /tmp/ompi.* now and then fail to create it, exit 1).
    env = dict(ENV, TMPDIR=os.path.join(w, "t", f"{k:05d}"))
    os.makedirs(env["TMPDIR"])
    t0 = time.monotonic()
    if FORK and not exec_only(case):
        # as under LIMIT's /bin/sh, which sets PWD to the directory it starts in
        err_path = os.path.join(env["TMPDIR"], "stderr")
        code = server().run(case.args, cwd, dict(env, PWD=cwd) if LIMIT else env, err_path)
        with open(err_path, "rb") as f:
            err = f.read().decode("utf-8", "replace")
        return k, case, code, err, time.monotonic() - t0, cwd
    try:
        p = subprocess.run(LIMIT + [os.fsencode(SPAM)] + [x if isinstance(x, bytes) else os.fsencode(x) for x in case.args],
                           capture_output=True, env=env, cwd=cwd, timeout=TIMEOUT, stdin=subprocess.DEVNULL)
        code, err = p.returncode, p.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired as e:
        code, err = "timeout", (e.stderr or b"").decode("utf-8", "replace")
    return k, case, code, err, time.monotonic() - t0, cwd


def verdict(case, code, err, cwd):
    """Problems of one finished case (empty: as expected)."""
    problems = []
    lines = err.strip("\n").split("\n") if err.strip("\n") else []
    if any(s in err for s in SANITIZER) or code == 86:
        problems.append("sanitizer report: " + " | ".join(l for l in lines if any(s in l for s in SANITIZER) or " #" in l[:6])[:1500])
    if code == "timeout":
        return problems + [f"no exit within {TIMEOUT} s"]
    if code < 0 or code not in (0, 1, 2, 3, 86):
        problems.append(f"crash: exit {code}" + (f" (signal {-code})" if code < 0 else ""))
    if code not in case.expect:
        problems.append(f"exit {code}, expected {'/'.join(map(str, sorted(case.expect)))}")
    written = tree(cwd)
    if code == 2:
        if len(lines) != 1 or not lines[0].startswith("spam-ark: error: "):
            problems.append(f"{len(lines)} stderr lines, not one 'spam-ark: error: ' line")
        elif case.option and case.option.lstrip("-").lower() not in lines[0].lower():
            problems.append(f"the message does not name {case.option.lstrip('-')}")
        if hasattr(case, "refused_cleanly"):
            problems += case.refused_cleanly(cwd)
        elif written:
            problems.append(f"wrote {written[:5]}")
    elif code == 1 and len(lines) != 1:
        problems.append(f"exit 1 with {len(lines)} stderr lines")
    elif code in (0, 3) and (case.run or code == 3):
        path = os.path.join(cwd, case.outdir, "summary.json")
        try:
            s = strict_json(path)
            want = ("ok", "max_steps") if code == 0 else ("unstable",)
            if s.get("status") not in want:
                problems.append(f"summary status {s.get('status')!r}, expected {want!r}")
        except (OSError, ValueError) as e:
            problems.append(f"summary.json: {e}")
    elif code == 0 and written:
        problems.append(f"-help/-version wrote {written[:5]}")
    if problems:
        problems.append("stderr: " + " | ".join(lines[:3])[:400])
    return problems


counts = {}
by_category = {}
slowest = []
t_start = time.monotonic()
# SPAM_FUZZ_VERDICTS=file: each case's exit code and problems, a line each in the corpus's
# order (to compare two runs, say through the fork server and with SPAM_FUZZ_EXEC=1).
verdicts = open(os.environ["SPAM_FUZZ_VERDICTS"], "w", encoding="utf-8") if os.environ.get("SPAM_FUZZ_VERDICTS") else None
with concurrent.futures.ThreadPoolExecutor(JOBS) as pool:
    for k, case, code, err, dt, cwd in pool.map(lambda kc: execute(*kc), enumerate(cases)):
        problems = verdict(case, code, err, cwd)
        if verdicts:
            print(f"{k}\t[{case.category}] {case.name!r}\t{code}\t" + "; ".join(problems), file=verdicts)
        label = {0: "ran (0)", 1: "failed (1)", 2: "refused (2)", 3: "unstable (3)", "timeout": "timeouts"}.get(code, "crashes")
        if any(p.startswith("sanitizer") for p in problems):
            counts["sanitizer reports"] = counts.get("sanitizer reports", 0) + 1
            if code in (86,):
                label = "crashes"
        counts[label] = counts.get(label, 0) + 1
        cat = by_category.setdefault(case.category, {})
        cat[label] = cat.get(label, 0) + 1
        if len(case.expect) > 1:
            cat["open (several codes allowed)"] = cat.get("open (several codes allowed)", 0) + 1
        slowest.append((dt, case.name))
        if problems:
            c.check(False, f"[{case.category}] {case.name}: " + "; ".join(problems))
        else:
            c.passed += 1
            shutil.rmtree(cwd, ignore_errors=True)
        shutil.rmtree(os.path.join(w, "t", f"{k:05d}"), ignore_errors=True)

for srv in servers:
    c.check(srv.close() == 0, "the fork server ended cleanly")
if verdicts:
    verdicts.close()
elapsed = time.monotonic() - t_start
left = f"; the {SANITIZED}-stride run under the sanitizers takes the rest" if SANITIZED > 1 else ""
own = sum(map(exec_only, cases))
how = f"in the fork server's children ({own} a start of spam-ark, exec_only)" if FORK else "each a start of spam-ark"
print(f"\ninputs tried: {len(cases)} (stride {STRIDE} over {len(generated)} generated cases{left}), {elapsed:.0f} s with {JOBS} at a time, {how}")
for key in ("refused (2)", "ran (0)", "unstable (3)", "failed (1)", "crashes", "timeouts", "sanitizer reports"):
    print(f"  {key:20s} {counts.get(key, 0)}")
for cat, d in by_category.items():
    n = sum(v for k, v in d.items() if not k.startswith("open"))
    print(f"  {cat:9s} {n} inputs: " + ", ".join(f"{k} {v}" for k, v in sorted(d.items())))
slowest.sort(reverse=True)
print("slowest: " + "; ".join(f"{n} {t:.1f} s" for t, n in slowest[:5]))
c.check(counts.get("crashes", 0) == 0, f"no crashes ({counts.get('crashes', 0)})")
c.check(counts.get("timeouts", 0) == 0, f"no timeouts ({counts.get('timeouts', 0)})")
c.check(counts.get("sanitizer reports", 0) == 0, f"no sanitizer reports ({counts.get('sanitizer reports', 0)})")
c.finish()
