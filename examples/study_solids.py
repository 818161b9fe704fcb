#!/usr/bin/python3
"""The conservation readings of docs/solids.md: the plane waves' KE + IE and the rotors' L.

    examples/study_solids.py [--spam-ark build/spam-ark] [--out out/solids]

Runs into OUT/NAME/:
  planewave_transverse, planewave_longitudinal   options/planewave.opts (rtol 1e-10): the
      largest |E - E0| / |E0| of KE + IE (summary.json energy_rel_drift_max);
  rotor_R0, rotor_R2                             options/rotor.opts, one revolution: L/L0 of
      the body (timeseries.csv l_body0) after 60, 120 and 360 degrees;
  rotor_R2_Tij (rtol 1e-9), rotor_R2_Ti (rtol 1e-10): the largest |L/L0 - 1| over the
      revolution, the energy drift and the rejected steps;
  rotor_md_rtol1e-8, rotor_md_rtol1e-10          options/rotor-md.opts: the same.
Draws OUT/solids.png (|L/L0 - 1| against the rotation of every rotor run; the plane
waves' |E - E0|/|E0| against time) and writes OUT/solids.json (examples/chart_readings.py).
"""
import argparse
import csv
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
try:
    import numpy as np
    import matplotlib
except ImportError:
    if os.path.realpath(sys.executable) != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("study_solids.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import chart_readings  # noqa: E402

REV = 160 * math.pi  # one nominal revolution of the n = 8 rotor: 20 n pi
OPTS = {k: os.path.join(REPO, "options", f"{k}.opts") for k in ("planewave", "rotor", "rotor-md")}
ROTOR = ["-ts_max_time", f"{REV:.10g}", "-output_interval", f"{REV / 360:.10g}", "-snapshot_interval", "0"]
RUNS = [  # name, options, label
    ("planewave_transverse", ["-options_file", OPTS["planewave"], "-planewave_mode", "transverse", "-snapshot_interval", "0"],
     "transverse wave"),
    ("planewave_longitudinal", ["-options_file", OPTS["planewave"], "-planewave_mode", "longitudinal", "-snapshot_interval", "0"],
     "longitudinal wave"),
    ("rotor_R0", ["-options_file", OPTS["rotor"]] + ROTOR, "R0, continuity"),
    ("rotor_R2", ["-options_file", OPTS["rotor"], "-coordinates", "R2"] + ROTOR, "R2"),
    ("rotor_R2_Tij", ["-options_file", OPTS["rotor"], "-coordinates", "R2", "-angmom", "Tij", "-ts_rtol", "1e-9",
                      "-ts_atol", "1e-9"] + ROTOR, "R2 + T_ij, rtol 1e-9"),
    ("rotor_R2_Ti", ["-options_file", OPTS["rotor"], "-coordinates", "R2", "-angmom", "Ti", "-ts_rtol", "1e-10",
                     "-ts_atol", "1e-10"] + ROTOR, "R2 + T_i, rtol 1e-10"),
    ("rotor_md_rtol1e-8", ["-options_file", OPTS["rotor-md"], "-ts_rtol", "1e-8", "-ts_atol", "1e-8"] + ROTOR,
     "MD springs, rtol 1e-8"),
    ("rotor_md_rtol1e-10", ["-options_file", OPTS["rotor-md"], "-ts_rtol", "1e-10", "-ts_atol", "1e-10"] + ROTOR,
     "MD springs, rtol 1e-10"),
]


def run(a, name, opts):
    d = os.path.join(a.out, name)
    p = subprocess.run([a.spam_ark] + opts + ["-output_dir", d, "-output_overwrite", "-quiet"], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"study_solids: {name}: spam-ark exits {p.returncode}: {p.stderr.strip()[-300:]}")
    with open(os.path.join(d, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    ts = {k: np.array([float(r[k]) for r in rows]) for k in ("t", "total", "l_body0") if k in rows[0]}
    return d, ts, chart_readings.books(d)


def at(ts, degrees):
    t = degrees / 360 * REV
    return float(np.interp(t, ts["t"], ts["l_body0"]) / ts["l_body0"][0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    ap.add_argument("--out", default="out/solids")
    a = ap.parse_args()
    readings, dirs = {}, []
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.6))
    for k, (name, opts, label) in enumerate(RUNS):
        d, ts, books = run(a, name, opts)
        dirs.append(d)
        r = {"energy_rel_drift_max": books["energy_rel_drift_max"], "steps": books["steps"],
             "rejected_steps": books["rejected_steps"]}
        style = dict(color=f"C{k}", marker="osD^v<>p"[k % 8], ms=3, markevery=max(1, len(ts["t"]) // 12), lw=1.2)
        if name.startswith("planewave"):
            e = np.abs(ts["total"] / ts["total"][0] - 1)
            bx.semilogy(ts["t"][1:], np.maximum(e[1:], 1e-17), label=label, **style)
        else:
            ratio = ts["l_body0"] / ts["l_body0"][0]
            r.update({f"L_over_L0_{deg}": at(ts, deg) for deg in (60, 120, 360)})
            r["L_rel_err_max"] = float(np.max(np.abs(ratio - 1)))
            ax.semilogy(ts["t"][1:] / REV * 360, np.maximum(np.abs(ratio[1:] - 1), 1e-17), label=label, **style)
        readings[name.replace("-", "_")] = r
        print(name, " ".join(f"{k}={v:.4g}" for k, v in r.items() if v is not None), flush=True)
    ax.set_xlabel("nominal rotation (degrees)")
    ax.set_ylabel("|L / L0 - 1| of the body (floor 1e-17)")
    ax.set_title("Scenes rotor and rotor-md, 217 particles: angular momentum, one revolution", fontsize=10)
    bx.set_xlabel("time t (reduced units)")
    bx.set_ylabel("|E / E0 - 1|, E = KE + IE (floor 1e-17)")
    bx.set_title("Scene planewave, A = 0.25, rtol 1e-10: energy", fontsize=10)
    for x in (ax, bx):
        x.grid(True, which="both", alpha=0.3)
        x.legend(fontsize=7)
    fig.tight_layout()
    png = os.path.join(a.out, "solids.png")
    fig.savefig(png, dpi=110)
    chart_readings.write(png, readings, runs=dirs)
    print(f"png={png}")


if __name__ == "__main__":
    main()
