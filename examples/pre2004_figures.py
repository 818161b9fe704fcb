#!/usr/bin/python3
"""Regenerates the charts of Hoover, Hoover & Merritt, PRE 69, 016702 (2004) with spam-ark:

  fig1_tensile.png           log KE(t), tensile crystal, sigma0 = 0.01, 0.02 (standard SPAM)
                             and 0.02 with R2 averaging and with Monaghan's viscosity
  fig3_planewaves.png        KE (dashed) and IE (full) of the transverse and longitudinal waves
  fig4_rotor.png             rotor after 120 degrees: MD springs, SPAM summed density,
                             SPAM continuity density
  fig5_rotor_averaging.png   R1 / R2 with continuity and chain-rule densities, 120 and 360 deg
  fig6_angular_momentum.png  L(t)/L0 over one revolution for the variants
  fig7_torque_scaling.png    T_ij and T_i torque scaling with R1 / R2 after 360 degrees

One command (after building):
    /usr/bin/python3 examples/pre2004_figures.py [--spam-ark build/spam-ark] [--out out/pre2004]
Runs take about a minute on two cores; the PNGs go to examples/.
"""
import argparse
import csv
import glob
import sys
import math
import os
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import spam_manifest  # noqa: E402
REV = 160 * math.pi  # one nominal revolution of the n = 8 rotor: 20 n pi


def run(binary, outroot, name, args):
    out = os.path.join(outroot, name)
    # Each figure is made afresh: the run replaces the files of an earlier one.
    cmd = [binary] + [str(a) for a in args] + ["-output_dir", out, "-output_overwrite", "-snapshot_hdf5", "false"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 3):
        raise SystemExit(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr}")
    return out


def series(out):
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def snapshot(out, t):
    """Particle ids, positions and time of the CSV snapshot nearest time t, of those the
    run's manifest lists (rows sorted by particle id)."""
    man = spam_manifest.read(out)
    spam_manifest.check(man, out, "pre2004_figures")
    best, bt = None, None
    for ts, path in spam_manifest.files(man, out, "snapshot_csv"):
        if best is None or abs(ts - t) < abs(bt - t):
            best, bt = path, ts
    d = np.genfromtxt(best, delimiter=",", skip_header=1, names=True)
    order = np.argsort(d["id"])
    return d["id"][order], d["x"][order], d["y"][order], bt


def rotor(binary, outroot, name, extra, t_end=REV):
    return run(binary, outroot, name, ["-options_file", os.path.join(ROOT, "options", "rotor.opts"), "-ts_max_time", t_end,
                                       "-snapshot_interval", REV / 3, "-output_interval", REV / 240] + extra)


def material_row(out):
    """The ids of the material line drawn in every rotor panel: the row of particles through
    the centre at t = 0 (|y - y_cm| below a quarter spacing), ordered by x, and the id of its
    outermost particle on the +x side, the marked one."""
    ids, x, y, _ = snapshot(out, 0.0)
    xc, yc = x - x.mean(), y - y.mean()
    row = np.nonzero(np.abs(yc) < 0.25)[0]
    row = row[np.argsort(xc[row])]
    return ids[row], ids[row[-1]]


