#!/usr/bin/python3
"""Onset of convection in the scene's cell: SPAM against linear theory.

Runs spam-ark -options_file options/convection.opts (32 x 16, Pr = 1, g = 0.0125,
T_b = 1.25, T_t = 0.75) at Ra = f Ra_c for each f of --ra and each seed amplitude
(-convection_amplitude) of --seeds, Ra_c from tests/convection_linear.py for the same cell
(the options file plus --extra), and measures
(a) the growth rate of the roll the periodic cell holds nearest onset (k = 2 pi / L, L = 2H:
    the linear theory's fastest mode of the cell at every Ra here). Its amplitude in each
    CSV snapshot is the mass-weighted projection of T - T0(y) on T'(y) exp(i k x), T' the
    linear eigenfunction's temperature (real: the onset is stationary), scaled to the
    roll's peak vertical velocity: its noise floor from the sound that fills the cell is
    about 10 x below that of the projection of v_y (also printed).
    ln(amplitude) is fitted by a line over its exponential phase: from where the
    disturbance has become the linear eigenmode (its T' row profile correlates with the
    eigenfunction's at 0.98 or more and its phase, where the roll sits, turns by at most
    0.1 rad per e-folding time 1/s, at every snapshot up to the window's end: MODE_CORR,
    MODE_PHASE) to where it reaches 0.2 x its saturated value (the mean from saturation
    on): with dA/dt = s A - g A^3 the rate there is still 0.96 s, so the fit is low by
    about 2 %. A seed whose amplitude there (or at its minimum) is already 0.05 x the
    saturated one starts near saturation ("saturated start"; "late mode" when the disturbance
    becomes the mode only there): flagged in the table.
    Goal of the project: within 20 %. Also printed: Ra_eff, the Ra at which the
    continuum's roll grows at the measured rate (how far from the continuum SPAM's cell is).
(b) the onset: Nu - 1 of the saturated state (Nu from one e-folding time 1/s after the
    roll's amplitude first reaches 0.9 x its final value to the end, at least 3/s long: a
    run that ends sooner is continued from its checkpoint; from the wall heat rates as
    examples/plot_convection.py computes it)
    against Ra, fitted by a line through the two lowest Ra (weakly nonlinear theory:
    Nu - 1 is linear in Ra - Ra_c near onset; the higher points curve) and extrapolated to
    Nu - 1 = 0. Only points above the conduction state's noise floor count (3 x the
    discrete flux error of the exact start, |Nu(t = 0) - 1|, as tests/run_convection.py;
    0.017 in this cell). Also printed: the bracket (the highest Ra still conducting, the
    lowest convecting); an extrapolated onset below it means Nu jumps (subcritical).
    Also reported: where the parabola through the three lowest such points crosses zero
    (how far the line's onset is moved by the curvature of Nu - 1 in Ra).
    Goal: within 10 % of Ra_c and the same for every seed (spread below 10 % of Ra_c): a
    supercritical onset does not depend on the seed.

Measured with the plain SPAM gas of today (options/convection.opts unchanged, 2 cores at
load 3-7): the 16 default runs took 252 s (6-35 s each; about 2-3.5 ms per unit of time).
No roll grows at 1.2-3 Ra_c from any seed: its amplitude falls from its peak at
2e-5 - 5e-3 per unit time where theory has it grow at 9.8e-4 - 4.9e-3, and Nu = 0.998-1.008
(noise floor 0.017): no onset found. Beyond (--ra 6,10,14,20 --seeds 0.01,0.1 --t-end 4000,
176 s): from 0.01 no rolls up to 20 Ra_c; from 0.1 none at 6 Ra_c and rolls at 10, 14,
20 Ra_c (Nu = 1.68, 1.89, 2.12): a seed-dependent, discontinuous onset between 6 and 10 Ra_c.

Each run's end time is sized from the linear rate s of its Ra: the seed's projection on the
roll is about 0.05 of -convection_amplitude (512 random velocities), the saturated roll's
vertical velocity about 10 chi / H (Boussinesq rolls near onset), so growth takes
ln(0.5 / amplitude) e-foldings; then 3 e-foldings to saturate and 3 to average Nu:
t_end = (ln(0.5 / amplitude) + 6) / s (1.2 Ra_c, amplitude 1e-4: s = 9.8e-4, t_end = 14,800).
That is a first guess (a seed's disturbance may first decay: 1.2 Ra_c, seed 1e-2, for about
3000 time units): a run is continued until Nu's average, from saturation + 1/s, spans 3/s
(tests/convection_roll.py: SAT_LEVEL, NU_WINDOW; every run alike, and the Nu-Ra chart's runs with
examples/convection_sweep.py --saturate). --t-end keeps the end time given.
--t-scale multiplies it, --t-end replaces it. Snapshots every 1/(8 s)
(about 18 points per decade of growth).

Usage (from the repository's root):
  /usr/bin/python3 tests/run_convection_onset.py --spam-ark build/spam-ark --workdir /tmp/onset \\
      [--ra 1.2,1.5,2,3] [--seeds 1e-4,1e-3,1e-2,1e-1] [--t-end T | --t-scale F] \\
      [--extra "-spam_option value ..."] [-o results.json] [--report-only] [--reuse]
--reuse analyses the runs already in --workdir again (those that reached their end time).
Exit status 1 when a goal is missed (0 with --report-only)."""
import argparse
import json
import math
import os
import shlex
import shutil
import sys
import time

