#!/usr/bin/python3
"""The Gresho-Chan vortex (-scene gresho): a steady inviscid rotation,
v_phi = 5r, 2 - 5r, 0 (r in units of the box edge L, breaks at 0.2 and 0.4), held by the
pressure P = 5 + 12.5 r^2, ...; gamma = 5/3, rho = 1, no viscosity. The exact solution is
the initial state for all time; the test runs to t = 0.5 (standard time units: t = 0.5 L
here; the peak turns 0.4 of a revolution) at n = 24 and 48 particles per row of the
triangular lattice, -kernel wendland_c4 -h 3.

Why Wendland C4: Lucy's kernel at h = 3 (2.79 spacings of this lattice) is unstable on the
triangular lattice of the gas at rest: random velocities of 1e-3 grew to 0.09 by t = 0.75 L
in a gas of P = 5.8 without the vortex; with Wendland C4 at the same h they stayed 6e-4
(Lucy at h = 2.5: stable; Wendland C2 at h = 3: grew to 0.035). The isentropic gas
(the other force path) grows the same noise: the lattice's linear stability under
pressure, which depends on the kernel's shape at the neighbour distances (Morris 1996),
not one force pass. Not analysed further here.

What is checked and why the bounds:
- The set-up: the binned v_phi(r) of the t = 0 snapshot is the exact profile (to 1e-12).
- L1 error of v_phi binned in r (25 bins of 0.02 L in r < 0.5 L, each bin's mean against
  the mean of the exact profile over the same particles): inviscid SPH keeps no particle
  order under shear; the error is the E0 error of the SPH pressure gradient on the
  disordered particles, first order in h/L, the velocity change across a kernel range
  |dv/dr| h = 5 h/L at most; the bin mean averages it: bound 2.5 h/L (0.29 and 0.145).
  Measured: at t = 0.5 L 0.0886 (n = 24) and 0.0603 (n = 48), order 0.56 in 1/n, as slow as standard SPH is known to converge on this
  problem (its noise is not dissipated). Error falls with resolution: ratio below 0.85.
- Peak of the binned v_phi within 5 h/L of the exact peak 1 (the kernel smooths the
  tent's corner over h, and the vortex may not gain or lose more than the profile's change
  across a kernel range). Measured 0.806 and 0.796 (bounds 0.58 and 0.29 from 1).
Run time: 4.2 s of CPU for both runs (11 s wall on the shared machine).
- Angular momentum: the scheme conserves it exactly pair by pair (pressure forces along
  r_ij): timeseries.csv's torque_sum (the scheme's summed pair torque) is zero to
  round-off (bound 1e-12 L_z(0) per time unit L). The box is periodic, where angular
  momentum is not conserved: once the velocity noise reaches the box edge, pairs across
  it exert torque (L e x F_ij) and particles that wrap jump in L_z. Until then (t <= 0.2 L)
  L_z holds to 2e-3 of L_z(0) (measured 6.9e-4 at n = 24, 7.1e-5 at n = 48: the wraps
  and edge pairs begin earlier in the smaller box); the drift at t = 0.5 L is printed
  (-5.4e-2 and -4.1e-2).
- Energy to the integrator's accuracy: |E - E0| / E0 below 10 rtol = 1e-5."""
import math
import os
import re

import numpy as np

from spamrun import Checks, arguments, manifest_files, run, table

H, T_END, RTOL, BINS = 3.0, 0.5, 1e-6, 25


def snapshot(path):
    """x, y, vx, vy of a CSV snapshot ('#' lines are comments)."""
    with open(path) as f:
        lines = [line for line in f if not line.startswith("#")]
    head = lines[0].strip().split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:] if line.strip()])
    return [data[:, head.index(n)] for n in ("x", "y", "vx", "vy")]


def exact(r):
    return np.where(r < 0.2, 5 * r, np.where(r < 0.4, 2 - 5 * r, 0.0))


def binned(path, L, centre):
    """Bin means of v_phi and of the exact profile over the particles of each bin (r < 0.5 L)."""
    x, y, vx, vy = snapshot(path)
    dx, dy = x - centre[0], y - centre[1]
    r = np.hypot(dx, dy)
    vphi = (dx * vy - dy * vx) / np.maximum(r, 1e-300)
    idx = np.floor(r / L / (0.5 / BINS)).astype(int)
    got, want = [], []
    for b in range(BINS):
        s = idx == b
        if s.any():
            got.append(vphi[s].mean())
            want.append(exact(r[s] / L).mean())
    return np.array(got), np.array(want)


