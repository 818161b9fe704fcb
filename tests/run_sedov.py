#!/usr/bin/python3
"""The Sedov-Taylor blast: -scene sedov in 2D (cylindrical), gamma = 5/3,
density 1 at rest on a 48^2 periodic lattice, E0 = 1e4 deposited within h = 3 of the
centre, ambient e0 = 1e-3; run to t = 2.4 (shock radius 17.9 = 0.37 of the box), CSV
snapshots every 0.3. 9-12 s (labelled slow). The 3D blast (20^3 = 8000 particles) takes
61 s on this path (one thread) and ends at R = 2.4 h: not tested (docs/scenes/sedov.md).

The exact solution (shock_exact.py): R(t) = xi0 (E t^2/rho)^(1/4), xi0 computed from the
self-similar ODEs and the energy integral: 1.15379 for gamma = 5/3 cylindrical (the same
code gives 1.00402 cylindrical and 1.03277 spherical for gamma = 1.4 and 1.15166 spherical
for 5/3, the commonly quoted 1.004, 1.033 and 1.152: checked; and the cylindrical 5/3 value
is the same to 3e-6 with four times the steps. It is not the 1.128 sometimes quoted). The density just behind the shock is the strong-shock
limit (gamma+1)/(gamma-1) = 4.

What SPH can show of it: the shell behind the shock is thin (rho falls from 4 to 2 within
about 0.1 R) and a summed density averages it over the kernel's range h. So the test
compares like with like: the exact density profile averaged by the kernel (projected
across the shell, planar approximation, shock_exact.sedov_smoothed_density) is the
reference of both the radius and the peak; the estimator of the radius is the same on
both profiles: the outer radius where the (radially binned, bins 0.5 wide) density falls
to the mean of its peak and the ambient 1.

Checks and tolerances (measured values at this commit in parentheses):
- radius at t = 0.6, 1.2, 1.8, 2.4 against the smoothed exact one: within h/4 (the
  kernel's own smoothing is in the reference; what remains is the viscous width of the
  shock, about h, acting on the front's asymmetry, and the start from a blob of radius h
  instead of a point; measured +0.39, +0.22, +0.06, -0.24 spacings);
  and against xi0 (E t^2)^(1/4) itself: within h/2 (measured +1.13, +0.82, +0.59, +0.27 spacings);
- the growth exponent, a least-squares fit of ln R against ln t over t in [0.6, 2.4]:
  within the radius bound's share of the smoothed exact radii's fit, and within 0.1 of
  2/(D+2) = 1/2. Derivation: radius errors bounded by e1, e2 at the ends of a span of
  ln(t2/t1) move the fitted slope by at most (e1/R1 + e2/R2)/ln(t2/t1) = (0.75/10.1 +
  0.75/18.1)/ln 4 = 0.084 with e = h/4. Measured 0.426; the smoothed exact radii give
  0.4625 (the kernel's lead of the half-level radius shrinks relative to R: the estimator
  itself bends the exponent), so 0.037 of the 0.074 is the estimator's and 0.037 the
  run's (the start from a blob of radius h, the viscous width);
- the peak density: below the strong-shock limit 4, and within 15% of the smoothed exact
  peak (measured 0.90-0.92 of it at every time: the viscous broadening spreads the shell
  beyond the kernel's average; at t = 2.4 the peak is 2.10, 53% of the limit 4, the
  smoothed exact 2.30);
- energy kept to 1e-5 of the total (measured 2.2e-7; rtol 1e-6)."""
import csv
import math
import os

import numpy as np

from shock_exact import half_level_radius, sedov_profile, sedov_smoothed_density, sedov_xi0
from spamrun import Checks, arguments, manifest_files, run, summary

DIM, N, H, E0, GAMMA = 2, 48, 3.0, 1e4, 5.0 / 3.0
T_END, DT = 2.4, 0.3
T_CHECK = (0.6, 1.2, 1.8, 2.4)
BIN = 0.5


def radial_profile(path):
    """(t, bin radii, mean summed density per bin) of one CSV snapshot about the centre."""
    with open(path) as f:
        t = float(f.readline().split("=")[1])
        rows = list(csv.DictReader(f))
    x = np.array([[float(r[a]) for a in "xyz"[:DIM]] for r in rows])
    rho = np.array([float(r["rho_sum"]) for r in rows])
    r = np.linalg.norm(x - 0.5 * N, axis=1)
    b = np.floor(r / BIN).astype(int)
    cnt = np.bincount(b)
    s = np.bincount(b, rho)
    ok = cnt > 0
    return t, ((np.arange(len(cnt)) + 0.5) * BIN)[ok], s[ok] / cnt[ok]


# The commonly quoted xi0 (three decimals), the solver's check: (nu, gamma) -> xi0.
TABULATED = {(2, 1.4): 1.004, (3, 1.4): 1.033, (3, 5.0 / 3.0): 1.152}


