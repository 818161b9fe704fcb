#!/usr/bin/python3
"""The walls' books close the energy and momentum balances over a run.

The 2D expansion's 16^2 gas (-material gas, gamma 2, e0 1) fills one corner of a 32 x 32 box
with four mirror walls: free-slip adiabatic at x = 0 and 32, no-slip at y = 0 (isothermal,
T_w = 2: it heats the gas) and y = 32 (adiabatic, moving at 0.2 along x: it drags and works on
the gas), with shear viscosity and conduction 0.5, to t = 40 at rtol 1e-7. The gas hits every
wall, the hot one puts heat in, the moving one does work.

Checked at every output row:
  energy    |E(t) - E(0) - (wall_work + wall_heat)| / E(0) <= 20 rtol: the books are integrated
            with the state by the same method, so what is left is the method's global error
            (measured: about 2 rtol; 20 leaves room for the reflections' restarts);
  momentum  |P(t) - P(0) - wall_impulse| / sqrt(2 M E0) <= 1e-9: the books sum the same pair
            forces the particles feel (summary.json's drift, in double: round-off), and the
            CSV prints 11 significant digits of P and of the impulse (|P| up to ~10 sqrt(2 M E0));
  heat      wall_heat grows (the hot wall heats: T_w = 2 against the gas's T = 1) and the
            adiabatic walls' heat rates are zero to round-off (< 1e-12 of the hot wall's): an
            adiabatic image's heat flux is its source's mirrored, the pair terms cancel across
            the wall (corner images are booked to the isothermal or moving wall);
  work      the static free-slip walls do no work at any instant (|rate| < 1e-9 of the
            moving wall's largest): the gas and its images in such a wall are one half of a
            mirror-symmetric system.
And summary.json's energy drift is the net one (<= 20 rtol) while E itself changes by far more.
"""
import math
import os

from spamrun import Checks, arguments, run, summary, table

RTOL = 1e-7
a = arguments()
c = Checks()
out = os.path.join(a.workdir, "walls")
code, _, err = run(a.spam_ark, ["-expansion_n", "16", "-material", "gas", "-viscosity_shear", "0.5", "-conductivity", "0.5",
                                "-wall_xlo", "freeslip", "-wall_xhi", "freeslip", "-wall_ylo", "noslip", "-wall_ylo_temperature", "2",
                                "-wall_yhi", "noslip", "-wall_yhi_velocity", "0.2,0", "-ts_max_time", "40", "-output_interval", "2",
                                "-ts_rtol", str(RTOL), "-ts_atol", "1e-12", "-snapshot_interval", "0"], out)
c.check(code == 0, f"walled run exit {code} {err.strip()[-300:]}")
t = table(os.path.join(out, "timeseries.csv"))
E0, M = t["total"][0], t["mass"][0]
pscale = math.sqrt(2 * M * E0)
eerr = max(abs(E - E0 - w - q) / E0 for E, w, q in zip(t["total"], t["wall_work"], t["wall_heat"]))
echange = max(abs(E - E0) / E0 for E in t["total"])
c.check(eerr <= 20 * RTOL, f"energy: max |E - E0 - (work + heat)| / E0 = {eerr:.2e} (<= {20 * RTOL:.0e}), while |E - E0| / E0 reaches {echange:.3f}")
perr = max(math.hypot(px - t["px"][0] - jx, py - t["py"][0] - jy) / pscale
           for px, py, jx, jy in zip(t["px"], t["py"], t["wall_impulse_x"], t["wall_impulse_y"]))
c.check(perr <= 1e-9, f"momentum: max |P - P0 - impulse| / sqrt(2 M E0) = {perr:.1e} (<= 1e-9, the CSV's digits)")
hot = max(abs(v) for v in t["wall_ylo_heat_rate"])
adiabatic = max(abs(v) for f in ("xlo", "xhi", "yhi") for v in t[f"wall_{f}_heat_rate"])
c.check(t["wall_heat"][-1] > 0 and adiabatic < 1e-12 * hot, f"heat: {t['wall_heat'][-1]:.4g} in through the hot wall (largest rate {hot:.3g}); adiabatic walls' rates <= {adiabatic:.1e}")
moving = max(abs(v) for v in t["wall_yhi_work_rate"])
still = max(abs(v) for f in ("xlo", "xhi") for v in t[f"wall_{f}_work_rate"])
c.check(moving > 0 and still < 1e-9 * moving, f"work: moving wall's largest rate {moving:.3g}, the static free-slip walls' {still:.1e}")
s = summary(out)
c.check(s["energy_rel_drift_max"] <= 20 * RTOL and s["momentum_rel_drift_max"] <= 1e-12,
        f"summary.json drifts net of the walls: energy {s['energy_rel_drift_max']:.2e}, momentum {s['momentum_rel_drift_max']:.1e}; post_step_jumps {s['post_step_jumps']}")
c.finish()