import numpy as np

from spamrun import Checks, run, table, summary
import convection_linear as cl
from convection_roll import roll_amplitudes, run_to_saturation, nu_from

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "examples"))
import plot_convection as pc  # noqa: E402

OPTIONS = os.path.join(HERE, "..", "options", "convection.opts")

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--spam-ark", required=True)
ap.add_argument("--workdir", required=True)
ap.add_argument("--ra", default="1.2,1.5,2,3", help="Ra / Ra_c of the runs (comma separated)")
ap.add_argument("--seeds", default="1e-4,1e-3,1e-2,1e-1", help="-convection_amplitude of the runs (comma separated)")
ap.add_argument("--t-end", type=float, default=None, help="end time of every run (default: sized from the linear rate)")
ap.add_argument("--t-scale", type=float, default=1.0, help="multiplies the sized end time")
ap.add_argument("--extra", default="", help="options passed to every run (and to the linear theory's cell)")
ap.add_argument("-o", "--output", default=None, help="results as JSON")
ap.add_argument("--readings", default=None, help="the growth table and the onsets as a page's readings (examples/chart_readings.py)")
ap.add_argument("--report-only", action="store_true", help="exit 0 whatever the goals")
ap.add_argument("--no-onset", action="store_true", help="check the growth rates only (the onset needs Ra near Ra_c)")
ap.add_argument("--reuse", action="store_true", help="keep the runs already in --workdir that reached their end time (analysis only)")
a = ap.parse_args(sys.argv[1:] + shlex.split(os.environ.get("SPAM_ONSET_ARGS", "")))  # ctest sets the CI subset here
if not a.reuse:
    shutil.rmtree(a.workdir, ignore_errors=True)
os.makedirs(a.workdir, exist_ok=True)
factors = [float(x) for x in a.ra.split(",")]
seeds = [float(x) for x in a.seeds.split(",")]
extra = shlex.split(a.extra)
c = Checks()

# The linear theory of the cell the runs see: the options file, then --extra.
cell, _, _ = cl.parse(["-options_file", OPTIONS] + extra)
t0 = time.time()
ra_c, kc = cl.critical(cell)
k1 = 2 * math.pi / cell.L
print(f"linear theory ({time.time() - t0:.1f} s): Ra_c = {ra_c:.4f}, k_c H = {kc:.4f}; the runs' roll k H = {k1 * cell.H:.4f}; "
      f"cell {cell.nx} x {cell.ny}, g = {cell.g:g}, T_b = {cell.t_bottom:g}, T_t = {cell.t_top:g}, Pr = {cell.prandtl:g}")


# The fit window's start: the disturbance is the linear eigenmode once its T' row profile
# correlates with the eigenfunction's (roll_amplitudes' C) at MODE_CORR or above and its
# phase has turned by at most MODE_PHASE over the e-folding time 1/s before, at every
# snapshot up to the window's end. At 0.98 what is not the eigenmode's shape is at most
# sqrt(1 - 0.98^2) = 0.2 of the profile's norm (the goal's 20 %); a non-stationary part of
# relative size eps turns the phase by up to eps: 0.1 rad, a tenth. A seed within SAT_START
# of the saturated amplitude there (less than ln(0.2 / 0.05) = 1.4 e-foldings before the
# window's end) starts near saturation, and a run whose disturbance becomes the mode only
# there reaches it late: their rates are fitted to 0.5 x saturation and flagged.
MODE_CORR, MODE_PHASE, SAT_START = 0.98, 0.1, 0.05


