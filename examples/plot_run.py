#!/usr/bin/python3
"""One chart for any spam-ark run: energies, conservation, step sizes and the last particles.

    examples/plot_run.py RUN_DIR [-o OUT.png]        # default RUN_DIR/run.png

Works on the output directory of every scene (its own particles from -scene file included):
it reads what every run writes (manifest.json, summary.json, timeseries.csv, steps.csv and
the CSV particle snapshots) through examples/spamread.py. Four panels:
  1. kinetic, internal, potential (gravity) and total energy against time;
  2. conservation: |E - E0|, |P - P0| and |L - L0| against time, each over the scale
     summary.json names (energy_scale, momentum_scale, angular_momentum_scale); with
     mirror walls, the balances less the walls' work, heat and impulse;
  3. every accepted step's size against time, coloured by what set it (accuracy, the CFL
     or force bound, an output or the end), with the rejected steps marked;
  4. the last snapshot's particles: positions coloured by speed (1D: velocity against x;
     3D: the x-y projection).
All quantities are in the run's reduced units (docs/outputs.md, "Units").
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import spamread  # noqa: E402

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LIMIT_COLOURS = {"accuracy": "#1f77b4", "cfl": "#ff7f0e", "force": "#2ca02c",
                 "output": "#9467bd", "end": "#d62728", "fixed": "#7f7f7f"}


def finite(a):
    return a[np.isfinite(a)]


def energies(ax, ts):
    t = ts["t"]
    for name, label in (("kinetic", "kinetic"), ("internal", "internal"),
                        ("potential", "potential (gravity)"), ("total", "total")):
        y = ts.get(name)
        if y is None or not np.isfinite(y).any() or (name == "potential" and not np.any(y)):
            continue
        ax.plot(t, y, "-k" if name == "total" else "-", lw=2 if name == "total" else 1.3, label=label)
    ax.set_xlabel("time t (reduced units)")
    ax.set_ylabel("energy (reduced units)")
    ax.set_title("Energies")
    ax.legend(fontsize=8)


def conservation(ax, ts, s):
    """Deviation from t = 0 over the summary's scale. With mirror walls the walls' integrated
    work, heat and impulse (timeseries columns wall_*) are what the fluid's energy and momentum
    may change by, so the balances E - E0 - work - heat and P - P0 - impulse are drawn, and
    angular momentum, which the walls' torque changes unbooked, is left out."""
    t = ts["t"]
    walls = "wall_work" in ts
    dim = int(s.get("dim", 2))
    drawn = 0
    for name, cols, scale_key, booked in (
            ("energy", ("total",), "energy_scale", ("wall_work", "wall_heat")),
            ("momentum", ("px", "py", "pz")[:dim], "momentum_scale", ("wall_impulse_x", "wall_impulse_y", "wall_impulse_z")[:dim]),
            ("angular momentum", ("lx", "ly", "lz"), "angular_momentum_scale", None)):
        scale = s.get(scale_key)
        if not scale or not all(c in ts for c in cols) or (walls and booked is None):
            continue
        v = np.stack([ts[c] for c in cols], axis=1)
        if walls:
            if not all(b in ts for b in booked):
                continue
            w = np.stack([ts[b] for b in booked], axis=1)
            v = v - (w.sum(axis=1, keepdims=True) if name == "energy" else w)
        if not np.isfinite(v).all():
            continue
        dev = np.linalg.norm(v - v[0], axis=1) / scale
        label = "%s%s / %s" % (name, " - walls' " + ("work - heat" if name == "energy" else "impulse") if walls else "",
                               scale_key)
        if name == "angular momentum" and s.get("angular_momentum_not_conserved"):
            label += " (%s)" % s["angular_momentum_not_conserved"]  # a change, not a drift
        ax.semilogy(t, np.maximum(dev, np.finfo(float).eps), "-", label=label)
        drawn += 1
    ax.set_xlabel("time t (reduced units)")
    ax.set_ylabel("|X(t) - X(0)| / scale (relative)")
    ax.set_title("Conservation%s (floor: machine epsilon)" % (", walls booked" if walls else ""))
    if drawn:
        ax.legend(fontsize=8)


