#!/usr/bin/python3
"""Free expansion with mirror walls (CiSE 2001: "very similar" to the
periodic run): the 2D gas of -scene expansion (n^2 particles in one corner of a box of edge
2n) with free-slip walls on all four faces instead of periodic images.

Why the comparisons and their bounds:
  * Walled n against periodic 2n. A free-slip wall is a mirror plane: the walled box is one
    quadrant of a periodic box of edge 4n holding the gas doubled to (2n)^2, which is the
    periodic run with 2n at the same lattice spacing, h and time (only the seeded random
    offsets, 1% of the spacing, are not mirror-symmetric). So dS/(N k ln 4) of the two runs
    must agree at every output time up to the estimator's noise from those offsets; bound
    0.02 (BOUND_MIRROR; measured below).
  * Walled n against periodic n at the same n, h and time (the paper's comparison), at
    t = 2 tau (tau = n / c; the abscissa's end of CiSE Fig. 3 and of
    run_expansion_entropy.py). By the mirror argument this is periodic 2n against periodic
    n: the same gas at the same spacing and h in a box twice the size, which in the
    continuum would be the same flow at half the time (x, t -> 2x, 2t); h is not scaled,
    so the two differ by the estimator's dependence on h/n, which run_expansion_entropy.py
    bounds by 10% of N k ln 4 for either: half of that, 0.05 (BOUND_SAME). At 4 tau the two
    are printed: the periodic estimate sags (0.82) while the walled one, like the periodic
    2n run, keeps rising (0.91).
  * Energy. A static free-slip wall does no work (the mirror system is half of a symmetric
    doubled one), so the walled isentropic gas conserves its energy to the integrator's
    tolerance: drift below 1e-4 at rtol 1e-6 (as the periodic test). The walls' work book
    is exactly 0 (the force of a static wall does no work: F . v_w with v_w = 0). Particles
    that cross a wall between steps are reflected (counted in post_step_jumps, printed):
    the reflection keeps |v| and the mirrored density, so it costs no energy.
Measured at the commit of docs/scenes/expansion-walls.md (printed by this test)."""
import os
from spamrun import Checks, arguments, run, summary, table

a = arguments()
c = Checks()
N, H_KERNEL = 24, 7
BOUND_MIRROR, BOUND_SAME = 0.02, 0.05
WALLS = ["-wall_xlo", "freeslip", "-wall_xhi", "freeslip", "-wall_ylo", "freeslip", "-wall_yhi", "freeslip"]
t_end = 4.0 * N  # 4 tau at the sound speed 1 of the default isentrope


def expansion(name, n, extra):
    out = os.path.join(a.workdir, name)
    code, _, err = run(a.spam_ark, ["-dim", 2, "-expansion_n", n, "-h", H_KERNEL, "-ts_max_time", t_end,
                                    "-output_interval", N / 8, "-snapshot_interval", 0] + extra, out)
    c.check(code == 0, f"{name}: expansion runs (exit {code}) {err.strip()}")
    return out


walled = expansion("walls", N, WALLS)
same = expansion("periodic", N, [])
double = expansion("periodic2n", 2 * N, [])
tw, tp, td = (table(os.path.join(d, "timeseries.csv")) for d in (walled, same, double))
dmirror = max(abs(x - y) for x, y in zip(tw["dS_sum_ratio"], td["dS_sum_ratio"]))
c.check(dmirror < BOUND_MIRROR, f"walled n = {N} against periodic n = {2 * N}: max |d(dS/(N k ln 4))| {dmirror:.4f} over t <= 4 tau (< {BOUND_MIRROR})")
mid = min(range(len(tw["t"])), key=lambda k: abs(tw["t"][k] - 2 * N))
fw, fp = tw["dS_sum_ratio"][mid], tp["dS_sum_ratio"][mid]
c.check(abs(fw - fp) < BOUND_SAME, f"walled against periodic at n = {N}, t = {tw['t'][mid] / N:g} tau: dS/(N k ln 4) {fw:.4f} and {fp:.4f}, difference {fw - fp:+.4f} (< {BOUND_SAME}); periodic 2n {td['dS_sum_ratio'][mid]:.4f}")
for key, v in (("mirror_max", dmirror), ("walled_2tau", fw), ("periodic_2tau", fp), ("walled_4tau", tw["dS_sum_ratio"][-1]),
               ("periodic_4tau", tp["dS_sum_ratio"][-1]), ("periodic2n_4tau", td["dS_sum_ratio"][-1])):
    c.reading(key, v)
print(f"     at t = 4 tau: walled {tw['dS_sum_ratio'][-1]:.4f}, periodic {tp['dS_sum_ratio'][-1]:.4f}, periodic 2n {td['dS_sum_ratio'][-1]:.4f}")
s = summary(walled)
c.check(s["energy_rel_drift_max"] < 1e-4, f"walled: energy drift {s['energy_rel_drift_max']:.2e} at rtol 1e-6 (< 1e-4; periodic {summary(same)['energy_rel_drift_max']:.2e}); {s['post_step_jumps']} wall crossings reflected")
for key, v in (("energy_walled", s["energy_rel_drift_max"]), ("energy_periodic", summary(same)["energy_rel_drift_max"]),
               ("crossings", s["post_step_jumps"])):
    c.reading(key, v)
work = max(abs(w) for w in tw["wall_work"])
c.check(work <= 1e-12 * tw["total"][0], f"walled: the static walls' work book stays 0 (max |W| {work:.2e})")
c.reading("wall_work_max", work)
c.finish(a.readings)