def exponential_fit(t, A, C, phi, lag, t_sat, seed_share):
    """(rate, t_from, t_to, note) of the line through ln A over the exponential phase: from
    the first snapshot after which the disturbance is the eigenmode (C >= MODE_CORR and the
    phase's turn over the lag snapshots before (1/s) <= MODE_PHASE at every snapshot up to
    the window's end) to where A reaches 0.2 x its saturated value (the mean from t_sat
    on): "exponential". Notes otherwise: "saturated start" (seed_share, the seed's own
    projection on the roll, its v_y at t = 0, is SAT_START of the saturated v_y or more: the
    seed is velocity only, so A, of T', starts from 0 whatever the seed), "late mode" (A is SAT_START x saturation or more where the
    criterion is first met for good), both fitted up to 0.5 x saturation (at least three
    snapshots), "not modal" (the
    criterion is not met before 0.2 x saturation: fitted from where A first exceeds 3 x its
    minimum, a rate of the projection, not of the mode), "none" (no growth: saturation below
    3 x the minimum; the slope of ln A from its peak to the end, how fast what the seed and
    the start's transient put into the roll decays)."""
    sat = np.mean(A[t >= t_sat]) if np.any(t >= t_sat) else A[-1]
    turn = np.array([abs(math.remainder(phi[i] - phi[i - lag], 2 * math.pi)) if i >= lag else math.pi for i in range(len(t))])
    modal = (C >= MODE_CORR) & (turn <= MODE_PHASE)
    pos = t > 0
    t, A, modal = t[pos], A[pos], modal[pos]

    def first(i_from, cond):
        return next((i for i in range(i_from, len(A)) if cond(A[i])), len(A) - 1)

    i_min = int(np.argmin(A[: int(np.argmax(A)) + 1]))
    i1 = first(0, lambda x: x >= 0.2 * sat)
    i_mode = i1 + 1
    while i_mode > 0 and modal[i_mode - 1]:
        i_mode -= 1
    i0 = i_mode if i_mode <= i1 else first(i_min, lambda x: x > 3 * A[i_min])
    if sat < 3 * A[i_min]:
        i0, i1, note = int(np.argmax(A)), len(A) - 1, "none"
    elif seed_share >= SAT_START:
        i1, note = max(first(i0, lambda x: x >= 0.5 * sat), i0 + 2), "saturated start"
    elif A[i0] >= SAT_START * sat:
        i1, note = max(first(i0, lambda x: x >= 0.5 * sat), i0 + 2), "late mode"
    elif i_mode > i1:
        note = "not modal"
    else:
        note = "exponential"
    if i1 - i0 < 2:
        return float("nan"), float(t[i0]), float(t[i1]), note + " (too few snapshots)"
    p = np.polyfit(t[i0:i1 + 1], np.log(A[i0:i1 + 1]), 1)
    return float(p[0]), float(t[i0]), float(t[i1]), note


def band_rates(t, A, t_start):
    """The growth rate of ln A within each decade of amplitude (1e-7..1e-6, ..., 1e-2..1e-1),
    fitted over the snapshots after t_start whose A lies in it, before A first leaves the
    decade upwards (at least 3 snapshots): how the rate changes as the roll grows. A rate
    that falls from decade to decade long before saturation says that what grew at small
    amplitude is not the linear roll of the continuum."""
    out = {}
    for e in range(-7, -1):
        lo, hi = 10.0 ** e, 10.0 ** (e + 1)
        idx = [i for i in range(len(t)) if t[i] >= t_start and lo <= A[i] < hi]
        above = next((i for i in range(len(t)) if t[i] >= t_start and A[i] >= hi), len(t))
        idx = [i for i in idx if i < above]
        if len(idx) >= 3:
            out[f"1e{e}"] = float(np.polyfit(t[idx], np.log(A[idx]), 1)[0])
    return out


