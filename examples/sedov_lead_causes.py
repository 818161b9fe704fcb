#!/usr/bin/python3
"""Three candidate causes of the adaptive Sedov front's lead, measured on spam-ark runs.

Usage:
    /usr/bin/python3 examples/sedov_lead_causes.py DIR [DIR ...] [--readings FILE] [--fit-from T] [--ideal-times T,T] [--bin W]

Per snapshot after t = 0 of every run directory (-scene sedov, CSV snapshots, 2D or 3D),
R = xi0 (E0 t^2/rho0)^(1/(D+2)) the self-similar radius (tests/shock_exact.py), lengths in
lattice spacings:

1. Where the mass is, and what the estimator makes of the exact flow on the run's own
   particles. Each particle stands for the mass of its lattice cell, the cell reaching half
   a spacing beyond it; if that half cell were the lead, the particles' mass would be where
   the exact flow puts it and only the summed density's half level would lead.
   - R_mass: the radius holding as many particles as the exact flow holds inside R (the
     run's lattice particles that started within R), midway between the last of them and
     the next by radius; mass_lead = R_mass - R. And the displacement of the Lagrangian
     mass shells: the radius enclosing a fraction q of that count, run minus exact flow
     (mass_shift.q0_9 etc.; q > 1 is gas ahead of the shock in the exact flow).
   - The ideal particles: the run's initial lattice moved by the self-similar Lagrangian
     map to R (every particle where the exact flow puts its gas, with the exact radial
     velocity), their density summed as the run sums it (slow: brute force; --ideal-times
     limits it to some snapshots, --max-targets to a random sample of the front's particles) (its kernel; at the adaptive range
     each h_i solves rho_i h_i^D = eta^D m within the run's bounds; periodic images).
     The same binned half level (sedov_radii.py's R_half) of those densities gives
     R_half_ideal: R_half_ideal - R is the estimator's own bias on exact particles (the
     kernel's average and the particles' discreteness together), and R_half - R_half_ideal
     is the run's lead in the estimator's own terms. R_velocity_ideal likewise for the
     radial velocity's half level (r > R/2).
2. Heating and motion ahead of the shock: the particles in shells 1 spacing wide beyond
   R_mass (ahead_k: R_mass + k .. R_mass + k + 1), their mean specific energy over the
   post-shock e2 = 2 U^2/(gamma+1)^2 (U = dR/dt), the part of it beyond the adiabatic
   compression of the ambient e0 (the viscosity's heating), their radial velocity over
   the post-shock v2 = 2U/(gamma+1), density, pressure over the post-shock P2 and the
   distance they have moved from where they started (the exact flow: 0 for all of it).
   Beside e, what a steady viscous shock gives its gas at that speed: with a cold gas at
   rest ahead, mass, momentum and energy fluxes through the layer give e = v^2/2 at every
   point of it (P + q = rho0 U v, rho0 U (e + v^2/2) = (P + q) v), so e_steady_over_e2 =
   mean(v_r^2)/v2^2; e beyond it is heat the layer's gas did not get from the steady
   shock's work (in SPH the pair's viscous heating is shared evenly by the two particles,
   the cold one ahead included).
3. The time origin: per run, R^2 = a^2 (t - t0) fitted by least squares over the snapshots
   from --fit-from on, for R_mass, R_velocity, R_half, R_moment: a over the self-similar
   a_ss = xi0 (E0/rho0)^(1/4) (2D; 3D: R = a (t - t0)^(2/5), fitted as R^(5/2)), t0, and the
   rms residual; beside it the time origin alone (a = a_ss) and the constant lead dR
   (R = R_exact + dR), each with its rms. A late
   start (t0 > 0) with a = a_ss is a blast that started from a finite blob; a > a_ss is
   a front that runs faster than the point blast's (its lead grows as t^(1/2) in 2D).
One line per snapshot goes to stdout; --readings writes the readings as JSON.
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
from sedov_radii import lagrangian_radius, moment_constant  # noqa: E402
from shock_exact import half_level_radius, kernel_w, sedov_profile, sedov_xi0  # noqa: E402

BIN = 0.5
SHELLS = (0.5, 0.8, 0.9, 0.95, 0.99, 1.0, 1.02, 1.05)


def snapshot(path, dim):
    """(t, x, v, m, e, rho_sum) of a CSV snapshot, rows in particle id order."""
    with open(path) as f:
        t = float(f.readline().split("=")[1])
        rows = list(csv.DictReader(f))
    rows.sort(key=lambda r: int(r["id"]))
    col = lambda k: np.array([float(r[k]) for r in rows])  # noqa: E731
    x = np.stack([col(a) for a in "xyz"[:dim]], axis=1)
    v = np.stack([col("v" + a) for a in "xyz"[:dim]], axis=1)
    return t, x, v, col("m"), col("e"), col("rho_sum")


def binned_half(r, q, lo=0.0, ambient=1.0):
    """The half level of q binned in r (bins BIN wide, the bins' mean; only r > lo)."""
    b = np.floor(r / BIN).astype(int)
    cnt, s = np.bincount(b), np.bincount(b, q)
    rb = (np.arange(len(cnt)) + 0.5) * BIN
    ok = (cnt > 0) & (rb > lo)
    return half_level_radius(rb[ok], s[ok] / cnt[ok], ambient)


def summed_density(xt, xs, m, box, sm, dim):
    """The summed density at the targets xt of the particles xs (masses m), as the run sums
    it: its kernel at range h (fixed) or at each target's own h solving rho h^D = eta^D m
    within the bounds (adaptive, evolved: bisection in h, rho h^D grows with h).
    Periodic minimum images; brute force in chunks of targets, each target's neighbours
    within the largest range padded into one array."""
    kernel, h = sm.get("kernel", "lucy"), float(sm["h"])
    adaptive = sm.get("smoothing_length", "fixed") != "fixed"
    eta = float(sm.get("h_eta", 0.0) or 0.0) or h
    lo, hi = (float(sm.get("h_min", 1.0)) * h, float(sm.get("h_max", 1.0)) * h) if adaptive else (h, h)
    out = np.empty(len(xt))
    c = max(8, min(128, 4000000 // len(xs)))  # a chunk's distances: a few 10 MB
    for a in range(0, len(xt), c):
        d = xt[a:a + c, None, :] - xs[None, :, :]
        d -= box * np.round(d / box)
        dist = np.sqrt(np.sum(d * d, axis=2))
        near = dist < hi
        kmax = int(near.sum(axis=1).max())
        idx = np.argsort(~near, axis=1, kind="stable")[:, :kmax]
        dn = np.take_along_axis(dist, idx, axis=1)
        mn = np.where(np.take_along_axis(near, idx, axis=1), m[idx], 0.0)
        rho_at = lambda hv: np.sum(kernel_w(kernel, dim, hv[:, None], dn) * mn, axis=1)  # noqa: E731
        if not adaptive:
            out[a:a + c] = rho_at(np.full(len(dn), h))
            continue
        hl, hh = np.full(len(dn), lo), np.full(len(dn), hi)
        for _ in range(40):
            hm = 0.5 * (hl + hh)
            up = rho_at(hm) * hm ** dim < eta ** dim * np.mean(m)
            hl, hh = np.where(up, hm, hl), np.where(up, hh, hm)
        out[a:a + c] = rho_at(0.5 * (hl + hh))
    return out


def fit_sqrt(ts, rs, xi0, e0, dim):
    """R^((D+2)/2) = a^((D+2)/2) (t - t0): least squares in t; returns a / a_ss - 1, t0, the
    rms residual in R; the time origin alone at a = a_ss (t0_at_ss) with its rms; and the
    constant lead dR with its rms."""
    ts, rs = np.asarray(ts), np.asarray(rs)
    p = (dim + 2) / 2.0
    slope, icpt = np.polyfit(ts, rs ** p, 1)
    a, t0 = slope ** (1.0 / p), -icpt / slope
    a_ss = xi0 * e0 ** (1.0 / (dim + 2))
    res = rs - a * np.clip(ts - t0, 0.0, None) ** (1.0 / p)
    rex = a_ss * ts ** (1.0 / p)
    dr = float(np.mean(rs - rex))
    # The time origin alone (a = a_ss): t - t0 = (R/a_ss)^p per snapshot, then the mean.
    t0_ss = float(np.mean(ts - (rs / a_ss) ** p))
    res_ss = rs - a_ss * np.clip(ts - t0_ss, 0.0, None) ** (1.0 / p)
    return {"a_over_ss": float(a / a_ss - 1.0), "t0": float(t0), "rms": float(np.sqrt(np.mean(res ** 2))),
            "t0_at_ss": t0_ss, "t0_at_ss_rms": float(np.sqrt(np.mean(res_ss ** 2))),
            "dR": dr, "dR_rms": float(np.sqrt(np.mean((rs - rex - dr) ** 2))), "t_from": float(ts[0]), "t_to": float(ts[-1]), "points": len(ts)}


def key(x):
    return ("q%g" % x).replace(".", "_")


def run_causes(d, fit_from, ideal_times=None, max_targets=8000):
    man, sm = spam_manifest.open_run(d, "sedov_lead_causes", scene="sedov")
    snaps = list(spam_manifest.files(man, d, "snapshot_csv"))
    dim, gamma = int(sm["dim"]), float(sm["gas_gamma"])
    n = spam_manifest.option(man, "sedov_n", 20.0 if dim == 3 else 48.0)
    e0 = spam_manifest.option(man, "sedov_energy", 1e4)
    e_amb = float(sm.get("gas_e0", spam_manifest.option(man, "gas_e0", 1e-3)))
    xi0, cm = sedov_xi0(dim, gamma), moment_constant(dim, gamma)
    l, f, g, _ = sedov_profile(dim, gamma)
    lag = lagrangian_radius(dim, gamma)
    sigma = {2: 2.0 * np.pi, 3: 4.0 * np.pi}[dim]
    centre, box = 0.5 * n, float(n)
    _, x0, _, m0, _, _ = snapshot(snaps[0][1], dim)
    d0 = x0 - centre
    r0 = np.linalg.norm(d0, axis=1)
    base = float(np.sum(m0 * r0 ** 2))
    rows = []
    for t, path in snaps[1:]:
        t, x, v, m, e, rho = snapshot(path, dim)
        dx = x - centre
        r = np.linalg.norm(dx, axis=1)
        vr = np.sum(v * dx, axis=1) / np.maximum(r, 1e-300)
        R = xi0 * (e0 * t * t) ** (1.0 / (dim + 2))
        U = 2.0 / (dim + 2) * R / t
        e2, v2, rho2 = 2.0 * U * U / (gamma + 1) ** 2, 2.0 * U / (gamma + 1), (gamma + 1) / (gamma - 1)
        p2 = (gamma - 1) * rho2 * e2
        # The ideal particles: the run's lattice where the exact flow puts its gas.
        inside = r0 < R
        ri = np.where(inside, R * np.interp(np.clip(r0 / R, 0.0, 1.0), lag[0], lag[1]), r0)
        xi = centre + d0 * (ri / np.maximum(r0, 1e-300))[:, None]
        vri = np.where(inside, U * np.interp(np.clip(ri / R, l[-1], 1.0), l[::-1], f[::-1]), 0.0)
        # Mass radii: the count the exact flow holds inside R, and fractions of it.
        count = int(np.sum(inside))
        rs, ris = np.sort(r), np.sort(ri)
        r_mass = 0.5 * (rs[count - 1] + rs[count])
        r_mass_ideal = 0.5 * (ris[count - 1] + ris[count])
        shift = {}
        for q in SHELLS:
            k = int(round(q * count))
            if 0 < k < len(rs):
                shift[key(q)] = float(0.5 * (rs[k - 1] + rs[k]) - 0.5 * (ris[k - 1] + ris[k]))
        # The estimator on the ideal particles (targets: the front's region only).
        r_half_ideal = peak_ideal = float("nan")
        if ideal_times is None or any(abs(t - q) < 1e-6 * max(1.0, t) for q in ideal_times):
            tgt = np.flatnonzero((ri > 0.5 * R) & (ri < R + 3.0 * float(sm["h"])))
            if len(tgt) > max_targets:  # a sample of them, the same on every run (3D)
                tgt = np.sort(np.random.default_rng(1).choice(tgt, max_targets, replace=False))
            rho_i = summed_density(xi[tgt], xi, m0, box, sm, dim)
            r_half_ideal, peak_ideal = binned_half(ri[tgt], rho_i / m0[tgt])
        r_vel_ideal, _ = binned_half(ri, vri / U, lo=0.5 * R, ambient=0.0)
        r_half, peak = binned_half(r, rho / m)
        r_vel, _ = binned_half(r, vr / U, lo=0.5 * R, ambient=0.0)
        i2 = float(np.sum(m * r * r)) - base
        r_mom = (i2 / (sigma * cm)) ** (1.0 / (dim + 2))
        row = {"t": t, "R_exact": R, "R_mass": r_mass, "mass_lead": r_mass - R, "R_mass_ideal": r_mass_ideal, "mass_lead_ideal": r_mass_ideal - R,
               "mass_shift": shift, "R_half": r_half, "half_lead": r_half - R, "peak": peak,
               "R_half_ideal": r_half_ideal, "half_lead_ideal": r_half_ideal - R, "peak_ideal": peak_ideal, "half_lead_over_ideal": r_half - r_half_ideal,
               "R_velocity": r_vel, "velocity_lead": r_vel - R, "R_velocity_ideal": r_vel_ideal, "velocity_lead_ideal": r_vel_ideal - R,
               "R_moment": r_mom, "moment_lead": r_mom - R, "e2": e2, "v2": v2, "p2": p2, "ahead": {}}
        # Ahead of the mass front: shells 1 spacing wide.
        moved = r - r0
        for k in range(4):
            sel = (r >= r_mass + k) & (r < r_mass + k + 1)
            if not np.any(sel):
                continue
            rho_s, e_s = rho[sel] / m[sel], e[sel]
            heat = e_s - e_amb * np.maximum(rho_s, 1e-300) ** (gamma - 1.0)
            row["ahead"]["k%d" % k] = {"count": int(np.sum(sel)), "e_over_e2": float(np.mean(e_s) / e2), "heat_over_e2": float(np.mean(heat) / e2),
                                       "e_over_e0": float(np.mean(e_s) / e_amb), "vr_over_v2": float(np.mean(vr[sel]) / v2),
                                       "e_steady_over_e2": float(np.mean(vr[sel] ** 2) / v2 ** 2), "rho": float(np.mean(rho_s)),
                                       "p_over_p2": float(np.mean((gamma - 1) * rho[sel] * e_s) / p2), "moved": float(np.mean(moved[sel]))}
        rows.append(row)
        a0 = row["ahead"].get("k0", {})
        print(f"{d}: t = {t:.4g}: R {R:.3f}; mass lead {row['mass_lead']:+.3f} (ideal {row['mass_lead_ideal']:+.3f}); "
              f"shells {' '.join('%s %+.2f' % (k2, s) for k2, s in shift.items())}; half level {row['half_lead']:+.3f}, on ideal particles {row['half_lead_ideal']:+.3f} "
              f"(run over ideal {row['half_lead_over_ideal']:+.3f}); velocity {row['velocity_lead']:+.3f} (ideal {row['velocity_lead_ideal']:+.3f}); "
              f"ahead 0..1: e/e2 {a0.get('e_over_e2', float('nan')):.3g}, heat/e2 {a0.get('heat_over_e2', float('nan')):.3g}, vr/v2 {a0.get('vr_over_v2', float('nan')):.3f}, "
              f"rho {a0.get('rho', float('nan')):.3f}, P/P2 {a0.get('p_over_p2', float('nan')):.3g}, moved {a0.get('moved', float('nan')):+.3f}")
    by_time = {("t%.4g" % q["t"]).replace(".", "_"): q for q in rows}
    use = [q for q in rows if q["t"] >= fit_from - 1e-12]
    fits = {}
    for k2 in ("R_mass", "R_velocity", "R_half", "R_moment", "R_half_ideal"):
        pts = [q for q in use if np.isfinite(q[k2])]
        if len(pts) < 3:
            continue
        fits[k2] = fit_sqrt([q["t"] for q in pts], [q[k2] for q in pts], xi0, e0, dim)
        ff = fits[k2]
        print(f"{d}: {k2}: R = a (t - t0)^(2/(D+2)) over t {ff['t_from']:g}..{ff['t_to']:g}: a/a_ss - 1 = {ff['a_over_ss']:+.4f}, t0 = {ff['t0']:+.4f} "
              f"(rms {ff['rms']:.3f}); t0 alone {ff['t0_at_ss']:+.4f} (rms {ff['t0_at_ss_rms']:.3f}); constant lead {ff['dR']:+.3f} (rms {ff['dR_rms']:.3f})")
    return {"dim": dim, "n": n, "h": float(sm["h"]), "h_eta": float(sm.get("h_eta", 0.0) or 0.0), "kernel": sm.get("kernel", "lucy"),
            "smoothing_length": sm.get("smoothing_length", "fixed"), "viscosity_beta": float(sm.get("viscosity_beta", 0.0)),
            "xi0": xi0, "a_ss": xi0 * e0 ** (1.0 / (dim + 2)), "snapshots": rows, "at": by_time, "fits": fits}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--readings")
    ap.add_argument("--fit-from", type=float, default=1.0, help="first snapshot time of the R(t) fits (default %(default)s)")
    ap.add_argument("--ideal-times", help="comma-separated snapshot times of the ideal particles' summed density (default: every snapshot)")
    ap.add_argument("--max-targets", type=int, default=8000, help="at most this many particles (a fixed random sample) in the ideal half level's bins (default %(default)s)")
    ap.add_argument("--bin", type=float, default=BIN, help="width of the radial bins of the half levels (default %(default)s)")
    a = ap.parse_args()
    globals()["BIN"] = a.bin
    out = {}
    for d in a.dirs:
        times = [float(x) for x in a.ideal_times.split(",")] if a.ideal_times else None
        out[os.path.basename(os.path.normpath(d)).replace(".", "_")] = run_causes(d, a.fit_from, times, a.max_targets)
    if a.readings:
        chart_readings.write_json(a.readings, out, runs=a.dirs)


if __name__ == "__main__":
    main()