def run_case(a, c, n):
    """Runs -scene gresho -gresho_n n to t = 0.5 L; returns (L, hL, l1 at the end, peak, outdir)."""
    out = os.path.join(a.workdir, f"n{n}")
    L = n * math.sqrt(2 / math.sqrt(3))  # n spacings a of the lattice of density 1
    t_end = T_END * L
    args = ["-scene", "gresho", "-gresho_n", n, "-kernel", "wendland_c4", "-h", H, "-ts_rtol", RTOL, "-ts_max_time", t_end,
            "-snapshot_interval", t_end, "-snapshot_hdf5", 0, "-output_interval", t_end / 50]
    code, stdout, err = run(a.spam_ark, args, out)
    if not c.check(code == 0, f"n = {n}: run to t = {T_END} L completes (exit {code}) {err.strip()}"):
        c.finish()
    # The box centre and unit as the scene prints them.
    m = re.search(r"centre \(([-0-9.e+]+), ([-0-9.e+]+)\), unit L = ([-0-9.e+]+)", stdout)
    if not c.check(m is not None and abs(float(m.group(3)) / L - 1) < 1e-9, f"n = {n}: the scene states its centre and unit L = {L:.6f}"):
        c.finish()
    centre = (float(m.group(1)), float(m.group(2)))
    paths = manifest_files(out, "snapshot_csv")
    got0, want0 = binned(paths[0], L, centre)
    c.check(np.max(np.abs(got0 - want0)) < 1e-12, f"n = {n}: t = 0: binned v_phi = exact profile to {np.max(np.abs(got0 - want0)):.1e} (bound 1e-12)")
    got, want = binned(paths[-1], L, centre)
    l1 = np.mean(np.abs(got - want))
    hL = H / L
    c.check(l1 < 2.5 * hL, f"n = {n}: t = {T_END}: L1 of binned v_phi {l1:.4f} below 2.5 h/L = {2.5 * hL:.4f}")
    peak = got.max()
    c.check(abs(peak - 1) < 5 * hL, f"n = {n}: t = {T_END}: peak of binned v_phi {peak:.4f} within 5 h/L = {5 * hL:.3f} of 1")
    ts = table(os.path.join(out, "timeseries.csv"))
    t, lz, torque, total = (np.array(ts[k]) for k in ("t", "lz", "torque_sum", "total"))
    tq = np.max(np.abs(torque)) / (lz[0] / L)
    c.check(tq < 1e-12, f"n = {n}: summed pair torque {tq:.1e} of L_z(0) per time unit L (bound 1e-12): pair forces central")
    early = np.max(np.abs(lz[t <= 0.2 * L] / lz[0] - 1))
    c.check(early < 2e-3, f"n = {n}: L_z to {early:.1e} of L_z(0) until t = 0.2 L (bound 2e-3); at t = {T_END} L: {lz[-1] / lz[0] - 1:+.2e} (periodic box)")
    de = np.max(np.abs(total / total[0] - 1))
    c.check(de < 10 * RTOL, f"n = {n}: energy to {de:.1e} (bound 10 rtol = {10 * RTOL:g})")
    for k, v in (("h_over_L", hL), ("l1", l1), ("l1_bound", 2.5 * hL), ("peak", peak), ("lz_early", early),
                 ("lz_end", lz[-1] / lz[0] - 1), ("torque", tq), ("energy", de)):
        c.reading(f"n{n}.{k}", v)
    return l1


a = arguments()
c = Checks()
l1s = [run_case(a, c, n) for n in (24, 48)]
c.check(l1s[1] / l1s[0] < 0.85, f"L1 falls with resolution: {l1s[0]:.4f} -> {l1s[1]:.4f}, ratio {l1s[1] / l1s[0]:.3f} (bound 0.85; order {math.log2(l1s[0] / l1s[1]):.2f})")
c.reading("order", math.log2(l1s[0] / l1s[1]))
c.finish(a.readings)
