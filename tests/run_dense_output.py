#!/usr/bin/python3
"""Outputs from the method's dense output, hard stops only on request.

(a) Interpolating (the default for adaptive methods), the steps do not depend on the
    output interval and no step is cut by an output time: the interpolant writes into a
    scratch vector, so the integrator sees the same states whatever the cadence. On the
    harmonic chain (springs: no neighbour list) the step count must be identical; on the
    expansion an output's density summation may rebuild the neighbour list, which reorders
    sums at round-off: at most 1 step apart there. steps.csv has only "accuracy" steps and
    at most one "end" step (cut to land on t_end, which is still hit exactly).
(b) The kinetic energy interpolated at the output times agrees with a run that stops at
    each of them, within the bound derived below for the chain's zone-boundary mode.
(d) The cost is counted whole: ARKODE's and CVODE's interpolants evaluate the RHS at each
    output time. The run's last line, summary.json's rhs_evals_total and SUNDIALS' own
    statistics (-sundials_stats "RHS fn evals") give the same total, the method's and the
    interpolant's counts added.
(c) -output_stop restores the stops: every output time is a step end, steps.csv says
    "output", summary.json says "stopped"; scenes with post-step jumps (mirror walls) and
    fixed steps do not interpolate and say why.

The bound of (b). The chain starts at rest in u_i = A (-1)^i, a single oscillator of
frequency w = 2 sqrt(k/m) = 2: every particle has v = -A w sin(w t), KE = N m v^2 / 2, so a
velocity error dv (the same for all particles, by symmetry) moves KE by at most
N m A w |dv|. Two sources of dv between the two runs:
  - global error at the step ends: each accepted step's local error is at most the
    tolerance in the weighted RMS norm (weight rtol (c0 + |v|) + atol for velocities, c0 = 1
    the chain's sound speed); over 2N components, the velocity RMS error per step is at most
    sqrt(2) times the weight; summed without cancellation over the steps of both runs:
    dv_glob <= sqrt(2) (steps_dense + steps_stop) (rtol (c0 + A w) + atol);
  - the interpolant of degree d inside a step of length h: the polynomial interpolation
    remainder with all nodes in the step, |v^(d+1)| / (d+1)! h^(d+1) = A w (w h)^(d+1) / (d+1)!
    (d = min(5, q - 1) for ERKStep's Hermite interpolant of an order-q table: DP5 4, F8 5;
    PETSc's 5dp dense output has degree 4; CVODE's interpolant is its Adams predictor, of
    the order of the controlled local error, so it is inside the global term: d = None).
"""
import math
import os
import re
from collections import Counter
from spamrun import Checks, Runner, arguments, summary, table

a = arguments()
runner = Runner(a.spam_ark, a.workdir)  # each run a forked child of the fork server
c = Checks()
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHAIN = os.path.join(ROOT, "options", "chain.opts")
T_END, RTOL, ATOL = 10.0, 1e-6, 1e-9
N, M, AMP, W, C0 = 64, 1.0, 0.01, 2.0, 1.0  # chain.opts: 64 unit masses, k = 1, A = 0.01

METHODS = {  # name: (options, interpolant degree or None)
    "arkode DP5": (["-ts_type", "arkode"], 4),
    "arkode F8": (["-ts_type", "arkode", "-arkode_table", "ARKODE_FEHLBERG_13_7_8"], 5),
    "cvode": (["-ts_type", "cvode"], None),
    "rk 5dp": (["-ts_type", "rk", "-ts_rk_type", "5dp"], 4),
}


def chain_run(name, extra, interval, stop):
    out = os.path.join(a.workdir, f"{name.replace(' ', '_')}_{interval}_{stop}")
    code, _, err = runner.run(["-options_file", CHAIN] + extra + [
        "-ts_rtol", RTOL, "-ts_atol", ATOL, "-ts_max_time", T_END, "-output_interval", interval,
        "-snapshot_interval", 0, "-output_stop", stop], out)
    if not c.check(code == 0, f"{name}: interval {interval}, -output_stop {stop}: exit {code} {err.strip()}"):
        return None
    return summary(out), table(os.path.join(out, "steps.csv")), table(os.path.join(out, "timeseries.csv"))


