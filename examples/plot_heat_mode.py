#!/usr/bin/python3
"""Chart a spam-ark heat-mode run (-scene heat-mode): the mode's amplitude against time.

Usage:
    examples/plot_heat_mode.py DIR [-o OUT.png]

DIR is the output directory of
    spam-ark -options_file options/heat-mode.opts -output_dir DIR
(CSV snapshots; the files are those manifest.json lists). The amplitude e'(t) is the
projection 2/N sum (e_i - <e>) cos(k x_i(0)) of each snapshot's energies on the mode,
x_i(0) from the first snapshot. The figure (default DIR/heat-mode.png) shows e'(t)/e'(0)
(points) against the isochoric decay exp(-kappa k^2 t / (rho c_v)) (line) and the
isobaric one, kappa k^2 / (rho c_p) (dashed), c_v = 1/(gamma - 1), on a log scale.
L, gamma, kappa and the mass come from the run's options (scene defaults: -heatmode_n 24,
-conductivity 1, -mass 1; gamma 2 in 2D, else 1 + 2/D). One line goes to stdout.
"""
import argparse
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


def columns(path, names):
    with open(path) as f:
        lines = [line for line in f if not line.startswith("#")]
    head = lines[0].strip().split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:] if line.strip()])
    return [data[:, head.index(n)] for n in names]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("dir")
    p.add_argument("-o", "--out")
    a = p.parse_args()
    man, _ = spam_manifest.open_run(a.dir, "plot_heat_mode.py")
    snaps = spam_manifest.files(man, a.dir, "snapshot_csv")
    if len(snaps) < 3:
        sys.exit(f"plot_heat_mode.py: {a.dir}: needs CSV snapshots (-snapshot_csv, -snapshot_interval)")
    opts = man.get("options", "")
    dim = int(option(opts, "dim", 2))
    L = option(opts, "heatmode_n", 24)
    gamma = option(opts, "gas_gamma", 2.0 if dim == 2 else 1 + 2 / dim)
    kappa, rho = option(opts, "conductivity", 1.0), option(opts, "mass", 1.0)
    k = 2 * math.pi / L
    sigma_v = (gamma - 1) * kappa * k * k / rho
    (x0,) = columns(snaps[0][1], ["x"])
    t, amp = [], []
    for ti, path in snaps:
        (e,) = columns(path, ["e"])
        t.append(ti)
        amp.append(2 / len(e) * np.sum((e - e.mean()) * np.cos(k * x0)))
    t, amp = np.array(t), np.array(amp)
    fit = -np.polyfit(t, np.log(amp), 1)[0]
    fig, ax = plt.subplots(figsize=(7, 5))
    ax.semilogy(t * sigma_v, amp / amp[0], "o", ms=5, color="tab:red", label=f"SPAM (fitted rate {fit:.5g})")
    tt = np.linspace(0, t[-1], 200)
    ax.semilogy(tt * sigma_v, np.exp(-sigma_v * tt), "k-", label=f"isochoric exp(-kappa k^2 t/(rho c_v)), rate {sigma_v:.5g}")
    ax.semilogy(tt * sigma_v, np.exp(-sigma_v / gamma * tt), "k--", label=f"isobaric kappa k^2/(rho c_p), rate {sigma_v / gamma:.5g}")
    ax.set_xlabel("t x kappa k^2 / (rho c_v)")
    ax.set_ylabel("mode amplitude e'(t) / e'(0)")
    ax.set_title(f"Heat mode: {dim}D, L = {L:g}, gamma = {gamma:g}, kappa = {kappa:g}, h = {option(opts, 'h', 3.0):g}")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    out = a.out or os.path.join(a.dir, "heat-mode.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"rate={fit:.6g} isochoric={sigma_v:.6g} relative_error={fit / sigma_v - 1:+.4f} png={out}")
    chart_readings.write(out, dict(chart_readings.books(a.dir), rate=fit, isochoric=sigma_v, isobaric=sigma_v / gamma,
                                   relative_error=fit / sigma_v - 1, over_isobaric=fit / (sigma_v / gamma) - 1),
                         runs=[a.dir])


if __name__ == "__main__":
    main()
