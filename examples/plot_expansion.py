#!/usr/bin/python3
"""Chart a spam-ark free-expansion run (Hoover & Hoover, CiSE 2001, Figs. 2 and 3).

Usage:
    examples/plot_expansion.py DIR [-o OUT.png]

DIR is the output directory of
    spam-ark -options_file options/expansion.opts -output_dir DIR
and must hold manifest.json, summary.json, timeseries.csv and CSV snapshots. The
files are those the manifest lists, never a glob of the directory: a file left by
another run is not drawn. A run whose status is "failed" is refused; one that is
"running", "interrupted" or "unstable" is drawn with a warning on stderr.

The figure (default DIR/expansion.png) has
  * top row:      up to four particle snapshots, evenly spaced in time (first and
                  last included), dots coloured by density on one shared scale
                  (1D runs show the phase plane x, vx instead of x, y);
  * bottom left:  entropy increase dS / (N k ln V) against t / tau, from the
                  particle sum (solid) and the grid integral (dashed), with the
                  ideal-gas value 1 as a reference line;
  * bottom right: kinetic, internal and total energy against t / tau, with the
                  relative drift of the total energy on a twin axis.

One line goes to stdout:
    final dS_sum_ratio=<v> dS_grid_ratio=<v> max_rel_energy_drift=<v> png=<path>
On a missing or malformed input the script prints one line to stderr and exits
with status 2.

Needs numpy and matplotlib (Debian: python3-numpy, python3-matplotlib).  If the
python3 found first on PATH lacks them but /usr/bin/python3 has them, the script
re-runs itself with /usr/bin/python3.
"""

import argparse
import csv
import json
import math
import os
import re
import sys

EXIT_INPUT = 2      # missing or malformed input
EXIT_RUNTIME = 3    # missing dependencies, cannot write the PNG

SYSTEM_PYTHON = "/usr/bin/python3"
REEXEC_GUARD = "SPAM_ARK_PLOT_REEXEC"

MAX_SNAPSHOT_PANELS = 4

TIMESERIES_COLUMNS = ("t", "kinetic", "internal", "total",
                      "dS_sum_ratio", "dS_grid_ratio")


class InputError(Exception):
    """A missing or malformed input; reported as one line, exit status 2."""


def fail(message, status):
    message = " ".join(str(message).split())      # always exactly one line
    sys.stderr.write("plot_expansion: error: %s\n" % message)
    sys.exit(status)


# --------------------------------------------------------------------------
# dependencies
# --------------------------------------------------------------------------

def import_plotting():
    """Import numpy and matplotlib (Agg); re-exec under Debian's python if needed."""
    try:
        import numpy                                    # noqa: F401
        import matplotlib
    except ImportError as exc:
        here = os.path.realpath(sys.executable or "")
        if (os.environ.get(REEXEC_GUARD) != "1"
                and os.path.exists(SYSTEM_PYTHON)
                and os.path.realpath(SYSTEM_PYTHON) != here):
            env = dict(os.environ)
            env[REEXEC_GUARD] = "1"
            sys.stdout.flush()
            sys.stderr.flush()
            os.execve(SYSTEM_PYTHON,
                      [SYSTEM_PYTHON, os.path.abspath(sys.argv[0])] + sys.argv[1:],
                      env)
        fail("%s; install numpy and matplotlib "
             "(Debian: apt-get install python3-numpy python3-matplotlib)" % exc,
             EXIT_RUNTIME)
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    return np, plt


# --------------------------------------------------------------------------
# reading the run directory
# --------------------------------------------------------------------------

def as_float(value, what):
    if isinstance(value, bool):
        raise InputError("%s is not a number: %r" % (what, value))
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError("%s is not a number: %r" % (what, value))


