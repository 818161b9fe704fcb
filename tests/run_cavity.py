"""The lid-driven cavity (scene cavity) at Re = 100 against Ghia, Ghia & Shin (1982).

Set-up: the scene's defaults (gas, gamma 2, Mach U/c = 0.1, U = 0.1, eta = U L / Re at
rho = 1) on the n x n unit lattice, Wendland C2 at h = 3 (the gas's square lattice is
unstable under Lucy: docs/scenes/couette.md), n = 32 and 48, run to T_END = 6 L/U from rest.
Options in --extra "..." are passed to every run (the gas scheme under development), after
the test's own, so they win. Each run is compared from its final CSV (-final_csv): u/U on
the vertical centreline at Ghia's 15 inner points of Table I and v/U on the horizontal one
at those of Table II, each a kernel-weighted average over the particles within h of the
point and their wall images (tests/cavity_profile.py). Printed per resolution: the
L-infinity errors, the extrema (min u, max v, min v on a fine line) with their errors
relative to Ghia's, and the steadiness: the change of the kinetic energy over the last L/U
relative to its value.

What is asserted is what holds with today's plain SPAM (docs/scenes/cavity.md: at Mach 0.1
the particles' velocity noise, of order 0.1 U, swamps the vortex at Re = 100):
  * every run ends (exit 0);
  * the primary vortex turns the right way (clockwise, as the lid at the top drives it
    along +x): the gas's angular momentum about the centre, sum m ((x - L/2) v_y -
    (y - L/2) v_x) / (M U L), is negative. It sums every particle, so the velocity noise
    (of order 0.1 U per particle, random in sign) contributes about 0.03 / sqrt(N), below
    1e-3 (measured at Re = 100 today: -8.6e-3 at n = 32, -3.9e-3 at n = 48; the well-formed
    vortex of Re = 10 at n = 32: -4.1e-2);
  * the lid drags the layer under it: u/U at Ghia's point nearest the lid (y = 0.9766,
    where Ghia has 0.84 at Re = 100) is positive.
The extrema's signs are no test: noise alone makes a maximum positive and a minimum negative.
The project's goal, printed but not asserted (the lead tightens it when the scheme gets
there): each extremum within GOAL = 3 % of Ghia's at Re = 100, and the kinetic energy
steady to 1 % over the last L/U."""
import argparse
import csv
import os
import shlex
import shutil
import time
from spamrun import Checks, run
from cavity_profile import compare, read_particles

GOAL, STEADY = 0.03, 0.01
U, H_KERNEL = 0.1, 3.0

ap = argparse.ArgumentParser()
ap.add_argument("--spam-ark", required=True)
ap.add_argument("--workdir", required=True)
ap.add_argument("--extra", default="", help="options passed to every run (after the test's own)")
ap.add_argument("--n", type=int, nargs="+", default=[32, 48], help="lattice points per side")
ap.add_argument("--re", type=int, default=100, choices=(100, 1000))
ap.add_argument("--t-end", type=float, default=6.0, help="end time in units of L/U")
a = ap.parse_args()
shutil.rmtree(a.workdir, ignore_errors=True)
os.makedirs(a.workdir)
c = Checks()
extra = shlex.split(a.extra)
goal_met = True
for n in a.n:
    L = float(n)
    lu = L / U
    out = os.path.join(a.workdir, f"n{n}")
    final = os.path.join(a.workdir, f"final_n{n}.csv")
    t0 = time.time()
    code, _, err = run(a.spam_ark, ["-scene", "cavity", "-cavity_n", n, "-cavity_re", a.re, "-cavity_lid_velocity", U,
                                    "-kernel", "wendland_c2", "-h", H_KERNEL, "-ts_max_time", a.t_end * lu,
                                    "-output_interval", lu / 8, "-snapshot_interval", 0, "-final_csv", final] + extra, out)
    wall = time.time() - t0
    if not c.check(code == 0, f"n = {n}: cavity runs to {a.t_end:g} L/U (exit {code}, {wall:.1f} s) {err.strip()}"):
        continue
    parts = read_particles(final)
    r = compare(parts, L, U, H_KERNEL, a.re)
    with open(os.path.join(out, "timeseries.csv")) as f:
        ts = list(csv.DictReader(f))
    t = [float(x["t"]) for x in ts]
    ke = [float(x["kinetic"]) for x in ts]
    before = min(range(len(t)), key=lambda k: abs(t[k] - (t[-1] - lu)))
    dke = abs(ke[-1] - ke[before]) / ke[-1]
    e, g, rel = r["extrema"], r["ghia_extrema"], r["rel"]
    lz = sum((p[0] - L / 2) * p[3] - (p[1] - L / 2) * p[2] for p in parts) / (len(parts) * U * L)
    print(f"n = {n}: Re {a.re}, L-inf error (units of U) u {r['linf_u']:.3f}, v {r['linf_v']:.3f}; "
          f"min u {e['u_min']:+.4f} (Ghia {g['u_min']:+.5f}, {rel['u_min']:+.1%}), "
          f"max v {e['v_max']:+.4f} (Ghia {g['v_max']:+.5f}, {rel['v_max']:+.1%}), "
          f"min v {e['v_min']:+.4f} (Ghia {g['v_min']:+.5f}, {rel['v_min']:+.1%}); "
          f"angular momentum about the centre {lz:+.4f} M U L; KE {ke[-1]:.4g}, its change over the last L/U {dke:.1%}", flush=True)
    c.check(lz < 0, f"n = {n}: the primary vortex turns clockwise: angular momentum about the centre {lz:+.4f} M U L (< 0)")
    top = r["u"][-2]
    c.check(top > 0, f"n = {n}: the lid drags the layer under it: u/U at y = 0.9766 L {top:+.3f} (> 0; Ghia {r['ghia_u_top']:+.5f})")
    met = all(abs(x) <= GOAL for x in rel.values()) and dke <= STEADY
    goal_met = goal_met and met
    print(f"goal (not asserted) n = {n}: extrema within {GOAL:.0%} of Ghia's and KE steady to {STEADY:.0%} over the last L/U: "
          f"{'met' if met else 'not met'} (worst extremum {max(abs(x) for x in rel.values()):.1%}, KE change {dke:.1%})", flush=True)
print(f"goal (not asserted): {'met' if goal_met else 'not met'} at every resolution; options given: {a.extra or '(none)'}")
c.finish()
