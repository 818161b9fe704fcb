#!/usr/bin/python3
"""Chart a spam-ark Gresho-vortex run (-scene gresho).

Usage:
    examples/plot_gresho.py DIR [-o OUT.png]

DIR is the output directory of
    spam-ark -options_file options/gresho.opts -output_dir DIR
(CSV snapshots at t = 0 and at the end; the files are those manifest.json lists). The
figure (default DIR/gresho.png) has
  * left:  v_phi against r / L at t = 0 and at the last snapshot: every particle as a dot,
           the means in bins of 0.02 L as markers, the exact steady profile as a line;
  * right: the particles at the last snapshot coloured by v_phi.
One line goes to stdout: t/L, the L1 error of the binned profile, its peak and the png.
The box follows from -gresho_n of the run's options, as scene_gresho.c builds it.
"""
import argparse
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402

BINS = 25


def exact(r):
    """The standard profile v_phi(r), r in units of L."""
    return np.where(r < 0.2, 5 * r, np.where(r < 0.4, 2 - 5 * r, 0.0))


def geometry(options):
    """(L, centre) of the box scene_gresho.c builds for -gresho_n (default 32)."""
    m = re.search(r"-gresho_n (\d+)", options)
    n = int(m.group(1)) if m else 32
    a = math.sqrt(2 / math.sqrt(3))
    ny = max(2, 2 * int(math.floor(n / math.sqrt(3) + 0.5)))
    return n * a, (0.5 * n * a, 0.5 * ny * a * math.sqrt(3) / 2)


def snapshot(path):
    with open(path) as f:
        lines = [line for line in f if not line.startswith("#")]
    head = lines[0].strip().split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:] if line.strip()])
    return {k: data[:, head.index(k)] for k in ("x", "y", "vx", "vy")}


def profile(s, L, centre):
    """r / L and v_phi of every particle; bin centres, bin means and the L1 error."""
    dx, dy = s["x"] - centre[0], s["y"] - centre[1]
    r = np.hypot(dx, dy)
    vphi = (dx * s["vy"] - dy * s["vx"]) / np.maximum(r, 1e-300)
    rl = r / L
    idx = np.floor(rl / (0.5 / BINS)).astype(int)
    rc, mean, err = [], [], []
    for b in range(BINS):
        sel = idx == b
        if sel.any():
            rc.append(rl[sel].mean())
            mean.append(vphi[sel].mean())
            err.append(abs(vphi[sel].mean() - exact(rl[sel]).mean()))
    return rl, vphi, np.array(rc), np.array(mean), float(np.mean(err))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("dir")
    p.add_argument("-o", "--out")
    a = p.parse_args()
    man, _ = spam_manifest.open_run(a.dir, "plot_gresho.py")
    snaps = spam_manifest.files(man, a.dir, "snapshot_csv")
    if len(snaps) < 2:
        sys.exit(f"plot_gresho.py: {a.dir}: need CSV snapshots at t = 0 and later (-snapshot_csv, -snapshot_interval)")
    L, centre = geometry(man.get("options", ""))
    (t0, p0), (t1, p1) = snaps[0], snaps[-1]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5.2))
    rr = np.linspace(0, 0.5, 501)
    for (t, path), colour, marker in (((t0, p0), "tab:blue", "o"), ((t1, p1), "tab:red", "s")):
        rl, vphi, rc, mean, l1 = profile(snapshot(path), L, centre)
        ax.plot(rl, vphi, ".", ms=1.5, color=colour, alpha=0.35)
        ax.plot(rc, mean, marker, color=colour, ms=5, label=f"SPAM, t = {t / L:.2f} L: bin means (L1 = {l1:.4f})")
    ax.plot(rr, exact(rr), "k-", lw=1.5, label="exact steady profile")
    ax.set_xlim(0, 0.5)
    ax.set_xlabel("r / L")
    ax.set_ylabel("azimuthal velocity v_phi (reduced units)")
    ax.set_title("Gresho vortex: v_phi(r), particles as dots")
    ax.legend(fontsize=8, loc="upper right")
    s = snapshot(p1)
    rl, vphi, rc, mean, l1 = profile(s, L, centre)
    sc = bx.scatter(s["x"] / L, s["y"] / L, c=vphi, s=4, cmap="viridis", vmin=-0.1, vmax=1.1)
    bx.set_aspect("equal")
    bx.set_xlabel("x / L")
    bx.set_ylabel("y / L")
    bx.set_title(f"Gresho vortex: particles at t = {t1 / L:.2f} L coloured by v_phi")
    fig.colorbar(sc, ax=bx, label="v_phi (reduced units)")
    out = a.out or os.path.join(a.dir, "gresho.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"t/L={t1 / L:.4f} L1_binned={l1:.5f} peak_binned={mean.max():.4f} png={out}")
    chart_readings.write(out, dict(chart_readings.books(a.dir), t_over_L=t1 / L, l1_binned=l1,
                                   peak_binned=float(mean.max())), runs=[a.dir])


if __name__ == "__main__":
    main()
