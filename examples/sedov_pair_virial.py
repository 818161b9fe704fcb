#!/usr/bin/python3
"""The pair virial of an adaptive-range Sedov snapshot: the pressure's part, the artificial
viscosity's, and where the viscosity's acts (small 2D runs: pairs by direct search).

Usage:
    /usr/bin/python3 examples/sedov_pair_virial.py RUN_DIR [--readings FILE]

The particles' second moment I2 = sum m |r - c|^2 has I2'' = 2 sum m v^2 + 2 sum_pairs
F_ij . r_ij. With the grad-h pressure forces (docs/models.md) the pressure's pair virial
is exactly D sum_i m_i P_i/rho_i (sum_j m_j r_ij w'(r_ij, h_i) = -D rho_i Omega_i), so
I2'' = 4K + 2D(gamma - 1)U: the inviscid blast's, and in 3D at gamma 5/3 simply 4E. What
the particles' I2 holds beyond that comes from (a) Monaghan's viscosity, whose pair force
-m_i m_j Pi_ij (g_i + g_j)/2 r_ij adds m_i m_j Pi_ij |g_i + g_j|/2 r^2 >= 0 to the virial,
and (b) the particles whose h_i is held at the upper bound, where the solve takes Omega = 1
in place of the formula. This script recomputes, from the last CSV snapshot of a run at
-smoothing_length adaptive (Lucy's kernel, the run's eta and bounds: h_i solved again by
bisection from the snapshot's positions; checked against its rho_sum), both parts and
the viscous virial in radial shells, with the share of approaching pairs in each.
The direct pair search is O(N^2): runs of a few thousand particles.
"""
import argparse
import csv
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402


def lucy(dim, h):
    return 5.0 / (math.pi * h * h) if dim == 2 else 105.0 / (16.0 * math.pi * h ** 3)


def kernel_w(dim, r, h):
    q = r / h
    return np.where(q < 1, lucy(dim, h) * (1 + 3 * q) * (1 - q) ** 3, 0.0)


