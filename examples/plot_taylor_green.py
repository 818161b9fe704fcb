#!/usr/bin/python3
"""Chart a spam-ark Taylor-Green run (-scene taylor-green): kinetic energy against time.

Usage:
    examples/plot_taylor_green.py DIR [DIR ...] [-o OUT.png]

DIR is the output directory of
    spam-ark -options_file options/taylor-green.opts -output_dir DIR
The figure (default DIR/taylor-green.png) shows KE(t)/KE(0) from timeseries.csv (points)
against the continuum decay exp(-2 D nu k^2 t), nu = eta/rho, k = 2 pi / L (line), on a
log scale. One line goes to stdout: the fitted rate, the continuum rate, their relative
difference and the png. L, D, eta and the mass come from the run's options (defaults of
the scene: -taylorgreen_n 24, -dim 2, -viscosity_shear 2, -mass 1).

With several DIRs (the same vortex at other resolutions, Reynolds numbers or schemes) each
run is one marker against the one continuum line exp(-x), x the time in e-foldings of
that run's own continuum rate; the readings (OUT.json) are per run, keyed L<n>_<scheme>
(and _re<Re> when the runs' Reynolds numbers differ):
Re = U L / nu, the fitted and continuum rates, and the KE at the end over the continuum's.
"""
import argparse
import csv
import json
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


def load(d):
    """One run's KE series and the continuum's rate, from its timeseries and options."""
    man, _ = spam_manifest.open_run(d, "plot_taylor_green.py")
    ts = spam_manifest.files(man, d, "timeseries")
    path = ts[0][1] if ts else os.path.join(d, "timeseries.csv")
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
    with open(os.path.join(d, "summary.json")) as f:
        scheme = json.load(f).get("gas_scheme", "")
    return dict(t=t, ke=ke, L=L, dim=dim, nu=nu, rate=rate, fit=fit, h=option(opts, "h", 3.0),
                re=option(opts, "taylorgreen_amplitude", 1e-4) * L / nu, scheme=scheme,
                ke_over_continuum=float(ke[-1] / ke[0] / math.exp(-rate * t[-1])))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("dir", nargs="+", help="one run, or several (each its own marker: the KE against the continuum "
                                          "in e-foldings of each run's own rate)")
    p.add_argument("-o", "--out")
    a = p.parse_args()
    runs = [load(d) for d in a.dir]
    if len(runs) == 1:
        fig, ax = plt.subplots(figsize=(7, 5))
    else:  # the second panel: KE over the continuum's, where a per cent shows
        fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5))
    xmax = 0.0
    for i, r in enumerate(runs):
        x = r["t"] * r["rate"]
        xmax = max(xmax, x[-1])
        if len(runs) == 1:
            label = f"SPAM (fitted rate {r['fit']:.5g})"
        else:
            label = (f"L = {r['L']:g}, Re = {r['re']:.4g}{', ' + r['scheme'] if r['scheme'] else ''}: "
                     f"KE / continuum at the end {r['ke_over_continuum']:.4f}")
        ax.semilogy(x, r["ke"] / r["ke"][0], "osD^v"[i % 5], ms=4, color=f"C{i}", label=label)
        if len(runs) > 1:
            ax2.plot(x, r["ke"] / r["ke"][0] / np.exp(-x), "osD^v"[i % 5] + "-", ms=4, lw=0.8, color=f"C{i}",
                     label=f"L = {r['L']:g}, Re = {r['re']:.4g}{', ' + r['scheme'] if r['scheme'] else ''}")
    xx = np.linspace(0, xmax, 200)
    if len(runs) == 1:
        r = runs[0]
        ax.semilogy(xx, np.exp(-xx), "k-", label=f"continuum exp(-2D nu k^2 t), rate {r['rate']:.5g}")
        ax.set_title(f"Taylor-Green vortex: {r['dim']}D, L = {r['L']:g}, nu = {r['nu']:g}, h = {r['h']:g}")
    else:
        ax.semilogy(xx, np.exp(-xx), "k-", label="continuum exp(-2D nu k^2 t)")
        ax.set_title(f"scene taylor-green: KE against the continuum decay, {runs[0]['dim']}D, h = {runs[0]['h']:g}")
        ax2.axhline(1.0, color="k", lw=1)
        ax2.set_xlabel("t x 2 D nu k^2 (continuum e-foldings)")
        ax2.set_ylabel("KE(t) / (KE(0) exp(-2 D nu k^2 t))")
        ax2.set_title("scene taylor-green: KE over the continuum's")
        ax2.legend(fontsize=8)
        ax2.grid(True, alpha=0.3)
    ax.set_xlabel("t x 2 D nu k^2 (continuum e-foldings)")
    ax.set_ylabel("kinetic energy KE(t) / KE(0)")
    ax.legend(fontsize=8 if len(runs) > 1 else 10)
    ax.grid(True, which="both", alpha=0.3)
    out = a.out or os.path.join(a.dir[0], "taylor-green.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    if len(runs) == 1:
        r = runs[0]
        print(f"rate={r['fit']:.6g} continuum={r['rate']:.6g} relative_error={r['fit'] / r['rate'] - 1:+.4f} png={out}")
        chart_readings.write(out, dict(chart_readings.books(a.dir[0]), rate=r["fit"], continuum=r["rate"],
                                       relative_error=r["fit"] / r["rate"] - 1), runs=[a.dir[0]])
        return
    readings = {}
    several_re = len({round(r["re"], 6) for r in runs}) > 1
    for d, r in zip(a.dir, runs):
        key = f"L{r['L']:g}" + (f"_{r['scheme']}" if r["scheme"] else "") + (f"_re{r['re']:.4g}" if several_re else "")
        readings[key] = dict(chart_readings.books(d), L=r["L"], re=r["re"], rate=r["fit"], continuum=r["rate"],
                             ke_over_continuum=r["ke_over_continuum"], t_over_e_folding=float(r["t"][-1] * r["rate"]))
        print(f"{key}: Re {r['re']:.4g}, KE at the end over the continuum's {r['ke_over_continuum']:.4f} "
              f"({r['t'][-1] * r['rate']:.3g} e-foldings)")
    print(f"png={out}")
    chart_readings.write(out, readings, runs=list(a.dir))


if __name__ == "__main__":
    main()