# Fractions of the saturated amplitude (the mean from t_sat on, as exponential_fit) that
# sat_band_rates fits in: the roll's rate as it grows, on one scale for every seed and Ra.
SAT_BANDS = (0.003, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5)


def sat_band_rates(t, A, H2, t_sat, t_start):
    """({band: rate}, {band: max H2}) of ln A within each range of SAT_BANDS (A over its
    saturated value), fitted as band_rates fits a decade (the snapshots after t_start in the
    range before A first leaves it upwards, at least 3): where, on the way to saturation, the
    rate departs from the fit's, and how much second harmonic (roll_amplitudes' H2) the
    disturbance carries there."""
    sat = np.mean(A[t >= t_sat]) if np.any(t >= t_sat) else A[-1]
    rates, harm = {}, {}
    for lo, hi in zip(SAT_BANDS[:-1], SAT_BANDS[1:]):
        above = next((i for i in range(len(t)) if t[i] >= t_start and A[i] >= hi * sat), len(t))
        idx = [i for i in range(above) if t[i] >= t_start and lo * sat <= A[i] < hi * sat]
        if len(idx) >= 3:
            key = f"{lo:g}-{hi:g}"
            rates[key] = float(np.polyfit(t[idx], np.log(A[idx]), 1)[0])
            harm[key] = float(np.nanmax(H2[idx]))
    return rates, harm


def effective_ra(rate, k):
    """The Ra at which the continuum's roll grows at this rate (bisection in log Ra between
    Ra_c and 1000 Ra_c; the rate rises with Ra): how far SPAM's cell is from the
    continuum's. nan when the roll did not grow or grew faster than at 1000 Ra_c."""
    if not (rate > 0):
        return float("nan")
    lo, hi = math.log(ra_c), math.log(1000 * ra_c)
    if cl.growth(cell, k, math.exp(hi))[0] < rate:
        return float("nan")
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if cl.growth(cell, k, math.exp(mid))[0] < rate:
            lo = mid
        else:
            hi = mid
    return math.exp(0.5 * (lo + hi))


def write_readings(path, results, seeds):
    """The page's table (a row per Ra: the growth rate over linear theory's per seed, then
    Nu of each seed) and the onsets, with the command and commit (examples/chart_readings.py)."""
    import chart_readings
    by = {(r["ra_over_ra_c"], r["amplitude"]): r for r in results["runs"]}
    ras = sorted({r["ra_over_ra_c"] for r in results["runs"]})

    def cell(f, amp, key, spec):
        r = by.get((f, amp))
        if r is None:
            return ""
        flag = {"saturated start": " (saturated start)", "late mode": " (late mode)", "not modal": " (not modal)", "none": " (no growth)"}
        return format(r[key], spec) + (next((v for k, v in flag.items() if r["fit"].startswith(k)), "") if key == "s_ratio" else "") \
            + (" (not saturated)" if key == "nu" and not r["saturated"] else "")
    columns = ["Ra / Ra_c"] + [f"s / s_linear, seed {amp:g}" for amp in seeds] + [f"Nu, seed {amp:g}" for amp in seeds]
    rows = [[f"{f:g}"] + [cell(f, amp, "s_ratio", ".2f") for amp in seeds] + [cell(f, amp, "nu", ".3f") for amp in seeds]
            for f in ras]
    onset = [{"seed": float(k), "ra_onset_over_ra_c": v["ra_onset"] / results["ra_c"],
              "ra_onset_parabola_over_ra_c": v["ra_onset_parabola"] / results["ra_c"],
              "parabola_minus_line_over_ra_c": (v["ra_onset_parabola"] - v["ra_onset"]) / results["ra_c"]}
             for k, v in results["onset"].items()]
    # The rate by decade of the roll's amplitude over |linear rate| (band_rates), a row per run.
    decades = sorted({d for r in results["runs"] for d in r["band_rates"]}, key=float)
    bands = chart_readings.table(["Ra / Ra_c", "seed", "s linear"] + [f"A {d} to 1e{int(d[2:]) + 1}" for d in decades],
                                 [[f"{r['ra_over_ra_c']:g}", f"{r['amplitude']:g}", f"{r['s_theory']:.2e}"]
                                  + [format(r["band_rates"][d] / abs(r["s_theory"]), "+.2f") if d in r["band_rates"] else ""
                                     for d in decades] for r in results["runs"]])
    # The same by fraction of the saturated amplitude (sat_band_rates), with the largest
    # second-harmonic share in each range.
    sb = [f"{lo:g}-{hi:g}" for lo, hi in zip(SAT_BANDS[:-1], SAT_BANDS[1:])]
    sat_bands = chart_readings.table(["Ra / Ra_c", "seed", "fit"] + [f"A/A_sat {b}" for b in sb],
                                     [[f"{r['ra_over_ra_c']:g}", f"{r['amplitude']:g}", f"{r['s_ratio']:.2f}"]
                                      + [f"{r['sat_band_rates'][b] / abs(r['s_theory']):+.2f} ({r['sat_band_h2'][b]:.3f})"
                                         if b in r["sat_band_rates"] else "" for b in sb] for r in results["runs"]])
    chart_readings.write_json(path, {"ra_c": results["ra_c"], "options": results["extra"],
                                     "growth": chart_readings.table(columns, rows), "onset": onset, "bands": bands,
                                     "sat_bands": sat_bands,
                                     "runs": [{k: r[k] for k in ("ra_over_ra_c", "amplitude", "s_theory", "s_measured", "s_ratio",
                                                                 "nu", "band_rates", "sat_band_ratio", "sat_band_h2_max", "h2_saturated", "mode_corr_min_fit",
                                                                 "ra_effective_over_ra_c", "post_step_jumps", "ke_end",
                                                                 "fit", "seed_share", "fit_from", "fit_to", "nu_from_t", "t_end", "saturated", "extensions")} for r in results["runs"]]})


