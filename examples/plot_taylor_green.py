#!/usr/bin/python3
"""Chart a spam-ark Taylor-Green run (-scene taylor-green): kinetic energy against time.

Usage:
    examples/plot_taylor_green.py DIR [-o OUT.png]

DIR is the output directory of
    spam-ark -options_file options/taylor-green.opts -output_dir DIR
The figure (default DIR/taylor-green.png) shows KE(t)/KE(0) from timeseries.csv (points)
against the continuum decay exp(-2 D nu k^2 t), nu = eta/rho, k = 2 pi / L (line), on a
log scale. One line goes to stdout: the fitted rate, the continuum rate, their relative
difference and the png. L, D, eta and the mass come from the run's options (defaults of
the scene: -taylorgreen_n 24, -dim 2, -viscosity_shear 2, -mass 1).
"""
import argparse
import csv
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402


def option(options, name, default):
    m = re.search(r"-%s (\S+)" % name, options)
    return float(m.group(1)) if m else default


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("dir")
    p.add_argument("-o", "--out")
    a = p.parse_args()
    man, _ = spam_manifest.open_run(a.dir, "plot_taylor_green.py")
    ts = spam_manifest.files(man, a.dir, "timeseries")
    path = ts[0][1] if ts else os.path.join(a.dir, "timeseries.csv")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    t = np.array([float(r["t"]) for r in rows])
    ke = np.array([float(r["kinetic"]) for r in rows])
    opts = man.get("options", "")
    L, dim = option(opts, "taylorgreen_n", 24), int(option(opts, "dim", 2))
    nu = option(opts, "viscosity_shear", 2.0) / option(opts, "mass", 1.0)
    k = 2 * math.pi / L
    rate = 2 * dim * nu * k * k
    fit = -np.polyfit(t, np.log(ke), 1)[0]
    fig, ax = plt.subplots(figsize=(7, 5))
    ax.semilogy(t * rate, ke / ke[0], "o", ms=4, color="tab:blue", label=f"SPAM (fitted rate {fit:.5g})")
    tt = np.linspace(0, t[-1], 200)
    ax.semilogy(tt * rate, np.exp(-rate * tt), "k-", label=f"continuum exp(-2D nu k^2 t), rate {rate:.5g}")
    ax.set_xlabel("t x 2 D nu k^2 (continuum e-foldings)")
    ax.set_ylabel("kinetic energy KE(t) / KE(0)")
    ax.set_title(f"Taylor-Green vortex: {dim}D, L = {L:g}, nu = {nu:g}, h = {option(opts, 'h', 3.0):g}")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    out = a.out or os.path.join(a.dir, "taylor-green.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"rate={fit:.6g} continuum={rate:.6g} relative_error={fit / rate - 1:+.4f} png={out}")
    chart_readings.write(out, dict(chart_readings.books(a.dir), rate=fit, continuum=rate, relative_error=fit / rate - 1),
                         runs=[a.dir])


if __name__ == "__main__":
    main()
