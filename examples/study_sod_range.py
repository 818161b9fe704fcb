#!/usr/bin/python3
"""Sod's shock tube against the kernel's range h: the errors of tests/run_sod.py's measures.

    examples/study_sod_range.py [--h 3 --h 4 ...] [--sod-n 400] [--spam-ark build/spam-ark] [--out out/sod_range]
                                [--chart OUT.png]

Runs options/sod.opts (1D) at each h (lattice spacings) into OUT/hH/, measures each run's
last snapshot as tests/run_sod.py does (plateaus u*, p*, rho*L, rho*R leaving 2h at each end
of the star regions; shock and contact where rho crosses the mean of its two sides; the fan
ends from a straight-line fit of u over the fan's middle half) and draws OUT/sod_range.png:
the plateaus' relative errors and the fronts' offsets (in h) against h. OUT/sod_range.json
(examples/chart_readings.py) holds the table the page quotes.
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(REPO, "tests"))
try:
    import numpy as np  # noqa: F401
    import matplotlib
except ImportError:
    if os.path.realpath(sys.executable) != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("study_sod_range.py needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import chart_readings  # noqa: E402
import spam_manifest  # noqa: E402
from run_sod import measure, profile  # noqa: E402

PLATEAUS = [("rho*L", "ρ*L"), ("rho*R", "ρ*R"), ("u*", "u*"), ("p*", "p*")]
FRONTS = ["fan head", "fan tail", "shock", "contact"]


def run(a, h):
    d = os.path.join(a.out, f"h{h:g}")
    args = [a.spam_ark, "-options_file", os.path.join(REPO, "options", "sod.opts"), "-sod_n", str(a.sod_n),
            "-h", f"{h:g}", "-snapshot_interval", f"{0.2 * a.sod_n:g}", "-snapshot_hdf5", "0",
            "-output_dir", d, "-output_overwrite", "-quiet"]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"study_sod_range: spam-ark -h {h:g} exits {p.returncode}: {p.stderr.strip()[-300:]}")
    snap = spam_manifest.files(spam_manifest.read(d), d, "snapshot_csv")[-1][1]
    t, x, rho, u, pr = profile(snap, a.sod_n)
    plateaus, fronts = measure(t, x, rho, u, pr, h / a.sod_n)
    row = {k: got / want - 1.0 for k, (got, want) in plateaus.items()}
    for k, (got, want) in fronts.items():
        row[k] = (got[0] - want) / (h / a.sod_n) if len(got) == 1 else float("nan")
    return d, row


def pct(v):
    return f"{v:+.2%}".replace("-", "−")


def off(v):
    return f"{v:+.2f} h".replace("-", "−")


def chart(hs, rows, path, n):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
    markers = "osD^v<>"
    for k, (key, label) in enumerate(PLATEAUS):
        ax1.plot(hs, [100 * r[key] for r in rows], marker=markers[k], color=f"C{k}", label=label)
    for k, key in enumerate(FRONTS):
        ax2.plot(hs, [r[key] for r in rows], marker=markers[k], color=f"C{k + 4}", label=key)
    ax1.axhspan(-3, 3, color="0.9", zorder=0, label="test's bound (3%)")
    ax2.axhspan(-1, 1, color="0.9", zorder=0, label="test's bound (1 h)")
    ax1.set_ylabel("plateau error (measured / exact − 1), %")
    ax2.set_ylabel("front offset from exact, in units of h")
    for ax in (ax1, ax2):
        ax.set_xlabel("kernel range h (lattice spacings)")
        ax.axhline(0, color="k", lw=0.6)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax1.set_title(f"Scene sod, 1D, n = {n}: star states against h")
    ax2.set_title(f"Scene sod, 1D, n = {n}: fronts against h")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--h", type=float, action="append")
    ap.add_argument("--sod-n", type=int, default=400)
    ap.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    ap.add_argument("--out", default="out/sod_range")
    ap.add_argument("--chart", help="PNG path (default OUT/sod_range.png; the readings go beside it)")
    a = ap.parse_args()
    hs = a.h or [3, 4, 5, 6, 7, 8, 10]
    dirs, rows = [], []
    for h in hs:
        d, r = run(a, h)
        dirs.append(d)
        rows.append(r)
        print(f"h={h:g} " + " ".join(f"{k}={v:+.4f}" for k, v in r.items()), flush=True)
    png = a.chart or os.path.join(a.out, "sod_range.png")
    chart(hs, rows, png, a.sod_n)
    cells = [[f"{h:g}"] + [pct(r[k]) for k, _ in PLATEAUS] + [off(r[k]) for k in FRONTS] for h, r in zip(hs, rows)]
    readings = {"sod_n": a.sod_n,
                "table": chart_readings.table(["h"] + [lab for _, lab in PLATEAUS] + FRONTS, cells),
                "rows": {f"h{h:g}": {k.replace("*", "_star_").replace(" ", "_").strip("_"): v for k, v in r.items()}
                         for h, r in zip(hs, rows)}}
    chart_readings.write(png, readings, runs=dirs)
    print(f"png={png}")


if __name__ == "__main__":
    main()
