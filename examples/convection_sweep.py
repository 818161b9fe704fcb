#!/usr/bin/python3
"""Nusselt number against Rayleigh number of the spam-ark Rayleigh-Benard cell.

Usage:
    examples/convection_sweep.py --spam-ark build/spam-ark [--workdir DIR]
        [--ratios 0.5,0.8,1.2,1.6,2,3,4,5] [--nx 32 --ny 16] [--t-end T] [--amplitude A] [--saturate] [--sized-end] [--onset]
        [--variant NAME="OPTIONS" ...] [-o OUT.png] [--readings]

Runs -scene convection (options/convection.opts: T_b = 1.25, T_t = 0.75, Pr = 1,
g = 0.1 c_p / H) at Ra = ratio x 1707.76 (the superadiabatic Rayleigh number), each to
t_end (default: the scene's, one thermal diffusion time H^2/chi, times --diffusion-times),
and takes Nu = (mean heat flux through the walls) / (kappa (T_b - T_t) / H) averaged
over the last half of each run (examples/plot_convection.py, nusselt()). The chart has
Nu against Ra / Ra_c with the continuum onset (rigid-rigid walls, Boussinesq: 1707.76)
marked. Each --variant NAME="OPTIONS" (repeatable; default one variant, "default", with no
options) runs every ratio with those options added; each variant has its own colour and
marker, and a run that fails (say exit 3, unstable) is drawn as a cross on Nu = 1 and
listed. Prints one line per run: variant ratio Ra Nu Nu_bottom Nu_top ke_final ms_per_rhs t_end
nu_from_t nu_rule nu_last_quarter (Nu over the last quarter of its average: equal to Nu in a
steady state).
A run whose particles crossed the walls (summary.json post_step_jumps > 0) is circled: its
Nu is not that of clean rolls.
With --readings, the runs and a table of Nu (hot, cold wall) per ratio and variant are
written beside the chart (OUT.json, examples/chart_readings.py) for the pages' markers.

Near onset the roll grows slowly (its linear rate s vanishes at Ra_c), so a fixed end time
leaves it short of saturation there. --sized-end sizes each run's end time from the linear
rate s of the cell (tests/convection_linear.py) at its Ra, as tests/run_convection_onset.py
does: the seed's projection on the roll is about 0.05 of its amplitude, the saturated roll
about 0.5 (in these units), so growth takes ln(0.5 / amplitude) e-foldings, then 3 to
saturate and 3 to average Nu over (end time (ln(0.5 / amplitude) + 6) / s, Nu over the last
3 / s). Where s <= 0 (below onset) the run ends at --t-end (or the options file's) and Nu
is the mean over its second half. A variant may set its own -convection_amplitude (the
last value given wins); the sized end time uses it.

--saturate (with --t-end or --sized-end: the first end time) makes each run last until its
roll has saturated, by the rule of tests/run_convection_onset.py (tests/convection_roll.py):
the run writes CSV snapshots (every 1/(8 s), at least t_end / 200 apart) and a checkpoint
every 1/s (s: the cell's linear rate at its Ra); the roll's amplitude A is the projection of
T - T0(y) on the linear eigenfunction; saturation is where A first reaches 0.9 of its end
value (its mean over the last 1/s); a run that ends before saturation + 4/s is continued
from its checkpoint to that time (again while it moves, at most 4 times; then drawn as a
hollow square, "not saturated"), and Nu is averaged from saturation + 1/s to the end. A
run that conducts, below the cell's linear onset (s <= 0) or whose roll did not grow (A at
the end, its mean over the run's last tenth, below 3 x its minimum), is not continued: its
Nu is over the second half. The readings give each run's rule (nu_rule) and start of Nu's
average (nu_from_t). --reuse takes a run continued past its end time if it has snapshots;
a run made without --saturate (no snapshots) it keeps as it is, Nu over its second half
(nu_rule "second half, kept"; drawn with a dot inside).

--onset draws, per variant, the line of Nu - 1 through the two lowest ratios that convect
(Nu - 1 above 3 x the discrete flux error of the start, |Nu(t = 0) - 1|, as
tests/run_convection_onset.py counts them) extrapolated to Nu = 1: weakly nonlinear theory
has Nu - 1 linear in Ra - Ra_c near onset, so the intercept is the onset. With --readings
the onset of each variant (in units of 1707.76 and of the cell's linear Ra_c) is written too,
and that of the line through the next two ratios (without the lowest): how far the curvature
of Nu - 1 in Ra moves it.
--reuse analyses runs already in --workdir that reached their end time again.
"""

