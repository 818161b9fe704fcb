#!/usr/bin/python3
"""The lid-driven cavity (scene cavity) at Re = 100 against Ghia, Ghia & Shin (1982).

Set-up: the scene's defaults (the gas's flow scheme, gamma 2, Mach U/c = 0.1, U = 0.1,
eta = U L / Re at rho = 1) on the n x n unit lattice, Wendland C2 at h = 3 (the gas's square
lattice is unstable under Lucy: docs/scenes/couette.md), n = 32 and 64 (c h / nu = 94 and
47; the lid's boundary layer L / sqrt(Re) is 1.1 h and 2.1 h), run to T_END = 12 L/U from
rest. Options in --extra "..." are passed to every run after the test's own, so they win.

Each run writes a CSV snapshot every L/(4U); the profiles are the mean over the snapshots
of the last AVERAGE = 2 L/U (9 snapshots): u/U on the vertical centreline at Ghia's 15
inner points of Table I and v/U on the horizontal one at those of Table II, each a
kernel-weighted average over the particles within h of the point and their wall images
(tests/cavity_profile.py). A single snapshot will not do: the sound the lid keeps launching
moves one snapshot's extrema by several per cent (n = 64, one snapshot: the worst extremum
6.6 % off at 12 L/U, 2.3 % at 20 L/U, with the kinetic energy steady to 0.2 %).

Why 12 L/U: the kinetic energy from rest reaches its steady value to 2 % by 7 L/U at n = 64
(0.96 of it at 6 L/U, within +-1.5 % from 7 to 20 L/U); the slowest viscous mode of the
cell decays as exp(-2 pi^2 t U / (Re L)), by e^-0.2 per L/U at Re = 100, to 0.1 of its
start by 12 L/U.

Asserted:
  * every run ends (exit 0);
  * the primary vortex turns clockwise (the lid at the top drives it along +x): the gas's
    angular momentum about the centre, sum m ((x - L/2) v_y - (y - L/2) v_x) / (M U L),
    is negative (noise contributes about 0.03 / sqrt(N), below 1e-3);
  * the lid drags the layer under it: u/U at y = 0.9766 L (Ghia: 0.84) is positive;
  * at the finest n (unless --no-goal): min u on x = L/2, max v and min v on y = L/2 within
    SMOOTHING + 2 s / sqrt(4) of Ghia's extrema, and the mean profiles within LINF = 0.05 U
    of his points. SMOOTHING = 2 % is the resolution's: at n = 64 the kernel average over
    h = 3 spacings smooths a profile's peak of half-width w ~ 0.1 L by about (h / w)^2 / 10
    ~ 2 % (Wendland C2's second moment). The flow at n = 64 is not steady: the lid's sound
    and the particles' noise move a single snapshot's extrema by s = 2-6 % (measured, the
    spread printed below), and the mean over 9 snapshots holds about 4 independent ones,
    so the mean carries s / 2 of noise; two of those are allowed. (A round-off change of
    the pair sums moved max v from -2.3 % to -4.2 % with s from 2.7 % to 5.8 %: the 3 %
    goal, printed, is within that noise.) The L-infinity bound: the profiles' steepest slopes, about 4 U / L
    near the lid, times the h/4 = 0.012 L that the kernel average's centre can sit off a
    particle ring: 0.05 U.
    The third extremum, min v (the downflow beside the wall the lid runs into), was 5.8-7.7 %
    too strong at n = 64 while the flow scheme's viscosity took two passes (grad v, then the
    stress): measured with the pair form, +1.9 %, -0.7 % and -1.7 % for the three extrema,
    spreads 1.2-1.3 %.
Printed per resolution: the L-infinity errors, the extrema with their errors relative to
Ghia's, the spread of the extrema over the averaged snapshots, the angular momentum and the
change of the kinetic energy over the last L/U."""
import argparse
import math
import csv
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import time
from spamrun import Checks, run, summary
from cavity_profile import combine, read_particles, snapshot_profiles

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples")
GOAL, LINF = 0.03, 0.05
SMOOTHING, INDEPENDENT = 0.02, 4  # the kernel's smoothing of a peak; independent snapshots of the mean
T_END, AVERAGE, PER_LU = 12.0, 2.0, 4
U, H_KERNEL = 0.1, 3.0

