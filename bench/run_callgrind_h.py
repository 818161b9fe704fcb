#!/usr/bin/python3
"""Instructions per right-hand side at the fixed, the adaptive and the evolved kernel range,
the same scene and N (valgrind's callgrind: counts that do not depend on the machine's load).

Each range runs the Sedov blast (options/sedov.opts: the gas, gamma 5/3, Monaghan's
viscosity, h = 3, E0 = 1e4) under callgrind counting inside the right-hand side only
(--toggle-collect=SpamRhs: every evaluation, its list updates and, at the adaptive range,
its h solve; the set-up's first list and solve come before the loop), from t = 0 to
--t-end at the integrator's own steps. Per RHS = the instructions counted over the
process's evaluations (summary.json's rhs_evals_process). The blast's state changes the
costs (the adaptive solve's Newton passes, the near rows' reach), so the count is over a
whole short run rather than one evaluation. Ratios to the fixed range at the same N are
the measure (the issue's goal: at most 1.5).

    bench/run_callgrind_h.py --readings bench/readings/callgrind_h.json
"""

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
TOGGLE = "SpamRhs"
RANGES = {"fixed": [], "adaptive": ["-smoothing_length", "adaptive", "-h_eta", "3"],
          "evolved": ["-smoothing_length", "evolved", "-h_eta", "3"]}
# (label, dim, lattice points per direction, end time): at the end R = xi0 (E0 t^2)^(1/(D+2))
# is 3.8 h in 2D (a grown blast, its core dilute) and 1.3 h in 3D (a young one: 3D at a
# grown blast is minutes under callgrind).
CASES = [("2d_48", 2, 48, 1.0), ("3d_16", 3, 16, 0.2)]


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"))
    ap.add_argument("--cases", default=",".join(c[0] for c in CASES), help="of " + ", ".join(c[0] for c in CASES))
    ap.add_argument("--readings", default=None, help="write the table to this JSON (examples/chart_readings.py)")
    ap.add_argument("--workdir", default=None, help="scratch directory (default: a temporary one)")
    return ap.parse_args(argv)


def totals(path):
    """The counted instructions of a callgrind output file (its 'totals:' or 'summary:' line)."""
    for line in Path(path).read_text().splitlines():
        m = re.match(r"^(?:totals|summary):\s+(\d+)", line)
        if m:
            return int(m.group(1))
    raise SystemExit("no totals line in %s" % path)


def counted_run(cmd, toggle, cg, log, out, cwd=None):
    """Runs spam-ark's cmd under callgrind, counting inside the function toggle: its
    summary.json (in out), the counted instructions, the process's RHS evaluations and the
    command as run (valgrind's tool and toggle, then spam-ark's arguments)."""
    vg = ["valgrind", "--tool=callgrind", "--toggle-collect=" + toggle, "--callgrind-out-file=%s" % cg]
    with open(log, "w") as fh:
        rc = subprocess.run(vg + cmd, stdout=fh, stderr=subprocess.STDOUT, cwd=cwd).returncode
    if rc != 0:
        raise SystemExit("callgrind run failed (rc %d): see %s" % (rc, log))
    sm = json.loads((Path(out) / "summary.json").read_text())
    return sm, totals(cg), int(sm["rhs_evals_process"]), " ".join(vg[:3] + [str(x) for x in cmd[1:]])


def counted_record(cmd, toggle, workdir, name, out):
    """counted_run of one named run in workdir, as the record the callgrind benches keep:
    the command (paths relative), particles, evaluations, steps, instructions in all and per RHS."""
    sm, ir, evals, command = counted_run(cmd, toggle, workdir / ("callgrind_%s.out" % name), workdir / ("callgrind_%s.log" % name),
                                         out, cwd=str(REPO_ROOT))
    return {"command": command.replace(str(REPO_ROOT) + "/", "").replace(str(workdir) + "/", ""),
            "n_particles": int(sm["n_particles"]), "rhs_evals": evals, "steps": int(sm["steps"]), "instructions": ir,
            "instructions_per_rhs": ir / evals}


def run_one(args, case, name, extra, workdir):
    label, dim, n, t_end = case
    out = workdir / ("%s_%s" % (label, name))
    cg = workdir / ("callgrind_%s_%s.out" % (label, name))
    cmd = [args.spam_ark, "-options_file", str(REPO_ROOT / "options" / "sedov.opts"), "-dim", str(dim),
           "-sedov_n", str(n), "-ts_max_time", str(t_end), "-output_interval", str(t_end),
           "-snapshot_interval", "0", "-snapshot_hdf5", "0", "-output_dir", str(out), "-output_overwrite", "-quiet"] + extra
    sm, ir, evals, command = counted_run(cmd, TOGGLE, cg, workdir / ("callgrind_%s_%s.log" % (label, name)), out)
    return {"command": command.replace(str(REPO_ROOT) + "/", ""),
            "n_particles": int(sm["n_particles"]), "rhs_evals": evals, "instructions": ir,
            "instructions_per_rhs": ir / evals, "instructions_per_particle_rhs": ir / evals / int(sm["n_particles"]),
            "pair_visits_per_rhs": sm["pair_interactions_per_s"] * sm["rhs_time_s"] / evals}


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    if not shutil.which("valgrind"):
        raise SystemExit("valgrind (callgrind) is needed")
    args.spam_ark = str(Path(args.spam_ark).resolve())
    workdir = Path(args.workdir) if args.workdir else Path(tempfile.mkdtemp(prefix="spam-ark-cgh-"))
    workdir.mkdir(parents=True, exist_ok=True)
    want = args.cases.split(",")
    res = {}
    for case in CASES:
        if case[0] not in want:
            continue
        rec = {name: run_one(args, case, name, extra, workdir) for name, extra in RANGES.items()}
        for name in RANGES:
            rec[name]["ratio_to_fixed"] = rec[name]["instructions_per_rhs"] / rec["fixed"]["instructions_per_rhs"]
        rec["dim"], rec["n"], rec["t_end"] = case[1], case[2], case[3]
        res[case[0]] = rec
        for name in RANGES:
            r = rec[name]
            print("%s %-8s N %6d: %4d RHS, %.4g instructions per RHS (%.0f per particle), %.3f x fixed"
                  % (case[0], name, r["n_particles"], r["rhs_evals"], r["instructions_per_rhs"],
                     r["instructions_per_particle_rhs"], r["ratio_to_fixed"]))
    if args.readings:
        sys.path.insert(0, str(REPO_ROOT / "examples"))
        import chart_readings
        chart_readings.write_json(args.readings, res)
    if not args.workdir:
        shutil.rmtree(workdir, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
