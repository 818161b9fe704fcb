"""Elastic plane waves (PRE Sec. V): the measured periods of the transverse and the
longitudinal standing wave on the 24 x 24 crystal agree with the periods of the
linearised SPAM equations on the perfect lattice (dispersion_lucy.c) within 0.5% at the
paper's amplitude 0.25, and within 0.05% at amplitude 0.05 (the remainder is the
amplitude's second-order shift); the continuum periods differ by 4.5%, so the check can
tell the two apart. KE + IE is constant to 1e-6 at rtol 1e-10 (the SPAM energy equation
conserves it exactly; the rest is the integrator's error)."""
import os

from planewave_period import measured_period, predicted_periods
from spamrun import Checks, arguments, run, summary, table

a = arguments()
c = Checks()
for mode in ("transverse", "longitudinal"):
    for amp, tol in ((0.25, 5e-3), (0.05, 5e-4)):
        out = os.path.join(a.workdir, f"{mode}{amp:g}")
        code, stdout, err = run(a.spam_ark, ["-scene", "planewave", "-planewave_mode", mode, "-planewave_amplitude", amp,
                                             "-ts_rtol", 1e-10, "-ts_atol", 1e-12, "-output_interval", 0.1,
                                             "-snapshot_interval", 0], out)
        c.check(code == 0, f"{mode} A={amp}: run completes (exit {code}) {err.strip()}")
        spam, continuum = predicted_periods(stdout)
        ts = table(os.path.join(out, "timeseries.csv"))
        period, nmin = measured_period(ts["t"], ts["kinetic"])
        c.check(nmin >= 3, f"{mode} A={amp}: {nmin} kinetic-energy minima found (>= 3)")
        c.check(abs(period / spam - 1) < tol, f"{mode} A={amp}: period {period:.5f} vs linearised SPAM {spam:.5f} "
                f"({period / spam - 1:+.2e}, tolerance {tol:g}); continuum {continuum:.5f}")
        c.check(abs(spam / continuum - 1) > 0.02, f"{mode}: SPAM and continuum periods differ by {spam / continuum - 1:+.2%}")
        s = summary(out)
        c.check(s["energy_rel_drift_max"] < 1e-6, f"{mode} A={amp}: KE + IE drift {s['energy_rel_drift_max']:.2e} (< 1e-6)")
        ke, ie = max(ts["kinetic"]), ts["internal"][0]
        c.check(abs(ke / ie - 1) < 0.01, f"{mode} A={amp}: peak KE {ke:.6g} vs initial IE {ie:.6g}: full exchange within 1%")
c.finish()
