#!/usr/bin/python3
"""Why options/couette.opts uses Wendland C2: the Couette gas's square lattice at rest under
the Lucy kernel and under Wendland C2, both at h = 3, in the papers' equations
(-gas_scheme plain) and in the flow scheme (the default for a viscous gas).

    examples/couette_rest_lattice.py [--spam-ark build/spam-ark] [--workdir /tmp/couette-rest]
        [--t-end 128] [--readings docs/scenes/couette_rest_lattice.json]

Runs options/couette.opts with the upper wall at rest (-couette_speed 0) to t = --t-end with
each scheme and kernel and writes, per scheme and kernel, the kinetic energy at the first and
the last output row and its largest (timeseries.csv, 16 rows) as the readings
docs/scenes/couette.md quotes. An unstable lattice shows as a
kinetic energy grown by orders of magnitude from its round-off start; a stable one stays at it.
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import chart_readings  # noqa: E402
import spamread  # noqa: E402

KERNELS = ("lucy", "wendland_c2")
SCHEMES = ("plain", "flow")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    ap.add_argument("--workdir", default="/tmp/couette-rest")
    ap.add_argument("--t-end", type=float, default=128.0)
    ap.add_argument("--readings", help="write the readings JSON here")
    a = ap.parse_args()
    readings, runs = {"t_end": a.t_end}, []
    for scheme, kernel in ((s, k) for s in SCHEMES for k in KERNELS):
        out = os.path.join(a.workdir, f"{scheme}_{kernel}")
        cmd = [a.spam_ark, "-options_file", os.path.join(REPO, "options", "couette.opts"), "-couette_speed", "0",
               "-gas_scheme", scheme, "-kernel", kernel, "-ts_max_time", str(a.t_end), "-output_interval", str(a.t_end / 16),
               "-snapshot_interval", "0", "-quiet", "-output_dir", out, "-output_overwrite"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"couette_rest_lattice: {scheme} {kernel}: exit {p.returncode}: {p.stderr.strip()}")
        ts = spamread.Run(out).timeseries()
        r = readings.setdefault(scheme, {})[kernel] = {
            "ke_start": float(ts["kinetic"][0]), "ke_end": float(ts["kinetic"][-1]), "ke_max": float(ts["kinetic"].max())}
        print(f"{scheme} {kernel}: kinetic energy {r['ke_start']:.2e} at t = {ts['t'][0]:g}, largest {r['ke_max']:.2e}, "
              f"{r['ke_end']:.2e} at t = {ts['t'][-1]:g}")
        runs.append(out)
    if a.readings:
        chart_readings.write_json(a.readings, readings, runs)


if __name__ == "__main__":
    main()
