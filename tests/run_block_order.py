#!/usr/bin/python3
"""The order and conservation of -ts_type block_kdk (block individual steps, kick-drift-kick)
on a small scene with a spread of bins and no symmetry: 16 x 16 particles of the ideal gas
(gamma 1.4, unit lattice, periodic, h = 3, summation density, Monaghan's viscosity) with
e = 1 + 20 exp(-r^2/4) about an off-centre point (sound speed from 1.2 to 6.3: the bins
reach level 2) and random velocities (deviation 0.1 per component, fixed seed; summed
|m v| 86), run to T = 1.

Steps: the top step D = s (-ts_dt), -block_cfl s, -block_force s for s = 1/16, 1/32,
1/64 (the coarser s = 1/4 and 1/8 are not yet in the asymptotic range: orders 1.3-1.9). Halving all three halves every particle's wanted step and the top step together,
so each particle keeps its bin (its level k = ceil(log2(D / dt_i)) is unchanged) and the
method is kick-drift-kick at fixed bins: a second-order method. The errors are measured
against DP5 at -ts_rtol 1e-11 (its own error ~1e-9, below the finest run's by 10^4): max
|x - x_ref| over the particles at T.

Measured (block_max_level 16; and with -block_max_level 0, the global kick-drift-kick on
the shortest wanted step):
  s      1/16      1/32      1/64      order of the last halving
  block  3.13e-4   8.20e-5   2.10e-5   1.96
  global 1.59e-4   3.97e-5   1.03e-5   1.95
The order of the finer halving must be within 0.2 of 2 (the next term of the error is
third order and at these steps moves the observed order by less than 0.1).

Conservation: the total energy drift (|E(T) - E(0)| / E(0)) is the method's error, second
order (block 1.2e-5, 3.3e-6, 8.7e-7: orders 1.86, 1.93; global 1.4e-5, 4.2e-6, 1.1e-6): the order of its finer halving
within 0.3 of 2. The momentum: in one bin every pair's forces act on both particles over
the same times, so the total momentum is kept to round-off (measured 0 exactly; bound 1e-12
of the particles' summed |m v|). With several bins a pair's forces act on its two
particles at different times (each at its own step's ends), so momentum is not kept
exactly; its error is the method's, second order (measured 3.1e-4, 7.6e-5, 1.5e-5: orders 2.0, 2.35): its
finer halving must show an order above 1.5.

Also: the options of the other methods' error control are refused with block_kdk, and the
block options with another method. 1.3 s of CPU (labelled fast)."""
import os

import numpy as np

from block_gas_scene import N, T, scene, write_gas  # noqa: F401
from spamrun import Checks, arguments, one_line, run, summary, table

SCALES = (0.0625, 0.03125, 0.015625)
ORDER_TOL, ENERGY_ORDER_TOL, MOMENTUM_ORDER_MIN, ROUNDOFF = 0.2, 0.3, 1.5, 1e-12


def go(a, c, gas, name, extra):
    """(final positions, velocities, summary, timeseries, stdout) of one run, or None."""
    out = os.path.join(a.workdir, name)
    last = os.path.join(out, "final.csv")
    code, so, err = run(a.spam_ark, scene(gas) + extra + ["-final_csv", last, "-ts_view"], out)
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()[-300:]}"):
        return None
    f = table(last)
    x = np.array([f["x"], f["y"]]).T
    v = np.array([f["vx"], f["vy"]]).T
    return x, v, summary(out), table(os.path.join(out, "timeseries.csv")), so


def order(e):
    return float(np.log2(e[-2] / e[-1]))


a = arguments()
c = Checks()
gas = os.path.join(a.workdir, "gas.csv")
write_gas(gas)
ref = go(a, c, gas, "reference", ["-ts_rtol", 1e-11, "-ts_atol", 1e-14])
for label, level in (("block", 16), ("global", 0)):
    runs = [go(a, c, gas, f"{label}_{s}", ["-ts_type", "block_kdk", "-ts_dt", s, "-block_cfl", s, "-block_force", s, "-block_max_level", level]) for s in SCALES]
    if ref is None or any(r is None for r in runs):
        continue
    xerr, derr, perr = [], [], []
    for x, v, s, ts, so in runs:
        dx = x - ref[0]
        dx -= N * np.round(dx / N)  # periodic: the nearest image
        xerr.append(float(np.max(np.abs(dx))))
        derr.append(abs(ts["total"][-1] - ts["total"][0]) / abs(ts["total"][0]))
        perr.append(max(max(abs(p - ts[k][0]) for p in ts[k]) for k in ("px", "py")))
    deepest = int(runs[-1][4].split("deepest bin")[1].split()[0])
    print(f"     {label}: x errors " + ", ".join(f"{e:.3e}" for e in xerr) + f"; energy {', '.join(f'{e:.2e}' for e in derr)}; momentum {', '.join(f'{e:.2e}' for e in perr)}; deepest bin {deepest}")
    c.check(deepest >= 2 if level else deepest == 0, f"{label}: deepest bin {deepest} ({'several bins' if level else 'one bin'})")
    c.check(abs(order(xerr) - 2) < ORDER_TOL, f"{label}: position error order {order(xerr):.2f} from s = {SCALES[-2]} to {SCALES[-1]} (2 within {ORDER_TOL})")
    c.check(abs(order(derr) - 2) < ENERGY_ORDER_TOL, f"{label}: energy drift {derr[-1]:.1e}, order {order(derr):.2f} (2 within {ENERGY_ORDER_TOL})")
    if level:
        c.check(order(perr) > MOMENTUM_ORDER_MIN, f"{label}: momentum error {perr[-1]:.1e}, order {order(perr):.2f} (above {MOMENTUM_ORDER_MIN}: mixed bins keep it to the method's order)")
    else:
        scale = float(np.sum(np.abs(runs[-1][1])))
        c.check(max(perr) <= ROUNDOFF * scale, f"{label}: momentum kept to round-off ({max(perr):.1e} <= {ROUNDOFF:g} of sum |m v| = {scale:.1f})")
    c.reading(f"{label}.x_errors", xerr)
    c.reading(f"{label}.order", order(xerr))
    c.reading(f"{label}.energy_order", order(derr))
    c.reading(f"{label}.energy_drift", derr)
    c.reading(f"{label}.momentum_error", perr)
# The error-control options of the other methods are refused, and the block ones elsewhere.
for extra, words in ((["-ts_type", "block_kdk", "-ts_rtol", 1e-6], "-ts_rtol"), (["-ts_type", "block_kdk", "-step_cfl", 0.3], "-step_cfl"), (["-block_cfl", 0.1], "-block_cfl")):
    code, _, err = run(a.spam_ark, scene(gas) + ["-ts_max_time", 0.01] + extra, os.path.join(a.workdir, "refused"))
    line = one_line(err) or ""
    c.check(code != 0 and words in line and "applies to" in line, f"{' '.join(map(str, extra))}: refused ({line.strip()[:200]})")
c.finish(a.readings)