results = {"ra_c": ra_c, "k_c_H": kc, "k_roll_H": k1 * cell.H, "extra": a.extra, "runs": []}
for f in factors:
    ra = f * ra_c
    s_theory, y, fields = cl.mode(cell, k1, ra)
    s_theory = s_theory.real
    for amp in seeds:
        if a.t_end is not None:
            t_end = a.t_end
        elif s_theory > 0:
            t_end = a.t_scale * (math.log(0.5 / amp) + 6.0) / s_theory
        else:
            t_end = a.t_scale * 5.0 * cell.H ** 2 / (cell.transport(ra)[1] / (cell.mass * cell.cp))
        dt_out = 0.125 / s_theory if s_theory > 0 else t_end / 40.0
        dt_out = min(dt_out, t_end / 20.0)
        extend = a.t_end is None and s_theory > 0  # an end time given is kept
        name = f"ra{f:g}_amp{amp:g}"
        out = os.path.join(a.workdir, name)
        args = ["-options_file", OPTIONS, "-convection_ra", ra, "-convection_amplitude", amp,
                "-snapshot_interval", dt_out, "-snapshot_hdf5", 0, "-output_interval", dt_out / 2] + extra
        if extend:
            args += ["-checkpoint_interval", 1.0 / s_theory]
        w0 = time.time()
        done = os.path.join(out, "summary.json")
        if a.reuse and os.path.exists(done) and summary(out).get("status") == "ok" and summary(out)["t_final"] > t_end * (1 - 1e-6):
            code, err, t_end = 0, "(reused)", summary(out)["t_final"]
        else:
            shutil.rmtree(out, ignore_errors=True)
            code, so, err = run(a.spam_ark, args + ["-ts_max_time", t_end], out, timeout=6 * 3600)
        if not c.check(code == 0, f"{name}: run completes (exit {code}, {time.time() - w0:.1f} s) {err.strip()[-300:]}"):
            continue
        extensions, saturated = 0, True

        def amplitudes():
            return roll_amplitudes(cell, out, k1, y, fields)

        def go_on(t):
            """Continues the run from its checkpoint to t (None: no checkpoint)."""
            if not os.path.exists(os.path.join(out, "checkpoint.h5")):
                return None
            code, so, err = run(a.spam_ark, args + ["-ts_max_time", t, "-restart", os.path.join(out, "checkpoint.h5")], out, timeout=6 * 3600)
            return c.check(code == 0, f"{name}: continued run completes (exit {code}) {err.strip()[-300:]}")
        if extend:
            t_end, series, extensions, saturated = run_to_saturation(t_end, s_theory, amplitudes, go_on,
                                                                     log=lambda m: print(f"{name}: {m}", flush=True))
        else:
            series = amplitudes()
        tt, A, Av, C, phi, H2 = series
        wall = time.time() - w0
        sm, ts = summary(out), table(os.path.join(out, "timeseries.csv"))
        if err == "(reused)":
            wall = sm["wall_time_s"]  # the run's own time, not the analysis's
        if extend:
            t_avg = nu_from(tt, A, s_theory)
        else:
            t_avg = t_end - 3.0 / s_theory if s_theory > 0 else 0.5 * t_end
        nu, nub, nut, (qb, qt) = pc.nusselt(sm, ts, cell.t_bottom, cell.t_top, t_avg)
        # The seed is velocity only: its T' follows as the seed's v advects the mean gradient,
        # not as the mode. The other modes' share (decaying at least at the slowest thermal
        # rate chi q^2, q^2 = k^2 + (pi / H)^2, relative to the growing one) falls below
        # e^-2 = 14 % after 2 / (s + chi q^2): the rates by decade start there.
        chi = cell.transport(ra)[1] / (cell.mass * cell.cp)
        t_start = 2.0 / (max(s_theory, 0.0) + chi * (k1 ** 2 + (math.pi / cell.H) ** 2))
        lag = max(1, round(1.0 / (s_theory * dt_out))) if s_theory > 0 else 1  # snapshots in 1/s
        seed_share = float(Av[0] / np.mean(Av[tt >= t_avg])) if np.any(tt >= t_avg) and s_theory > 0 else float("nan")
        rate, fa, fb, note = exponential_fit(tt, A, C, phi, lag, t_avg, seed_share)
        rate_v = exponential_fit(tt, Av, C, phi, lag, t_avg, seed_share)[0]
        bands = band_rates(tt, A, t_start)
        sat_rates, sat_h2 = sat_band_rates(tt, A, H2, t_avg, t_start)
        # the same keyed for the page's markers (no dot in a key): "to0_02" is the range 0.01-0.02
        key_of = {f"{lo:g}-{hi:g}": "to" + f"{hi:g}".replace(".", "_") for lo, hi in zip(SAT_BANDS[:-1], SAT_BANDS[1:])}
        # saturation: the roll's amplitude over the last 1.5 e-folding times against the 1.5 before
        last = A[tt >= t_end - 1.5 / s_theory] if s_theory > 0 else A[-3:]
        prev = A[(tt >= t_end - 3.0 / s_theory) & (tt < t_end - 1.5 / s_theory)] if s_theory > 0 else A[-6:-3]
        drift = float(np.mean(last) / np.mean(prev)) if len(last) and len(prev) else float("nan")
        ke = ts["kinetic"]
        ra_eff = effective_ra(rate, k1) if note != "none" else float("nan")
        in_fit = (tt >= fa) & (tt <= fb)
        r = {"ra_over_ra_c": f, "ra": ra, "amplitude": amp, "t_end": t_end, "wall_s": wall, "rhs_evals": sm["rhs_evals"],
             "post_step_jumps": sm.get("post_step_jumps"), "s_theory": s_theory, "s_measured": rate, "s_measured_vy": rate_v, "ra_effective_over_ra_c": ra_eff / ra_c, "fit_from": fa, "fit_to": fb,
             "band_rates": bands, "sat_band_rates": sat_rates, "sat_band_h2": sat_h2,
             "sat_band_ratio": {key_of[b]: v / abs(s_theory) for b, v in sat_rates.items()},
             "sat_band_h2_max": {key_of[b]: v for b, v in sat_h2.items()},
             "h2_saturated": float(np.nanmean(H2[tt >= t_avg])) if np.any(tt >= t_avg) else float("nan"),
             "mode_corr_min_fit": float(np.min(C[in_fit])) if np.any(in_fit) else float("nan"),
             "fit": note, "seed_share": seed_share, "mode_corr_end": float(C[-1]), "series": {"t": tt.tolist(), "A": A.tolist(), "C": C.tolist(), "phase": phi.tolist(), "H2": H2.tolist()}, "saturated": saturated, "extensions": extensions,
             "roll_amplitude_min": float(A[1:].min()), "roll_amplitude_end": float(A[-1]),
             "roll_amplitude_vy_end": float(Av[-1]),
             "saturation_drift": drift, "nu": nu, "nu_hot": nub, "nu_cold": nut, "nu_start": 0.5 * (qb[0] + qt[0]),
             "nu_from_t": t_avg, "ke_start": ke[0], "ke_max": max(ke), "ke_end": ke[-1], "dir": out}
        results["runs"].append(r)
        print(f"{name}: t_end {t_end:.0f}, {wall:.1f} s wall, {sm['rhs_evals']} RHS; roll amplitude (T') min {A[1:].min():.3g} -> "
              f"end {A[-1]:.3g} (v_y: {Av[-1]:.3g}); s = {rate:.4g} ({note}, t {fa:.0f}-{fb:.0f}; from v_y {rate_v:.4g}) against {s_theory:.4g}; Nu = {nu:.4f} "
              f"(hot {nub:.4f}, cold {nut:.4f}, start {r['nu_start']:.4f}); KE {ke[0]:.3g} -> {ke[-1]:.3g}", flush=True)
        print(f"{name}: rate / |linear rate| by decade of the roll's amplitude: "
              + ", ".join(f"{k}: {v / abs(s_theory):+.2f}" for k, v in bands.items()), flush=True)
        print(f"{name}: rate / |linear rate| (largest second-harmonic share) by A / saturated A: "
              + ", ".join(f"{k}: {v / abs(s_theory):+.2f} ({sat_h2[k]:.3f})" for k, v in sat_rates.items()), flush=True)

