"""Error weights are translation invariant (positions weighed against h).

Moving every particle and the box by +1000 in x changes nothing physical, and the error
weights do not see it (test_weights checks them bit for bit). What remains is round-off:
coordinates near 1000 carry 1e-13 absolute rounding, which enters the error estimates of
the first steps from rest (themselves near round-off) and moves a step size by ~1e-5
relative at most. The accepted and rejected step counts must be equal and every
accepted step equal within 1e-4 relative."""
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
    return table(os.path.join(out, "steps.csv"))["dt"], s["rejected_steps"]


h0, r0 = steps("origin", [])
h1, r1 = steps("shifted", ["-scene_translate", "1000,0"])
c.check(len(h0) == len(h1) and r0 == r1, f"accepted steps {len(h0)} and {len(h1)}, rejected {r0} and {r1}")
worst = max(abs(a - b) / a for a, b in zip(h0, h1))
c.check(worst < 1e-4, f"largest relative difference of accepted steps {worst:.2e} (< 1e-4)")
c.finish()
