#!/usr/bin/python3
"""Instructions per right-hand side of the gas flow scheme, as a viscous gas gets it by
default, against the plain scheme (`-gas_scheme plain`), and what each of its laws adds
(valgrind's callgrind: counts that do not depend on the machine's load).

Cases, each at fixed steps so that every variant evaluates the same stages:
- taylor-green: options/taylor-green-re100.opts at L = 48 (Re = 100, Mach 0.1, no
  conduction), dt = 0.25 to t = 2.5;
- convection: the 32 x 16 cell of options/convection.opts with `-gas_scheme flow` (walls,
  gravity, conduction: the cell keeps the plain scheme unless asked), dt = 1 to t = 10.
Variants: plain; flow (the defaults: background pressure, transport shift, pair diffusion,
and where they apply -conduction_linear and -shift_compression); then flow with one law
turned off at a time (-background_pressure none, -shift_coefficient 0, -diffusion_form
gradient, -conduction_linear false, -shift_compression false), so that a law's cost is the
default's count less that variant's. A law that does not apply to a case (no conduction in
Taylor-Green; no gravity there, so no shift compression) is not run there. The two-pass form
(-diffusion_form gradient) also drops -conduction_linear, which needs the pair form: in the
convection case its share holds both.
Counted inside the right-hand side only (--toggle-collect=SpamRhs); per RHS = the
instructions over summary.json's rhs_evals_process.

    bench/run_callgrind_gas_flow.py --readings bench/readings/callgrind_gas_flow.json
"""

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

from run_callgrind_h import counted_record  # spam-ark under callgrind: its summary and counts

REPO_ROOT = Path(__file__).resolve().parent.parent
TOGGLE = "SpamRhs"
CASES = {
    "taylor-green": ["-options_file", "options/taylor-green-re100.opts", "-taylorgreen_n", "48",
                     "-arkode_fixed_step", "0.25", "-ts_max_time", "2.5"],
    "convection": ["-options_file", "options/convection.opts", "-arkode_fixed_step", "1", "-ts_max_time", "10"],
}
# Variant name -> options; "off:" variants are the flow scheme with one law off.
VARIANTS = {
    "plain": ["-gas_scheme", "plain"],
    "flow": ["-gas_scheme", "flow"],
    "off:background": ["-gas_scheme", "flow", "-background_pressure", "none"],
    "off:shift": ["-gas_scheme", "flow", "-shift_coefficient", "0"],
    "off:pair_diffusion": ["-gas_scheme", "flow", "-diffusion_form", "gradient"],
    "off:conduction_linear": ["-gas_scheme", "flow", "-conduction_linear", "false"],
    "off:shift_compression": ["-gas_scheme", "flow", "-shift_compression", "false"],
}
NOT_IN = {"taylor-green": ("off:conduction_linear", "off:shift_compression")}


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(REPO_ROOT / "build" / "spam-ark"))
    ap.add_argument("--cases", default=",".join(CASES), help="of " + ", ".join(CASES))
    ap.add_argument("--readings", default=None, help="write the table to this JSON (examples/chart_readings.py)")
    ap.add_argument("--workdir", default=None, help="scratch directory (default: a temporary one)")
    return ap.parse_args(argv)


def run_one(args, case, variant, workdir):
    name = "%s_%s" % (case, variant.replace(":", "_"))
    out = workdir / name
    cmd = [args.spam_ark, *CASES[case], *VARIANTS[variant], "-output_interval", "0", "-snapshot_interval", "0",
           "-output_dir", str(out), "-output_overwrite", "-quiet"]
    return counted_record(cmd, TOGGLE, workdir, name, out)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    if not shutil.which("valgrind"):
        raise SystemExit("valgrind (callgrind) is needed")
    args.spam_ark = str(Path(args.spam_ark).resolve())
    workdir = Path(args.workdir) if args.workdir else Path(tempfile.mkdtemp(prefix="cg_flow_"))
    workdir.mkdir(parents=True, exist_ok=True)
    res = {"cases": {}, "table": []}
    for case in args.cases.split(","):
        if case not in CASES:
            raise SystemExit("unknown case %s (one of %s)" % (case, ", ".join(CASES)))
        runs = {v: run_one(args, case, v, workdir) for v in VARIANTS if v not in NOT_IN.get(case, ())}
        plain, flow = runs["plain"]["instructions_per_rhs"], runs["flow"]["instructions_per_rhs"]
        row = {"runs": runs, "flow_over_plain": flow / plain,
               "law_share_of_plain": {v.split(":", 1)[1]: (flow - r["instructions_per_rhs"]) / plain
                                      for v, r in runs.items() if v.startswith("off:")}}
        res["cases"][case] = row
        print("%-13s N %d: plain %.4g, flow (defaults) %.4g instructions per RHS, flow / plain %.3f" % (
            case, runs["plain"]["n_particles"], plain, flow, row["flow_over_plain"]))
        for law, share in row["law_share_of_plain"].items():
            print("    %-20s %+.3f of plain's per RHS" % (law, share))
        res["table"].append([case, runs["plain"]["n_particles"], "%.4g" % plain, "%.4g" % flow,
                             "%.3f" % row["flow_over_plain"]]
                            + ["%+.3f" % row["law_share_of_plain"][law] if law in row["law_share_of_plain"] else ""
                               for law in ("background", "shift", "pair_diffusion", "conduction_linear",
                                           "shift_compression")])
    res["table"] = {"columns": ["case", "N", "plain instr./RHS", "flow instr./RHS", "flow / plain", "background",
                               "shift", "pair diffusion", "conduction_linear", "shift_compression"],
                    "rows": res["table"]}
    if args.readings:
        sys.path.insert(0, str(REPO_ROOT / "examples"))
        import chart_readings
        chart_readings.write_json(args.readings, res)


if __name__ == "__main__":
    main()
