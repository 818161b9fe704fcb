#!/usr/bin/python3
"""Velocity Verlet (kick-drift-kick) against an RK method of equal cost over 10^4 steps.

A periodic gas of 64 particles with random velocities (h = 3, t = 500). Verlet with
dt = 0.05 evaluates the force once per step (the end-of-step force is reused as the next
start: 10^4 + 1 evaluations); Heun's RK2 with dt = 0.1 spends the same 10^4. Verlet is
symplectic, so its energy error oscillates without secular growth: the largest error in the
second half of the run must not exceed 1.5 times that of the first half. RK2 is not: its
energy drifts steadily, so the error at the end must be at least 1.5 times the largest of
the first half, and 10 times Verlet's."""
import csv
import os
import random
from spamrun import Checks, arguments, run

a = arguments()
c = Checks()
gas = os.path.join(a.workdir, "gas.csv")
rng = random.Random(3)
with open(gas, "w") as f:
    f.write("x,y,vx,vy\n")
    for j in range(8):
        for i in range(8):
            f.write(f"{i + 0.5 + rng.uniform(-.1, .1)!r},{j + 0.5 + rng.uniform(-.1, .1)!r},"
                    f"{rng.uniform(-.3, .3)!r},{rng.uniform(-.3, .3)!r}\n")
common = ["-scene", "file", "-file_path", gas, "-box_len", "8,8", "-h", 3, "-snapshot_interval", 0,
          "-diag_entropy", 0, "-ts_max_time", 500, "-output_interval", 5]


def energy_errors(name, extra):
    out = os.path.join(a.workdir, name)
    code, _, err = run(a.spam_ark, common + extra, out)
    c.check(code == 0, f"{name}: exit {code} {err.strip()}")
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    e = [float(r["total"]) for r in rows]
    d = [abs(x - e[0]) / abs(e[0]) for x in e]
    half = len(d) // 2
    return max(d[1:half]), max(d[half:]), d[-1], int(rows[-1]["rhs_evals"]), int(rows[-1]["step"])


v1, v2, vend, vrhs, vsteps = energy_errors("kdk", ["-ts_type", "basicsymplectic", "-ts_dt", 0.05])
r1, r2, rend, rrhs, rsteps = energy_errors("rk2a", ["-ts_type", "rk", "-ts_rk_type", "2a", "-ts_adapt_type", "none",
                                                    "-ts_dt", 0.1])
c.check(vsteps == 10000 and vrhs == vsteps + 1,
        f"kick-drift-kick: {vsteps} steps cost {vrhs} force evaluations (one per step plus the first)")
c.check(v2 <= 1.5 * v1, f"Verlet energy error bounded: max {v1:.2e} in the first half, {v2:.2e} in the second")
c.check(rrhs == vrhs - 1, f"RK2 of equal cost: {rsteps} steps, {rrhs} RHS evaluations")
c.check(rend >= 1.5 * r1, f"RK2 energy drifts: {r1:.2e} (max, first half) -> {rend:.2e} at the end")
c.check(rend >= 10 * max(v1, v2), f"RK2 error {rend:.2e} >= 10 x Verlet's {max(v1, v2):.2e}")
c.reading("verlet.first_half", v1)
c.reading("verlet.second_half", v2)
c.reading("verlet.force_evals", vrhs)
c.reading("rk2.first_half", r1)
c.reading("rk2.end", rend)
c.finish(a.readings)
