#!/usr/bin/python3
"""Chart the shear-channel scenes (couette, poiseuille).

Usage:
    examples/plot_shear.py DIR [DIR ...] [-o OUT.png]

Each DIR is the output directory of one run of the same scene at one resolution, e.g.
    spam-ark -options_file options/couette.opts -couette_n N -output_dir DIR
with CSV snapshots (-snapshot_csv); the files are those manifest.json lists. The run's
scene, H (box edge y), eta, rho (mean summed density), U (couette: the upper wall's
velocity) and g (poiseuille: gravity_x) come from summary.json and the snapshots.

Left panel: v_x against y of the run with the largest H at several snapshot times, SPAM
rows (points) against the exact start-up series (lines) and the steady profile (dashed).
Right panel: the error of the row profile averaged over t in [H^2/nu, 1.5 H^2/nu] against
H/dx (log-log), rows and row pairs (the lattice's Nyquist mode cancels), with the fitted
slope of each. Prints one line per run: H, L2 and max error. Beside the chart, OUT.json
(examples/chart_readings.py) holds per run the errors, the walls' forces on the gas
(timeseries.csv wall_ylo_fx and wall_yhi_fx averaged over the same window) against the
exact one, the heating and the books' drifts, and the fitted orders. Needs matplotlib;
re-runs itself with /usr/bin/python3 when the python3 first on PATH lacks it.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chart_readings  # noqa: E402
from shear_profile import (couette_exact, errors, mean_profile, order, poiseuille_exact,  # noqa: E402
                           profile, row_pairs, snapshots, window_mean)
from spamrun import summary, table  # noqa: E402

try:
    import matplotlib  # noqa: E402
except ImportError:  # a python3 without matplotlib first on PATH: Debian's has it
    if os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3") and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("plot_shear: error: needs matplotlib (Debian: python3-matplotlib)")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(d):
    s = summary(d)
    n = int(round(s["box_len"][1]))
    snaps = snapshots(d)
    prof0 = profile(snaps[0][1], n)
    rho = sum(r for _, _, r in prof0) / len(prof0)
    nu = s["viscosity_shear"] / rho
    if s["scene"] == "couette":
        U = s["wall_yhi_velocity"][0]
        exact = lambda y, t: couette_exact(y, t, U, n, nu)
        peak = U
    elif s["scene"] == "poiseuille":
        g = s["gravity_x"]
        exact = lambda y, t: poiseuille_exact(y, t, g, n, nu)
        peak = g * n * n / (8 * nu)
    else:
        sys.exit(f"plot_shear: error: {d} is a run of -scene {s['scene']}, not couette or poiseuille")
    return dict(scene=s["scene"], n=n, nu=nu, snaps=snaps, exact=exact, peak=peak, dir=d, summary=s)


def row_heating(r):
    """The rise of the mean e over the run (last snapshot against the first), relative to
    the start's mean e: over all rows, in the two wall rows and in the two middle rows (the
    viscous heating is largest where the shear is)."""
    n, (_, first), (_, last) = r["n"], r["snaps"][0], r["snaps"][-1]
    if "e" not in first[0]:
        return None, None, None
    e0 = sum(p["e"] for p in first) / len(first)

    def rise(rows_j):
        sel = [p["e"] for p in last if rows_j is None or min(n - 1, max(0, int(math.floor(p["y"])))) in rows_j]
        return sum(sel) / len(sel) / e0 - 1
    return rise(None), rise({0, n - 1}), rise({n // 2 - 1, n // 2})


def run_readings(r, l2, mx, l2p):
    """What the page quotes of one run: errors (of the peak), the walls' forces averaged over
    the error's window against the exact force on the gas, heating and the books."""
    s, n = r["summary"], r["n"]
    ts = table(os.path.join(r["dir"], "timeseries.csv"))
    D = n * n / r["nu"]
    flo, fhi = window_mean(ts, "wall_ylo_fx", D), window_mean(ts, "wall_yhi_fx", D)
    L = s["box_len"][0] * (s["box_len"][2] or 1)
    if r["scene"] == "couette":
        exact = s["viscosity_shear"] * s["wall_yhi_velocity"][0] * L / n  # each wall, eta U A / H
    else:
        exact = -s["gravity_x"] * s["mass"] * s["n_particles"]         # both walls, -g M
    if r["scene"] == "couette":  # each wall against eta U A / H, the lower one pulling back
        force_err = max(abs(-flo / exact - 1), abs(fhi / exact - 1))
    else:
        force_err = abs((flo + fhi) / exact - 1)
    return {"H": n, "h_over_H": s["h"] / n, "wall_force_rel_err": force_err, "nyquist_over_l2_rows": 1 / (2 * n) / l2, "l2_rows": l2, "max_rows": mx, "l2_row_pairs": l2p,
            "nyquist": 1 / (2 * n), "l2_over_h_over_H_sq": l2 / (s["h"] / n) ** 2,
            "wall_ylo_fx": flo, "wall_yhi_fx": fhi, "wall_sum_fx": flo + fhi, "exact_force": exact,
            "heating": row_heating(r)[0], "heating_wall_rows": row_heating(r)[1], "heating_middle_rows": row_heating(r)[2],
            "momentum_rel_drift_max": s["momentum_rel_drift_max"], "energy_rel_drift_max": s["energy_rel_drift_max"],
            "steps": s["steps"], "rhs_evals": s["rhs_evals"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("-o", "--out", default=None)
    a = ap.parse_args()
    runs = sorted((load(d) for d in a.dirs), key=lambda r: r["n"])
    scene = runs[0]["scene"]
    out = a.out or os.path.join(a.dirs[-1], f"{scene}.png")
    # The error-against-resolution panel needs two resolutions at least: with one run it
    # would be a single point, which says nothing; the profiles are drawn alone then.
    if len(runs) > 1:
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    else:
        fig, ax1 = plt.subplots(1, 1, figsize=(6, 4.5))
        ax2 = None
    big = runs[-1]
    D = big["n"] ** 2 / big["nu"]
    # the snapshots nearest to these fractions of the diffusion time (rho is not exactly 1)
    chosen = sorted({min(range(len(big["snaps"])), key=lambda k: abs(big["snaps"][k][0] - f * D))
                     for f in (0.0625, 0.125, 0.25, 0.5, 1.5)})
    chosen = [big["snaps"][k] for k in chosen]
    colours = plt.cm.viridis([k / max(1, len(chosen) - 1) for k in range(len(chosen))])
    yy = [big["n"] * k / 200 for k in range(201)]
    for (t, rows), col in zip(chosen, colours):
        p = profile(rows, big["n"])
        ax1.plot([v / big["peak"] for _, v, _ in p], [y / big["n"] for y, _, _ in p], "o", ms=3.5, color=col,
                 label=f"SPAM t = {t / D:.3g} H²/ν")
        ax1.plot([big["exact"](y, t) / big["peak"] for y in yy], [y / big["n"] for y in yy], "-", color=col, lw=1)
    ax1.plot([big["exact"](y, 1e6 * D) / big["peak"] for y in yy], [y / big["n"] for y in yy], "k--", lw=1, label="exact steady")
    ax1.set_xlabel("v_x / " + ("U" if scene == "couette" else "peak speed g H²/(8ν)"))
    ax1.set_ylabel("y / H")
    ax1.set_title(f"{scene}: profiles, H/dx = {big['n']} (lines: exact series)")
    ax1.legend(fontsize=7)
    ns, e_rows, e_pairs, per_run = [], [], [], {}
    for r in runs:
        Dr = r["n"] ** 2 / r["nu"]
        prof = mean_profile(r["snaps"], r["n"], Dr)
        ex = lambda y: r["exact"](y, 1.25 * Dr)
        l2, mx = errors(prof, ex, r["peak"])
        l2p, _ = errors(row_pairs(prof), ex, r["peak"])
        ns.append(r["n"])
        e_rows.append(l2)
        e_pairs.append(l2p)
        per_run[f"n{r['n']}"] = run_readings(r, l2, mx, l2p)
        print(f"{scene} H/dx = {r['n']}: L2 {l2:.3e} max {mx:.3e} (rows), L2 {l2p:.3e} (row pairs), of the peak")
    if ax2 is not None:
        error_panel(ax2, scene, ns, e_rows, e_pairs)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"png={out}")
    readings = {"scene": scene, "runs": per_run, "range": {
        k: [min(v[k] for v in per_run.values()), max(v[k] for v in per_run.values())]
        for k in ("heating", "momentum_rel_drift_max", "wall_force_rel_err", "nyquist_over_l2_rows")}}
    if len(ns) > 1:
        readings["order_rows"], readings["order_row_pairs"] = order(ns, e_rows), order(ns, e_pairs)
        readings["order_rows_steps"] = [order(ns[k:k + 2], e_rows[k:k + 2]) for k in range(len(ns) - 1)]
        readings["ratio_rows_steps"] = [e_rows[k] / e_rows[k + 1] for k in range(len(ns) - 1)]
    chart_readings.write(out, readings, runs=[r["dir"] for r in runs])


def error_panel(ax2, scene, ns, e_rows, e_pairs):
    ax2.loglog(ns, e_rows, "o-", color="C0", label=f"rows (slope {-order(ns, e_rows):.2f})")
    ax2.loglog(ns, e_pairs, "s-", color="C1", label=f"row pairs (slope {-order(ns, e_pairs):.2f})")
    ax2.set_xlabel("H / dx (h/dx fixed)")
    ax2.set_ylabel("L2 error of v_x / peak, t in [1, 1.5] H²/ν")
    ax2.set_title(f"{scene}: error against resolution")
    ax2.legend(fontsize=8)
    ax2.grid(True, which="both", alpha=0.3)


if __name__ == "__main__":
    main()
