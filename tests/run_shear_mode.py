#!/usr/bin/python3
"""The shear mode vx = U sin(k y) of the viscous gas (examples/study_shear_mode.py --quick:
Wendland C4, the ordered 32 x 32 lattice, c h / nu = 0.01, 1, 100).

Asserted is only what is physics today:
- the measurement itself, on made-up series: the envelope fit returns the decay rate of a
  damped cosine and of a pure exponential, the zero crossings its frequency, and an
  overdamped mode's single crossing counts as no ringing;
- where viscosity dominates (c h / nu = 0.01 and 1) the measured rate is that of the
  linear theory of the perfect lattice, v'' + a v' + w2 v = 0 with a = nu |K|^2 the SPAM
  Laplacian of the mode and w2 the pressure's stiffness of sliding rows (the lattice sums
  of tests/lattice_modes.py, done for every kernel in the study), within 0.5 % (measured
  1e-4 and below: 40 snapshots, the integrator's rtol 1e-6 against the sound speed);
- at c h / nu = 0.01 the stiffness is negligible (w2 / a^2 ~ 1e-6) and the rate is nu k^2
  times the kernel's smoothing |K|^2 / k^2 (0.957 for Wendland C4 at k h = 0.59): the
  bound on the distance to nu k^2 is 1 - |K|^2/k^2 + 0.005. At c h / nu = 1 the
  stiffness (negative for Wendland C4 on the square lattice) lowers it by 0.6 % more
  (0.952), which the linear theory holds and the smoothing bound would not;
- no ringing there (the mode does not change sign);
- every run completes (exit 0) and its snapshots are read.
Printed, not asserted: c h / nu = 100 under the plain scheme, where pressure dominates; the
square lattice under Wendland C4 has a negative shear stiffness (the linear theory's mode
grows) and the run's amplitude passes 1.05 U (flag "grew") and then rings.
The default scheme of a viscous gas (the flow scheme, no option) at c h / nu = 100, the same
kernel and lattice: asserted within (1 - |K|^2/k^2) / 4 + 0.005 of nu k^2 (its pair
Laplacian smooths the mode a quarter as much as the two-pass form, docs/gas-flow.md; plus
the measurement's 0.005), no ringing, no flag. The issue's goal, 5 %, is wider. The full
chart (every kernel, both starts, up to c h / nu = 1000) is docs/shear-mode.md's.

Measured run time: 6-9 s (machine load 2-5), 32 s beside a run of the full study, before the
flow scheme's run (about 4 s alone) was added."""
import json
import os
import subprocess
import sys

import numpy as np

from spamrun import Checks, arguments

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "examples"))
import study_shear_mode as study  # noqa: E402


def synthetic(c):
    t = np.linspace(0, 100, 201)
    s, w = 0.03, 0.4
    A = np.exp(-s * t) * np.cos(w * t)
    got, _ = study.envelope_rate(t, A)
    c.check(abs(got / s - 1) < 1e-3, f"envelope rate of a damped cosine: {got:.6g} (exact {s})")
    got_w, n = study.ringing(t, A)
    c.check(abs(got_w / w - 1) < 1e-3, f"ringing frequency of a damped cosine: {got_w:.6g} (exact {w}, {n} crossings)")
    got, _ = study.envelope_rate(t, np.exp(-s * t))
    c.check(abs(got / s - 1) < 1e-12, f"envelope rate of an exponential: {got:.6g}")
    A = study.theory_amplitude(1.0, 0.01, t)  # overdamped, one crossing
    got_w, n = study.ringing(t, A)
    c.check(got_w == 0 and n == 1, f"overdamped mode: one crossing ({n}), no ringing ({got_w})")


def main():
    a = arguments()
    c = Checks()
    synthetic(c)
    out = os.path.join(a.workdir, "study")
    argv = [sys.executable, os.path.join(os.path.dirname(HERE), "examples", "study_shear_mode.py"), "--quick",
            "--spam-ark", a.spam_ark, "--out", out, "--variant", "plain=-gas_scheme plain"]  # the lattice theory is the plain scheme's
    p = subprocess.run(argv, capture_output=True, text=True, timeout=600)
    print(p.stdout)
    if not c.check(p.returncode == 0, f"the quick study completes (exit {p.returncode}) {p.stderr.strip()[-2000:]}"):
        c.finish()
    rows = json.load(open(os.path.join(out, "shear_mode.json")))
    for r in rows:
        X, ratio, th = r["ch_over_nu"], r["decay_ratio"], r["theory_decay_ratio"]
        c.check(r["exit_code"] == 0 and r["snapshots"] >= 40,
                f"c h/nu {X:g}: run exit {r['exit_code']}, {r['snapshots']} snapshots read")
        if X <= 1.0:
            smooth = 1 - r["laplacian_factor"]
            if X <= 0.011:
                c.check(abs(ratio - 1) <= smooth + 0.005,
                        f"c h/nu {X:g}: s/(nu k^2) = {ratio:.5f}, within {smooth + 0.005:.4f} of 1 "
                        f"(the kernel's smoothing 1 - |K|^2/k^2 = {smooth:.4f}, plus 0.005)")
            c.check(abs(ratio - th) <= 0.005, f"c h/nu {X:g}: s/(nu k^2) = {ratio:.5f} equals the lattice's linear "
                                               f"theory {th:.5f} within 0.005")
            c.check(r["ringing_ratio"] == 0 and not r["flag"],
                    f"c h/nu {X:g}: no ringing (w/(nu k^2) = {r['ringing_ratio']:g}), no flag ({r['flag'] or 'none'})")
        else:
            print(f"info: c h/nu {X:g}: s/(nu k^2) = {ratio:.4g} (linear theory {th:.4g}), "
                  f"w/(nu k^2) = {r['ringing_ratio']:.4g}, flags: {r['flag'] or 'none'}, "
                  f"final A/U = {r['final_amplitude']:.3g}, max transverse displacement {r['max_dy']:.3g}")
    flow(a, c)
    c.finish()


def flow(a, c):
    """The default scheme of a viscous gas where pressure dominates (c h / nu = 100)."""
    out = os.path.join(a.workdir, "study_flow")
    argv = [sys.executable, os.path.join(os.path.dirname(HERE), "examples", "study_shear_mode.py"), "--quick",
            "--spam-ark", a.spam_ark, "--out", out, "--variant", "flow=", "--ratio", "100"]
    p = subprocess.run(argv, capture_output=True, text=True, timeout=600)
    print(p.stdout)
    if not c.check(p.returncode == 0, f"the flow scheme's run completes (exit {p.returncode}) {p.stderr.strip()[-2000:]}"):
        return
    for r in json.load(open(os.path.join(out, "shear_mode.json"))):
        ratio, bound = r["decay_ratio"], (1 - r["laplacian_factor"]) / 4 + 0.005
        c.check(r["exit_code"] == 0 and r["snapshots"] >= 40,
                f"flow, c h/nu {r['ch_over_nu']:g}: run exit {r['exit_code']}, {r['snapshots']} snapshots read")
        c.check(abs(ratio - 1) <= bound, f"flow, c h/nu {r['ch_over_nu']:g}: s/(nu k^2) = {ratio:.5f}, within "
                                         f"{bound:.4f} of 1 (a quarter of the kernel's smoothing, plus 0.005)")
        c.check(r["ringing_ratio"] == 0 and r["crossings"] == 0 and not r["flag"],
                f"flow, c h/nu {r['ch_over_nu']:g}: no ringing ({r['crossings']} zero crossings), "
                f"no flag ({r['flag'] or 'none'})")


if __name__ == "__main__":
    main()
