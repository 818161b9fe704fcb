#!/usr/bin/python3
"""-ts_type block_kdk's pass restricted to the active particles (-block_restricted, the
default) gives the result of the whole right-hand side at each tick (-block_restricted 0)
up to round-off, on a small blast where the bins spread and particles are woken: the 2D
Sedov scene (options/sedov.opts without its -ts_rtol) at -sedov_n 20, -sedov_energy 1e3,
-block_cfl = -block_force 0.2, top steps at most 0.2 (-ts_dt), to T = 0.6 (3 cycles).

What must agree, and why to round-off only: the restricted pass visits, for each active
particle, the pairs the full walk visits, in the same order, with the same pair function;
its neighbours' densities are the same sums, with the mass multiplied in after the kernel
(the full pass's chunked rows fold it into the kernel's scale) -- a difference of a few
units in the last place of a sum of ~30 terms, relative ~1e-15. The bins are decided from
those rates, so the two runs must take the same bins: equal particle steps and woken
counts (integers, exact). The states then differ by the round-off of each evaluation added
over the ~40 evaluations: measured max |difference| / max |value| 9e-17 (x), 1.4e-15 (v),
8e-16 (e). The bound is 1e-11 of each field's largest magnitude: above the measured by
10^3-10^5, and far below a real fault (the neighbours' densities left unsummed -- only the
active particles' -- made the velocities differ by 0.05 of their largest, the positions by
0.02 and the bins by 12 particle steps).

Also: the restricted pass must have run (restricted evaluations > 0, among them some for
woken particles), and -block_restricted true is refused where the model has no such pass
(a gas with conduction). With -block_wake_delay (a wake off the needed bin's grid waits for
that grid's next tick) the same two runs must agree as well (the same bins, the same
bound), some wakes must have been put off, and there must be fewer particle steps than
without it (a woken particle no longer takes the deepest bin the tick's alignment allows,
which wakes its neighbours in turn; measured here: 3356 particle steps against 3420, 84
woken and 64 put off against 148 woken). Under 2 s of CPU (labelled fast)."""
import os

import numpy as np

from spamrun import Checks, arguments, one_line, run, table

ROUNDOFF = 1e-11
FIELDS = ("x", "y", "vx", "vy", "e")


def go(a, c, opts, name, extra):
    """(final table, -ts_view counts) of one run, or None."""
    out = os.path.join(a.workdir, name)
    last = os.path.join(out, "final.csv")
    args = ["-options_file", opts, "-sedov_n", 20, "-sedov_energy", 1e3, "-ts_max_time", 0.6, "-ts_dt", 0.2, "-output_interval", 0, "-snapshot_interval", 0,
            "-ts_type", "block_kdk", "-block_cfl", 0.2, "-block_force", 0.2, "-final_csv", last, "-ts_view"] + extra
    code, so, err = run(a.spam_ark, args, out)
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()[-300:]}"):
        return None
    line = next(l for l in so.splitlines() if "block cycles" in l)
    rline = next(l for l in so.splitlines() if "restricted evaluations" in l)
    counts = {"steps": int(line.split("particle steps")[1].split()[0]), "woken": int(line.split("woken")[1].split(")")[0]),
              "restricted": int(rline.split("restricted evaluations")[1].split()[0]), "wake_evals": int(rline.split("woken particles")[1].split(")")[0]),
              "delayed": int(next(l for l in so.splitlines() if "wakes put off" in l).split(":")[-1])}
    return table(last), counts


a = arguments()
c = Checks()
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
opts = os.path.join(a.workdir, "sedov_no_rtol.opts")  # block_kdk refuses -ts_rtol
with open(os.path.join(root, "options", "sedov.opts")) as f, open(opts, "w") as g:
    g.writelines(l for l in f if not l.startswith("-ts_rtol"))
part = go(a, c, opts, "restricted", [])
full = go(a, c, opts, "full", ["-block_restricted", 0])


def agree(part, full, tag):
    """The restricted and the full run: the same bins, the states within ROUNDOFF."""
    (tp, cp), (tf, cf) = part, full
    c.check(cp["steps"] == cf["steps"] and cp["woken"] == cf["woken"], f"{tag}the same bins: particle steps {cp['steps']} / {cf['steps']}, woken {cp['woken']} / {cf['woken']}")
    for k in FIELDS:
        scale = float(np.max(np.abs(tf[k])))
        diff = float(np.max(np.abs(np.asarray(tp[k]) - np.asarray(tf[k]))))
        c.check(diff <= ROUNDOFF * scale, f"{tag}{k}: restricted and full differ by {diff:.1e} <= {ROUNDOFF:g} of max |{k}| = {scale:.3g}")
        if not tag:
            c.reading(f"relative_difference.{k}", diff / scale)


if part and full:
    (tp, cp), (tf, cf) = part, full
    print(f"     restricted: {cp}; full: {cf}")
    c.check(cp["restricted"] > 0 and cp["wake_evals"] > 0 and cf["restricted"] == 0, f"restricted evaluations {cp['restricted']} (for woken particles {cp['wake_evals']}) in the restricted run, {cf['restricted']} in the full one")
    c.check(cp["woken"] > 0 and cp["delayed"] == 0, f"particles woken: {cp['woken']} (the limiter acts), none put off without -block_wake_delay ({cp['delayed']})")
    agree(part, full, "")
# -block_wake_delay: the same agreement; wakes put off, fewer particle steps.
dpart = go(a, c, opts, "restricted_delay", ["-block_wake_delay", 1])
dfull = go(a, c, opts, "full_delay", ["-block_restricted", 0, "-block_wake_delay", 1])
if dpart and dfull and part:
    print(f"     -block_wake_delay, restricted: {dpart[1]}; full: {dfull[1]}")
    agree(dpart, dfull, "-block_wake_delay: ")
    c.check(dpart[1]["delayed"] > 0, f"-block_wake_delay: wakes put off {dpart[1]['delayed']}")
    c.check(dpart[1]["steps"] < part[1]["steps"], f"-block_wake_delay: particle steps {dpart[1]['steps']} < {part[1]['steps']} without it")
    c.reading("wake_delay.steps_ratio", dpart[1]["steps"] / part[1]["steps"])
# Asked for where the model has no restricted pass: refused, not ignored.
code, _, err = run(a.spam_ark, ["-options_file", opts, "-sedov_n", 20, "-ts_max_time", 0.01, "-ts_type", "block_kdk", "-block_restricted", 1, "-conductivity", 0.1],
                   os.path.join(a.workdir, "refused"))
line = one_line(err) or ""
c.check(code != 0 and "-block_restricted" in line, f"-block_restricted 1 with conduction: refused ({line.strip()[:200]})")
c.finish(a.readings)