def read_summary(path):
    if not os.path.isfile(path):
        raise InputError("missing %s" % path)
    try:
        with open(path, "r", encoding="utf-8") as fh:
            summary = json.load(fh)
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError("cannot parse %s: %s" % (path, exc))
    if not isinstance(summary, dict):
        raise InputError("%s: expected a JSON object" % path)

    for key in ("sound_traversal_time", "volume_ratio"):
        if key not in summary:
            raise InputError("%s: missing key \"%s\"" % (path, key))
    tau = as_float(summary["sound_traversal_time"],
                   "%s: sound_traversal_time" % path)
    if not (math.isfinite(tau) and tau > 0):
        raise InputError("%s: sound_traversal_time must be positive, got %r"
                         % (path, summary["sound_traversal_time"]))
    ratio = as_float(summary["volume_ratio"], "%s: volume_ratio" % path)
    if not (math.isfinite(ratio) and ratio > 1):
        raise InputError("%s: volume_ratio must be > 1, got %r"
                         % (path, summary["volume_ratio"]))
    summary["sound_traversal_time"] = tau
    summary["volume_ratio"] = ratio

    dim = summary.get("dim")
    if dim is not None:
        if isinstance(dim, bool) or dim not in (1, 2, 3):
            raise InputError("%s: dim must be 1, 2 or 3, got %r" % (path, dim))
        summary["dim"] = int(dim)
    return summary


def read_timeseries(path, np):
    """Return {column: float array} for the columns the chart needs, by header name."""
    if not os.path.isfile(path):
        raise InputError("missing %s" % path)
    try:
        with open(path, "r", encoding="utf-8", newline="") as fh:
            rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError("cannot read %s: %s" % (path, exc))
    if not rows:
        raise InputError("%s is empty" % path)
    header = [c.strip() for c in rows[0]]
    where = {}
    for i, name in enumerate(header):
        where.setdefault(name, i)
    missing = [c for c in TIMESERIES_COLUMNS if c not in where]
    if missing:
        raise InputError("%s: missing column(s) %s" % (path, ", ".join(missing)))
    if len(rows) < 2:
        raise InputError("%s has a header but no data rows" % path)

    data = {c: [] for c in TIMESERIES_COLUMNS}
    for lineno, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise InputError("%s: data row %d has %d fields, header has %d"
                             % (path, lineno, len(row), len(header)))
        for c in TIMESERIES_COLUMNS:
            data[c].append(as_float(row[where[c]].strip(),
                                    "%s: row %d, column %s" % (path, lineno, c)))
    out = {c: np.asarray(v, dtype=float) for c, v in data.items()}
    if not np.all(np.isfinite(out["t"])):
        raise InputError("%s: column t has non-finite values" % path)
    return out


