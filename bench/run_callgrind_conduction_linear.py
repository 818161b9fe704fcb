#!/usr/bin/python3
"""Instructions per right-hand side with and without -conduction_linear (valgrind's
callgrind: counts that do not depend on the machine's load).

Cases, each run with `-conduction_linear false` and `true`:
- convection: the 32 x 16 cell of options/convection.opts with `-gas_scheme flow` (walls,
  gravity, the explicit method's whole RHS), fixed steps dt = 1 to t = 10. The
  correction adds the corrected grad T (a 2 x 2 solve a particle), its gather and one
  dot product per pair side to the force walk; walk 1 computes grad T for the shift's
  drift either way.
- heat mode, implicit: options/heat-mode.opts under -ts_type arkode_imex to t = 50 (the
  diffusion part then also walks for grad T, which nothing else there reads; the
  stage preconditioner's assembly walks once more for the correction's b).
Counted inside the right-hand side only (--toggle-collect=SpamRhsSolidPart: both parts under
arkode_imex), and separately the Jacobian's assembly (SpamDiffusionJacAssemble) in the
implicit case. Per RHS = the instructions over summary.json's rhs_evals_process.

    bench/run_callgrind_conduction_linear.py --readings docs/conduction_linear_cost.json
"""

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

from run_callgrind_h import counted_record  # spam-ark under callgrind: its summary and counts

REPO_ROOT = Path(__file__).resolve().parent.parent
CASES = {
    "convection": ["-options_file", "options/convection.opts", "-gas_scheme", "flow", "-arkode_fixed_step", "1", "-ts_max_time", "10"],
    "heat_mode_imex": ["-options_file", "options/heat-mode.opts", "-ts_type", "arkode_imex", "-ts_max_time", "50"],
}


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"))
    ap.add_argument("--readings", default=None, help="write the table to this JSON (examples/chart_readings.py)")
    ap.add_argument("--workdir", default=None, help="scratch directory (default: a temporary one)")
    return ap.parse_args(argv)


def run_one(args, case, lin, toggle, workdir):
    name = "%s_%s_%s" % (case, "on" if lin else "off", toggle)
    out = workdir / name
    cmd = [args.spam_ark, *CASES[case], "-conduction_linear", "true" if lin else "false", "-output_interval", "0",
           "-snapshot_interval", "0", "-output_dir", str(out), "-output_overwrite", "-quiet"]
    return counted_record(cmd, toggle, workdir, name, out)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    if not shutil.which("valgrind"):
        raise SystemExit("valgrind (callgrind) is needed")
    args.spam_ark = str(Path(args.spam_ark).resolve())
    workdir = Path(args.workdir) if args.workdir else Path(tempfile.mkdtemp(prefix="cg_lin_"))
    workdir.mkdir(parents=True, exist_ok=True)
    res = {"cases": {}}
    for case in CASES:
        row = {}
        for lin in (False, True):
            row["on" if lin else "off"] = run_one(args, case, lin, "SpamRhsSolidPart", workdir)
        row["ratio_per_rhs"] = row["on"]["instructions_per_rhs"] / row["off"]["instructions_per_rhs"]
        if case.endswith("imex"):
            for lin in (False, True):
                row["jacobian_" + ("on" if lin else "off")] = run_one(args, case, lin, "SpamDiffusionJacAssemble", workdir)
            row["jacobian_ratio"] = row["jacobian_on"]["instructions"] / row["jacobian_off"]["instructions"]
        res["cases"][case] = row
        print("%-16s per RHS: off %.4g, on %.4g instructions, ratio %.3f%s" % (
            case, row["off"]["instructions_per_rhs"], row["on"]["instructions_per_rhs"], row["ratio_per_rhs"],
            (", Jacobian assembly ratio %.3f" % row["jacobian_ratio"]) if "jacobian_ratio" in row else ""))
    if args.readings:
        sys.path.insert(0, str(REPO_ROOT / "examples"))
        import chart_readings
        chart_readings.write_json(args.readings, res)


if __name__ == "__main__":
    main()
