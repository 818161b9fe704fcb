#!/usr/bin/python3
"""Chart a spam-ark Sod shock-tube run against the exact Riemann solution.

Usage:
    /usr/bin/python3 examples/plot_sod.py DIR [-o OUT.png] [--window 0.5]

DIR is the output directory of
    spam-ark -options_file options/sod.opts -output_dir DIR
(any -dim; CSV snapshots needed). The last CSV snapshot the manifest lists is drawn:
density, velocity, pressure p = (gamma - 1) rho e (rho the summed density) and energy per
unit mass e against x, in the units of the classical tube (x / n at t / n, n = -sod_n:
the solution depends on x/t only). 1D: every particle a dot; 2D and 3D: every particle a
faint dot and the means of slices one lattice spacing thick as dots. The exact solution
(tests/shock_exact.py, Newton's iteration for p*) is the line. Densities and pressures are
shown in units of the left state (divided by -mass).

One line goes to stdout: t, N, the plateau means and png=<path>. Beside the chart, OUT.json
(examples/chart_readings.py) holds what the page quotes: the plateaus and fronts as
tests/run_sod.py measures them (slice means; plateaus leave 2h at each end of the star
regions) and the run's steps and energy drift. A missing or malformed input is one line on
stderr and exit status 2.
"""
import argparse
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests"))

import numpy as np  # noqa: E402
import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402
from run_sod import measure, profile  # noqa: E402
from shock_exact import Riemann  # noqa: E402


def fail(msg):
    sys.stderr.write("plot_sod: error: %s\n" % " ".join(str(msg).split()))
    sys.exit(2)


def read_snapshot(path, dim):
    with open(path) as f:
        first = f.readline()
        if not first.startswith("# t="):
            fail("%s: no '# t=' line" % path)
        t = float(first.split("=")[1])
        rows = list(csv.DictReader(f))
    if not rows or "rho_sum" not in rows[0] or "e" not in rows[0]:
        fail("%s: needs the columns rho_sum and e (a -material gas run)" % path)
    col = {k: np.array([float(r[k]) for r in rows]) for k in ("x", "vx", "e", "rho_sum")}
    return t, col


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dir")
    ap.add_argument("-o", "--out")
    ap.add_argument("--window", type=float, default=0.5, help="half-width of the x range drawn (tube units)")
    a = ap.parse_args()
    man, sm = spam_manifest.open_run(a.dir, "plot_sod", scene="sod")
    snaps = spam_manifest.files(man, a.dir, "snapshot_csv")
    if not snaps:
        fail("%s: no CSV snapshot (run with -snapshot_csv true and -snapshot_interval > 0)" % a.dir)
    dim, h, gamma = int(sm["dim"]), float(sm["h"]), float(sm["gas_gamma"])
    n, mass = spam_manifest.option(man, "sod_n", 200.0), spam_manifest.option(man, "mass", 1.0)
    t, c = read_snapshot(snaps[-1][1], dim)
    if t <= 0:
        fail("the last snapshot is at t = 0")
    ts, x = t / n, c["x"] / n
    rho, u, e = c["rho_sum"] / mass, c["vx"], c["e"]
    p = (gamma - 1.0) * rho * e
    exact = Riemann((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), gamma)
    xx = np.linspace(-a.window, a.window, 4001)
    er, eu, ep = exact.sample(xx / ts)
    ee = ep / ((gamma - 1.0) * er)
    fields = [("density rho / rho_L", rho, er), ("velocity u / sqrt(p_L/rho_L)", u, eu),
              ("pressure p / p_L", p, ep), ("energy per unit mass e / (p_L/rho_L)", e, ee)]
    keys, inv, cnt = np.unique(np.floor(c["x"]).astype(int), return_inverse=True, return_counts=True)

    def slices(v):
        return np.bincount(inv, v) / cnt
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True)
    for ax, (label, v, ev) in zip(axes.flat, fields):
        m = np.abs(x) <= a.window
        if dim == 1:
            ax.plot(x[m], v[m], "o", ms=2.5, color="tab:blue", label="SPAM particles")
        else:
            ax.plot(x[m], v[m], ".", ms=1, color="tab:blue", alpha=0.15, label="SPAM particles")
            xs, vs = slices(c["x"]) / n, slices(v)
            ms = np.abs(xs) <= a.window
            ax.plot(xs[ms], vs[ms], "o", ms=2.5, color="tab:blue", label="SPAM slice means")
        ax.plot(xx, ev, "-", color="black", lw=1.2, label="exact (Riemann)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("x / L (tube units: x / n, n = %g lattice spacings)" % n)
    axes[0, 0].legend(loc="upper right", fontsize=8)
    fig.suptitle("Scene sod, %dD: N = %d, h = %g spacings = %.4f L, gamma = %g, t = %.4g L/sqrt(p_L/rho_L)"
                 % (dim, sm["n_particles"], h, h / n, gamma, ts))
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "sod.png")
    fig.savefig(out, dpi=110)
    s = exact.speeds()
    star = (x > s["left_tail"] * ts + 2 * h / n) & (x < s["contact"] * ts - 2 * h / n)
    if star.any():
        print("t=%.6g N=%d rho*L=%.5f (exact %.5f) p*=%.5f (exact %.5f) png=%s"
              % (ts, sm["n_particles"], rho[star].mean(), exact.rho_star_l, p[star].mean(), exact.p_star, out))
    else:  # h too coarse for a plateau 2h clear of the fan tail and the contact
        print("t=%.6g N=%d rho*L plateau narrower than 4h png=%s" % (ts, sm["n_particles"], out))
    chart_readings.write(out, readings(snaps[-1][1], n, h, sm), runs=[a.dir])


def readings(snapshot, n, h, sm):
    """The test's measures of one run: plateaus (value, exact, relative error) and the
    fronts' offsets from the exact positions in units of h."""
    t, x, rho, u, p = profile(snapshot, n)
    plateaus, fronts = measure(t, x, rho, u, p, h / n)
    out = {"dim": int(sm["dim"]), "n_particles": sm["n_particles"], "h": h, "sod_n": n, "h_over_n": h / n,
           "steps": sm.get("steps"), "rhs_evals": sm.get("rhs_evals"),
           "energy_rel_drift_max": sm.get("energy_rel_drift_max")}
    names = {"u*": "u_star", "p*": "p_star", "rho*L": "rho_star_l", "rho*R": "rho_star_r"}
    for k, (got, want) in plateaus.items():
        out[names[k]] = {"value": got, "exact": want, "rel": got / want - 1.0}
    for k, (got, want) in fronts.items():
        out[k.replace(" ", "_")] = {"exact": want, "offset_h": [(g - want) / (h / n) for g in got]}
    return out


if __name__ == "__main__":
    main()
