#!/usr/bin/python3
"""Taylor-Green at Re = 100 against PySPH, the peer of the weakly compressible SPH schemes.

The same flow on both sides: the periodic Taylor-Green vortex at Re = U L / nu = 100 and
Mach U / c = 0.1, from its exact start to one e-folding of the kinetic energy (t_e =
L^2 / (16 pi^2 nu)); the measure is KE(t_e) / (KE(0) e^-1), 1 for the continuum.
  * spam-ark: the default viscous gas (the flow scheme), gamma = 2, Lucy's kernel with
    range h = 3 spacings, L x L unit lattice, rtol 1e-6 (as tests/run_taylor_green_flow.py);
  * PySPH (python3-pysph, its examples/taylor_green.py): the schemes given (EDAC, the
    entropically damped artificial compressibility of Ramachandran & Puri; TVF, the
    transport-velocity formulation of Adami, Hu & Adams), quintic spline with h = dx, so
    the kernel reaches 3 spacings as spam-ark's does; c0 = 10 U; its fixed step
    0.25 h / (c0 + U); n x n particles.
Both run on one core. Printed per n: the KE ratio of each code, spam-ark's error over the
peer's, and the run times (PySPH's own run time from its .info file, which leaves out its
one-off compilation; spam-ark's wall time from summary.json) with their ratio.
This is a measurement, not a test; the machine's load is printed with it.

Usage (spam-ark built in build/; python3-pysph installed: `tools/deps.sh --bench`):
    /usr/bin/python3 bench/run_taylor_green_pysph.py [--n 48,96] [--schemes edac,tvf]
        [--workdir DIR] [-o results.json]
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples"))
import chart_readings  # noqa: E402
RE, MACH, U, GAMMA, H = 100.0, 0.1, 0.1, 2.0, 3.0
PYSPH_EXAMPLE = "/usr/lib/python3/dist-packages/pysph/examples/taylor_green.py"


def spam(exe, n, work):
    """KE(t_e)/(KE0 e^-1) and the wall time of spam-ark's run on the n x n lattice."""
    nu = U * n / RE
    k = 2 * math.pi / n
    t_e = 1.0 / (4 * nu * k * k)
    out = work / f"spam_{n}"
    shutil.rmtree(out, ignore_errors=True)
    e0 = (U / MACH) ** 2 / (GAMMA * (GAMMA - 1.0))
    args = [exe, "-scene", "taylor-green", "-dim", "2", "-taylorgreen_n", str(n), "-taylorgreen_amplitude", str(U),
            "-material", "gas", "-gas_gamma", str(GAMMA), "-gas_e0", str(e0), "-viscosity_shear", str(nu),
            "-h", str(H), "-ts_max_time", str(t_e), "-output_interval", str(t_e / 10), "-snapshot_interval", "0",
            "-ts_rtol", "1e-6", "-quiet", "-output_dir", str(out)]
    subprocess.run(args, check=True, capture_output=True)
    s = json.loads((out / "summary.json").read_text())
    rows = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    return {"ke_ratio": float(rows["kinetic"][-1] / rows["kinetic"][0] / math.exp(-1.0)), "time_s": s["wall_time_s"],
            "rhs_evals": s["rhs_evals"], "ch_over_nu": H / nu}


def pysph(scheme, n, work):
    """The same measure from PySPH's example, and its run time (compilation left out)."""
    out = work / f"pysph_{scheme}_{n}"
    shutil.rmtree(out, ignore_errors=True)
    t_e = RE / (16 * math.pi ** 2)  # its L = U = 1
    cmd = [sys.executable, PYSPH_EXAMPLE, "--scheme", scheme, "--nx", str(n), "--re", str(RE), "--tf", f"{t_e:.8f}",
           "--pfreq", "1000000000", "-d", str(out)]
    subprocess.run(cmd, check=True, capture_output=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    d = np.load(out / "results.npz")
    info = json.loads((out / "taylor_green.info").read_text())
    # ke_ex follows the exact decay on the same particles: the ratio is the measure above.
    return {"ke_ratio": float(d["ke"][-1] / d["ke"][0] / (d["ke_ex"][-1] / d["ke_ex"][0])), "time_s": info["cpu_time"],
            "t_end": float(d["t"][-1])}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--exe", default=str(ROOT / "build/spam-ark"))
    p.add_argument("--n", default="48,96", help="particles per side (comma separated)")
    p.add_argument("--schemes", default="edac,tvf", help="PySPH schemes (comma separated)")
    p.add_argument("--workdir", default="/tmp/spam-tg-pysph")
    p.add_argument("-o", "--output", default=None, help="readings as JSON (examples/chart_readings.py: the pages quote them)")
    a = p.parse_args()
    if not os.path.exists(PYSPH_EXAMPLE):
        sys.exit(f"run_taylor_green_pysph: {PYSPH_EXAMPLE} not found (install python3-pysph)")
    work = Path(a.workdir)
    work.mkdir(parents=True, exist_ok=True)
    load = os.getloadavg()[0]
    res = {"re": RE, "mach": MACH, "runs": []}
    print(f"Taylor-Green, Re = {RE:g}, Mach {MACH:g}, to one e-folding of KE; load {load:.1f} on {os.cpu_count()} cores")
    print(f"{'n':>4} {'code':>14} {'KE(t_e)/cont.':>14} {'error':>9} {'run s':>8} {'err/peer':>9} {'time/peer':>10}")
    for n in (int(v) for v in a.n.split(",")):
        t0 = time.time()
        s = spam(a.exe, n, work)
        res["runs"].append({"n": n, "code": "spam-ark", **s})
        res[f"spam_{n}"] = s
        print(f"{n:>4} {'spam-ark':>14} {s['ke_ratio']:>14.4f} {s['ke_ratio'] - 1:>+9.4f} {s['time_s']:>8.1f}")
        for scheme in a.schemes.split(","):
            q = pysph(scheme, n, work)
            res["runs"].append({"n": n, "code": f"pysph-{scheme}", **q})
            res[f"pysph_{scheme}_{n}"] = dict(q, error_over_peer=abs(s["ke_ratio"] - 1) / abs(q["ke_ratio"] - 1),
                                               time_over_peer=s["time_s"] / q["time_s"])
            print(f"{n:>4} {'PySPH ' + scheme:>14} {q['ke_ratio']:>14.4f} {q['ke_ratio'] - 1:>+9.4f} {q['time_s']:>8.1f} "
                  f"{abs(s['ke_ratio'] - 1) / abs(q['ke_ratio'] - 1):>9.3f} {s['time_s'] / q['time_s']:>10.3f}")
        res[f"wall_all_{n}_s"] = time.time() - t0
    if a.output:
        chart_readings.write_json(a.output, res)
        print(f"readings in {a.output}")


if __name__ == "__main__":
    main()
