#!/usr/bin/python3
"""Chart the lid-driven cavity (scene cavity) against Ghia, Ghia & Shin (1982).

Usage:
    examples/plot_cavity.py DIR [-o OUT.png] [--csv FILE] [--average L/U]

DIR is the output directory of one run, e.g.
    spam-ark -options_file options/cavity.opts -output_dir DIR
with CSV snapshots (-snapshot_csv): the mean profiles of those the manifest lists over the
last --average L/U (default 2: the lid's sound moves one snapshot's extrema by several per
cent) are compared, or FILE (a -final_csv) when given. L (box edge), U (the lid's velocity, wall_yhi_velocity), h, eta,
m and the sound speed (L / sound_traversal_time) come from summary.json; Re = U L m / eta
(rho = m on the unit lattice) picks Ghia's column (100 or 1000, the nearer).

Left: u/U along the vertical centreline x = L/2 against y/L; middle: v/U along the
horizontal centreline y = L/2 against x/L. Grey dots: the particles within half a spacing of
the centreline (their raw velocities); line: the kernel-weighted average of the particles
within h and their wall images (tests/cavity_profile.py); open squares: Ghia's table.
Right: the reading, computed from the data: the regime, the L-infinity errors at Ghia's
points, the extrema against Ghia's, and the change of the kinetic energy over the last L/U
(timeseries.csv). The same reading is printed. Needs matplotlib; re-runs itself with
/usr/bin/python3 when the python3 first on PATH lacks it.
"""
import argparse
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import ghia1982  # noqa: E402
from cavity_profile import compare, read_particles  # noqa: E402
from spamrun import manifest, summary  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402

try:
    import matplotlib  # noqa: E402
except ImportError:  # a python3 without matplotlib first on PATH: Debian's has it
    if os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3") and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("plot_cavity: error: needs matplotlib (Debian: python3-matplotlib)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def snapshots(d, given, average):
    """(paths, t) of the snapshots to compare: the given CSV (at the run's final time), else
    the CSV snapshots the manifest lists from average L/U before the last one to it; t is
    the last one's time."""
    if given:
        return [given], summary(d)["t_final"]
    snaps = [e for e in manifest(d)["files"] if e.get("kind") == "snapshot_csv"]
    if not snaps:
        sys.exit(f"plot_cavity: error: {d} has no CSV snapshot (run with -snapshot_csv, or give --csv)")
    s = summary(d)
    t_last, lu = float(snaps[-1]["t"]), s["box_len"][0] / s["wall_yhi_velocity"][0]
    late = [e for e in snaps if float(e["t"]) >= t_last - average * lu - 1e-9]
    return [os.path.join(d, e["name"]) for e in late], t_last