ap = argparse.ArgumentParser()
ap.add_argument("--spam-ark", required=True)
ap.add_argument("--workdir", required=True)
ap.add_argument("--extra", default="", help="options passed to every run (after the test's own)")
ap.add_argument("--n", type=int, nargs="+", default=[32, 64], help="lattice points per side")
ap.add_argument("--re", type=int, default=100, choices=(100, 1000))
ap.add_argument("--t-end", type=float, default=T_END, help="end time in units of L/U")
ap.add_argument("--average", type=float, default=AVERAGE, help="average the profiles over the snapshots of the last AVERAGE L/U")
ap.add_argument("--no-goal", action="store_true", help="print the goal at the finest n without asserting it (another scheme, another Re)")
ap.add_argument("--readings", help="write each n's errors to this JSON file (when the test passes) for the pages that quote them")
a = ap.parse_args()
shutil.rmtree(a.workdir, ignore_errors=True)
os.makedirs(a.workdir)
c = Checks()
extra = shlex.split(a.extra)


def snapshot_time(path):
    """The time on a particle CSV's first line ("# t=...")."""
    with open(path) as f:
        head = f.readline()
    return float(head.split("t=")[1].split()[0]) if head.startswith("#") and "t=" in head else None


def late_snapshots(out, t_from):
    """The particle lists of the CSV snapshots written at t >= t_from."""
    names = sorted(x for x in os.listdir(out) if x.startswith("particles_") and x.endswith(".csv"))
    paths = [os.path.join(out, x) for x in names]
    return [read_particles(p) for p in paths if (snapshot_time(p) or -1.0) >= t_from - 1e-9]


def chart_reading(out, rel):
    """examples/plot_cavity.py on the run: it writes its PNG and prints the same extrema's
    errors (whole per cent) as this test computes from the same snapshots."""
    png = os.path.join(out, "cavity.png")
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, "plot_cavity.py"), out, "-o", png, "--average", str(a.average)],
                       capture_output=True, text=True)
    said = [ln.split() for ln in p.stdout.splitlines() if ln.strip().startswith(("min u", "max v", "min v"))]
    got = {f"{w[0]}_{w[1]}".replace("min_u", "u_min").replace("max_v", "v_max").replace("min_v", "v_min"): w[-1] for w in said}
    want = {k: f"{v:+.0%}" for k, v in rel.items()}
    c.check(p.returncode == 0 and os.path.exists(png) and os.path.getsize(png) > 10000 and got == want,
            f"plot_cavity.py on the run: exit {p.returncode}, its extrema's errors {got} as the test's {want}")