def only_accuracy(st):
    """Every step set by accuracy, but possibly the last, cut to land on t_end."""
    lim = Counter(st["limit"])
    return set(lim) <= {"accuracy", "end"} and lim["end"] <= 1 and (lim["end"] == 0 or st["limit"][-1] == "end")


for name, (extra, degree) in METHODS.items():
    coarse, fine, stop = (chain_run(name, extra, 1.0, "false"), chain_run(name, extra, 0.05, "false"),
                          chain_run(name, extra, 0.05, "true"))
    if not (coarse and fine and stop):
        continue
    (sc, stc, _), (sf, stf, tsf), (ss, sts, tss) = coarse, fine, stop
    # (a)
    c.check(sc["output_mode"] == sf["output_mode"] == "interpolated" and sf["interpolated_rows"] >= 190,
            f"{name}: interpolated ({sf['interpolated_rows']} of {len(tsf['t'])} rows from the interpolant)")
    c.check(sc["steps"] == sf["steps"], f"{name}: {sc['steps']} steps with 11 rows, {sf['steps']} with 201 (identical)")
    c.check(sc["rhs_evals"] == sf["rhs_evals"], f"{name}: the method's RHS evaluations do not depend on the rows "
            f"({sc['rhs_evals']}, {sf['rhs_evals']}; the interpolant's own: {sc['interpolation_rhs_evals']}, "
            f"{sf['interpolation_rhs_evals']})")
    c.check(only_accuracy(stf), f"{name}: no step cut by an output time (limits {dict(Counter(stf['limit']))})")
    c.check(stf["t"][-1] == T_END, f"{name}: the last step ends on t_end exactly ({stf['t'][-1]!r})")
    # (c)
    hit = all(any(abs(t - s) <= 1e-12 * T_END for s in sts["t"]) for t in tss["t"][1:])
    c.check(ss["output_mode"] == "stopped" and hit and Counter(sts["limit"])["output"] >= 150 and ss["steps"] > sf["steps"],
            f"{name}: -output_stop: every output time a step end, {Counter(sts['limit'])['output']} steps cut by outputs, "
            f"{ss['steps']} steps against {sf['steps']} interpolating")
    # (b)
    same_t = len(tsf["t"]) == len(tss["t"]) and all(abs(x - y) <= 1e-9 * T_END for x, y in zip(tsf["t"], tss["t"]))
    if not c.check(same_t, f"{name}: both runs write rows at the same {len(tss['t'])} times"):
        continue
    steps_t = stf["t"]
    hmax = max(stf["dt"])
    dv_glob = math.sqrt(2.0) * (sf["steps"] + ss["steps"]) * (RTOL * (C0 + AMP * W) + ATOL)
    dv_int = 0.0 if degree is None else AMP * W * (W * hmax) ** (degree + 1) / math.factorial(degree + 1)
    bound = N * M * AMP * W * (dv_glob + dv_int)
    diff = max(abs(x - y) for x, y in zip(tsf["kinetic"], tss["kinetic"]))
    exact = max(abs(ke - 0.5 * N * M * (AMP * W * math.sin(W * t)) ** 2) for t, ke in zip(tsf["t"], tsf["kinetic"]))
    c.check(diff <= bound, f"{name}: |KE interpolated - KE stopped| <= {diff:.3e}, bound {bound:.3e} "
            f"(h_max {hmax:.3f}, interpolant term {N * M * AMP * W * dv_int:.2e}; error against the exact KE {exact:.2e}, "
            f"KE scale {0.5 * N * M * (AMP * W) ** 2:.4g})")
    c.reading(f"{name.replace(' ', '_')}.ke_diff", diff)
    c.reading(f"{name.replace(' ', '_')}.bound", bound)

# (a) on a nonlinear scene with a neighbour list: the expansion gas.
EXP = ["-expansion_n", 12, "-h", 3, "-ts_max_time", 12, "-snapshot_interval", 4, "-ts_rtol", 1e-4]
counts = {}
for interval in (0.5, 0.05):
    out = os.path.join(a.workdir, f"expansion_{interval}")
    code, _, err = runner.run(EXP + ["-output_interval", interval], out)
    if c.check(code == 0, f"expansion, interval {interval}: exit {code} {err.strip()}"):
        counts[interval] = (summary(out)["steps"], only_accuracy(table(os.path.join(out, "steps.csv"))))