def ke_change(d, lu):
    """The relative change of the kinetic energy over the last L/U of timeseries.csv."""
    with open(os.path.join(d, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    t = [float(r["t"]) for r in rows]
    ke = [float(r["kinetic"]) for r in rows]
    k = min(range(len(t)), key=lambda i: abs(t[i] - (t[-1] - lu)))
    return abs(ke[-1] - ke[k]) / ke[-1] if ke[-1] > 0 else math.nan


def load(d, given, average):
    s = summary(d)
    if s["scene"] != "cavity":
        sys.exit(f"plot_cavity: error: {d} is a run of -scene {s['scene']}, not cavity")
    L, U, h = s["box_len"][0], s["wall_yhi_velocity"][0], s["h"]
    nu = s["viscosity_shear"] / s["mass"]
    c = L / s["sound_traversal_time"]
    re = U * L / nu
    ghia_re = min(ghia1982.U, key=lambda r: abs(math.log(r / re)))
    paths, t = snapshots(d, given, average)
    snaps = [read_particles(p) for p in paths]
    parts = snaps[-1]
    return dict(L=L, U=U, h=h, nu=nu, c=c, re=re, ghia_re=ghia_re, t=t, parts=parts, n=round(math.sqrt(len(parts))),
                cmp=compare(snaps, L, U, h, ghia_re), dke=ke_change(d, L / U), average=average if not given else 0.0)


def reading(r):
    """The lines of the reading, from the data."""
    m = r["cmp"]
    e, g, rel = m["extrema"], m["ghia_extrema"], m["rel"]
    return [f"Re = U L / nu = {r['re']:.4g}", f"Mach U / c = {r['U'] / r['c']:.3g}", f"c h / nu = {r['c'] * r['h'] / r['nu']:.3g}",
            f"n = {r['n']} (L = {r['L']:g}), h = {r['h']:g}", f"t = {r['t'] * r['U'] / r['L']:.3g} L/U", "",
            f"profiles: mean of {r['cmp']['snapshots']} snapshot(s)", f"  over the last {r['average']:g} L/U", "",
            f"Ghia column: Re = {r['ghia_re']}", "L-inf error at Ghia's points:", f"  u {m['linf_u']:.3f} U, v {m['linf_v']:.3f} U", "",
            "extrema (SPAM, Ghia, error):", f"  min u {e['u_min']:+.3f} {g['u_min']:+.4f} {rel['u_min']:+.0%}",
            f"  max v {e['v_max']:+.3f} {g['v_max']:+.4f} {rel['v_max']:+.0%}", f"  min v {e['v_min']:+.3f} {g['v_min']:+.4f} {rel['v_min']:+.0%}", "",
            "KE change over the last L/U:", f"  {r['dke']:.1%}"]


def near_line(parts, L, U, axis):
    """(position / L, velocity / U) of the particles within half a spacing of a centreline:
    axis 0, u against y on x = L/2; axis 1, v against x on y = L/2."""
    return [(p[1 - axis] / L, p[2 + axis] / U) for p in parts if abs(p[axis] - 0.5 * L) < 0.5]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("-o", "--out", default=None)
    ap.add_argument("--csv", default=None, help="a -final_csv of the run, instead of its CSV snapshots")
    ap.add_argument("--average", type=float, default=2.0, help="average the profiles over the CSV snapshots of the last AVERAGE L/U (default 2; 0: the last one)")
    a = ap.parse_args()
    if not (a.average >= 0.0):
        sys.exit("plot_cavity: error: --average must be >= 0")
    r = load(a.dir, a.csv, a.average)
    m, re = r["cmp"], r["ghia_re"]
    out = a.out or os.path.join(a.dir, "cavity.png")
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(14, 5), gridspec_kw={"width_ratios": [1, 1, 0.6]})
    raw = near_line(r["parts"], r["L"], r["U"], 0)
    ax1.plot([u for _, u in raw], [y for y, _ in raw], ".", color="0.6", ms=4, label="SPAM particles within dx/2")
    ax1.plot(m["u_line"], m["line"], "-", color="C0", lw=1.5, label="SPAM, kernel average")
    ax1.plot(m["u"], ghia1982.U_Y, "o", color="C0", ms=4, label="SPAM at Ghia's points")
    ax1.plot(ghia1982.U[re], ghia1982.U_Y, "s", mfc="none", mec="k", ms=7, label=f"Ghia et al. 1982, Re = {re}")
    ax1.set_xlabel("u / U on x = L/2")
    ax1.set_ylabel("y / L")
    ax1.set_title("u along the vertical centreline")
    raw = near_line(r["parts"], r["L"], r["U"], 1)
    ax2.plot([x for x, _ in raw], [v for _, v in raw], ".", color="0.6", ms=4, label="SPAM particles within dx/2")
    ax2.plot(m["line"], m["v_line"], "-", color="C0", lw=1.5, label="SPAM, kernel average")
    ax2.plot(ghia1982.V_X, m["v"], "o", color="C0", ms=4, label="SPAM at Ghia's points")
    ax2.plot(ghia1982.V_X, ghia1982.V[re], "s", mfc="none", mec="k", ms=7, label=f"Ghia et al. 1982, Re = {re}")
    ax2.set_xlabel("x / L")
    ax2.set_ylabel("v / U on y = L/2")
    ax2.set_title("v along the horizontal centreline")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="lower right" if ax is ax1 else "lower left")
    lines = reading(r)
    ax3.axis("off")
    ax3.text(0.0, 1.0, "\n".join(lines), va="top", ha="left", family="monospace", fontsize=8.5, transform=ax3.transAxes)
    fig.suptitle(f"scene cavity: lid-driven cavity at Re = {r['re']:.4g}, n = {r['n']}, t = {r['t'] * r['U'] / r['L']:.3g} L/U, against Ghia, Ghia & Shin (1982)")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    print("\n".join(lines))
    print(f"png={out}")
    m = r["cmp"]
    chart_readings.write(out, dict(chart_readings.books(a.dir), re=r["re"], n=r["n"], t_over_LU=r["t"] * r["U"] / r["L"],
                                   snapshots=m["snapshots"], linf_u=m["linf_u"], linf_v=m["linf_v"],
                                   extrema=m["extrema"], ghia_extrema=m["ghia_extrema"], rel=m["rel"],
                                   ke_change_last_LU=r["dke"]), runs=[a.dir])


if __name__ == "__main__":
    main()