def panel(ax, out, t, title):
    """The rotor at the snapshot nearest t about its centre of mass: all particles (grey),
    the material line that lay along +x at t = 0 (blue, through the rotor), its outermost
    particle marked (red star) with an arrow from the centre, and the direction a rigid
    body turning at the nominal rate would point to (dashed): the angle between the two is
    the rotor's lag or lead."""
    row_ids, mark_id = material_row(out)
    ids, x, y, ts = snapshot(out, t)
    xc, yc = x - x.mean(), y - y.mean()
    where = {int(i): k for k, i in enumerate(ids)}
    row = [where[int(i)] for i in row_ids if int(i) in where]
    k = where[int(mark_id)]
    ax.plot(xc, yc, ".", ms=3, color="0.55")
    ax.plot(xc[row], yc[row], "-o", ms=2.5, lw=1, color="tab:blue", label="material line (along +x at t = 0)")
    ax.annotate("", xy=(xc[k], yc[k]), xytext=(0, 0), arrowprops=dict(arrowstyle="->", color="tab:red", lw=1.4))
    ax.plot(xc[k], yc[k], "*", ms=11, color="tab:red", label="marked particle")
    nominal = 2 * math.pi * ts / REV
    r = math.hypot(xc[k], yc[k])
    ax.plot([0, r * math.cos(nominal)], [0, r * math.sin(nominal)], "--", color="k", lw=0.8, label="nominal rigid rotation")
    turned = math.degrees(math.atan2(yc[k], xc[k])) % 360
    ax.set_aspect("equal")
    ax.set_xlim(-12, 12)
    ax.set_ylim(-12, 12)
    ax.set_xlabel("x - x_cm (lattice spacings)", fontsize=7)
    ax.set_ylabel("y - y_cm (lattice spacings)", fontsize=7)
    ax.set_title(f"{title}\nt = {ts:.0f}: marked particle at {turned:.0f} deg (nominal {math.degrees(nominal) % 360:.0f})",
                 fontsize=7)
    ax.tick_params(labelsize=6)
    ax.grid(True, alpha=0.3)


def legend_once(fig, ax):
    """One legend for the figure, from the first panel (the same symbols in every panel)."""
    h, lab = ax.get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=3, fontsize=7)


def fig1(binary, outroot):
    base = ["-options_file", os.path.join(ROOT, "options", "tensile.opts"), "-snapshot_interval", 0]
    cases = [("sigma0 = 0.01", ["-tensile_stress", 0.01]), ("sigma0 = 0.02", ["-tensile_stress", 0.02]),
             ("sigma0 = 0.02, R2", ["-tensile_stress", 0.02, "-coordinates", "R2"]),
             ("sigma0 = 0.02, Monaghan viscosity", ["-tensile_stress", 0.02, "-viscosity", "monaghan"])]
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, (label, extra) in enumerate(cases):
        s = series(run(binary, outroot, f"tensile{i}", base + extra))
        ax.semilogy(s["t"], s["kinetic"], label=label)
    ax.set_xlabel("t (reduced time units)")
    ax.set_ylabel("kinetic energy (reduced units)")
    ax.set_title("Tensile instability (PRE Fig. 1): 576 particles, one kicked with v = 1e-10", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "fig1_tensile.png"), dpi=120)


