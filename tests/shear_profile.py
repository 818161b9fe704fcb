"""Shear channels (couette, poiseuille): the exact profiles with their start-up series, and
the SPAM profile binned by lattice row from a run's CSV snapshots."""
import math
import os
from spamrun import manifest

TERMS = 200  # series terms: the first neglected one is below 1e-6 of the steady peak at t = 0


def couette_exact(y, t, U, H, nu):
    """v_x of plane Couette flow started from rest: U y/H minus the decaying sine series
    sum_k 2 U (-1)^(k+1) / (k pi) sin(k pi y/H) exp(-k^2 pi^2 nu t/H^2)."""
    v = U * y / H
    for k in range(1, TERMS + 1):
        decay = math.exp(-(k * math.pi) ** 2 * nu * t / H ** 2)
        if decay < 1e-300:
            break
        v -= 2 * U * (-1) ** (k + 1) / (k * math.pi) * math.sin(k * math.pi * y / H) * decay
    return v


def poiseuille_exact(y, t, g, H, nu):
    """v_x of plane Poiseuille flow started from rest: g/(2 nu) y (H - y) minus the series
    over odd k of 4 g H^2 / (nu k^3 pi^3) sin(k pi y/H) exp(-k^2 pi^2 nu t/H^2)."""
    v = 0.5 * g / nu * y * (H - y)
    for k in range(1, 2 * TERMS, 2):
        decay = math.exp(-(k * math.pi) ** 2 * nu * t / H ** 2)
        if decay < 1e-300:
            break
        v -= 4 * g * H ** 2 / (nu * (k * math.pi) ** 3) * math.sin(k * math.pi * y / H) * decay
    return v


def snapshots(outdir):
    """[(t, rows)] of the CSV snapshots the manifest lists; rows are dicts of floats."""
    out = []
    for e in manifest(outdir)["files"]:
        if e.get("kind") != "snapshot_csv":
            continue
        with open(os.path.join(outdir, e["name"])) as f:
            lines = [ln for ln in f if not ln.startswith("#") and ln.strip()]
        names = lines[0].strip().split(",")
        rows = [dict(zip(names, map(float, ln.split(",")))) for ln in lines[1:]]
        out.append((float(e["t"]), rows))
    return out


def profile(rows, n):
    """Per lattice row j (0 <= y < n binned by floor(y)): mean y, mean v_x and mean summed
    density (or None where the snapshot has no rho_sum). Empty rows are left out."""
    bins = [[] for _ in range(n)]
    for r in rows:
        j = min(n - 1, max(0, int(math.floor(r["y"]))))
        bins[j].append(r)
    prof = []
    for b in bins:
        if not b:
            continue
        rho = [r["rho_sum"] for r in b if "rho_sum" in r]
        prof.append((sum(r["y"] for r in b) / len(b), sum(r["vx"] for r in b) / len(b),
                     sum(rho) / len(rho) if rho else None))
    return prof


def mean_profile(snaps, n, t_from):
    """The row profiles of the snapshots at t >= t_from, averaged over those snapshots."""
    profs = [profile(rows, n) for t, rows in snaps if t >= t_from - 1e-9]
    return [tuple(sum(p[k][c] for p in profs) / len(profs) for c in range(3)) for k in range(len(profs[0]))]


def row_pairs(prof):
    """Rows 2k and 2k+1 averaged: the lattice's Nyquist mode (v alternating row by row)
    cancels."""
    return [((prof[k][0] + prof[k + 1][0]) / 2, (prof[k][1] + prof[k + 1][1]) / 2, None)
            for k in range(0, len(prof) - 1, 2)]


def window_mean(ts, column, t_from):
    """Mean of a timeseries column over the rows at t >= t_from."""
    v = [x for t, x in zip(ts["t"], ts[column]) if t >= t_from - 1e-9]
    return sum(v) / len(v)


def errors(prof, exact, peak):
    """L2 (root mean square over rows) and max error of the binned v_x against exact(y),
    both relative to the peak speed."""
    d = [v - exact(y) for y, v, _ in prof]
    return math.sqrt(sum(x * x for x in d) / len(d)) / abs(peak), max(abs(x) for x in d) / abs(peak)


def order(ns, errs):
    """Least-squares slope p of log(err) against log(1/n): err ~ n^-p."""
    xs = [math.log(n) for n in ns]
    ys = [math.log(e) for e in errs]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return -sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