# (a) growth rates
print("\nRa/Ra_c  amplitude  t_end    wall s  s theory    s measured  ratio   fit              fit from  s from v_y  Ra_eff/Ra_c  Nu       Nu from  sat. drift")
for r in results["runs"]:
    ratio = r["s_measured"] / r["s_theory"] if r["s_theory"] else float("nan")
    r["s_ratio"] = ratio
    print(f"{r['ra_over_ra_c']:<7.3g}  {r['amplitude']:<9.0e}  {r['t_end']:<7.0f}  {r['wall_s']:<6.1f}  {r['s_theory']:<10.4g}  "
          f"{r['s_measured']:<10.4g}  {ratio:<6.3f}  {r['fit'][:15]:<15}  {r['fit_from']:<8.0f}  {r['s_measured_vy']:<10.4g}  {r['ra_effective_over_ra_c']:<11.4g}  "
          f"{r['nu']:.4f}{'' if r['saturated'] else ' (not saturated)'}   {r['nu_from_t']:<7.0f}  {r['saturation_drift']:.3f}")
# Asserted for the smallest seed, whose exponential phase is the longest. A larger seed
# starts nearer saturation: its fit window is shorter and its rate moves with round-off (a
# change of the pair sums' order moved the 1e-2 seed's ratio from 1.195 to 1.233 at 2 Ra_c
# and from 1.126 to 0.917 at 3 Ra_c, the 1e-3 seed's by 0.03 and 0.01, when the window
# started at 3 x the minimum of A): printed.
for r in results["runs"]:
    text = (f"Ra = {r['ra_over_ra_c']:g} Ra_c, amplitude {r['amplitude']:g}: growth rate {r['s_measured']:.4g} against linear "
            f"{r['s_theory']:.4g} (ratio {r['s_ratio']:.3f}; goal within 20 %; {r['fit']})")
    met = r["fit"] == "exponential" and abs(r["s_ratio"] - 1) < 0.2
    if r["amplitude"] == min(seeds):
        c.check(met, text)
    else:
        print(f"goal (not asserted): {text}: {'met' if met else 'not met'}")

