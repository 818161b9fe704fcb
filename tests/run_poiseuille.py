#!/usr/bin/python3
"""Plane Poiseuille flow: gas between no-slip walls at rest at y = 0 and
y = H, driven along x by the body force g = 8 nu U / H^2 (the scene's default gravity, peak
speed U = 0.1), started from rest, against v_x = g / (2 nu) y (H - y).

Set-up: unit square lattice (rho = 1), Wendland C2 kernel with h = 3 (h/dx fixed), eta = 1
(nu = 1), 8 columns along the periodic x, H = n = 8, 16, 32, run to 1.5 H^2/nu; Mach
U/c = 0.07, Re = U H / nu <= 3.2, adiabatic walls. The profile is binned by lattice row and
averaged over the snapshots in [H^2/nu, 1.5 H^2/nu] (transient below 5e-5 of the peak).

The gas takes the flow scheme's default, viscosity as a pair Laplacian in one pass. The
two-pass gradient form leaves the velocity that alternates row by row undamped (its SPAM
gradient is zero); at a no-slip wall the image v_g = -v_i continues the parabola oddly
and the rows within h of the wall drive that mode: with the gradient form the profile is
6 % off at n = 16 even with Monaghan's pair viscosity at alpha = 0.1 as a damper
(docs/scenes/poiseuille.md).

Why the tolerances:
  * Steady profile. Inside, the pair Laplacian is exact for a parabola on the full lattice
    (its normalisation makes a quadratic field's Laplacian exact); the near-wall band
    of width h, where the images' curvature is wrong, perturbs the profile by O((h/H)^2) of
    the peak. Asserted: L2 error below C (h/H)^2 with C = 3 (measured C printed: 0.2 to 0.7),
    and an order of at least 1.2 from n = 8 to 16 (measured 1.5). From n = 16 to 32 the
    error meets the sliding lattice's noise, about 0.5 % of the peak (the Couette test's
    row-pair profile: below 1 %), so its order there is printed, not asserted.
  * Force balance. At steady state the walls hold the whole body force: the two walls'
    forces on the gas (books wall_ylo_fx + wall_yhi_fx, averaged over the window) sum to
    -g M, up to the window's mean rate of change of momentum (the lattice noise's; measured
    within 0.5% of g M): 2% (BOUND_FORCE).
Measured values are printed; docs/scenes/poiseuille.md has them with the commit."""
import os
from spamrun import Checks, arguments, run, summary, table
from shear_profile import errors, mean_profile, order, poiseuille_exact, snapshots, window_mean

a = arguments()
c = Checks()
U, ETA, H_KERNEL, NX = 0.1, 1.0, 3.0, 8
BOUND_C, BOUND_FORCE = 3.0, 0.02
ns = (8, 16, 32)
l2s = []
for n in ns:
    diffusion = n * n / ETA  # H^2 / nu at rho = 1
    out = os.path.join(a.workdir, f"n{n}")
    code, _, err = run(a.spam_ark, ["-scene", "poiseuille", "-poiseuille_n", n, "-poiseuille_nx", NX, "-poiseuille_speed", U,
                                    "-h", H_KERNEL, "-kernel", "wendland_c2", "-viscosity_shear", ETA,
                                    "-ts_max_time", 1.5 * diffusion, "-output_interval", diffusion / 32,
                                    "-snapshot_interval", diffusion / 32, "-snapshot_csv"], out)
    if not c.check(code == 0, f"n = {n}: poiseuille runs (exit {code}) {err.strip()}"):
        continue
    g = summary(out)["gravity_x"]
    prof = mean_profile(snapshots(out), n, diffusion)
    nu = ETA / (sum(r for _, _, r in prof) / len(prof))
    peak = g * n * n / (8 * nu)
    l2, mx = errors(prof, lambda y: poiseuille_exact(y, 1.25 * diffusion, g, n, nu), peak)
    l2s.append(l2)
    bound = BOUND_C * (H_KERNEL / n) ** 2
    c.check(l2 < bound, f"n = {n}: profile L2 {l2:.2e}, max {mx:.2e} of the peak {peak:.4g} (< {BOUND_C:g} (h/H)^2 = {bound:.3f}; C = {l2 / (H_KERNEL / n) ** 2:.2f})")
    ts = table(os.path.join(out, "timeseries.csv"))
    fw = window_mean(ts, "wall_ylo_fx", diffusion) + window_mean(ts, "wall_yhi_fx", diffusion)
    gm = g * ts["mass"][0]
    c.check(abs(fw / -gm - 1) < BOUND_FORCE, f"n = {n}: walls' force on the gas {fw:.5f} against -g M = {-gm:.5f} (ratio {fw / -gm:.4f}; within {BOUND_FORCE:.0%})")
if len(l2s) == len(ns):
    p = order(ns[:2], l2s[:2])
    c.check(p >= 1.2, f"profile L2 error falls with n ({', '.join(f'{e:.2e}' for e in l2s)}): order {p:.2f} from 8 to 16 (>= 1.2); "
                      f"{order(ns[1:], l2s[1:]):.2f} from 16 to 32 (the noise floor)")
c.finish()
