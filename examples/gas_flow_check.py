#!/usr/bin/env python3
"""Measures the gas flow scheme against the plain one on the two flows of docs/gas-flow.md
and prints a markdown table (the page's numbers come from this script, not by hand):

  shear mode: vx = U sin(k y) on the 32 x 32 unit lattice, periodic, gamma = 2, e = 1
  (P ~ 1, c = 1.41), nu = 0.035 (c h / nu = 121), to t = 300; the amplitude A(t_end) of
  the sin(k y) mode of vx against exp(-nu k^2 t) and against the lattice's own viscous
  operator (tests/lattice_modes.py is the theory of that operator; here its rate at
  32^2 is taken from the run at c h / nu = 0.12, where pressure does nothing);
  Taylor-Green: Re = 100, Mach 0.1, L = 48 (tests/run_taylor_green_flow.py at two
  resolutions): KE at one e-folding over the continuum.

Usage: /usr/bin/python3 examples/gas_flow_check.py [--spam-ark build/spam-ark] [--workdir DIR]
"""
import argparse
import csv
import glob
import math
import os
import subprocess
import tempfile

KERNELS = ("lucy", "cubic_spline", "quintic_spline", "wendland_c2", "wendland_c4", "wendland_c6")


def shear(binary, work, kernel, scheme, e=1.0, nu=0.035, n=32, t_end=300.0, U=0.01):
    d = os.path.join(work, f"shear_{kernel}_{scheme}_{e:g}")
    path = os.path.join(work, f"shear_{e:g}.csv")
    with open(path, "w") as f:
        f.write("x,y,vx,vy,e\n")
        for j in range(n):
            for i in range(n):
                f.write(f"{i + 0.5},{j + 0.5},{U * math.sin(2 * math.pi * (j + 0.5) / n)},0,{e}\n")
    cmd = [binary, "-scene", "file", "-file_path", path, "-dim", 2, "-box_len", n, "-material", "gas", "-gas_gamma", 2,
           "-viscosity_shear", nu, "-h", 3, "-kernel", kernel, "-gas_scheme", scheme, "-ts_max_time", t_end,
           "-output_interval", t_end, "-snapshot_interval", t_end, "-snapshot_csv", "-output_dir", d, "-output_overwrite"]
    r = subprocess.run([str(x) for x in cmd], capture_output=True, text=True)
    if r.returncode:
        return float("nan")
    last = sorted(glob.glob(os.path.join(d, "particles_*.csv")))[-1]
    k = 2 * math.pi / n
    rows = list(csv.DictReader(line for line in open(last) if not line.startswith("#")))
    return sum(float(p["vx"]) * math.sin(k * float(p["y"])) for p in rows) * 2 / len(rows) / U


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spam-ark", default="build/spam-ark")
    ap.add_argument("--workdir", default=None)
    a = ap.parse_args()
    work = a.workdir or tempfile.mkdtemp(prefix="gas_flow_")
    nu, k, t = 0.035, 2 * math.pi / 32, 300.0
    exact = math.exp(-nu * k * k * t)
    print(f"Shear mode, 32^2, c h / nu = {math.sqrt(2) * 3 / nu:.0f}, t = {t:g}: amplitude (exact {exact:.4f}); "
          "rate = ln A / ln A_exact\n")
    print("| kernel | plain A | plain rate | flow A | flow rate | flow rate at c h / nu = 0.12 |")
    print("|---|---|---|---|---|---|")
    for kern in KERNELS:
        p, f, lo = shear(a.spam_ark, work, kern, "plain"), shear(a.spam_ark, work, kern, "flow"), shear(a.spam_ark, work, kern, "flow", e=1e-6)
        rate = lambda A: math.log(A) / math.log(exact) if A > 0 else float("nan")  # noqa: E731
        print(f"| {kern} | {p:+.4f} | {rate(p):.3f} | {f:+.4f} | {rate(f):.3f} | {rate(lo):.3f} |")


if __name__ == "__main__":
    main()
