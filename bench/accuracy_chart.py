#!/usr/bin/python3
"""The time-to-accuracy chart of run_accuracy.py: wall time against accuracy, one curve per
spam-ark method and one for LAMMPS, a row per size and a column per accuracy measure.

    /usr/bin/python3 bench/accuracy_chart.py RESULTS.json [MORE.json ...] [docs/time_to_accuracy.png]

(several JSON files, one size each for instance, make one chart with a row per size).
"""
import json
import sys
from pathlib import Path

# One colour and marker per method in every panel (and any other bench chart that shows them).
METHOD_STYLE = {
    "lammps": {"color": "black", "marker": "s", "label": "LAMMPS velocity Verlet (fix nve), dt"},
    "dp5": {"color": "tab:blue", "marker": "o", "label": "spam-ark Dormand-Prince 5(4), rtol"},
    "bs3": {"color": "tab:green", "marker": "^", "label": "spam-ark Bogacki-Shampine 3(2), rtol"},
    "kdk": {"color": "tab:orange", "marker": "D", "label": "spam-ark velocity Verlet (kdk), dt"},
}
MEASURES = (("ke_err", "relative error of KE(t = 10)"), ("pos_err", "largest position error at t = 10"))


def draw(out, path, tkey="wall_s"):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    results = out["results"]
    fig, axes = plt.subplots(len(results), 2, figsize=(13, 5.2 * len(results)), squeeze=False)
    for row, res in zip(axes, results):
        for ax, (measure, name) in zip(row, MEASURES):
            curves = [c for c in METHOD_STYLE if any(s["curve"] == c for s in res["settings"])]
            for c in curves:
                st = METHOD_STYLE[c]
                # In ladder order (loose to tight), so that a tolerance that bought no accuracy shows.
                pts = sorted((s for s in res["settings"] if s["curve"] == c and s["status"] == "ok"),
                             key=lambda s: -s["param"])
                ax.loglog([s["err"][measure] for s in pts], [s[tkey] for s in pts], "-",
                          color=st["color"], marker=st["marker"], label=st["label"])
                for s in pts:
                    ax.annotate("%g" % s["param"], (s["err"][measure], s[tkey]), textcoords="offset points",
                                xytext=(4, 3), fontsize=7, color=st["color"])
                bad = [s for s in res["settings"] if s["curve"] == c and s["status"] != "ok"]
                for s in bad:
                    # No error to place it by: drawn at the left edge, at its wall time if any.
                    y = s[tkey] or max(x[tkey] for x in res["settings"] if x[tkey])
                    ax.plot([min(EPS_LO, min(x["err"][measure] for x in res["settings"] if x["err"]))], [y],
                            "x", color="red", mfc="none", ms=10,
                            label="%s %g: %s" % (c, s["param"], s["status"]))
            for eps in out["eps"]:
                ax.axvline(eps, color="0.85", lw=0.8, zorder=0)
            ax.invert_xaxis()
            lo, hi = ax.get_ylim()
            ax.set_ylim(lo, hi * 4.0)  # room for the table of ratios above the curves
            ax.set_xlabel("%s (reduced units; more accurate to the right)" % name)
            ax.set_ylabel("wall time of the whole process, s (median of %s)" % out["repeats"])
            ax.set_title("2D isentropic expansion, h = 3, N = %d: time to accuracy" % res["n"], fontsize=10)
            ax.grid(True, which="major", alpha=0.3)
            ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FuncFormatter(
                lambda v, _: "%g" % v if "%.0e" % v in MINOR_LABELS else ""))
            text = ratio_text(res["tta"][measure], res["tta_cpu"][measure], res["reference"], measure)
            ax.text(0.02, 0.98, text, transform=ax.transAxes, va="top", fontsize=7.5, family="monospace",
                    bbox={"facecolor": "white", "alpha": 0.85, "edgecolor": "0.7"})
            ax.legend(loc="upper right", fontsize=7.5)
    fig.suptitle("spam-ark against LAMMPS on one core each, from the same particles to t = 10 "
                 "(commit %s, bench/run_accuracy.py)" % out.get("commit", "?"), fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    write_readings(out, path)


MEASURE_NAMES = {"ke_err": "KE", "pos_err": "position"}


def fmt_setting(curve, param):
    return ("dt %g" % param) if curve in ("lammps", "kdk") else ("%s rtol %g" % (curve.upper(), param))


def table_rows(out):
    """The page's table: for every size, measure and accuracy that both programs reached, the
    cheapest settings, their wall times and the ratios (as run, per repeat, interpolated, in
    CPU time and of the run loops alone)."""
    rows = []
    for res in out["results"]:
        for measure in ("ke_err", "pos_err"):
            for row, crow, lrow in zip(res["tta"][measure], res["tta_cpu"][measure], res["tta_loop"][measure]):
                if "ratio_runs" not in row:
                    continue
                c = row["curves"]
                best, lam = c[row["best_spam_runs"]], c["lammps"]
                per = row["ratio_runs_per_repeat"]
                rows.append([str(res["n"]), "%s %.0e" % (MEASURE_NAMES[measure], row["eps"]),
                             "%s, %.3f s" % (fmt_setting(row["best_spam_runs"], best["setting"]), best["runs_s"]),
                             "%s, %.3f s" % (fmt_setting("lammps", lam["setting"]), lam["runs_s"]),
                             "%.3f (%.3f–%.3f)" % (row["ratio_runs"], min(per), max(per)), "%.3f" % row["ratio_interp"],
                             "%.3f" % crow["ratio_runs"] if "ratio_runs" in crow else "–",
                             "%.3f" % lrow["ratio_runs"] if "ratio_runs" in lrow else "–"])
    return rows


def write_readings(out, path):
    """The chart's readings beside it (PATH.json, examples/chart_readings.py): the table of
    bench/README.md, the target's line and the machine's load at the start and the end."""
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
    import chart_readings
    cols = ["N", "accuracy", "spam-ark", "LAMMPS", "ratio as run (per repeat)", "interpolated", "CPU", "run loops only"]
    chart_readings.write(str(path), {"table": chart_readings.table(cols, table_rows(out)),
                                     "target": out.get("target", {}), "repeats": out["repeats"],
                                     "target_text": out.get("target", {}).get("line", "") + "\n",
                                     "sizes": [r["n"] for r in out["results"]], "noise": out.get("noise"),
                                     "load_1min_start": out.get("load_1min_start")})


EPS_LO = 1e-4
# Minor ticks of the time axis that get a label (2, 3 and 5 times a power of ten).
MINOR_LABELS = {"%de%+03d" % (m, e) for m in (2, 3, 5) for e in range(-3, 4)}


def ratio_text(rows, cpu_rows, ref, measure):
    """The ratio spam-ark / LAMMPS at each accuracy, from the data (runs as made), in wall
    time and in CPU time, and how far the reference is converged."""
    lines = ["accuracy  spam-ark / LAMMPS, cheapest settings", "          wall   CPU   (spam-ark method)"]
    for r, c in zip(rows, cpu_rows):
        if "ratio_runs" in r:
            lines.append("%7.0e   %.2f   %.2f  (%s)" % (r["eps"], r["ratio_runs"], c.get("ratio_runs", float("nan")),
                                                       r["best_spam_runs"]))
        else:
            lines.append("%7.0e   -  (not reached by both)" % r["eps"])
    lines.append("reference against %s: %.0e" % (ref["check_method"].replace("ARKODE_", "").lower(),
                                                 ref["check_" + measure]))
    return "\n".join(lines)


def merge(paths):
    """One record from the JSON of several runs (say one size each): their results in order of N."""
    outs = [json.loads(Path(p).read_text()) for p in paths]
    out = dict(outs[0])
    out["results"] = sorted((r for o in outs for r in o["results"]), key=lambda r: r["n"])
    out["commit"] = ", ".join(sorted({o.get("commit", "?") for o in outs}))
    if len({o["repeats"] for o in outs}) > 1:
        out["repeats"] = "/".join(str(o["repeats"]) for o in outs)
    return out


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    png = [a for a in args if a.endswith(".png")]
    path = Path(png[0]) if png else Path(__file__).resolve().parent.parent / "docs" / "time_to_accuracy.png"
    draw(merge([a for a in args if not a.endswith(".png")]), path)
    print("chart in %s" % path)


if __name__ == "__main__":
    main()
