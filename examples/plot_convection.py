#!/usr/bin/python3
"""Chart a spam-ark Rayleigh-Benard run (Hoover & Hoover, CiSE 2001, Fig. 4).

Usage:
    examples/plot_convection.py DIR [-o OUT.png] [--t-bottom 1.25 --t-top 0.75]

DIR is the output directory of
    spam-ark -options_file options/convection.opts -output_dir DIR
and must hold manifest.json, summary.json, timeseries.csv and CSV snapshots (the files
the manifest lists, never a glob). The wall temperatures are those of the run
(-wall_ylo_temperature, -wall_yhi_temperature; the scene's defaults 1.25 and 0.75).

The figure (default DIR/convection.png) has
  * top:          the last snapshot, particles coloured by temperature T = (gamma-1) e,
                  velocity arrows, the walls drawn at y = 0 and y = H;
  * bottom left:  kinetic energy against time (log scale): decay or growth to a plateau;
  * bottom right: the heat rate per unit wall length into the fluid through the hot
                  wall and out through the cold one, in units of the conduction value
                  kappa (T_b - T_t) / H: their mean is the Nusselt number.

One line goes to stdout:
    Ra=<v> Ra_c=1707.76 Nu=<v> (mean over the last half) ke_final=<v> png=<path>

The functions rayleigh() and nusselt() are shared with examples/convection_sweep.py.
"""

import argparse
import csv
import json
import math
import os
import sys

RA_CRITICAL = 1707.76  # rigid-rigid walls, Boussinesq (Chandrasekhar), at k_c = 3.117 / H