def fig3(binary, outroot):
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.5))
    for ax, mode in zip(axes, ("transverse", "longitudinal")):
        out = run(binary, outroot, f"planewave_{mode}", ["-options_file", os.path.join(ROOT, "options", "planewave.opts"),
                                                         "-planewave_mode", mode, "-snapshot_interval", 0])
        s = series(out)
        ax.plot(s["t"], s["kinetic"], "--", label="kinetic")
        ax.plot(s["t"], s["internal"], "-", label="internal")
        ax.set_title(f"planewave: {mode} wave, A = 0.25 (PRE Fig. 3)", fontsize=9)
        ax.set_xlabel("t (reduced time units)")
        ax.set_ylabel("energy (reduced units)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "fig3_planewaves.png"), dpi=120)


def fig4(binary, outroot, runs):
    fig, axes = plt.subplots(1, 3, figsize=(10.5, 4.4))
    runs["md"] = run(binary, outroot, "rotor_md", ["-options_file", os.path.join(ROOT, "options", "rotor-md.opts"),
                                                   "-snapshot_interval", REV / 3, "-output_interval", REV / 240])
    runs["summed"] = rotor(binary, outroot, "rotor_summed", ["-density", "summation"], REV / 3)
    runs["R0"] = rotor(binary, outroot, "rotor_R0", [])
    for ax, (key, title) in zip(axes, (("md", "(a) MD springs"), ("summed", "(b) SPAM, summed density"),
                                       ("R0", "(c) SPAM, continuity density"))):
        panel(ax, runs[key], REV / 3, title)
    fig.suptitle("Rotor, 217 particles, after 120 degrees (PRE Fig. 4)", fontsize=9)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    legend_once(fig, axes[0])
    fig.savefig(os.path.join(HERE, "fig4_rotor.png"), dpi=120)


def fig5(binary, outroot, runs):
    fig, axes = plt.subplots(2, 4, figsize=(13, 7.6))
    cols = [("R1", "continuity"), ("R2", "continuity"), ("R1", "chain-rule"), ("R2", "chain-rule")]
    for c, (coords, dens) in enumerate(cols):
        key = f"{coords}-{dens}"
        runs[key] = rotor(binary, outroot, f"rotor_{key}", ["-coordinates", coords, "-density", dens])
        for r, t in enumerate((REV / 3, REV)):
            panel(axes[r][c], runs[key], t, f"{coords}, {dens}")
    fig.suptitle("Rotor, 217 particles, velocity averaging (PRE Fig. 5): 120 degrees (top) and 360 degrees (bottom)",
                 fontsize=9)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    legend_once(fig, axes[0][0])
    fig.savefig(os.path.join(HERE, "fig5_rotor_averaging.png"), dpi=120)


def fig7(binary, outroot, runs):
    fig, axes = plt.subplots(2, 2, figsize=(8, 8.6))
    for r, angm in enumerate(("Tij", "Ti")):
        for c, coords in enumerate(("R1", "R2")):
            key = f"{angm}-{coords}"
            runs[key] = rotor(binary, outroot, f"rotor_{key}", ["-coordinates", coords, "-angmom", angm])
            panel(axes[r][c], runs[key], REV, f"{angm} torque scaling, {coords}")
    fig.suptitle("Rotor, 217 particles, torque scaling after 360 degrees (PRE Fig. 7)", fontsize=9)
    fig.tight_layout(rect=(0, 0.05, 1, 1), h_pad=2.5)
    legend_once(fig, axes[0][0])
    fig.savefig(os.path.join(HERE, "fig7_torque_scaling.png"), dpi=120)


def fig6(runs):
    """L/L0 over one revolution (PRE Fig. 6) and, since several variants keep L to round-off
    and their curves lie on top of each other at 1, log10 |L/L0 - 1| beside it."""
    fig, (ax, axl) = plt.subplots(1, 2, figsize=(11.5, 4.2))
    for k, (key, label) in enumerate((("md", "MD springs"), ("R0", "SPAM R0"), ("R1-continuity", "R1"),
                                      ("R2-continuity", "R2"), ("Tij-R2", "R2 + T_ij"), ("Ti-R2", "R2 + T_i"))):
        s = series(runs[key])
        deg, ratio = s["t"] / REV * 360, s["l_body0"] / s["l_body0"][0]
        sty = dict(color=f"C{k}", linestyle=["-", "--", "-.", ":"][k % 4], lw=1.3)
        ax.plot(deg, ratio, label=label, **sty)
        axl.semilogy(deg[1:], np.maximum(np.abs(ratio[1:] - 1), 1e-17), label=label, **sty)
    ax.set_xlabel("nominal rotation (degrees)")
    ax.set_ylabel("L / L0")
    ax.set_title("Angular momentum of the rotor, 217 particles (PRE Fig. 6)", fontsize=9)
    ax.legend(fontsize=8)
    axl.axhline(2.0 ** -52, color="0.5", lw=0.8)
    axl.text(5, 2.0 ** -52 * 1.5, "double round-off 2^-52", fontsize=7, color="0.4")
    axl.set_xlabel("nominal rotation (degrees)")
    axl.set_ylabel("|L / L0 - 1| (floor 1e-17)")
    axl.set_title("The same, on a log scale: the curves hidden at 1", fontsize=9)
    axl.grid(True, which="both", alpha=0.3)
    axl.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "fig6_angular_momentum.png"), dpi=120)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spam-ark", default=os.path.join(ROOT, "build", "spam-ark"))
    p.add_argument("--out", default=os.path.join(ROOT, "out", "pre2004"))
    a = p.parse_args()
    runs = {}
    fig1(a.spam_ark, a.out)
    fig3(a.spam_ark, a.out)
    fig4(a.spam_ark, a.out, runs)
    fig5(a.spam_ark, a.out, runs)
    fig7(a.spam_ark, a.out, runs)
    fig6(runs)
    print("wrote", ", ".join(sorted(os.path.basename(f) for f in glob.glob(os.path.join(HERE, "fig*.png")))))


if __name__ == "__main__":
    main()