def check_xi0(c):
    """The Sedov solver against the tabulated cases, and its own case converged in the
    step count (4000 against 16000 steps to l = 1e-4: 3e-6 apart)."""
    for (nu, g), v in TABULATED.items():
        got = sedov_xi0(nu, g)
        c.check(abs(got - v) <= 5e-4, f"xi0 (nu = {nu}, gamma = {g:.4f}) = {got:.5f} (quoted {v}, to half its last digit)")
    xi0 = sedov_xi0(DIM, GAMMA)
    l, f, g, h = sedov_profile(DIM, GAMMA, steps=16000, l_min=1e-4)
    fine = (2 * math.pi * 0.25 * -np.trapz((0.5 * g * f * f + h / (GAMMA - 1)) * l, l)) ** -0.25
    c.check(abs(xi0 - fine) <= 1e-5, f"xi0 (cylindrical, gamma 5/3) = {xi0:.5f}, {fine:.5f} with 16000 steps to l = 1e-4")
    return xi0


def main():
    a = arguments()
    c = Checks()
    out = os.path.join(a.workdir, "d2")
    code, _, err = run(a.spam_ark, ["-scene", "sedov", "-dim", DIM, "-sedov_n", N, "-h", H, "-sedov_energy", E0,
                                    "-ts_max_time", T_END, "-snapshot_interval", DT, "-snapshot_hdf5", "0"], out)
    if not c.check(code == 0, f"run exits 0 ({err.strip()[-200:]})"):
        c.finish()
    xi0 = check_xi0(c)
    prof = sedov_profile(DIM, GAMMA)
    times, radii, smooth_radii = [], [], []
    for path in manifest_files(out, "snapshot_csv"):
        t, rb, rho = radial_profile(path)
        if not any(abs(t - tc) < 1e-6 for tc in T_CHECK):
            continue
        r_exact = xi0 * (E0 * t * t) ** (1.0 / (DIM + 2))
        grid = np.arange(0.0, r_exact + 2 * H, 0.05)
        r_sm, peak_sm = half_level_radius(grid, sedov_smoothed_density(grid, r_exact, DIM, GAMMA, H, prof))
        r_half, peak = half_level_radius(rb, rho)
        times.append(t)
        radii.append(r_half)
        smooth_radii.append(r_sm)
        c.check(abs(r_half - r_sm) <= H / 4, f"t = {t:.2f}: radius {r_half:.3f} against the smoothed exact {r_sm:.3f}: {r_half - r_sm:+.3f} (bound h/4 = {H / 4})")
        c.check(abs(r_half - r_exact) <= H / 2, f"t = {t:.2f}: radius {r_half:.3f} against xi0 (E t^2)^(1/4) = {r_exact:.3f}: {r_half - r_exact:+.3f} (bound h/2 = {H / 2})")
        c.check(peak < (GAMMA + 1) / (GAMMA - 1) and abs(peak / peak_sm - 1) <= 0.15,
                f"t = {t:.2f}: peak density {peak:.3f} = {peak / peak_sm:.3f} of the smoothed exact {peak_sm:.3f} (bound 15% below or above), {peak / 4:.2f} of the limit 4")
        for key, v in (("R", r_half), ("R_smoothed", r_sm), ("R_power_law", r_exact), ("dR_smoothed", r_half - r_sm),
                       ("dR_power_law", r_half - r_exact), ("peak", peak), ("peak_smoothed", peak_sm),
                       ("peak_ratio", peak / peak_sm), ("peak_over_limit", peak / ((GAMMA + 1) / (GAMMA - 1)))):
            c.reading(f"t{t:g}".replace(".", "_") + "." + key, v)
    c.check(len(times) == len(T_CHECK), f"snapshots at t = {T_CHECK}: {len(times)} found")
    if len(times) >= 2:
        slope = np.polyfit(np.log(times), np.log(radii), 1)[0]
        slope_sm = np.polyfit(np.log(times), np.log(smooth_radii), 1)[0]
        bound = (H / 4 / radii[0] + H / 4 / radii[-1]) / math.log(times[-1] / times[0])
        c.check(abs(slope - slope_sm) <= bound, f"growth exponent {slope:.4f} against the smoothed exact radii's {slope_sm:.4f}: {slope - slope_sm:+.4f} (bound {bound:.3f})")
        c.reading("exponent", slope)
        c.reading("exponent_smoothed", slope_sm)
        c.reading("exponent_bound", bound)
        c.check(abs(slope - 0.5) <= 0.1 and bound <= 0.1, f"growth exponent {slope:.4f} (smoothed exact {slope_sm:.4f}) against 2/(D+2) = 0.5 (bound 0.1; the radius bound allows {bound:.3f})")
    sm = summary(out)
    c.check(sm["energy_rel_drift_max"] < 1e-5, f"energy drift {sm['energy_rel_drift_max']:.2e} < 1e-5")
    c.reading("energy_rel_drift_max", sm["energy_rel_drift_max"])
    c.finish(a.readings)


if __name__ == "__main__":
    main()
