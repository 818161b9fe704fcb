#!/usr/bin/python3
"""Stopping at every output time against interpolating (dense output): the steps each takes
and the largest energy drift of the rows it writes, for three ARKODE tables at two
tolerances, on the precision study's scene (the 2D expansion of 24^2 particles, h = 3, to
t = 16, a row every 0.8).

Interpolating is the default for adaptive ARKODE runs; -output_stop true stops the
integrator at every output time, which cuts a step there (steps.csv's limit "output").
Printed and, with --readings FILE, written for docs/integrators.md as a table.

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_dense_output.py [--readings FILE]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples"))
import chart_readings  # noqa: E402

SCENE = ["-expansion_n", "24", "-h", "3", "-ts_max_time", "16", "-snapshot_interval", "4", "-output_interval", "0.8",
         "-snapshot_hdf5", "0", "-quiet", "-output_overwrite"]
TABLES = (("Fehlberg 8(7)", "ARKODE_FEHLBERG_13_7_8"), ("Dormand–Prince 5(4)", "ARKODE_DORMAND_PRINCE_7_4_5"),
          ("Verner 6(5)", "ARKODE_VERNER_8_5_6"))
RTOLS = (1e-4, 1e-6)


def one_run(spam, out, table, rtol, stop):
    args = [spam] + SCENE + ["-output_dir", out, "-ts_rtol", repr(rtol), "-arkode_table", table]
    if stop:
        args += ["-output_stop", "true"]
    p = subprocess.run(args, capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit(f"{' '.join(args)}: exit {p.returncode}: {p.stderr.strip()[-300:]}")
    s = json.load(open(os.path.join(out, "summary.json")))
    with open(os.path.join(out, "steps.csv")) as f:
        cut = sum(1 for r in csv.DictReader(line for line in f if not line.startswith("#")) if r["limit"] == "output")
    return {"steps": s["steps"], "cut": cut, "drift": s["energy_rel_drift_max"], "mode": s["output_mode"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=str(ROOT / "build" / "spam-ark"))
    ap.add_argument("--readings", default=None, help="write the table docs/integrators.md quotes to this JSON")
    a = ap.parse_args()
    rows, runs = [], {}
    with tempfile.TemporaryDirectory(prefix="spam_dense_") as d:
        for name, table in TABLES:
            for rtol in RTOLS:
                st = one_run(a.spam_ark, os.path.join(d, "stop"), table, rtol, True)
                it = one_run(a.spam_ark, os.path.join(d, "interp"), table, rtol, False)
                runs[f"{table}_{rtol:g}"] = {"stopping": st, "interpolating": it}
                rows.append([f"{name}, " + f"{rtol:.0e}".replace("e-0", "e-"), f"{st['steps']} ({st['cut']})", f"{it['steps']}",
                             f"{st['drift']:.1e} / {it['drift']:.1e}".replace("e-0", "e-")])
                print(" | ".join(rows[-1]) + f"   [{st['mode']} / {it['mode']}]")
    if a.readings:
        chart_readings.write_json(a.readings, {"runs": runs, "table": chart_readings.table(
            ["table, rtol", "steps stopping (cut by outputs)", "steps interpolating",
             "max energy drift stopping / interpolating"], rows)})


if __name__ == "__main__":
    main()
