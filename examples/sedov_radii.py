#!/usr/bin/python3
"""The Sedov blast's radius three ways, from spam-ark runs' CSV snapshots (2D or 3D).

Usage:
    /usr/bin/python3 examples/sedov_radii.py DIR [DIR ...] [--readings FILE]

For every snapshot after t = 0 of every run directory (-scene sedov, CSV snapshots):
- R_half: the half-level radius of plot_sedov.py and tests/run_sedov.py (radial bins 0.5
  wide of the summed density; the outer radius where it falls to the mean of its peak and
  the ambient 1);
- R_moment: the radius of the self-similar blast whose mass has the particles' second
  moment about the centre. Mass stays on the particles, so
      I2(t) = sum_i m_i (|r_i(t) - c|^2 - |r_i(0) - c|^2)
  (no kernel, no binning), and for the self-similar density rho0 g(r/R)
      I2 = sigma rho0 R^(D+2) C,  C = int_0^1 l^(D+1) g(l) dl - 1/(D+2),
  sigma = 2 pi (2D) or 4 pi (3D), so R_moment = (I2 / (sigma rho0 C))^(1/(D+2)).
  A symmetric spreading of the mass (a kernel's averaging, a viscous shock's width)
  leaves I2 unchanged: for f = rho - rho0, int |x|^2 (K*f) = int |y|^2 f + s^2 int f and
  int f = 0 (mass is conserved). So R_moment carries none of the half level's bias from
  the front's width; it measures where the mass went;
- R_exact = xi0 (E0 t^2/rho0)^(1/(D+2)) (tests/shock_exact.py).
Then, per run, the time offset t0 and the space offset dR fitted to R_moment (and to
R_half) over the snapshots: R = R_exact(t - t0) and R = R_exact(t) + dR, least squares,
with the rms residual of each: a blast started from a blob of finite size is the point
blast late by a constant t0 (its lead falls as t^-1/2 in 2D), a bias of the estimator or a
front of constant structure leads by a constant dR.
One line per snapshot goes to stdout; --readings writes them with the fits as JSON.
"""
import argparse
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests"))

import numpy as np  # noqa: E402

import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402
from shock_exact import half_level_radius, sedov_profile, sedov_xi0  # noqa: E402

BIN = 0.5


def snapshot(path, dim):
    with open(path) as f:
        t = float(f.readline().split("=")[1])
        rows = list(csv.DictReader(f))
    x = np.array([[float(r[a]) for a in "xyz"[:dim]] for r in rows])
    return t, x, np.array([float(r["m"]) for r in rows]), np.array([float(r["rho_sum"]) for r in rows])


def moment_constant(dim, gamma):
    """C = int_0^1 l^(D+1) g dl - 1/(D+2) of the self-similar density g (l from 1 down)."""
    l, _, g, _ = sedov_profile(dim, gamma)
    return -np.trapz(l ** (dim + 1) * g, l) - 1.0 / (dim + 2)


def fit_offsets(ts, rs, xi0, e0, dim):
    """(t0, rms) of R = R_exact(t - t0) and (dR, rms) of R = R_exact(t) + dR."""
    ts, rs = np.asarray(ts), np.asarray(rs)
    rex = xi0 * (e0 * ts ** 2) ** (1.0 / (dim + 2))
    dr = float(np.mean(rs - rex))
    # R_exact(t - t0) = R  <=>  t - t0 = sqrt((R/xi0)^(D+2)/e0): t0 per snapshot, then the mean.
    t_of_r = np.sqrt((rs / xi0) ** (dim + 2) / e0)
    t0 = float(np.mean(ts - t_of_r))
    res_t = rs - xi0 * (e0 * (ts - t0) ** 2) ** (1.0 / (dim + 2))
    res_r = rs - rex - dr
    return (t0, float(np.sqrt(np.mean(res_t ** 2)))), (dr, float(np.sqrt(np.mean(res_r ** 2))))


def run_radii(d):
    man, sm = spam_manifest.open_run(d, "sedov_radii", scene="sedov")
    snaps = [(t, p) for t, p in spam_manifest.files(man, d, "snapshot_csv")]
    dim, gamma = int(sm["dim"]), float(sm["gas_gamma"])
    n = spam_manifest.option(man, "sedov_n", 20.0 if dim == 3 else 48.0)
    e0 = spam_manifest.option(man, "sedov_energy", 1e4)
    xi0, cm = sedov_xi0(dim, gamma), moment_constant(dim, gamma)
    sigma = {2: 2.0 * np.pi, 3: 4.0 * np.pi}[dim]
    centre = 0.5 * n
    _, x0, m0, _ = snapshot(snaps[0][1], dim)
    base = float(np.sum(m0 * np.sum((x0 - centre) ** 2, axis=1)))
    rows = []
    for t, path in snaps[1:]:
        t, x, m, rho = snapshot(path, dim)
        r = np.linalg.norm(x - centre, axis=1)
        b = np.floor(r / BIN).astype(int)
        cnt, s = np.bincount(b), np.bincount(b, rho / m)
        ok = cnt > 0
        r_half, peak = half_level_radius(((np.arange(len(cnt)) + 0.5) * BIN)[ok], s[ok] / cnt[ok])
        i2 = float(np.sum(m * r * r)) - base
        r_mom = (i2 / (sigma * 1.0 * cm)) ** (1.0 / (dim + 2))
        r_ex = xi0 * (e0 * t * t) ** (1.0 / (dim + 2))
        rows.append({"t": t, "R_exact": r_ex, "R_half": r_half, "R_moment": r_mom, "peak": peak,
                     "half_err": r_half / r_ex - 1.0, "moment_err": r_mom / r_ex - 1.0})
    by_time = {("t%.4g" % q["t"]).replace(".", "_"): q for q in rows}  # quotable keys: t12, t4_147
    ts = [q["t"] for q in rows]
    fits = {}
    for key in ("R_half", "R_moment"):
        (t0, rt), (dr, rr) = fit_offsets(ts, [q[key] for q in rows], xi0, e0, dim)
        fits[key] = {"t0": t0, "t0_rms": rt, "dR": dr, "dR_rms": rr}
    return {"dim": dim, "n": n, "h": float(sm["h"]), "xi0": xi0, "C": cm, "snapshots": rows, "at": by_time, "fits": fits,
            "wall_time_s": sm.get("wall_time_s"), "rhs_evals": sm.get("rhs_evals"), "n_particles": sm.get("n_particles")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--readings")
    a = ap.parse_args()
    out = {}
    for d in a.dirs:
        res = run_radii(d)
        out[os.path.basename(os.path.normpath(d)).replace(".", "_")] = res  # a dotted key could not be quoted
        for q in res["snapshots"]:
            print(f"{d}: t = {q['t']:.4g}: R_exact {q['R_exact']:.3f}, R_half {q['R_half']:.3f} ({q['half_err']:+.2%}), "
                  f"R_moment {q['R_moment']:.3f} ({q['moment_err']:+.2%}), peak {q['peak']:.3f}")
        for key, f in res["fits"].items():
            print(f"{d}: {key}: t0 = {f['t0']:+.4f} (rms {f['t0_rms']:.3f}), dR = {f['dR']:+.3f} (rms {f['dR_rms']:.3f})")
    if a.readings:
        chart_readings.write_json(a.readings, out, runs=a.dirs)


if __name__ == "__main__":
    main()