for n in a.n:
    L = float(n)
    lu = L / U
    out = os.path.join(a.workdir, f"n{n}")
    t0 = time.time()
    # No 600 s limit of its own: the n = 64 run took longer than that beside other jobs on
    # two cores; ctest's limit (tests/CMakeLists.txt) still ends a hang.
    code, _, err = run(a.spam_ark, ["-scene", "cavity", "-cavity_n", n, "-cavity_re", a.re, "-cavity_lid_velocity", U,
                                    "-kernel", "wendland_c2", "-h", H_KERNEL, "-ts_max_time", a.t_end * lu,
                                    "-output_interval", lu / 8, "-snapshot_interval", lu / PER_LU, "-snapshot_csv", "-snapshot_hdf5", 0] + extra, out, timeout=3600)
    wall = time.time() - t0
    if not c.check(code == 0, f"n = {n}: cavity runs to {a.t_end:g} L/U (exit {code}, {wall:.1f} s) {err.strip()}"):
        continue
    snaps = late_snapshots(out, (a.t_end - a.average) * lu)
    if not c.check(len(snaps) >= 2, f"n = {n}: {len(snaps)} snapshots in the last {a.average:g} L/U (at least 2)"):
        continue
    # Each snapshot's profiles once: their mean is what is held against Ghia, each alone
    # gives the spread of one snapshot's errors.
    profiles = [snapshot_profiles(s, L, U, H_KERNEL) for s in snaps]
    r = combine(profiles, a.re)
    one = [combine([p], a.re)["rel"] for p in profiles]
    spread = {k: statistics.pstdev(x[k] for x in one) for k in one[0]}
    with open(os.path.join(out, "timeseries.csv")) as f:
        ts = list(csv.DictReader(f))
    t = [float(x["t"]) for x in ts]
    ke = [float(x["kinetic"]) for x in ts]
    before = min(range(len(t)), key=lambda k: abs(t[k] - (t[-1] - lu)))
    dke = abs(ke[-1] - ke[before]) / ke[-1]
    # The lid's work heats the adiabatic cell: the internal energy's rise per L/U; and the
    # time from rest after which the kinetic energy stays within 2 % of its final value.
    ie = [float(x["internal"]) for x in ts]
    heating = (ie[-1] - ie[0]) / ie[0] / (t[-1] / lu)
    settled = next(t[k] / lu for k in range(len(t)) if all(abs(v - ke[-1]) <= 0.02 * ke[-1] for v in ke[k:]))
    e, g, rel = r["extrema"], r["ghia_extrema"], r["rel"]
    last = snaps[-1]
    lz = sum((p[0] - L / 2) * p[3] - (p[1] - L / 2) * p[2] for p in last) / (len(last) * U * L)
    print(f"n = {n}: Re {a.re}, mean of {len(snaps)} snapshots over the last {a.average:g} L/U: L-inf error (units of U) "
          f"u {r['linf_u']:.3f}, v {r['linf_v']:.3f}; "
          f"min u {e['u_min']:+.4f} (Ghia {g['u_min']:+.5f}, {rel['u_min']:+.1%}), "
          f"max v {e['v_max']:+.4f} (Ghia {g['v_max']:+.5f}, {rel['v_max']:+.1%}), "
          f"min v {e['v_min']:+.4f} (Ghia {g['v_min']:+.5f}, {rel['v_min']:+.1%}); "
          f"spread of one snapshot's errors {spread['u_min']:.1%}, {spread['v_max']:.1%}, {spread['v_min']:.1%}; "
          f"angular momentum about the centre {lz:+.4f} M U L; KE {ke[-1]:.4g}, its change over the last L/U {dke:.1%}, "
          f"within 2 % of it from {settled:.2f} L/U on; internal energy +{heating:.3%} per L/U", flush=True)
    for key, v in (("linf_u", r["linf_u"]), ("linf_v", r["linf_v"]), ("extrema", e), ("rel", rel), ("spread", spread),
                   ("snapshots", len(snaps)), ("t_over_LU", a.t_end), ("average_LU", a.average), ("steps", summary(out)["steps"]),
                   ("wall_s", wall), ("heating_per_LU", heating), ("ke_settled_LU", settled)):
        c.reading(f"n{n}.{key}", v)
    c.check(lz < 0, f"n = {n}: the primary vortex turns clockwise: angular momentum about the centre {lz:+.4f} M U L (< 0)")
    top = r["u"][-2]
    c.check(top > 0, f"n = {n}: the lid drags the layer under it: u/U at y = 0.9766 L {top:+.3f} (> 0; Ghia {r['ghia_u_top']:+.5f})")
    if n == min(a.n):
        chart_reading(out, rel)
    if n != max(a.n):
        continue
    held = {k: rel[k] for k in ("u_min", "v_max", "v_min")}
    bound = {k: SMOOTHING + 2 * spread[k] / math.sqrt(INDEPENDENT) for k in held}
    inside = all(abs(held[k]) <= bound[k] for k in held)
    worst = max(abs(x) for x in held.values())
    linf = max(r["linf_u"], r["linf_v"])
    text = (f"n = {n}: min u, max v and min v within the smoothing and the mean's noise of Ghia's ({held['u_min']:+.1%} within "
            f"{bound['u_min']:.1%}, {held['v_max']:+.1%} within {bound['v_max']:.1%}, {held['v_min']:+.1%} within "
            f"{bound['v_min']:.1%}) and profiles within {LINF} U of his "
            f"points (L-inf {linf:.3f} U)")
    if a.no_goal:
        print(f"goal (not asserted): {text}: {'met' if inside and linf <= LINF else 'not met'}; options given: {a.extra or '(none)'}")
    else:
        c.check(inside and linf <= LINF, text)
    print(f"goal (not asserted): n = {n}: the three extrema within {GOAL:.0%} of Ghia's: {'met' if worst <= GOAL else 'not met'}")
c.reading("options", a.extra)
c.finish(a.readings)
