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
(b) Ra = 0.5 Ra_c (below onset), to t = 2000 (two viscous times H^2/nu): nothing grows. The
    wall-layer adjustment of (a) puts a peak of KE in early (measured 0.23, against 0.013
    seeded); below onset the second half's KE stays under half that peak (measured 0.10:
    the mirror walls leave a floor of spurious motion, v/c_s ~ 1e-2, that does not decay
    to zero). Nu is within 3 x the discrete flux error of the exact start (|Nu(t=0) - 1|,
    computed in the run: 0.017 measured; the SPAM flux of the linear profile through mirror
    images) of 1 (measured 0.995).
(c) Ra = 20 Ra_c (above onset), to t = 6000: on this coarse lattice (H = 3.3 h) SPAM's own
    onset lies between 5 and 7.5 Ra_c (docs/scenes/convection.md: at 5 Ra_c nothing grows
    in 8000, at 7.5 and 10 Ra_c rolls grow and then fade), so the rolls are asserted at
    20 Ra_c: KE grows > 100 x the seeded KE (measured 315 x), and saturates: the mean KE over
    the last third is less than 3 x that over the middle third (while growing, KE rose 4.6 x
    in 800 time units, ~45 x per third; saturated, the rolls' KE still wanders 2.5..4.3:
    measured ratio 1.77), and Nu > 1.3 over the second half (measured 2.11; 2D Boussinesq
    rolls at Ra ~ 3e4 carry Nu of about 3).
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
out = go("below", ["-convection_ra", 0.5 * RA_C, "-output_interval", 10, "-snapshot_interval", 0, "-ts_max_time", 2000])
s, ts = summary(out), table(os.path.join(out, "timeseries.csv"))
nu, nub, nut, (qb, qt) = pc.nusselt(s, ts, 1.25, 0.75, 0.5 * ts["t"][-1])
err0 = max(abs(qb[0] - 1.0), abs(qt[0] - 1.0))
ke = ts["kinetic"]
second = [k for t, k in zip(ts["t"], ke) if t >= 0.5 * ts["t"][-1]]
c.check(max(second) < 0.5 * max(ke), f"Ra = 0.5 Ra_c: no growth, KE over the second half <= {max(second):.3g} (< 1/2 of the wall-layer peak {max(ke):.3g})")
c.check(abs(nu - 1.0) < 3 * err0, f"Ra = 0.5 Ra_c: Nu = {nu:.4f} (hot wall {nub:.4f}, cold wall {nut:.4f}) within 3 x {err0:.4f} of 1 "
        "(the discrete flux error of the exact start)")

# (c) above onset: 20 Ra_c, as the coarse lattice's own onset lies between 5 and 7.5 Ra_c
out = go("above", ["-convection_ra", 20 * RA_C, "-output_interval", 20, "-snapshot_interval", 0, "-ts_max_time", 6000])
s, ts = summary(out), table(os.path.join(out, "timeseries.csv"))
t_end = ts["t"][-1]
nu, nub, nut, _ = pc.nusselt(s, ts, 1.25, 0.75, 0.5 * t_end)
ke = ts["kinetic"]
mid = [k for t, k in zip(ts["t"], ke) if t_end / 3.0 <= t < 2.0 / 3.0 * t_end]
last = [k for t, k in zip(ts["t"], ke) if t >= 2.0 / 3.0 * t_end]
c.check(ke[-1] > 100 * ke[0], f"Ra = 20 Ra_c: KE grows from {ke[0]:.3g} (seeded) to {ke[-1]:.3g} (> 100 x)")
ratio = (sum(last) / len(last)) / (sum(mid) / len(mid))
c.check(ratio < 3.0, f"Ra = 20 Ra_c: KE saturates, mean over the last third / over the middle third = {ratio:.3f} (< 3; "
        f"KE ranges {min(last):.3g}..{max(last):.3g} over the last third)")
c.check(nu > 1.3, f"Ra = 20 Ra_c: Nu = {nu:.4f} over the second half (hot wall {nub:.4f}, cold wall {nut:.4f}) > 1.3")
print(f"ms per RHS (the cell with walls): {1e3 * s['rhs_time_s'] / s['rhs_evals']:.4f}")
c.finish()