def load(outdir):
    with open(os.path.join(outdir, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(outdir, "manifest.json")) as f:
        manifest = json.load(f)
    with open(os.path.join(outdir, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    series = {k: [float(r[k]) for r in rows] for k in rows[0]}
    snaps = [os.path.join(outdir, e["name"]) for e in manifest["files"] if e.get("kind") == "snapshot_csv" and "name" in e]
    return summary, series, snaps


def cell(summary):
    """(L, H, g, gamma, rho_mean) of the run: the box, the gravity and the lattice's mean
    density (the run's total mass over the box area)."""
    L, H = summary["box_len"][0], summary["box_len"][1]
    g = -summary["gravity_y"]
    gamma = summary["gas_gamma"]
    rho_mean = summary["n_particles"] * summary["mass"] / (L * H)
    return L, H, g, gamma, rho_mean


def rayleigh(summary, t_bottom, t_top):
    """Ra of the superadiabatic difference (Schwarzschild) and of the full difference:
    Ra = g alpha dT H^3 / (nu chi), alpha = 1/T_mean, nu = eta/rho_mean,
    chi = kappa/(rho_mean c_p), c_p = gamma/(gamma-1)."""
    L, H, g, gamma, rho = cell(summary)
    cp = gamma / (gamma - 1.0)
    nu = summary["viscosity_shear"] / rho
    chi = summary["conductivity"] / (rho * cp)
    scale = g / (0.5 * (t_bottom + t_top)) * H ** 3 / (nu * chi)
    dT = t_bottom - t_top
    return scale * (dT - g * H / cp), scale * dT


def heat_columns(series):
    """The timeseries columns of the heat rate into the fluid through the bottom (ylo) and
    top (yhi) walls (the wall books of walls.h)."""
    def find(face):
        names = [k for k in series if face in k and "heat" in k and "rate" in k]
        if not names:
            names = [k for k in series if face in k and "heat" in k]
        if not names:
            sys.exit(f"timeseries.csv has no heat-rate column of the {face} wall (columns: {', '.join(series)})")
        return names[0]
    return find("ylo"), find("yhi")


def nusselt(summary, series, t_bottom, t_top, t_from):
    """Nu = (mean heat flux through the walls) / (kappa (T_b - T_t) / H), the flux the
    mean of the heat in through the hot wall and out through the cold one, per unit wall
    length, averaged over the rows with t >= t_from. Returns (Nu, Nu_bottom, Nu_top, the
    per-row series of the mean in conduction units)."""
    L, H, g, gamma, rho = cell(summary)
    conduction = summary["conductivity"] * (t_bottom - t_top) / H * L
    cb, ct = heat_columns(series)
    qb = [q / conduction for q in series[cb]]
    qt = [-q / conduction for q in series[ct]]
    rows = [k for k, t in enumerate(series["t"]) if t >= t_from and k > 0]
    mean = lambda v: sum(v[k] for k in rows) / max(len(rows), 1)
    both = [0.5 * (a + b) for a, b in zip(qb, qt)]
    return mean(both), mean(qb), mean(qt), (qb, qt)


def snapshot(path):
    with open(path) as f:
        first = f.readline()
        t = float(first.split("=")[1]) if first.startswith("#") else float("nan")
        rows = list(csv.DictReader(f))
    cols = {k: [float(r[k]) for r in rows] for k in rows[0]}
    return t, cols


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("-o", "--out")
    ap.add_argument("--t-bottom", type=float, default=1.25)
    ap.add_argument("--t-top", type=float, default=0.75)
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    summary, series, snaps = load(a.dir)
    if not snaps:
        sys.exit("the run wrote no CSV snapshots (-snapshot_csv, -snapshot_interval)")
    L, H, g, gamma, rho = cell(summary)
    ra, ra_full = rayleigh(summary, a.t_bottom, a.t_top)
    t_end = series["t"][-1]
    nu, nub, nut, (qb, qt) = nusselt(summary, series, a.t_bottom, a.t_top, 0.5 * t_end)
    t, p = snapshot(snaps[-1])
    x = np.mod(np.array(p["x"]), L)
    y, T = np.array(p["y"]), (gamma - 1.0) * np.array(p["e"])
    vx, vy = np.array(p["vx"]), np.array(p["vy"])

    fig = plt.figure(figsize=(10, 8.5))
    ax = fig.add_axes([0.08, 0.45, 0.84, 0.46])
    sc = ax.scatter(x, y, c=T, cmap="coolwarm", s=max(4.0, 9000.0 / len(x)), vmin=a.t_top, vmax=a.t_bottom)
    # The flow drawn as the mass-weighted mean velocity of bins about h wide (4 x 4 lattice cells): single
    # particles also carry the noise of the mirror walls and of the seeded start.
    m = np.array(p["m"])
    nbx, nby = max(1, int(round(L / 4.0))), max(1, int(round(H / 4.0)))
    bx = np.clip((x / L * nbx).astype(int), 0, nbx - 1)
    by = np.clip((y / H * nby).astype(int), 0, nby - 1)
    M, U, V = np.zeros((nby, nbx)), np.zeros((nby, nbx)), np.zeros((nby, nbx))
    np.add.at(M, (by, bx), m)
    np.add.at(U, (by, bx), m * vx)
    np.add.at(V, (by, bx), m * vy)
    U, V = U / np.maximum(M, 1e-300), V / np.maximum(M, 1e-300)
    gx, gy = np.meshgrid((np.arange(nbx) + 0.5) * L / nbx, (np.arange(nby) + 0.5) * H / nby)
    vmax = float(np.max(np.hypot(U, V))) or 1.0
    ax.quiver(gx, gy, U, V, angles="xy", scale_units="xy", scale=vmax / (1.5 * L / nbx), width=0.003, color="k")
    for yw, name in ((0.0, f"hot wall T_b = {a.t_bottom:g}"), (H, f"cold wall T_t = {a.t_top:g}")):
        ax.axhline(yw, color="0.3", lw=2)
        ax.text(0.2, yw + (0.3 if yw == 0 else -0.8), name, fontsize=8)
    ax.set_xlim(0, L)
    ax.set_ylim(-0.5, H + 0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x (lattice units)")
    ax.set_ylabel("y (lattice units)")
    fig.colorbar(sc, ax=ax, label="temperature T = (gamma-1) e", shrink=0.8)
    ax.set_title(f"scene convection (CiSE 2001 Fig. 4): Ra = {ra:.4g} = {ra / RA_CRITICAL:.3g} Ra_c, Pr = "
                 f"{summary['viscosity_shear'] * summary['gas_gamma'] / (summary['gas_gamma'] - 1) / summary['conductivity']:.3g}, "
                 f"N = {len(x)}, t = {t:.4g}\narrows: mean velocity of {L / nbx:.3g} x {H / nby:.3g} bins (longest {vmax:.3g})", fontsize=10)

    ts = np.array(series["t"])
    ax1 = fig.add_axes([0.1, 0.06, 0.36, 0.28])
    ax1.semilogy(ts[1:], np.array(series["kinetic"])[1:], "C0-o", ms=2, label="SPAM kinetic energy")
    ax1.set_xlabel("time t")
    ax1.set_ylabel("kinetic energy (m = 1 units)")
    ax1.legend(fontsize=8)
    ax2 = fig.add_axes([0.56, 0.06, 0.38, 0.28])
    ax2.plot(ts[1:], qb[1:], "C3-s", ms=2, label="in through the hot wall")
    ax2.plot(ts[1:], qt[1:], "C0-^", ms=2, label="out through the cold wall")
    ax2.axhline(1.0, color="k", ls="--", lw=1, label="conduction (Nu = 1)")
    ax2.axvspan(0.5 * t_end, t_end, color="0.9", zorder=0)
    ax2.set_xlabel("time t")
    ax2.set_ylabel("heat rate / (kappa dT L / H)")
    ax2.set_title(f"Nu = {nu:.3f} (mean over the shaded half)", fontsize=9)
    ax2.legend(fontsize=8)
    out = a.out or os.path.join(a.dir, "convection.png")
    fig.savefig(out, dpi=110)
    print(f"Ra={ra:.6g} Ra_c={RA_CRITICAL} Nu={nu:.5g} Nu_bottom={nub:.5g} Nu_top={nut:.5g} "
          f"ke_final={series['kinetic'][-1]:.5g} png={out}")
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import chart_readings
    chart_readings.write(out, dict(chart_readings.books(a.dir), Ra=ra, Ra_c=RA_CRITICAL, Nu=nu, Nu_bottom=nub, Nu_top=nut,
                                   ke_final=float(series["kinetic"][-1])), runs=[a.dir])


if __name__ == "__main__":
    main()
