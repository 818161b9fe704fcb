#!/usr/bin/python3
"""OpenMP threads (-threads T) of the pair passes and the list build.

The same gas (a 48 x 48 expansion at h = 3 with random offsets, Dormand-Prince at a fixed
step 0.05 to t = 10, through the density pass with gamma = 1.4) run with T = 1, 2, 2
again and 3 (a fixed step, so that only the arithmetic differs between the runs):
- two runs with T = 2 write bit-identical final states (the threads' sums are added in a
  fixed order, and the rows are split by the list alone);
- T = 2 and 3 differ from T = 1 only by the order of the additions, so in the last bits
  and no more: final positions agree to 1e-11 h (round-off, 1e-16 per addition, over 200
  steps stays orders below this; a wrong pair or a lost thread's sum moves particles by
  O(1e-3 h) or more);
- the elastic solid (its own passes are serial) gets the threaded list, which is the list
  of one thread: its final state with T = 2 is bit-identical to T = 1.
"""
import os
from spamrun import Checks, arguments, run, table

a = arguments()
c = Checks()
gas = ["-scene", "expansion", "-dim", 2, "-expansion_n", 48, "-h", 3, "-eos_gamma", 1.4,
       "-expansion_amplitude", 0.2, "-ts_max_time", 10, "-arkode_fixed_step", 0.05,
       "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0]
solid = ["-options_file", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "planewave.opts"),
         "-ts_max_time", 5, "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0]


def final(name, args, threads):
    out = os.path.join(a.workdir, name)
    path = os.path.join(a.workdir, name + ".csv")
    rc, _, err = run(a.spam_ark, args + ["-threads", threads, "-final_csv", path], out)
    c.check(rc == 0, f"{name}: exit {rc} {err.strip()[:200]}")
    with open(path, "rb") as f:
        raw = f.read()
    return raw, table(path)


raw1, t1 = final("gas_t1", gas, 1)
raw2, t2 = final("gas_t2", gas, 2)
raw2b, _ = final("gas_t2_again", gas, 2)
raw3, t3 = final("gas_t3", gas, 3)
c.check(raw2 == raw2b, "T = 2 twice: bit-identical final states")
# The threads' sums are added in another order than one thread's: bit-identical output
# would mean the option never reached the passes.
c.check(raw1 != raw2 and raw1 != raw3, "T = 2 and 3 differ from T = 1 in the last bits (the threaded sums ran)")
h = 3.0
for name, t in (("T = 2", t2), ("T = 3", t3)):
    dev = max(abs(p - q) for col in ("x", "y") for p, q in zip(t[col], t1[col]))
    c.check(len(t["x"]) == len(t1["x"]) and dev < 1e-11 * h,
            f"{name} against T = 1: largest position difference {dev:.3e} (bound 1e-11 h = {1e-11 * h:.1e})")
    c.reading(f"T{name[-1]}.position_difference", dev)

s1, _ = final("solid_t1", solid, 1)
s2, _ = final("solid_t2", solid, 2)
c.check(s1 == s2, "elastic solid: T = 2 gives the final state of T = 1 bit for bit (same list)")
c.finish(a.readings)
