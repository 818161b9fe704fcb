#!/usr/bin/python3
"""-shift_compression's default (stratified): B's work on the shift's compression applies
where the background pressure is fitted along gravity and no no-slip wall moves, and nowhere
else.

(a) The convection cell of options/convection-onset.opts without its -shift_compression line
    (gravity across the walls, walls at rest), to t = 100: the default run equals the run
    with -shift_compression (true) to the last digit of every output (timing aside), and
    differs from the run with -shift_compression false (the term acts in 100 time units).
(b) The Taylor-Green vortex of tests/run_taylor_green_flow.py (periodic, no gravity: B is
    uniform), L = 16, to t = 50: the default run equals -shift_compression false, and
    differs from true (the term is not silently on or off where it was asked).
(c) The summary records the choice (stratified).
About 2 CPU-s."""
import os
import tempfile

from spamrun import Checks, arguments, run, same_outputs, summary

HERE = os.path.dirname(os.path.abspath(__file__))
CELL = os.path.join(HERE, "..", "options", "convection-onset.opts")

a = arguments()
c = Checks()
with open(CELL) as f:
    lines = [ln for ln in f if not ln.startswith("-shift_compression")]
opts = os.path.join(a.workdir, "cell.opts")
with open(opts, "w") as f:
    f.writelines(lines)


def go(name, args):
    out = os.path.join(a.workdir, name)
    code, _, err = run(a.spam_ark, args, out)
    c.check(code == 0, f"{name}: runs (exit {code}) {err.strip()[-200:]}")
    return out


cell = ["-options_file", opts, "-ts_max_time", 100, "-output_interval", 10, "-snapshot_interval", 0]
d, t, f = (go("cell_" + n, cell + x) for n, x in (("default", []), ("true", ["-shift_compression"]), ("false", ["-shift_compression", "false"])))
diff = same_outputs(t, d)
c.check(diff == "", f"convection cell: the default run equals -shift_compression true ({diff or 'same outputs'})")
c.check(same_outputs(f, d) != "", "convection cell: the default run differs from -shift_compression false")
s = summary(d)
c.check("stratified" in str(s), "the summary records -shift_compression stratified")

U, L = 0.1, 16
tg = ["-scene", "taylor-green", "-dim", 2, "-taylorgreen_n", L, "-taylorgreen_amplitude", U, "-material", "gas", "-gas_gamma", 2,
      "-gas_e0", 0.5, "-viscosity_shear", U * L / 100, "-h", 3, "-ts_max_time", 50, "-output_interval", 10, "-snapshot_interval", 0]
d, t, f = (go("tg_" + n, tg + x) for n, x in (("default", []), ("true", ["-shift_compression", "true"]), ("false", ["-shift_compression", "false"])))
diff = same_outputs(f, d)
c.check(diff == "", f"Taylor-Green (uniform B): the default run equals -shift_compression false ({diff or 'same outputs'})")
c.check(same_outputs(t, d) != "", "Taylor-Green: -shift_compression true differs from the default")
c.finish(a.readings)
