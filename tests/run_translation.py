#!/usr/bin/python3
"""Error weights are translation invariant (positions weighed against h).

Moving every particle and the box by +1000 in x changes nothing physical, and the error
weights do not see it (test_weights checks them bit for bit). What remains is round-off:
coordinates near 1000 carry 1e-13 absolute rounding, which enters the error estimates of
the first steps from rest (themselves near round-off) and moves a step size by ~1e-5
relative at most. The accepted and rejected step counts must be equal and every step the
controller chose equal within 1e-4 relative. A step cut to land on an output or end time
is the remainder t_out - t, so its own size says nothing of the controller: the round-off
of t (1e-5 of a 0.3 step) divided by a remainder of 0.04 would exceed 1e-4 without any
fault. Those steps are compared against the largest step instead."""
import os
from spamrun import Checks, arguments, run, summary, table

a = arguments()
c = Checks()
base = ["-expansion_n", 16, "-h", 3, "-ts_max_time", 16, "-ts_rtol", 1e-6, "-ts_atol", 1e-9, "-ts_dt", 0.01,
        "-output_interval", 0, "-snapshot_interval", 0]


def steps(name, extra):
    out = os.path.join(a.workdir, name)
    code, _, err = run(a.spam_ark, base + extra, out)
    c.check(code == 0, f"{name}: exit {code} {err.strip()}")
    s = summary(out)
    t = table(os.path.join(out, "steps.csv"))
    return list(zip(t["dt"], t["limit"])), s["rejected_steps"]


h0, r0 = steps("origin", [])
h1, r1 = steps("shifted", ["-scene_translate", "1000,0"])
c.check(len(h0) == len(h1) and r0 == r1, f"accepted steps {len(h0)} and {len(h1)}, rejected {r0} and {r1}")
big = max(dt for dt, _ in h0)
worst = max(abs(a - b) / (a if why == "accuracy" else big) for (a, why), (b, _) in zip(h0, h1))
c.check(worst < 1e-4, f"largest relative difference of accepted steps {worst:.2e} (< 1e-4)")
c.finish()