def rhs_count(s, st):
    """Every RHS evaluation of the run, the integrator's and the interpolant's (dense outputs)
    apart, from summary.json; steps.csv's count (the integrator's) while the run has no
    summary yet."""
    if "rhs_evals_total" in s:
        return "%d (integrator %d + interpolation %d)" % (s["rhs_evals_total"], s.get("rhs_evals", 0),
                                                         s.get("interpolation_rhs_evals", 0))
    return "%d (integrator; no summary.json yet)" % int(st["rhs_evals"][-1])


def step_sizes(ax, run):
    try:
        st = run.steps()
    except OSError:
        ax.text(0.5, 0.5, "no steps.csv", ha="center", transform=ax.transAxes)
        return
    if len(st.get("t", [])) == 0:
        ax.text(0.5, 0.5, "no steps taken", ha="center", transform=ax.transAxes)
        return
    limits = st["limit"] if "limit" in st else np.array(["?"] * len(st["t"]))
    for lim in sorted(set(limits.tolist())):
        k = limits == lim
        ax.semilogy(st["t"][k], st["dt"][k], ".", ms=4, color=LIMIT_COLOURS.get(lim),
                    label="set by %s (%d)" % (lim, int(k.sum())))
    rej = np.diff(np.concatenate([[0], st["rejected"]])) > 0
    if rej.any():
        ax.semilogy(st["t"][rej], st["dt"][rej], "x", color="red", ms=7,
                    label="after a rejection (%d)" % int(rej.sum()))
    ax.set_xlabel("time t (reduced units)")
    ax.set_ylabel("step size dt (reduced time)")
    ax.set_title("Accepted steps: %d, RHS evaluations %s" % (len(st["t"]), rhs_count(run.summary, st)))
    ax.legend(fontsize=8)


def particles(ax, run, dim):
    snaps = run.snapshots()
    if not snaps:
        ax.text(0.5, 0.5, "no particle snapshots\n(-snapshot_interval 0 or -snapshot_csv 0)",
                ha="center", transform=ax.transAxes)
        return
    t, p = snaps[-1]
    vel = [p[c] for c in ("vx", "vy", "vz") if c in p]
    speed = np.linalg.norm(np.stack(vel), axis=0) if vel else np.zeros(len(p["x"]))
    if dim == 1:
        ax.plot(p["x"], p.get("vx", speed), ".", ms=2)
        ax.set_xlabel("x (reduced length)")
        ax.set_ylabel("velocity vx (reduced units)")
    else:
        sc = ax.scatter(p["x"], p["y"], c=speed, s=max(0.3, min(12.0, 4000.0 / len(speed))), cmap="viridis",
                        linewidths=0)
        plt.colorbar(sc, ax=ax, label="speed |v| (reduced units)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (reduced length)")
        ax.set_ylabel("y (reduced length)" + (" (x-y projection)" if dim == 3 else ""))
    ax.set_title("Particles at t = %g (%d)" % (t if t is not None else float("nan"), len(speed)))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("-o", "--out", help="PNG to write (default RUN_DIR/run.png)")
    a = ap.parse_args(argv[1:])
    try:
        run = spamread.Run(a.run_dir)
        ts = run.timeseries()
    except (spamread.RunError, OSError) as exc:
        sys.stderr.write("plot_run.py: error: %s\n" % exc)
        return 2
    if run.status not in ("ok", "max_steps"):
        sys.stderr.write("plot_run.py: warning: %s: the run's status is %r; drawn as it is\n"
                         % (a.run_dir, run.status))
    s = run.summary
    dim = int(s.get("dim", 2))
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    energies(axes[0, 0], ts)
    conservation(axes[0, 1], ts, s)
    step_sizes(axes[1, 0], run)
    particles(axes[1, 1], run, dim)
    fig.suptitle("spam-ark, scene %s: %sD, %s particles, %s, kernel %s (h = %s), %s %s" % (
        s.get("scene"), dim, s.get("n_particles"), s.get("model"), s.get("kernel"), s.get("h"),
        s.get("method"), "rtol %g" % s["rtol"] if s.get("fixed_step", 0) == 0 and "rtol" in s else ""))
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    out = a.out or os.path.join(a.run_dir, "run.png")
    fig.savefig(out, dpi=110)
    print("wrote %s" % out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
