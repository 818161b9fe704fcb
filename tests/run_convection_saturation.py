#!/usr/bin/python3
"""The saturation rule the convection scripts share (tests/convection_roll.py), on rolls whose
answer is known: A(t) = A_s / (1 + (A_s / A_0 - 1) e^(-s t)), the logistic roll of
dA/dt = s A (1 - A / A_s), sampled every 1/(8 s) as the runs' snapshots are.

- saturation: the roll reaches 0.9 x its end value at t_90 = ln(9 (A_s / A_0 - 1)) / s; the
  end value is the mean over the last 1/s (within 1e-3 of A_s once the run is 4/s past t_90,
  which moves t_90 by less than 0.01/s), and the snapshot found is the first at or after
  t_90 (within one interval, 1/(8 s), after it).
- run_to_saturation: a run that ends before t_sat + 4/s (the onset study's run at 1.2 Ra_c
  stopped at t = 8000 with its roll just saturated) is continued to t_sat + 4/s, and again
  while that moves (its end value, still rising, put t_sat early): twice here, ending within
  two snapshot intervals of t_90 + 4/s; a run already past it
  is not continued; a roll that keeps growing exponentially (its end value always ahead)
  is continued MAX_EXTENSIONS times and reported not saturated; a run without a checkpoint
  (extend returns None) is not continued and is reported not saturated.
- nu_from: Nu's average starts 1/s after t_sat.
- grew: the logistic roll grew (end / minimum = A_s / A(first snapshot)); a roll that
  decays to noise (the conduction state) did not.
No spam-ark run: --spam-ark and --workdir are accepted and unused."""
import math

import numpy as np

from spamrun import Checks, arguments
import convection_roll as roll

arguments()
c = Checks()
S, A0, AS = 1e-3, 1e-3, 0.05
DT = 0.125 / S
T90 = math.log(9 * (AS / A0 - 1)) / S


def logistic(t_end):
    t = np.arange(0.0, t_end + 0.5 * DT, DT)
    return t, AS / (1 + (AS / A0 - 1) * np.exp(-S * t))


# saturation on a run long past it
t, A = logistic(T90 + 6 / S)
t_sat, a_end = roll.saturation(t, A, S)
c.check(abs(a_end / AS - 1) < 1e-3, f"end value {a_end:.5g} against A_s = {AS:g} (within 1e-3)")
c.check(T90 - 0.01 / S <= t_sat < T90 + DT, f"t_sat = {t_sat:.1f}: the first snapshot at or after t_90 = {T90:.1f} (one interval {DT:g})")
c.check(abs(roll.nu_from(t, A, S) - t_sat - 1 / S) < 1e-9, "Nu averaged from t_sat + 1/s")


class Run:
    """A run of the logistic roll that extend() continues (the log of its end times)."""

    def __init__(self, t_end, series=logistic, checkpoint=True):
        self.t_end, self.series, self.checkpoint, self.ends = t_end, series, checkpoint, []

    def amplitudes(self):
        return self.series(self.t_end)

    def extend(self, t):
        if not self.checkpoint:
            return None
        self.t_end = t
        self.ends.append(t)
        return True


# ends just after reaching 0.9 of its end value (as the 1.2 Ra_c run at t = 8000): continued once
r = Run(T90 + 0.5 / S)
t_end, series, n, sat = roll.run_to_saturation(r.t_end, S, r.amplitudes, r.extend, log=lambda m: None)
need = roll.saturation(series[0], series[1], S)[0] + (1 + roll.NU_WINDOW) / S
c.check(sat and 1 <= n <= 2 and t_end >= need * (1 - 1e-9) and abs(t_end - T90 - 4 / S) < 2 * DT,
        f"a run ending 0.5/s after t_90 is continued {n} time(s) to t = {t_end:.0f} (t_90 + 4/s = {T90 + 4 / S:.0f}), saturated: {sat}")
# already long enough: not continued
r = Run(T90 + 6 / S)
t_end, _, n, sat = roll.run_to_saturation(r.t_end, S, r.amplitudes, r.extend, log=lambda m: None)
c.check(sat and n == 0 and not r.ends, f"a run 6/s past t_90 is not continued ({n}), saturated: {sat}")
# a roll that grows exponentially to the end never saturates: MAX_EXTENSIONS continuations
r = Run(5 / S, series=lambda te: (np.arange(0.0, te + 0.5 * DT, DT), A0 * np.exp(S * np.arange(0.0, te + 0.5 * DT, DT))))
t_end, _, n, sat = roll.run_to_saturation(r.t_end, S, r.amplitudes, r.extend, log=lambda m: None)
c.check(not sat and n == roll.MAX_EXTENSIONS, f"an exponential roll: continued {n} times (MAX_EXTENSIONS {roll.MAX_EXTENSIONS}), saturated: {sat}")
# no checkpoint: not continued, reported
r = Run(T90 + 0.5 / S, checkpoint=False)
t_end, _, n, sat = roll.run_to_saturation(r.t_end, S, r.amplitudes, r.extend, log=lambda m: None)
c.check(not sat and n == 0 and t_end == T90 + 0.5 / S, f"no checkpoint: not continued ({n}), saturated: {sat}")

# grew: the logistic roll against one decaying to a noise floor of 1e-5
t, A = logistic(T90 + 6 / S)
c.check(roll.grew(t, A), "the logistic roll grew")
noise = 1e-5 * (1 + 0.5 * np.sin(7.3 * np.arange(len(t))))
c.check(not roll.grew(t, A0 * np.exp(-S * t) + noise), "a decaying disturbance over a noise floor did not grow")
c.finish()