def kernel_g(dim, r, h):
    """w'(r)/r."""
    q = r / h
    return np.where(q < 1, lucy(dim, h) * (-12.0) * (1 - q) ** 2 / (h * h), 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--readings")
    a = ap.parse_args()
    man, sm = spam_manifest.open_run(a.run, "sedov_pair_virial", scene="sedov")
    snaps = list(spam_manifest.files(man, a.run, "snapshot_csv"))
    dim, gamma, h0 = int(sm["dim"]), float(sm["gas_gamma"]), float(sm["h"])
    eta = float(sm["h_eta"]) or h0
    lo_b, hi_b = float(sm["h_min"]) * h0, float(sm["h_max"]) * h0
    n = spam_manifest.option(man, "sedov_n", 48.0)
    visc_a, visc_b = float(sm["viscosity_alpha"]), float(sm["viscosity_beta"])
    e_amb = spam_manifest.option(man, "gas_e0", 1e-3)
    t, path = snaps[-1]
    with open(path) as fh:
        t = float(fh.readline().split("=")[1])
        rows = list(csv.DictReader(fh))
    x = np.array([[float(r[c]) for c in "xyz"[:dim]] for r in rows])
    v = np.array([[float(r["v" + c]) for c in "xyz"[:dim]] for r in rows])
    m, e, rho_sum = (np.array([float(r[k]) for r in rows]) for k in ("m", "e", "rho_sum"))
    npart, box = len(m), float(n)
    ii, jj, dd = [], [], []
    for i in range(npart):
        d = x[i] - x[i + 1:]
        d -= box * np.round(d / box)
        k = np.where(np.sum(d * d, axis=1) < hi_b * hi_b)[0]
        ii.append(np.full(len(k), i))
        jj.append(k + i + 1)
        dd.append(d[k])
    I, J, D = np.concatenate(ii), np.concatenate(jj), np.concatenate(dd)
    R = np.sqrt(np.sum(D * D, axis=1))

    def rho_at(h):
        out = m * kernel_w(dim, 0.0, h)
        np.add.at(out, I, m[J] * kernel_w(dim, R, h[I]))
        np.add.at(out, J, m[I] * kernel_w(dim, R, h[J]))
        return out

    lo, hi = np.full(npart, lo_b), np.full(npart, hi_b)
    for _ in range(60):
        h = 0.5 * (lo + hi)
        below = rho_at(h) * h ** dim < eta ** dim * m
        lo, hi = np.where(below, h, lo), np.where(below, hi, h)
    h = 0.5 * (lo + hi)
    at_bound = h > hi_b * (1 - 1e-9)
    h[at_bound] = hi_b
    rho = rho_at(h)
    gi, gj = kernel_g(dim, R, h[I]), kernel_g(dim, R, h[J])
    s = np.zeros(npart)
    np.add.at(s, I, m[J] * gi * R * R)
    np.add.at(s, J, m[I] * gj * R * R)
    omega = -s / (dim * rho)                        # = 1 + (h/(D rho)) d rho/dh
    omega_run = np.where(at_bound, 1.0, omega)      # the solve's 1 at a bound
    P = (gamma - 1.0) * rho * e
    p = P / (omega_run * rho * rho)
    vir_p = float(np.sum(-m[I] * m[J] * (p[I] * gi + p[J] * gj) * R * R))
    vir_identity = float(dim * np.sum(m * P / rho))  # what Omega's formula everywhere would give
    vr = np.sum((v[I] - v[J]) * D, axis=1)
    hij = 0.5 * (h[I] + h[J])
    mu = hij * vr / (R * R + 0.01 * hij * hij)
    c0 = math.sqrt(gamma * (gamma - 1.0) * e_amb)  # the model's reference sound speed: the ambient's
    pi_ij = np.where(vr < 0, (-visc_a * c0 * mu + visc_b * mu * mu) / (0.5 * (rho[I] + rho[J])), 0.0)
    vir_v_pairs = -m[I] * m[J] * pi_ij * 0.5 * (gi + gj) * R * R
    vir_v = float(np.sum(vir_v_pairs))
    blast = float(dim * (gamma - 1.0) * (np.sum(m * e) - np.sum(m) * e_amb))
    centre = 0.5 * box
    rr = 0.5 * (np.linalg.norm(x[I] - centre, axis=1) + np.linalg.norm(x[J] - centre, axis=1))
    r_ex = None
    shells = []
    edges = np.arange(0.0, rr.max() + 1.0, 1.0)
    idx = np.digitize(rr, edges)
    for k in range(1, len(edges)):
        sel = idx == k
        if np.any(sel) and vir_v_pairs[sel].sum() > 1e-3 * vir_v:
            shells.append({"r_lo": float(edges[k - 1]), "r_hi": float(edges[k]), "viscous_share": float(vir_v_pairs[sel].sum() / vir_v),
                           "approaching": float(np.mean(vr[sel] < 0))})
    out = {"t": t, "n_particles": npart, "at_bound": int(np.sum(at_bound)), "rho_check": float(np.max(np.abs(rho - rho_sum))),
           "virial_pressure": vir_p, "virial_pressure_identity": vir_identity, "virial_blast_pressure": blast,
           "virial_viscous": vir_v, "viscous_over_blast": vir_v / blast, "bound_excess_over_blast": (vir_p - vir_identity) / blast,
           "shells": shells}
    print(f"{a.run}: t = {t:g}, {npart} particles ({out['at_bound']} at the upper bound; summed densities within {out['rho_check']:.1e} of the run's)")
    print(f"  pressure virial {vir_p:.1f} (with Omega's formula everywhere {vir_identity:.1f}; the blast's D(gamma-1)U {blast:.1f}): "
          f"the bound's Omega = 1 adds {out['bound_excess_over_blast']:+.2%}")
    print(f"  viscous virial {vir_v:.1f} = {out['viscous_over_blast']:.2%} of the blast's pressure virial; by shell (share of it, approaching pairs):")
    for q in shells:
        print(f"    r {q['r_lo']:5.1f} .. {q['r_hi']:5.1f}: {q['viscous_share']:6.1%}  ({q['approaching']:.0%})")
    if a.readings:
        chart_readings.write_json(a.readings, {os.path.basename(os.path.normpath(a.run)).replace(".", "_"): out}, runs=[a.run])


if __name__ == "__main__":
    main()