# (b) onset from Nu - 1 against Ra, per seed. Only points where Nu - 1 exceeds the
# conduction state's noise count: 3 x the discrete flux error of the exact start,
# |Nu(t = 0) - 1| (as tests/run_convection.py), else the line would extrapolate noise.
results["onset"] = {}
for amp in ([] if a.no_onset else seeds):
    runs = sorted((r for r in results["runs"] if r["amplitude"] == amp), key=lambda r: r["ra"])
    if len(runs) < 2:
        continue
    floor = 3 * max(abs(r["nu_start"] - 1.0) for r in runs)
    pts = [(r["ra"], r["nu"] - 1.0) for r in runs if r["nu"] - 1.0 > floor]
    fits = {"lowest two": float("nan"), "all": float("nan")}
    for label, sel in (("lowest two", slice(0, 2)), ("all", slice(None))):
        if len(pts) >= 2:
            x, yv = np.array([p[0] for p in pts[sel]]), np.array([p[1] for p in pts[sel]])
            slope, icpt = np.polyfit(x, yv, 1)
            fits[label] = -icpt / slope if slope > 0 else float("nan")
    # The line's curvature error: the parabola through the three lowest points, where it
    # crosses Nu - 1 = 0 nearest the line's onset (Nu - 1 bends down as Ra grows, so the
    # line through the two lowest falls below the curve's zero).
    fits["parabola"] = float("nan")
    if len(pts) >= 3:
        roots = np.roots(np.polyfit([p[0] for p in pts[:3]], [p[1] for p in pts[:3]], 2))
        roots = [r.real for r in roots if abs(r.imag) < 1e-12 * abs(r)]
        if roots and math.isfinite(fits["lowest two"]):
            fits["parabola"] = float(min(roots, key=lambda r: abs(r - fits["lowest two"])))
    # The bracket: the highest Ra still conducting below the lowest convecting one. An
    # extrapolated onset below the bracket means Nu jumps (a subcritical onset).
    quiet = [r["ra"] for r in runs if r["nu"] - 1.0 <= floor and (not pts or r["ra"] < pts[0][0])]
    bracket = [quiet[-1] / ra_c if quiet else None, pts[0][0] / ra_c if pts else None]
    results["onset"][f"{amp:g}"] = {"ra_onset": fits["lowest two"], "ra_onset_all": fits["all"], "ra_onset_parabola": fits["parabola"],
                                    "noise_floor": floor,
                                    "bracket_over_ra_c": bracket, "points": [(r["ra"], r["nu"] - 1.0) for r in runs]}
    on = fits["lowest two"]
    listing = ", ".join(f"{r['nu'] - 1:.4f}" for r in runs)
    at = ", ".join(f"{r['ra_over_ra_c']:g}" for r in runs)
    c.check(math.isfinite(on) and abs(on / ra_c - 1) < 0.1,
            f"amplitude {amp:g}: Nu - 1 = {listing} at Ra/Ra_c = {at}; {len(pts)} above the noise floor {floor:.4f}: onset "
            + (f"Ra = {on:.5g} = {on / ra_c:.4g} Ra_c (all points above the floor: {fits['all'] / ra_c:.4g} Ra_c)" if math.isfinite(on)
               else "not found (fewer than two points above the floor, or Nu not rising)")
            + f"; bracket (Ra/Ra_c conducting, convecting) = {bracket}; goal within 10 % of Ra_c")