import argparse
import json
import math
import os
import re
import shlex
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import plot_convection as pc  # noqa: E402
import convection_linear  # noqa: E402
import convection_roll as roll  # noqa: E402
from spamrun import manifest_files  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


STYLES = [("C3", "o"), ("C0", "s"), ("C2", "^"), ("C1", "D"), ("C4", "v")]


def amplitude_of(a, extra):
    """The run's seed amplitude: the variant's last -convection_amplitude, else --amplitude."""
    given = [extra[i + 1] for i in range(len(extra) - 1) if extra[i] == "-convection_amplitude"]
    return float(given[-1]) if given else a.amplitude


def end_time(a, cell, ratio, amplitude):
    """(end time, or None for the options file's; the time Nu is averaged from, or None for
    the second half of the run; s): --sized-end's end time where the cell's linear rate s
    (at Pr = 1, the sweep's) is positive (see the module's text), else --t-end."""
    if a.sized_end:
        s = convection_linear.growth(cell, 2 * math.pi / cell.L, ratio * pc.RA_CRITICAL)[0]
        if s > 0:
            t_end = (math.log(0.5 / amplitude) + 6.0) / s
            return t_end, t_end - 3.0 / s, s
    return (a.t_end or None), None, None


def run_one(a, cell, ratio, name, extra):
    """(Ra, Nu, Nu_bottom, Nu_top, KE_final, ms per RHS, Nu at the start, end time, wall
    crossings, the time Nu is averaged from, how: "second half", "saturated", "not saturated",
    "conducts", "sized", "second half, kept"; Nu over the last quarter of its average) of one
    run, or None when it fails."""
    out = os.path.join(a.workdir, name, f"ra{ratio:g}")
    t_end, t_from, _ = end_time(a, cell, ratio, amplitude_of(a, extra))
    how = "second half" if t_from is None else "sized"
    s = mode = None
    if a.saturate:
        s, y, fields = convection_linear.mode(cell, 2 * math.pi / cell.L, ratio * pc.RA_CRITICAL)
        s, mode = s.real, (y, fields)
    args = [a.spam_ark, "-options_file", os.path.join(HERE, "..", "options", "convection.opts"),
            "-convection_nx", a.nx, "-convection_ny", a.ny, "-convection_g", 0.1 * 2.0 / a.ny,
            "-convection_ra", ratio * pc.RA_CRITICAL, "-convection_amplitude", a.amplitude,
            "-output_dir", out, "-output_interval", t_end / 200 if t_end else 20]
    if a.saturate:  # CSV snapshots for the roll's amplitude, a checkpoint every 1/s to continue from
        args += ["-snapshot_interval", max(0.125 / s, t_end / 200) if s > 0 else t_end / 200, "-snapshot_hdf5", 0]
        args += ["-checkpoint_interval", 1.0 / s] if s > 0 else []
    else:
        args += ["-snapshot_interval", 0]
    args = [str(x) for x in args] + extra
    done = os.path.join(out, "summary.json")
    reused = False
    if a.reuse and os.path.exists(done) and os.path.exists(os.path.join(out, "stdout.txt")):
        with open(done) as f:
            sm = json.load(f)
        # --saturate: a run continued past its end time counts, if it has the snapshots
        reused = sm.get("status") == "ok" and (not t_end or abs(sm["t_final"] - t_end) < 1e-6 * t_end
                                                or (a.saturate and sm["t_final"] > t_end and manifest_files(out, "snapshot_csv")))
    if not reused:
        p = subprocess.run(args + ["-output_overwrite"] + (["-ts_max_time", str(t_end)] if t_end else []), capture_output=True, text=True)
        if p.returncode != 0:
            print(f"run failed (exit {p.returncode}): {' '.join(args)}: {p.stderr.strip()[-300:]}", file=sys.stderr)
            return None
        with open(os.path.join(out, "stdout.txt"), "w") as f:
            f.write(p.stdout)
    with open(os.path.join(out, "stdout.txt")) as f:
        m = re.search(r"convection: Ra = ([0-9.eE+-]+)", f.read())
    if a.saturate and reused and not manifest_files(out, "snapshot_csv"):
        how = "second half, kept"  # a run made without --saturate: no roll to measure, taken as it is
    elif a.saturate:
        t_from, how = saturate(args, out, cell, s, mode, summary_t(out), f"{name} {ratio:g}")
    summary, series, _ = pc.load(out)
    t_last = series["t"][-1]
    t_from = 0.5 * t_last if t_from is None else t_from
    nu, nub, nut, (qb, qt) = pc.nusselt(summary, series, a.t_bottom, a.t_top, t_from)
    # Nu over the last quarter of that average: a steady state has the same
    nu_late = pc.nusselt(summary, series, a.t_bottom, a.t_top, t_last - 0.25 * (t_last - t_from))[0]
    ms = 1e3 * summary["rhs_time_s"] / summary["rhs_evals"]
    return (float(m.group(1)), nu, nub, nut, series["kinetic"][-1], ms, 0.5 * (qb[0] + qt[0]), t_last,
            summary.get("post_step_jumps", 0), t_from, how, nu_late)


