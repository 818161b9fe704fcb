#!/usr/bin/python3
"""The Sedov blast's radius three ways, from spam-ark runs' CSV snapshots (2D or 3D).

Usage:
    /usr/bin/python3 examples/sedov_radii.py DIR [DIR ...] [--readings FILE] [--reference-times T,T] [--bin W]

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
- R_exact = xi0 (E0 t^2/rho0)^(1/(D+2)) (tests/shock_exact.py);
- I2 over the inviscid I2 the run's own energies give (the virial: inviscid_moment), and the
  radius that inviscid I2 would give: what I2 holds beyond it is the viscosity's stress
  (tests/run_sedov_virial.py), which makes R_moment lead;
- R_front: the shock radius whose self-similar profile, averaged by the kernel the way the
  run's summation averages it (the blast's own geometry, each point's own range at the
  adaptive and evolved ranges), has the particles' half level; and R_front_spread, the
  same with that average spread further by a Gaussian fitted to the particles' lower peak
  (the viscosity widens the front beyond the kernel's average, and the half level of a
  lower peak lies further out), with the run's kernel. The reference is slow at the
  adaptive range (a table of ranges): --reference-times limits it to some snapshots,
  --no-reference skips it;
- two positions of the front that no kernel averages (kernel_free): R_velocity, the half
  level of the binned radial velocity (the particles carry v; the self-similar step has its
  half level at R), and shell_displacement, the mean distance by which the particles that
  started between 0.7 R and 0.98 R lie beyond where the self-similar flow puts the gas that
  started there (a shell displaced by d puts the shock's equal-mass position about
  d rho2/(rho2 - rho0) ahead).
- energy_inside_half: the share of the blast's energy, sum m (v^2/2 + e - e0) with the
  ambient e0 subtracted, held by the particles within R_exact/2, beside the self-similar
  share (shock_exact.sedov_energy_fraction) and energy_half_bound's bound on the difference.
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
from shock_exact import (half_level_radius, sedov_gathered_adaptive, sedov_gathered_density,  # noqa: E402
                         sedov_energy_fraction, sedov_profile, sedov_xi0)

BIN = 0.5


def snapshot(path, dim, extra=False):
    """(t, x, m, rho_sum) of a CSV snapshot, rows in particle id order; with extra, also v
    and e (the internal energy per unit mass)."""
    with open(path) as f:
        t = float(f.readline().split("=")[1])
        rows = list(csv.DictReader(f))
    rows.sort(key=lambda r: int(r["id"]))
    x = np.array([[float(r[a]) for a in "xyz"[:dim]] for r in rows])
    out = (t, x, np.array([float(r["m"]) for r in rows]), np.array([float(r["rho_sum"]) for r in rows]))
    if extra:
        out += (np.array([[float(r["v" + a]) for a in "xyz"[:dim]] for r in rows]), np.array([float(r["e"]) for r in rows]))
    return out


def energy_inside(r, v, m, e, e_amb, r_cut):
    """The share of the blast's energy, sum m (v^2/2 + e - e_amb), held by the particles
    with r < r_cut (the ambient's internal energy subtracted: the self-similar blast has
    none)."""
    q = m * (0.5 * np.sum(v * v, axis=1) + e - e_amb)
    return float(np.sum(q[r < r_cut]) / np.sum(q))


def energy_half_bound(dim, gamma, radius, h, eta=None, h_max=None, profile=None):
    """(fraction, bound, range): the self-similar share of the energy inside R/2 and the bound
    on a run's departure from it. A particle carries its energy where it is, but the pressure
    that works on it is an average over its range: the gas within a range of the cut at R/2
    exchanges work across it, and its share of the energy is the self-similar energy density
    at R/2 (d fraction/dl there) times that range over R. The range at R/2 is the fixed h
    (eta None), or eta (m/rho(R/2))^(1/D) at the self-similar density there (m = 1,
    rho0 = 1), held at h_max."""
    prof = profile if profile is not None else sedov_profile(dim, gamma)
    frac, slope = sedov_energy_fraction(dim, gamma, 0.5, prof)
    rng = h if eta is None else min(eta * np.interp(0.5, prof[0][::-1], prof[2][::-1]) ** (-1.0 / dim), h_max)
    return frac, slope * rng / radius, rng


def lagrangian_radius(dim, gamma):
    """(l0, l): the self-similar radius l = r/R of the gas that started at l0 = r0/R (its
    mass coordinate: l0^D = D int_0^l g l'^(D-1) dl')."""
    l, _, g, _ = sedov_profile(dim, gamma)
    l, g = l[::-1], np.maximum(g[::-1], 0.0)  # the 3D core's g rounds to -5e-12
    m = np.concatenate([[0.0], np.cumsum(0.5 * (g[1:] * l[1:] ** (dim - 1) + g[:-1] * l[:-1] ** (dim - 1)) * np.diff(l))])
    return (m / m[-1]) ** (1.0 / dim), l


def kernel_free(r, r0, x, v, r_ex, t, dim, lag):
    """Two positions of the front that no kernel averages: the half level of the binned
    radial velocity (the particles carry v; the self-similar step from 0 to the post-shock
    speed has its half level at R), and the shell's mean excess displacement: each particle
    that started at r0 in 0.7 R..0.98 R against where the self-similar flow puts the gas
    that started there (mass coordinates); a shell displaced by d puts the shock's
    equal-mass position about d rho2/(rho2 - rho0) ahead."""
    vr = np.sum(v * x, axis=1) / np.maximum(r, 1e-300)
    rdot = 2.0 / (dim + 2) * r_ex / t
    b = np.floor(r / BIN).astype(int)
    cnt = np.bincount(b)
    rb = (np.arange(len(cnt)) + 0.5) * BIN
    ok = (cnt > 0) & (rb > 0.5 * r_ex)  # the front's peak, not a hot core's particles flung out
    r_vel, _ = half_level_radius(rb[ok], (np.bincount(b, vr / rdot)[ok] / cnt[ok]), 0.0)
    sel = (r0 > 0.7 * r_ex) & (r0 < 0.98 * r_ex)
    disp = float(np.mean(r[sel] - r_ex * np.interp(r0[sel] / r_ex, lag[0], lag[1])))
    return r_vel, disp


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


def gathered_reference(r_ex, dim, gamma, prof, sm):
    """The half level of the self-similar density averaged the way the run's summed density
    averages it (shock_exact.sedov_gathered_*: the run's kernel about each point, the
    blast's own geometry): at the one range h (fixed), or at each point's own range solving
    rho_bar h^D = eta^D m within the run's bounds (adaptive, evolved). Returns (R_ref, peak)."""
    h, kernel = float(sm["h"]), sm.get("kernel", "lucy")
    grid = np.arange(max(r_ex - 8.0, 0.0), r_ex + 2.5 * h, 0.05)
    if sm.get("smoothing_length", "fixed") == "fixed":
        rho = sedov_gathered_density(grid, r_ex, dim, gamma, h, prof, ns=80, na=180, kernel=kernel)
    else:
        eta = float(sm["h_eta"]) or h
        rho, _ = sedov_gathered_adaptive(grid, r_ex, dim, gamma, eta, (float(sm["h_min"]) * h, float(sm["h_max"]) * h), prof, nh=16, kernel=kernel)
    return half_level_radius(grid, rho) + (grid, rho)


def spread_to_peak(grid, rho, peak):
    """The averaged exact profile spread further by a Gaussian (across the front: planar, its
    width well below R) whose width makes its peak the particles' peak: the SPH front is
    wider than the kernel's average (the viscosity spreads the shock), and the half level
    of a lower peak lies further out. Returns (half level, sigma); sigma 0 when the
    particles' peak is not below the averaged one."""
    def spread(sig):
        if sig <= 0.0:
            return rho
        ds = grid[1] - grid[0]
        k = np.arange(-int(4 * sig / ds) - 1, int(4 * sig / ds) + 2) * ds
        w = np.exp(-0.5 * (k / sig) ** 2)
        w /= w.sum()
        pad = len(k) // 2
        ext = np.concatenate([np.full(pad, rho[0]), rho, np.full(pad, 1.0)])
        return np.convolve(ext, w, mode="valid")
    if peak >= rho.max():
        return half_level_radius(grid, rho)[0], 0.0
    lo, hi = 0.0, 10.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if spread(mid).max() > peak else (lo, mid)
    sig = 0.5 * (lo + hi)
    return half_level_radius(grid, spread(sig))[0], sig


def inviscid_moment(d, dim, gamma, e0, t):
    """I2 that the run's own energies give without the viscosity's stress (the virial):
    I2'' = 4K + 2D sum_i m_i P_i/rho_i = 4K + 2D(gamma - 1)(U - U_ambient(0)) with K, U the
    timeseries' kinetic and internal energies (the grad-h pressure forces satisfy it
    exactly: sum_j m_j r_ij w'(r_ij, h_i) = -D rho_i Omega_i). Integrated twice from rest,
    I2(t) = int_0^t (t - s) I2''(s) ds (trapezoids over the rows up to t). In 3D at gamma 5/3
    this is 4E0: I2 = 2 E0 t^2 whatever the blast's structure, so what the particles' I2
    holds beyond it is the viscosity's stress (and Omega = 1 where h_i is held at a bound)."""
    with open(os.path.join(d, "timeseries.csv")) as fh:
        rows = list(csv.DictReader(fh))
    ts = np.array([float(q["t"]) for q in rows])
    k = np.array([float(q["kinetic"]) for q in rows])
    tot = np.array([float(q["total"]) for q in rows])
    u_amb = tot[0] - e0
    acc = 4.0 * k + 2.0 * dim * (gamma - 1.0) * (tot - k - u_amb)
    sel = ts <= t + 1e-12
    return float(np.trapz((t - ts[sel]) * acc[sel], ts[sel]))


def run_radii(d, reference=True, reference_times=None):
    man, sm = spam_manifest.open_run(d, "sedov_radii", scene="sedov")
    snaps = [(t, p) for t, p in spam_manifest.files(man, d, "snapshot_csv")]
    dim, gamma = int(sm["dim"]), float(sm["gas_gamma"])
    n = spam_manifest.option(man, "sedov_n", 20.0 if dim == 3 else 48.0)
    e0 = spam_manifest.option(man, "sedov_energy", 1e4)
    xi0, cm, prof = sedov_xi0(dim, gamma), moment_constant(dim, gamma), sedov_profile(dim, gamma)
    e_amb = spam_manifest.option(man, "gas_e0", 1e-3)
    adaptive = sm.get("smoothing_length", "fixed") != "fixed"
    h = float(sm["h"])
    eta = (float(sm.get("h_eta", 0.0) or 0.0) or h) if adaptive else None
    sigma = {2: 2.0 * np.pi, 3: 4.0 * np.pi}[dim]
    centre = 0.5 * n
    _, x0, m0, _ = snapshot(snaps[0][1], dim)
    base = float(np.sum(m0 * np.sum((x0 - centre) ** 2, axis=1)))
    r0, lag = np.linalg.norm(x0 - centre, axis=1), lagrangian_radius(dim, gamma)
    rows = []
    for t, path in snaps[1:]:
        t, x, m, rho, v, e = snapshot(path, dim, extra=True)
        r = np.linalg.norm(x - centre, axis=1)
        b = np.floor(r / BIN).astype(int)
        cnt, s = np.bincount(b), np.bincount(b, rho / m)
        ok = cnt > 0
        r_half, peak = half_level_radius(((np.arange(len(cnt)) + 0.5) * BIN)[ok], s[ok] / cnt[ok])
        i2 = float(np.sum(m * r * r)) - base
        r_mom = (i2 / (sigma * 1.0 * cm)) ** (1.0 / (dim + 2))
        r_ex = xi0 * (e0 * t * t) ** (1.0 / (dim + 2))
        row = {"t": t, "R_exact": r_ex, "R_half": r_half, "R_moment": r_mom, "peak": peak,
               "half_err": r_half / r_ex - 1.0, "moment_err": r_mom / r_ex - 1.0, "half_lead": r_half - r_ex, "moment_lead": r_mom - r_ex}
        r_vel, disp = kernel_free(r, r0, x - centre, v, r_ex, t, dim, lag)
        row.update({"R_velocity": r_vel, "velocity_lead": r_vel - r_ex, "shell_displacement": disp})
        half_exact, bound, rng = energy_half_bound(dim, gamma, r_ex, h, eta, float(sm.get("h_max", 2.0)) * h, prof)
        share = energy_inside(r, v, m, e, e_amb, 0.5 * r_ex)
        row.update({"energy_inside_half": share, "energy_inside_half_exact": half_exact, "energy_inside_half_diff": share - half_exact,
                    "energy_inside_half_bound": bound, "range_at_half": rng})
        i2_inv = inviscid_moment(d, dim, gamma, e0, t)
        row["I2_over_inviscid"] = i2 / i2_inv - 1.0
        row["R_moment_inviscid_err"] = (i2_inv / (sigma * cm)) ** (1.0 / (dim + 2)) / r_ex - 1.0
        if reference and (reference_times is None or any(abs(t - q) < 1e-6 * max(1.0, t) for q in reference_times)):
            # The front: the radius whose kernel-averaged self-similar profile has the
            # particles' half level (the averaging's lead taken at R_exact and again at the
            # first estimate: it changes slowly with R).
            r_ref, peak_ref, grid, rho_ref = gathered_reference(r_ex, dim, gamma, prof, sm)
            r_front = r_half - (r_ref - r_ex)
            r_ref2, _, grid2, rho_ref2 = gathered_reference(r_front, dim, gamma, prof, sm)
            r_front1 = r_front
            r_front = r_half - (r_ref2 - r_front1)
            # The same with the reference spread to the particles' peak (spread_to_peak).
            r_sp, sig = spread_to_peak(grid2, rho_ref2, peak)
            r_front_sp = r_half - (r_sp - r_front1)
            row.update({"R_half_averaged_exact": r_ref, "peak_averaged_exact": peak_ref,
                        "half_lead_over_averaged": r_half - r_ref, "R_front": r_front, "front_err": r_front / r_ex - 1.0, "front_lead": r_front - r_ex,
                        "spread_sigma": sig, "R_front_spread": r_front_sp, "front_spread_err": r_front_sp / r_ex - 1.0, "front_spread_lead": r_front_sp - r_ex})
        rows.append(row)
    by_time = {("t%.4g" % q["t"]).replace(".", "_"): q for q in rows}  # quotable keys: t12, t4_147
    ts = [q["t"] for q in rows]
    fits = {}
    for key in ("R_half", "R_moment", "R_front", "R_front_spread", "R_velocity"):
        if any(key not in q for q in rows):
            continue
        (t0, rt), (dr, rr) = fit_offsets(ts, [q[key] for q in rows], xi0, e0, dim)
        fits[key] = {"t0": t0, "t0_rms": rt, "dR": dr, "dR_rms": rr}
    return {"dim": dim, "n": n, "h": float(sm["h"]), "h_eta": float(sm.get("h_eta", 0.0) or 0.0), "kernel": sm.get("kernel", "lucy"), "smoothing_length": sm.get("smoothing_length", "fixed"), "xi0": xi0, "C": cm, "snapshots": rows, "at": by_time, "fits": fits,
            "wall_time_s": sm.get("wall_time_s"), "rhs_evals": sm.get("rhs_evals"), "n_particles": sm.get("n_particles")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--readings")
    ap.add_argument("--no-reference", action="store_true", help="skip the kernel-averaged exact profile (slow at adaptive h)")
    ap.add_argument("--reference-times", help="comma-separated snapshot times to compare with it (default: every snapshot)")
    ap.add_argument("--bin", type=float, default=BIN, help="width of the radial bins of the half levels (default %(default)s)")
    a = ap.parse_args()
    globals()["BIN"] = a.bin
    out = {}
    for d in a.dirs:
        times = [float(x) for x in a.reference_times.split(",")] if a.reference_times else None
        res = run_radii(d, reference=not a.no_reference, reference_times=times)
        out[os.path.basename(os.path.normpath(d)).replace(".", "_")] = res  # a dotted key could not be quoted
        for q in res["snapshots"]:
            print(f"{d}: t = {q['t']:.4g}: R_exact {q['R_exact']:.3f}, R_half {q['R_half']:.3f} ({q['half_err']:+.2%}), "
                  f"R_moment {q['R_moment']:.3f} ({q['moment_err']:+.2%}; I2 {q['I2_over_inviscid']:+.2%} over the inviscid virial's), peak {q['peak']:.3f}, "
                  f"velocity's half level {q['velocity_lead']:+.3f}, shell displaced {q['shell_displacement']:+.3f}, "
                  f"energy inside R/2 {q['energy_inside_half']:.4f} (self-similar {q['energy_inside_half_exact']:.4f}, bound {q['energy_inside_half_bound']:.4f})"
                  + (f"; averaged exact: half level {q['R_half_averaged_exact']:.3f} (lead {q['half_lead_over_averaged']:+.3f}), "
                     f"peak {q['peak_averaged_exact']:.3f}; R_front {q['R_front']:.3f} ({q['front_err']:+.2%}); spread to the peak "
                     f"(sigma {q['spread_sigma']:.2f}): R_front {q['R_front_spread']:.3f} ({q['front_spread_err']:+.2%})" if "R_front" in q else ""))
        for key, f in res["fits"].items():
            print(f"{d}: {key}: t0 = {f['t0']:+.4f} (rms {f['t0_rms']:.3f}), dR = {f['dR']:+.3f} (rms {f['dR_rms']:.3f})")
    if a.readings:
        chart_readings.write_json(a.readings, out, runs=a.dirs)


if __name__ == "__main__":
    main()