ons = [v["ra_onset"] for v in results["onset"].values()]
if len(ons) > 1:
    spread = (max(ons) - min(ons)) / ra_c if all(math.isfinite(v) for v in ons) else float("nan")
    c.check(spread < 0.1, f"onset independent of the seed: spread {spread:.4g} Ra_c (goal below 0.1)")
results["total_wall_s"] = sum(r["wall_s"] for r in results["runs"])
print(f"total run time {results['total_wall_s']:.1f} s over {len(results['runs'])} runs")
print(f"(fit: exponential (from where the disturbance is the eigenmode: T' profile correlation >= {MODE_CORR}, phase turn <= {MODE_PHASE} rad "
      f"per 1/s), saturated start (the seed's v_y projection >= {SAT_START} x saturated), late mode (the mode reached at >= {SAT_START} x saturation), not modal (the correlation never settles: fitted from 3 x the minimum) or none (no growth: s is the slope of ln A "
      "from its peak to the end); Nu from: the start of Nu's average (saturation + 1/s); Ra_eff: the Ra at which "
      "the continuum's roll grows at the measured rate; sat. drift: the roll's amplitude over the last 1.5 e-folding times of the "
      "linear rate over that of the 1.5 before, 1 when saturated)")
if a.readings:
    write_readings(a.readings, results, seeds)
if a.output:
    with open(a.output, "w") as f:
        json.dump(results, f, indent=1)
    print(f"results in {a.output}")
if a.report_only:
    print(f"{c.passed} passed, {c.failed} failed (report only)")
    sys.exit(0)
c.finish()
