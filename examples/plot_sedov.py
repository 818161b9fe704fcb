#!/usr/bin/python3
"""Chart a spam-ark Sedov-Taylor blast run against the self-similar solution.

Usage:
    /usr/bin/python3 examples/plot_sedov.py DIR [-o OUT.png]

DIR is the output directory of
    spam-ark -options_file options/sedov.opts -output_dir DIR
(2D or 3D; CSV snapshots needed). Left: the summed density of every particle against its
distance from the centre (dots) at up to four snapshot times, with the self-similar
profile rho0 g(r/R(t)) (tests/shock_exact.py: the Sedov ODEs integrated from the strong
shock, xi0 from the energy integral) as a solid line and that profile averaged by the
kernel across the shell (what a summed density of the exact field gives) dashed. Right:
the shock radius of every snapshot, measured as the outer radius where the radially
binned density falls to the mean of its peak and the ambient (dots), and the same
estimator on the kernel-averaged exact profile (crosses), against the power law
R = xi0 (E0 t^2 / rho0)^(1/(D+2)) (line), log-log.

One line goes to stdout: xi0, the last radius and peak against the exact, png=<path>.
A missing or malformed input is one line on stderr and exit status 2.
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
from shock_exact import half_level_radius, sedov_profile, sedov_smoothed_density, sedov_xi0  # noqa: E402

BIN = 0.5  # radial bins of the radius estimator (lattice spacings)


def fail(msg):
    sys.stderr.write("plot_sedov: error: %s\n" % " ".join(str(msg).split()))
    sys.exit(2)


def radii_and_density(path, dim, centre, mass):
    with open(path) as f:
        first = f.readline()
        if not first.startswith("# t="):
            fail("%s: no '# t=' line" % path)
        t = float(first.split("=")[1])
        rows = list(csv.DictReader(f))
    if not rows or "rho_sum" not in rows[0]:
        fail("%s: needs the column rho_sum (-density summation)" % path)
    x = np.array([[float(r[a]) for a in "xyz"[:dim]] for r in rows])
    return t, np.linalg.norm(x - centre, axis=1), np.array([float(r["rho_sum"]) for r in rows]) / mass


def binned(r, rho):
    b = np.floor(r / BIN).astype(int)
    cnt = np.bincount(b)
    s = np.bincount(b, rho)
    ok = cnt > 0
    return ((np.arange(len(cnt)) + 0.5) * BIN)[ok], s[ok] / cnt[ok]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dir")
    ap.add_argument("-o", "--out")
    a = ap.parse_args()
    man, sm = spam_manifest.open_run(a.dir, "plot_sedov", scene="sedov")
    snaps = [(t, p) for t, p in spam_manifest.files(man, a.dir, "snapshot_csv") if t and t > 0]
    if not snaps:
        fail("%s: no CSV snapshot after t = 0" % a.dir)
    dim, h, gamma = int(sm["dim"]), float(sm["h"]), float(sm["gas_gamma"])
    n = spam_manifest.option(man, "sedov_n", 20.0 if dim == 3 else 48.0)
    e0, mass = spam_manifest.option(man, "sedov_energy", 1e4), spam_manifest.option(man, "mass", 1.0)
    xi0 = sedov_xi0(dim, gamma)
    prof = sedov_profile(dim, gamma)
    lam, g = prof[0], prof[2]
    shown = [snaps[int(round(k))][1] for k in np.linspace(0, len(snaps) - 1, min(4, len(snaps)))]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 7))
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, len(shown)))
    ts, rm, rs = [], [], []
    for t, path in snaps:
        t, r, rho = radii_and_density(path, dim, 0.5 * n, mass)
        R = xi0 * (e0 * t * t / mass) ** (1.0 / (dim + 2))
        grid = np.arange(0.0, R + 2 * h, 0.05)
        smooth = sedov_smoothed_density(grid, R, dim, gamma, h, prof)
        r_half, peak = half_level_radius(*binned(r, rho))
        r_sm, peak_sm = half_level_radius(grid, smooth)
        ts.append(t)
        rm.append(r_half)
        rs.append(r_sm)
        if path in shown:
            col = colours[shown.index(path)]
            ax.plot(r, rho, ".", ms=1.5, color=col, alpha=0.35)
            ax.plot(np.concatenate([lam[::-1] * R, [R, R, grid[-1]]]), np.concatenate([g[::-1], [g[0], 1.0, 1.0]]),
                    "-", color=col, lw=1.2, label="t = %.3g: exact (R = %.2f)" % (t, R))
            ax.plot(grid, smooth, "--", color=col, lw=1.0, label="t = %.3g: exact, kernel-averaged" % t)
    limit = (gamma + 1) / (gamma - 1)
    ax.axhline(limit, color="grey", lw=0.8, ls=":")
    ax.set_xlim(0, max(rs) + 2 * h)
    ax.text(ax.get_xlim()[1], limit, "strong-shock limit (gamma+1)/(gamma-1) = %.3g " % limit, va="bottom", ha="right", fontsize=8)
    ax.set_xlabel("distance from the centre r (lattice spacings)")
    ax.set_ylabel("summed density rho / rho0 (particles: dots)")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    ax.grid(alpha=0.3)
    tt = np.geomspace(min(ts), max(ts), 100)
    bx.loglog(tt, xi0 * (e0 * tt * tt / mass) ** (1.0 / (dim + 2)), "-", color="black",
              label="xi0 (E0 t^2/rho0)^(1/%d), xi0 = %.4f" % (dim + 2, xi0))
    bx.loglog(ts, rs, "x", color="tab:orange", label="half-level radius of the kernel-averaged exact profile")
    bx.loglog(ts, rm, "o", color="tab:blue", ms=4, label="half-level radius, SPAM")
    slope = np.polyfit(np.log(ts), np.log(rm), 1)[0] if len(ts) > 1 else float("nan")
    bx.set_xlabel("time t (reduced units)")
    bx.set_ylabel("shock radius R (lattice spacings)")
    bx.set_title("fitted exponent %.3f (self-similar %.3f)" % (slope, 2.0 / (dim + 2)), fontsize=10)
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3, which="both")
    fig.suptitle("Scene sedov, %dD: N = %d (%d^%d), h = %g, gamma = %.4g, E0 = %g"
                 % (dim, sm["n_particles"], n, dim, h, gamma, e0))
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "sedov.png")
    fig.savefig(out, dpi=110)
    print("xi0=%.5f t=%.4g R=%.3f (smoothed exact %.3f, power law %.3f) peak=%.3f (smoothed exact %.3f, limit %.3g) exponent=%.4f png=%s"
          % (xi0, ts[-1], rm[-1], rs[-1], xi0 * (e0 * ts[-1] ** 2 / mass) ** (1.0 / (dim + 2)), peak, peak_sm, limit, slope, out))
    chart_readings.write(out, dict(chart_readings.books(a.dir), xi0=xi0, t=ts[-1], R=rm[-1], R_smoothed_exact=rs[-1],
                                   R_power_law=xi0 * (e0 * ts[-1] ** 2 / mass) ** (1.0 / (dim + 2)),
                                   R_power_law_over_h=xi0 * (e0 * ts[-1] ** 2 / mass) ** (1.0 / (dim + 2)) / h,
                                   peak=peak, peak_smoothed_exact=peak_sm, limit=limit, exponent=slope), runs=[a.dir])


if __name__ == "__main__":
    main()