def list_snapshots(run_dir):
    """[(index, path)] of the CSV snapshots the manifest lists, in the order written."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import spam_manifest
    try:
        man = spam_manifest.read(run_dir)
        spam_manifest.check(man, run_dir, "plot_expansion")
    except spam_manifest.ManifestError as exc:
        raise InputError(str(exc))
    return list(enumerate(p for _, p in spam_manifest.files(man, run_dir, "snapshot_csv")))


def parse_time_line(line, path):
    text = line.strip()
    if not text.startswith("#"):
        raise InputError("%s: first line should be '# t=<time>', got %r" % (path, text[:60]))
    m = re.match(r"^#\s*t\s*=\s*(\S+)", text)
    if not m:
        raise InputError("%s: first line should be '# t=<time>', got %r" % (path, text[:60]))
    t = as_float(m.group(1), "%s: snapshot time" % path)
    if not math.isfinite(t):
        raise InputError("%s: snapshot time is not finite" % path)
    return t


def read_snapshot_time(path):
    try:
        with open(path, "r", encoding="utf-8") as fh:
            first = fh.readline()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError("cannot read %s: %s" % (path, exc))
    return parse_time_line(first, path)


def read_snapshot(path, np):
    """Return (t, {x,y,vx,rho: array}) for one particles_NNNNN.csv."""
    wanted = ("x", "y", "vx", "rho")
    try:
        with open(path, "r", encoding="utf-8") as fh:
            t = parse_time_line(fh.readline(), path)
            header = [c.strip() for c in fh.readline().strip().split(",")]
            # The density a model sums from positions is the column rho_sum (rho is a
            # carried density, which the file scene reads back).
            if "rho" not in header and "rho_sum" in header:
                header[header.index("rho_sum")] = "rho"
            missing = [c for c in wanted if c not in header]
            if missing:
                raise InputError("%s: missing column(s) %s" % (path, ", ".join(missing)))
            cols = [header.index(c) for c in wanted]
            lines = [ln for ln in fh if ln.strip()]
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError("cannot read %s: %s" % (path, exc))
    if not lines:
        raise InputError("%s has no particle rows" % path)
    for lineno, ln in enumerate(lines, start=3):
        if ln.count(",") != len(header) - 1:
            raise InputError("%s: particle row %d has %d fields, header has %d"
                             % (path, lineno, ln.count(",") + 1, len(header)))
    try:
        table = np.loadtxt(lines, delimiter=",", usecols=cols, ndmin=2, dtype=float)
    except ValueError as exc:
        raise InputError("%s: bad particle data: %s" % (path, exc))
    return t, {c: table[:, k] for k, c in enumerate(wanted)}


def choose_snapshots(times, count):
    """Indices into `times` (sorted) of up to `count` snapshots spread evenly in time."""
    n = len(times)
    if n <= count:
        return list(range(n))
    t0, t1 = times[0], times[-1]
    chosen = {0, n - 1}
    for k in range(1, count - 1):
        target = t0 + (t1 - t0) * k / (count - 1)
        order = sorted(range(n), key=lambda i: (abs(times[i] - target), i))
        for i in order:
            if i not in chosen:
                chosen.add(i)
                break
    return sorted(chosen)


def load_run(run_dir, np):
    if not os.path.exists(run_dir):
        raise InputError("run directory %s does not exist" % run_dir)
    if not os.path.isdir(run_dir):
        raise InputError("%s is not a directory" % run_dir)
    snaps = list_snapshots(run_dir)
    summary = read_summary(os.path.join(run_dir, "summary.json"))
    series = read_timeseries(os.path.join(run_dir, "timeseries.csv"), np)
    if not snaps:
        raise InputError("no particle snapshots (particles_NNNNN.csv) in %s" % run_dir)
    times = [read_snapshot_time(p) for _, p in snaps]
    order = sorted(range(len(snaps)), key=lambda i: (times[i], snaps[i][0]))
    snaps = [snaps[i] for i in order]
    times = [times[i] for i in order]
    picked = [read_snapshot(snaps[i][1], np)
              for i in choose_snapshots(times, MAX_SNAPSHOT_PANELS)]
    return summary, series, picked


# --------------------------------------------------------------------------
# numbers
# --------------------------------------------------------------------------

def energy_drift(total, np):
    """(relative drift series, max |E - E0| / |E0|); absolute if E0 == 0."""
    e0 = total[0]
    scale = abs(e0) if e0 != 0 and math.isfinite(e0) else 1.0
    rel = (total - e0) / scale
    finite = rel[np.isfinite(rel)]
    return rel, (float(np.max(np.abs(finite))) if finite.size else float("nan"))


def fmt_num(v):
    """Short human form for the title: ints stay ints, floats in %g."""
    if isinstance(v, bool) or v is None:
        return "?"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "%d" % v if v.is_integer() and abs(v) < 1e15 else "%g" % v
    return str(v)


def fmt_ratio(r):
    return "%d" % r if float(r).is_integer() else "%g" % r


# --------------------------------------------------------------------------
# drawing
# --------------------------------------------------------------------------

def dot_size(n, dim, width_pt):
    """Marker area (pt^2) so that dots roughly tile the final, expanded state."""
    n = max(int(n), 1)
    if dim == 1:
        return min(12.0, max(1.0, 4000.0 / n))
    spacing = width_pt / math.sqrt(n)
    return min(12.0, max(0.15, (0.75 * spacing) ** 2))


def padded(lo, hi, frac=0.04):
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return -1.0, 1.0
    span = hi - lo
    if span <= 0:
        span = max(abs(lo), 1.0)
    return lo - frac * span, hi + frac * span


def headroom(values, np, top=0.30, bottom=0.05):
    """y limits with a free band of `top` (fraction of the axis) above the data."""
    v = values[np.isfinite(values)]
    lo, hi = (float(v.min()), float(v.max())) if v.size else (0.0, 1.0)
    span = hi - lo
    if span <= 0:
        span = max(abs(hi), 1e-12)
        lo, hi = lo - span / 2, hi + span / 2
        span = hi - lo
    full = span / (1.0 - top - bottom)
    return lo - bottom * full, hi + top * full


def draw(summary, series, picked, out_path, np, plt):
    tau = summary["sound_traversal_time"]
    ratio = summary["volume_ratio"]
    dim = summary.get("dim")
    if dim is None:                       # infer: any y spread means 2D or 3D
        dim = 2 if any(np.ptp(s["y"]) > 0 for _, s in picked) else 1
    n_particles = summary.get("n_particles", len(picked[0][1]["x"]))
    ln_v = "ln %s" % fmt_ratio(ratio)

    fig = plt.figure(figsize=(13, 9), dpi=110, layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[0.85, 1.0])

    # ---- top row: snapshots -------------------------------------------------
    axes = top.subplots(1, len(picked), squeeze=False)[0]
    key_y = "vx" if dim == 1 else "y"
    xs = np.concatenate([s["x"] for _, s in picked])
    ys = np.concatenate([s[key_y] for _, s in picked])
    rhos = np.concatenate([s["rho"] for _, s in picked])
    finite = np.isfinite(rhos)
    vmin = float(np.min(rhos[finite])) if finite.any() else 0.0
    vmax = float(np.max(rhos[finite])) if finite.any() else 1.0
    if vmax <= vmin:
        vmin, vmax = vmin - 0.5, vmax + 0.5
    xlim = padded(float(np.nanmin(xs)), float(np.nanmax(xs)))
    ylim = padded(float(np.nanmin(ys)), float(np.nanmax(ys)), 0.08 if dim == 1 else 0.04)
    panel_pt = 13 * 72.0 / max(len(picked), 2) * 0.8
    size = dot_size(n_particles, dim, panel_pt)

    scatter = None
    for ax, (t, snap) in zip(axes, picked):
        x, y, rho = snap["x"], snap[key_y], snap["rho"]
        order = np.argsort(rho)           # densest drawn last, on top
        scatter = ax.scatter(x[order], y[order], c=rho[order], s=size,
                             cmap="viridis", vmin=vmin, vmax=vmax,
                             linewidths=0, rasterized=True)
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        if dim == 1:
            ax.set_box_aspect(1.0)        # x and vx have different units
            ax.set_xlabel("x")
            ax.set_ylabel("vx")
        else:
            ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel("x")
            ax.set_ylabel("y" if dim == 2 else "y (projected along z)")
        ax.set_title("t = %.4g  (%.3g τ)" % (t, t / tau), fontsize=11)
        ax.tick_params(labelsize=8)
    cbar = top.colorbar(scatter, ax=list(axes), shrink=0.85, pad=0.01)
    cbar.set_label("density ρ")

    # ---- bottom row ---------------------------------------------------------
    ax_s, ax_e = bottom.subplots(1, 2)
    t_tau = series["t"] / tau
    mark = "o" if len(t_tau) < 2 else None    # a single row still shows up

    ax_s.plot(t_tau, series["dS_sum_ratio"], "-", marker=mark, color="tab:blue", lw=1.8,
              label="sum over particles")
    ax_s.plot(t_tau, series["dS_grid_ratio"], "--", marker=mark, color="tab:red", lw=1.8,
              label="grid integration")
    ax_s.axhline(1.0, color="0.35", lw=1.0, ls=":",
                 label="ideal gas: ΔS = N k %s" % ln_v)
    vals = np.concatenate([series["dS_sum_ratio"], series["dS_grid_ratio"]])
    vals = vals[np.isfinite(vals)]
    lo = min(0.0, float(vals.min())) if vals.size else 0.0
    hi = max(1.0, float(vals.max())) if vals.size else 1.0
    ax_s.set_ylim(lo - 0.06 * (hi - lo), hi + 0.12 * (hi - lo))
    ax_s.set_xlim(t_tau[0], t_tau[-1] if t_tau[-1] > t_tau[0] else t_tau[0] + 1)
    ax_s.set_xlabel("t / τ (sound traversal times)")
    ax_s.set_ylabel("ΔS / (N k %s)" % ln_v)
    ax_s.set_title("Entropy increase (CiSE 2001, Fig. 3)", fontsize=11)
    ax_s.grid(alpha=0.3)
    ax_s.legend(loc="lower right", fontsize=9)

    rel, drift = energy_drift(series["total"], np)
    for key, colour, width in (("kinetic", "tab:orange", 1.6),
                               ("internal", "tab:green", 1.6),
                               ("total", "black", 2.0)):
        ax_e.plot(t_tau, series[key], "-", marker=mark, color=colour, lw=width, label=key)
    ax_e.set_xlim(*ax_s.get_xlim())
    ax_e.set_xlabel("t / τ (sound traversal times)")
    ax_e.set_ylabel("energy")
    ax_e.set_title("Energies", fontsize=11)
    ax_e.grid(alpha=0.3)

    ax_d = ax_e.twinx()
    drift_name = ("(E − E0) / |E0|" if series["total"][0] != 0
                  else "E − E0 (E0 = 0)")
    ax_d.plot(t_tau, rel, ":", marker=mark, color="tab:purple", lw=1.3,
              label="%s, max |·| = %.3g" % (drift_name, drift))
    ax_d.set_ylabel("relative total-energy drift", color="tab:purple")
    ax_d.tick_params(axis="y", colors="tab:purple", labelsize=8)
    ax_d.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3), useMathText=True)
    # leave the top quarter of both axes free for the legend
    ax_e.set_ylim(*headroom(np.concatenate([series["kinetic"], series["internal"],
                                            series["total"]]), np))
    ax_d.set_ylim(*headroom(rel, np))
    h1, l1 = ax_e.get_legend_handles_labels()
    h2, l2 = ax_d.get_legend_handles_labels()
    ax_e.legend(h1 + h2, l1 + l2, loc="upper center", ncol=2, fontsize=9,
                framealpha=0.9)

    # ---- title ----------------------------------------------------------------
    steps = summary.get("steps")
    rejected = summary.get("rejected_steps")
    steps_txt = fmt_num(steps)
    if rejected is not None:
        steps_txt += " (%s rejected)" % fmt_num(rejected)
    # the scene as run: mirror walls (summary.json wall_F: noslip or freeslip) named with it
    walls = sorted({v for k, v in summary.items() if re.fullmatch(r"wall_[xyz](lo|hi)", k)})
    scene = summary.get("scene", "?") + (" with %s walls" % " and ".join(walls) if walls else "")
    fig.suptitle(
        "%s — %sD, N = %s, volume ratio %s\n"
        "method %s, rtol %s, atol %s    |    steps %s, RHS evals %s%s"
        % (scene, fmt_num(dim), fmt_num(n_particles),
           fmt_ratio(ratio), summary.get("method", "?"),
           fmt_num(summary.get("rtol")), fmt_num(summary.get("atol")),
           steps_txt, fmt_num(summary.get("rhs_evals_total", summary.get("rhs_evals"))),
           ("" if summary.get("status") in (None, "", "ok")
            else "    |    status %s" % summary.get("status"))),
        fontsize=12)

    try:
        fig.savefig(out_path, dpi=110)
    except OSError as exc:
        fail("cannot write %s: %s" % (out_path, exc), EXIT_RUNTIME)
    finally:
        plt.close(fig)
    return drift


# --------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Chart a spam-ark free-expansion run (snapshots, entropy, energy).")
    parser.add_argument("run_dir", metavar="DIR", help="spam-ark -output_dir of the run")
    parser.add_argument("-o", "--output", metavar="OUT.png",
                        help="PNG to write (default: DIR/expansion.png)")
    args = parser.parse_args(argv)

    np, plt = import_plotting()
    run_dir = args.run_dir
    out_path = args.output or os.path.join(run_dir, "expansion.png")
    try:
        summary, series, picked = load_run(run_dir, np)
    except InputError as exc:
        fail(exc, EXIT_INPUT)

    drift = draw(summary, series, picked, out_path, np, plt)
    # repr() of a Python float is the shortest string that reads back exactly
    print("final dS_sum_ratio=%r dS_grid_ratio=%r max_rel_energy_drift=%r png=%s"
          % (float(series["dS_sum_ratio"][-1]), float(series["dS_grid_ratio"][-1]),
             float(drift), out_path))
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import chart_readings
    readings = dict(chart_readings.books(run_dir), max_rel_energy_drift=float(drift),
                    dS_sum_ratio={"t%g" % t: float(v) for t, v in zip(series["t"], series["dS_sum_ratio"])},
                    dS_sum_final=float(series["dS_sum_ratio"][-1]), dS_grid_final=float(series["dS_grid_ratio"][-1]),
                    dS_sum_max=float(max(series["dS_sum_ratio"])))
    chart_readings.write(out_path, readings, runs=[run_dir])
    return 0


if __name__ == "__main__":
    sys.exit(main())