if len(counts) == 2:
    (n1, ok1), (n2, ok2) = counts[0.5], counts[0.05]
    c.check(abs(n1 - n2) <= 1 and ok1 and ok2, f"expansion: {n1} steps with 25 rows, {n2} with 241 (at most 1 apart), "
            "none cut by an output time")

# (a) with the physical step bound active: the force bound reads the accelerations of the
# last RHS evaluation, and DP5's degree-4 Hermite interpolant makes one per row (ERKStep
# takes the bound after a step's stages, which overwrite them).
counts = {}
for interval in (0.8, 0.05):
    out = os.path.join(a.workdir, f"force_{interval}")
    code, _, err = runner.run(EXP[:-1] + [1e-5, "-step_force", 0.02, "-output_interval", interval], out)
    if c.check(code == 0, f"expansion -step_force 0.02, interval {interval}: exit {code} {err.strip()}"):
        s = summary(out)
        counts[interval] = (s["steps"], s["bound_limited_steps"], s["interpolation_rhs_evals"])
if len(counts) == 2:
    (n1, b1, i1), (n2, b2, i2) = counts[0.8], counts[0.05]
    c.check(abs(n1 - n2) <= 1 and b1 > 0 and b2 > 0, f"expansion -step_force: {n1} and {n2} steps ({b1}, {b2} set by the "
            f"bound; {i1} and {i2} RHS evaluations by the interpolant)")

# (c) what does not interpolate says why.
out = os.path.join(a.workdir, "walls")
code, _, err = runner.run(["-options_file", os.path.join(ROOT, "options", "expansion-walls.opts"), "-expansion_n", 12,
                           "-h", 3, "-ts_max_time", 6, "-output_interval", 1, "-snapshot_interval", 0], out)
if c.check(code == 0, f"mirror walls: exit {code} {err.strip()}"):
    s = summary(out)
    c.check(s["output_mode"] == "stopped" and "jumps" in s["output_mode_reason"],
            f"mirror walls stop at outputs: {s['output_mode']} ({s['output_mode_reason']})")
out = os.path.join(a.workdir, "verlet")
code, _, err = runner.run(["-options_file", CHAIN, "-ts_max_time", 2, "-output_interval", 0.25], out)
if c.check(code == 0, f"Verlet: exit {code} {err.strip()}"):
    s, st = summary(out), table(os.path.join(out, "steps.csv"))
    c.check(s["output_mode"] == "steps" and set(st["limit"]) == {"fixed"},
            f"fixed steps land on the outputs: {s['output_mode']} ({s['output_mode_reason']}), limits {set(st['limit'])}")
# (d) the whole cost, counted alike by the run, summary.json and SUNDIALS. ARKODE's Hermite
# interpolant evaluates f at each output time; CVODE's reads its Nordsieck array (none).
for name, extra, interp in (("arkode DP5", ["-ts_type", "arkode"], True), ("cvode", ["-ts_type", "cvode"], False)):
    out = os.path.join(a.workdir, f"cost_{name.replace(' ', '_')}")
    code, so, err = runner.run(EXP + extra + ["-output_interval", 0.05, "-sundials_stats"], out)
    if not c.check(code == 0, f"cost, {name}: exit {code} {err.strip()}"):
        continue
    s = summary(out)
    total = s["rhs_evals"] + s["interpolation_rhs_evals"]
    fn = re.search(r"RHS fn evals\s*=\s*(\d+)", so)
    line = re.search(r"(\d+) RHS evaluations( \(\+(\d+) by the interpolant: (\d+) in all\))?,", so)
    if not c.check(fn is not None and line is not None, f"cost, {name}: SUNDIALS' count and the run's last line are printed"):
        continue
    said = int(line.group(4)) if line.group(2) else int(line.group(1))
    c.check((s["interpolation_rhs_evals"] > 0) == interp and (line.group(2) is not None) == interp
            and int(line.group(1)) == s["rhs_evals"] and said == total and s["rhs_evals_total"] == total
            and int(fn.group(1)) == total,
            f"cost, {name}: method {s['rhs_evals']} + interpolant {s['interpolation_rhs_evals']} = {total}; "
            f"last line '{line.group(0)}'; summary {s['rhs_evals_total']}; SUNDIALS {fn.group(1)}")
c.finish(a.readings)