def summary_t(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["t_final"]


def saturate(args, out, cell, s, mode, t_end, label):
    """(the time Nu is averaged from, how) by the onset study's rule (tests/convection_roll.py):
    where the roll grows (linear rate s > 0 and roll.grew: its end value 3 x its minimum or
    more), the run is continued from its checkpoint until Nu's average, from one e-folding
    time 1/s after saturation, spans 3/s ("saturated"; "not saturated" when it cannot be);
    a run below the cell's linear onset (s <= 0) or whose roll did not grow conducts: Nu
    over the second half ("conducts"), not continued."""
    k = 2 * math.pi / cell.L

    def amplitudes():
        return roll.roll_amplitudes(cell, out, k, *mode)
    t, A = amplitudes()[:2]
    if not (s > 0 and roll.grew(t, A)):
        return None, "conducts"
    ckpt = os.path.join(out, "checkpoint.h5")

    def go_on(t_to):
        if not os.path.exists(ckpt):
            return None
        p = subprocess.run(args + ["-ts_max_time", str(t_to), "-restart", ckpt], capture_output=True, text=True)
        if p.returncode != 0:
            print(f"continuation failed (exit {p.returncode}): {label}: {p.stderr.strip()[-300:]}", file=sys.stderr)
        return p.returncode == 0
    _, series, _, saturated = roll.run_to_saturation(t_end, s, amplitudes, go_on, log=lambda msg: print(f"{label}: {msg}", flush=True))
    return roll.nu_from(series[0], series[1], s), "saturated" if saturated else "not saturated"


def onset(points):
    """(Ra_onset / 1707.76, the two ratios, floor) from [(ratio, Nu, Nu at the start)]: the line
    of Nu - 1 through the two lowest ratios above the floor 3 max |Nu_start - 1|, extrapolated
    to Nu - 1 = 0 (nan when fewer than two convect or Nu does not rise)."""
    floor = 3 * max(abs(n0 - 1.0) for _, _, n0 in points)
    up = sorted((r, nu - 1.0) for r, nu, _ in points if nu - 1.0 > floor)[:2]
    if len(up) < 2 or up[1][1] <= up[0][1]:
        return float("nan"), [r for r, _ in up], floor
    (r0, y0), (r1, y1) = up
    return r0 - y0 * (r1 - r0) / (y1 - y0), [r0, r1], floor


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spam-ark", required=True)
    ap.add_argument("--workdir", default="out/convection_sweep")
    ap.add_argument("--ratios", default="0.5,0.8,1.2,1.6,2,3,4,5")
    ap.add_argument("--nx", type=int, default=32)
    ap.add_argument("--ny", type=int, default=16)
    ap.add_argument("--t-end", type=float, default=0.0, help="end time of every run (0: the options file's)")
    ap.add_argument("--amplitude", type=float, default=0.01, help="-convection_amplitude of every run (the seeded kick)")
    ap.add_argument("--t-bottom", type=float, default=1.25)
    ap.add_argument("--t-top", type=float, default=0.75)
    ap.add_argument("--variant", action="append", default=None, help='NAME="OPTIONS" run at every ratio (repeatable)')
    ap.add_argument("--sized-end", action="store_true", help="end time from the linear growth rate where it is positive (see above)")
    ap.add_argument("--saturate", action="store_true", help="continue each run whose roll grows until it has saturated; Nu by the onset study's rule (see above)")
    ap.add_argument("--onset", action="store_true", help="draw and report each variant's onset from Nu - 1 (see above)")
    ap.add_argument("--xscale", choices=("log", "linear"), default="log", help="the Ra axis")
    ap.add_argument("--reuse", action="store_true", help="analyse the runs already in --workdir that reached their end time")
    ap.add_argument("-o", "--out", default=None)
    ap.add_argument("--readings", action="store_true", help="write the runs and the table beside the chart (OUT.json)")
    a = ap.parse_args()
    if a.saturate and not (a.t_end or a.sized_end):
        sys.exit("convection_sweep: error: --saturate needs --t-end or --sized-end (the first end time)")
    variants = []
    for v in a.variant or ["default="]:
        name, _, opts = v.partition("=")
        if not name or not re.fullmatch(r"[A-Za-z0-9_.+-]+", name):
            sys.exit(f"convection_sweep: error: --variant {v!r}: NAME=OPTIONS with a plain NAME")
        variants.append((name, shlex.split(opts)))
    if len(variants) > len(STYLES):
        sys.exit(f"convection_sweep: error: at most {len(STYLES)} variants")
    os.makedirs(a.workdir, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ratios = [float(r) for r in a.ratios.split(",")]
    fig, ax = plt.subplots(figsize=(7.5, 7))
    ax.set_xscale(a.xscale)
    cell = convection_linear.Cell(nx=a.nx, ny=a.ny, g=0.1 * 2.0 / a.ny, t_bottom=a.t_bottom, t_top=a.t_top)
    ra_cell, _ = convection_linear.cell_critical(cell)
    print("variant ratio Ra Nu Nu_bottom Nu_top ke_final ms_per_rhs t_end nu_from_t nu_rule nu_last_quarter")
    runs, onsets = {}, {}
    for (name, extra), (colour, marker) in zip(variants, STYLES):
        ok, failed = [], []
        for r in ratios:
            got = run_one(a, cell, r, name, extra)
            if got is None:
                failed.append(r)
                print(f"{name} {r:g} failed", flush=True)
                continue
            ra, nu, nub, nut, ke, ms, nu0, t_end, jumps, nu_from, how, nu_late = got
            ok.append((r, nu, nub, nut, nu0, jumps, how))
            runs.setdefault(name, {})[f"{r:g}".replace(".", "_")] = {"ratio": r, "Ra": ra, "Nu": nu, "Nu_bottom": nub,
                                                                   "Nu_top": nut, "wall_difference": nut - nub, "ke_final": ke,
                                                                   "Nu_start": nu0, "t_end": t_end, "post_step_jumps": jumps,
                                                                   "nu_from_t": nu_from, "nu_rule": how, "Nu_last_quarter": nu_late}
            print(f"{name} {r:g} {ra:.6g} {nu:.5f} {nub:.5f} {nut:.5f} {ke:.5g} {ms:.4f} {t_end:.0f} {nu_from:.0f} {how.replace(' ', '_')} {nu_late:.5f}", flush=True)
        label = f"{name}: {' '.join(extra)}" if extra else name
        ax.plot([x[0] for x in ok], [x[1] for x in ok], "-", color=colour, marker=marker, label=f"{label} (mean of both walls)")
        crossed = [x for x in ok if x[5]]
        if crossed:  # particles crossed the walls (reflected after the step): not a clean roll
            ax.plot([x[0] for x in crossed], [x[1] for x in crossed], "o", ms=14, mfc="none", mec=colour, mew=1.5,
                    label=f"{name}: particles crossed the walls, reflected (post_step_jumps > 0)")
        ax.plot([x[0] for x in ok] * 2, [x[2] for x in ok] + [x[3] for x in ok], "_", color=colour, ms=9)
        kept = [x for x in ok if x[6] == "second half, kept"]
        if kept:  # reused runs made without --saturate: Nu over their second half, the roll not measured
            ax.plot([x[0] for x in kept], [x[1] for x in kept], "o", ms=3.5, mfc="w", mec="0.2", mew=0.5, ls="none",
                    label=f"{name}, white dot: run kept from a sweep without --saturate (Nu over its second half)")
        short = [x for x in ok if x[6] == "not saturated"]
        if short:  # the roll had not saturated by the last continuation: Nu is low
            ax.plot([x[0] for x in short], [x[1] for x in short], "s", ms=13, mfc="none", mec=colour, mew=1.5,
                    label=f"{name}: roll not saturated by the run's end")
        if failed:
            ax.plot(failed, [1.0] * len(failed), "x", color=colour, ms=10, mew=2, label=f"{name}: run failed")
        if a.onset and len(ok) >= 2:
            r_on, used, floor = onset([(x[0], x[1], x[4]) for x in ok])
            onsets[name] = {"ra_onset_over_1707": r_on, "ra_onset_over_ra_c_cell": r_on * pc.RA_CRITICAL / ra_cell,
                            "ratios_fitted": used, "noise_floor": floor}
            print(f"{name}: onset from Nu - 1 through ratios {used} (floor {floor:.4f}): Ra = {r_on:.4g} x 1707.76 "
                  f"= {r_on * pc.RA_CRITICAL / ra_cell:.4f} of the cell's linear Ra_c", flush=True)
            if len(used) == 2:  # the same line without the lowest convecting ratio: how far Nu - 1 curves
                r_next, used_next, _ = onset([(x[0], x[1], x[4]) for x in ok if x[0] != used[0]])
                onsets[name].update({"next_ratios_fitted": used_next, "next_ra_onset_over_ra_c_cell": r_next * pc.RA_CRITICAL / ra_cell})
                print(f"{name}: the same through ratios {used_next}: {r_next * pc.RA_CRITICAL / ra_cell:.4f} of the cell's linear Ra_c", flush=True)
            if math.isfinite(r_on):
                nus = {x[0]: x[1] for x in ok}
                ax.plot([r_on, used[1]], [1.0, nus[used[1]]], "--", color=colour, lw=1,
                        label=f"{name}: Nu - 1 through {used[0]:g} and {used[1]:g}, to Nu = 1 at {r_on * pc.RA_CRITICAL / ra_cell:.3f} Ra_c")
    ax.plot([], [], "_", color="0.3", ms=9, label="bars: hot and cold wall")
    ax.axvline(1.0, color="k", ls="--", lw=1, label="continuum onset, rigid walls, Boussinesq (1707.76)")
    ax.axvline(ra_cell / pc.RA_CRITICAL, color="k", ls=":", lw=1.2, label=f"onset of this compressible cell, linear theory ({ra_cell:.2f})")
    print(f"linear theory of the cell: Ra_c = {ra_cell:.6g} ({ra_cell / pc.RA_CRITICAL:.4f} of 1707.76)")
    ax.axhline(1.0, color="0.5", ls=":", lw=1, label="conduction Nu = 1")
    ax.set_xlabel("Ra / Ra_c (superadiabatic Rayleigh number over 1707.76)")
    ax.set_ylabel("Nusselt number Nu")
    ax.set_title(f"scene convection: Nu against Ra\n{a.nx} x {a.ny} lattice, Pr = 1, T_b = {a.t_bottom:g}, T_t = {a.t_top:g}, "
                 f"kick {a.amplitude:g} c_s unless the variant sets it"
                 + ("\nruns whose roll grows continued until it saturated, Nu from 1/s after saturation (hollow squares: not saturated)" if a.saturate else ""),
                 fontsize=9)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12))
    out = a.out or os.path.join(a.workdir, "convection_nu_ra.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110, bbox_inches="tight")
    print(f"png={out}")
    if a.readings:
        import chart_readings

        def entry(name, r):
            x = runs.get(name, {}).get(f"{r:g}".replace(".", "_"))
            return f"{x['Nu']:.4f} ({x['Nu_bottom']:.4f}, {x['Nu_top']:.4f})" if x else "failed"
        chart_readings.write(out, {"runs": runs, "onset": onsets, "ra_c_cell": ra_cell, "table": chart_readings.table(
            ["Ra / Ra_c"] + [f"Nu, {name} (hot, cold wall)" for name, _ in variants],
            [[f"{r:g}"] + [entry(name, r) for name, _ in variants] for r in ratios])})


if __name__ == "__main__":
    main()
