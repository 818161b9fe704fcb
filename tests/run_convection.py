"""Rayleigh-Benard cell (-scene convection, CiSE 2001 Fig. 4) on a coarse 20 x 10 lattice
(N = 200, h = 3, g = 0.1 c_p / H = 0.02, gamma = 2, c_p = 2).

(a) Isothermal column at rest (T_b = T_t = 1, no seeded velocities): rho ~ exp(-g y / T),
    scale height T/g = 50 >> h. In the bulk the hydrostatic start is balanced to the SPAM
    pressure-gradient error, O((h / (T/g))^2) = 4e-3 of g. At a mirror wall the images carry
    their source's pressure, so the wall layer (within h) misses the hydrostatic pressure
    difference across it: an unbalanced force per unit mass of order g acting until sound
    has crossed the layer, h / c_s. The spurious velocity is then at most
        v / c_s ~ g (h / c_s) / c_s = g h / (gamma T) = 0.03,
    the bound asserted on max |v| / c_s over every snapshot to t = 10 sound traversal
    times (the layer adjusts and the motion then rings down; it must not grow).
(b) Ra = 0.5 Ra_c (below onset): the seeded velocities (0.01 c_s) and the wall-layer
    adjustment decay: KE at the end (one viscous time H^2/nu) below 1/10 of its initial
    value, and Nu within a tolerance of 1. Tolerance: the conduction state's heat flux is
    the discrete SPAM flux of a linear T through mirror images that continue it; its error
    is that of the kernel's first-moment lattice sum at h = 3 on the unit lattice plus
    the density variation across h (g h / T = 0.06): 10 % covers both.
(c) Ra = 5 Ra_c (above onset): the rolls grow and saturate: KE at the end is above 10 x
    its minimum and steady (the last fifth varies by less than 20 %), and Nu exceeds 1.2
    (Nu - 1 grows as ~ 1.4 (Ra/Ra_c - 1)^0.5 ... for Boussinesq rolls, about 2 at 5 Ra_c:
    the margin 1.2 leaves room for the coarse lattice's smeared boundary layers).
Measured values are printed by each check."""
import math
import os
import sys

from spamrun import Checks, arguments, run, table, manifest_files, summary

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import plot_convection as pc  # noqa: E402

RA_C = pc.RA_CRITICAL
a = arguments()
c = Checks()
CELL = ["-scene", "convection", "-convection_nx", 20, "-convection_ny", 10, "-h", 3, "-ts_rtol", 1e-4]


def go(name, extra):
    out = os.path.join(a.workdir, name)
    code, so, err = run(a.spam_ark, CELL + extra, out)
    c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()[-300:]}")
    if code != 0:
        c.finish()
    return out


def max_speed(out):
    """Largest |v| over every CSV snapshot of the run."""
    top = 0.0
    for path in manifest_files(out, "snapshot_csv"):
        with open(path) as f:
            f.readline()
            head = f.readline().strip().split(",")
            ix, iy = head.index("vx"), head.index("vy")
            for line in f:
                v = line.split(",")
                top = max(top, math.hypot(float(v[ix]), float(v[iy])))
    return top


# (a) the isothermal column at rest
g, gamma, T, h = 0.02, 2.0, 1.0, 3.0
cs = math.sqrt(gamma * T)
t_sound = 10.0 / cs
out = go("column", ["-wall_ylo_temperature", T, "-wall_yhi_temperature", T, "-convection_amplitude", 0,
                    "-ts_max_time", 10 * t_sound, "-snapshot_interval", t_sound, "-snapshot_hdf5", 0,
                    "-output_interval", t_sound])
bound = g * h / (gamma * T)
vmax = max_speed(out) / cs
c.check(vmax < bound, f"isothermal column: max |v| / c_s = {vmax:.3g} over 10 sound times (bound g h / (gamma T) = {bound:.3g})")

# (b) below onset
out = go("below", ["-convection_ra", 0.5 * RA_C, "-output_interval", 10, "-snapshot_interval", 0, "-ts_max_time", 1000])
s, ts = summary(out), table(os.path.join(out, "timeseries.csv"))
nu, nub, nut, _ = pc.nusselt(s, ts, 1.25, 0.75, 0.5 * ts["t"][-1])
ke = ts["kinetic"]
c.check(ke[-1] < 0.1 * ke[0], f"Ra = 0.5 Ra_c: KE decays, {ke[0]:.3g} -> {ke[-1]:.3g} (< 1/10)")
c.check(abs(nu - 1.0) < 0.1, f"Ra = 0.5 Ra_c: Nu = {nu:.4f} (hot wall {nub:.4f}, cold wall {nut:.4f}) within 0.1 of 1")

# (c) above onset
out = go("above", ["-convection_ra", 5 * RA_C, "-output_interval", 20, "-snapshot_interval", 0, "-ts_max_time", 6000])
s, ts = summary(out), table(os.path.join(out, "timeseries.csv"))
t_end = ts["t"][-1]
nu, nub, nut, _ = pc.nusselt(s, ts, 1.25, 0.75, 0.8 * t_end)
ke = ts["kinetic"]
last = [k for t, k in zip(ts["t"], ke) if t >= 0.8 * t_end]
c.check(ke[-1] > 10 * min(ke), f"Ra = 5 Ra_c: KE grows from its minimum {min(ke):.3g} to {ke[-1]:.3g} (> 10 x)")
c.check(max(last) < 1.2 * min(last), f"Ra = 5 Ra_c: KE plateau over the last fifth, {min(last):.4g}..{max(last):.4g} (within 20 %)")
c.check(nu > 1.2, f"Ra = 5 Ra_c: Nu = {nu:.4f} over the last fifth (hot wall {nub:.4f}, cold wall {nut:.4f}) > 1.2")
print(f"ms per RHS (the cell with walls): {1e3 * s['rhs_time_s'] / s['rhs_evals']:.4f}")
c.finish()
