#!/usr/bin/python3
"""Strong and weak scaling of spam-ark on this machine's two cores: 1 rank x 1 thread,
1 rank x 2 threads (-threads 2) and 2 ranks x 1 thread (mpiexec -n 2), the layouts
alternating within each repeat, so that a slow spell of the shared machine hits all three.

  /usr/bin/python3 bench/run_scaling.py [--repeats 3] [--cases strong-2d,strong-3d,weak-2d,weak-3d]
                                        [--steps-2d 20] [--steps-3d 8] [--quick]
                                        [--out bench/results/scaling] [--png docs/scaling.png]

Each run is the expansion scene (isentrope, gamma 1 + 2/D, Lucy's kernel, h = 3) with
Dormand-Prince at a fixed step of 0.05 and no outputs; the time per RHS evaluation is
rhs_time_s / rhs_evals of its summary.json (rank 0's on two ranks: every rank waits for
the others at the halo exchanges inside the RHS), the time per step is wall_time_s / steps;
"halo max" is summary.json's halo_ghosts_max_final (remote ghosts of the fullest rank).
Strong scaling: the same N on every layout, speed-up = T(1x1) / T(layout). Weak scaling: N
on one core and about 2N on two (the lattices are n^D, so the ratio is printed), efficiency
= [T(1x1, N1) / N1] / [T(layout, N2) / N2] / cores (1 is perfect). Ratios are of medians measured in
this run. The final kinetic energies of the layouts are printed beside, as a check that the
runs integrate the same gas (they differ in the last bits: the order of the pair sums).
Writes OUT.json, OUT.csv and the chart; exit code 1 if a run failed (drawn as a red X).
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from scaling_style import LAYOUT_STYLE, FAILED_STYLE  # noqa: E402

LAYOUTS = {"1x1": (1, 1), "1x2": (1, 2), "2x1": (2, 1)}  # ranks, threads
# case: dim, kind, lattice n per edge on one core, on two cores (weak: ~2x the particles)
CASES = {
    "strong-2d": (2, "strong", 512, 512),   # 262144 particles
    "strong-3d": (3, "strong", 46, 46),     # 97336
    "weak-2d": (2, "weak", 362, 512),       # 131044 per core
    "weak-3d": (3, "weak", 37, 46),         # 50653 per core; 97336 on two
}


def env():
    e = dict(os.environ)
    e.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_pml="ob1",
             OMP_NUM_THREADS="1")
    return e


def command(spam, layout, dim, n, steps, outdir):
    ranks, threads = LAYOUTS[layout]
    cmd = [spam, "-scene", "expansion", "-dim", str(dim), "-expansion_n", str(n), "-h", "3",
           "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5", "-arkode_fixed_step", "0.05",
           "-ts_max_steps", str(steps), "-ts_max_time", "%g" % ((steps + 0.5) * 0.05),
           "-snapshot_interval", "0", "-output_interval", "0", "-diag_entropy", "0",
           "-threads", str(threads), "-output_dir", outdir]
    if ranks > 1:
        cmd = ["mpiexec", "--oversubscribe", "-n", str(ranks)] + cmd
    return cmd


def one_run(spam, layout, dim, n, steps):
    with tempfile.TemporaryDirectory(prefix="spam_scaling_") as d:
        out = os.path.join(d, "o")
        cmd = command(spam, layout, dim, n, steps, out)
        t0 = time.monotonic()
        p = subprocess.run(cmd, capture_output=True, text=True, env=env())
        wall = time.monotonic() - t0
        run = {"layout": layout, "dim": dim, "n_edge": n, "N": n ** dim, "steps": steps, "rc": p.returncode,
               "process_s": wall, "command": " ".join(cmd[:-2] + ["-output_dir", "DIR"])}
        summ = os.path.join(out, "summary.json")
        if p.returncode != 0 or not os.path.isfile(summ):
            run["status"] = "failed"
            run["error"] = (p.stderr or p.stdout).strip().splitlines()[-1:] if (p.stderr or p.stdout) else ["exit %d" % p.returncode]
            return run
        s = json.load(open(summ))
        run.update(status=s["status"], rhs_evals=s["rhs_evals"], rhs_time_s=s["rhs_time_s"], wall_time_s=s["wall_time_s"],
                   run_steps=s["steps"], kinetic_final=s["kinetic_final"], ns_per_pair=s["ns_per_pair"],
                   ranks=s.get("ranks", 1), migrations=s.get("migrations", 0), halo_max=s.get("halo_ghosts_max_final", 0))
        if s["status"] != "max_steps":
            run["status"] = "failed"
            run["error"] = [s.get("reason", s["status"])]
            return run
        run["ms_per_rhs"] = 1e3 * s["rhs_time_s"] / s["rhs_evals"]
        run["ms_per_step"] = 1e3 * s["wall_time_s"] / max(1, s["steps"])
        return run


def median_of(runs, key):
    v = [r[key] for r in runs if r["status"] == "max_steps"]
    return statistics.median(v) if v else None


def summarise(case, runs):
    dim, kind, n1, n2 = CASES[case]
    res = {"case": case, "dim": dim, "kind": kind, "layouts": {}}
    for lay in LAYOUTS:
        rs = [r for r in runs if r["layout"] == lay]
        if not rs:
            continue
        res["layouts"][lay] = {"N": rs[0]["N"], "runs": len(rs), "failed": sum(r["status"] != "max_steps" for r in rs),
                               "ms_per_rhs": median_of(rs, "ms_per_rhs"), "ms_per_step": median_of(rs, "ms_per_step"),
                               "ms_per_rhs_all": [r.get("ms_per_rhs") for r in rs],
                               "kinetic_final": median_of(rs, "kinetic_final"), "ns_per_pair": median_of(rs, "ns_per_pair"),
                               "halo_max": median_of(rs, "halo_max"), "migrations": median_of(rs, "migrations")}
    base = res["layouts"].get("1x1", {"ms_per_rhs": None, "ms_per_step": None})
    for lay, v in res["layouts"].items():
        for t in ("ms_per_rhs", "ms_per_step"):
            key = ("speedup_" if kind == "strong" else "weak_efficiency_") + t.replace("ms_per_", "")
            if v[t] is None or base[t] is None:
                v[key] = None
            elif kind == "strong":
                v[key] = base[t] / v[t]
            else:  # per core: a layout on c cores is perfect when each core does what one did
                cores = int(lay.split("x")[0]) * int(lay.split("x")[1])
                v[key] = (base[t] / base["N"]) / (v[t] / v["N"]) / cores
    return res


def print_case(res):
    kind = res["kind"]
    ratio = "speed-up" if kind == "strong" else "weak efficiency"
    print("%s (%dD, %s scaling):" % (res["case"], res["dim"], kind))
    print("  %-6s %9s %11s %11s %14s %14s %18s %12s %10s" % ("layout", "N", "ms/RHS", "ms/step", ratio + "/RHS", ratio + "/step", "KE final", "KE vs 1x1",
                                                         "halo max"))
    ke1 = res["layouts"].get("1x1", {}).get("kinetic_final")
    for lay, v in res["layouts"].items():
        f = lambda x, fmt: (fmt % x) if x is not None else "failed"  # noqa: E731
        k1 = "speedup_rhs" if kind == "strong" else "weak_efficiency_rhs"
        k2 = "speedup_step" if kind == "strong" else "weak_efficiency_step"
        same_n = ke1 is not None and v["kinetic_final"] is not None and v["N"] == res["layouts"]["1x1"]["N"]
        print("  %-6s %9d %11s %11s %14s %14s %18s %12s %10s%s" % (lay, v["N"], f(v["ms_per_rhs"], "%.3f"), f(v["ms_per_step"], "%.2f"),
                                                       f(v[k1], "%.3f"), f(v[k2], "%.3f"), f(v["kinetic_final"], "%.10g"),
                                                       ("%.1e" % abs(v["kinetic_final"] / ke1 - 1)) if same_n else "-",
                                                       f(v["halo_max"], "%.0f"),
                                                       "  (%d of %d runs failed)" % (v["failed"], v["runs"]) if v["failed"] else ""))
    if kind == "weak" and {"1x1", "2x1"} <= set(res["layouts"]):
        print("  particles on two cores / on one: %.4f" % (res["layouts"]["2x1"]["N"] / res["layouts"]["1x1"]["N"]))


def chart(results, path, commit, load):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(13, 5))
    names = [r["case"] for r in results]
    for k, res in enumerate(results):
        kind = res["kind"]
        for j, (lay, v) in enumerate(res["layouts"].items()):
            st = LAYOUT_STYLE[lay]
            x = k + 0.2 * (j - 1)
            ns = [1e6 * t / v["N"] for t in v["ms_per_rhs_all"] if t is not None]
            if ns:
                ax[0].plot([x] * len(ns), ns, color=st["color"], marker=st["marker"], ls="", alpha=0.35, ms=5)
                ax[0].plot(x, 1e6 * v["ms_per_rhs"] / v["N"], color=st["color"], marker=st["marker"], ls="", ms=9,
                           label=st["label"] if k == 0 else None)
            if v["failed"]:
                ax[0].plot(x, 0, **FAILED_STYLE, label="failed run" if k == 0 and j == 0 else None)
            key = "speedup_rhs" if kind == "strong" else "weak_efficiency_rhs"
            if v[key] is not None:
                ax[1].plot(x, v[key], color=st["color"], marker=st["marker"], ls="", ms=9)
                ax[1].annotate("%.2f" % v[key], (x, v[key]), fontsize=7, xytext=(4, 3), textcoords="offset points")
            else:
                ax[1].plot(x, 0, **FAILED_STYLE)
    ax[1].axhline(2.0, color="gray", ls=":", lw=1, label="ideal strong speed-up on 2 cores")
    ax[1].axhline(1.0, color="gray", ls="--", lw=1, label="ideal weak efficiency (and the 1x1 reference)")
    ax[1].legend(fontsize=8, loc="upper right")
    labels = ["%s\nN = %s" % (n, " / ".join(sorted({str(v["N"]) for v in r["layouts"].values()}))) for n, r in zip(names, results)]
    for a in ax:
        a.set_xticks(range(len(results)))
        a.set_xticklabels(labels, fontsize=8)
        a.grid(True, axis="y", alpha=0.3)
    ax[0].set(ylabel="time per RHS evaluation per particle (ns)", title="expansion, h = 3, DP5 at dt = 0.05: cost per particle (small: each run)")
    ax[0].set_ylim(bottom=0)
    ax[1].set(ylabel="strong: T(1x1) / T(layout);  weak: efficiency", title="per RHS: strong speed-up and weak efficiency (medians, same run)")
    ax[1].set_ylim(0, 2.2)
    ax[0].legend(fontsize=8, loc="upper left")
    fig.suptitle("spam-ark on this machine's 2 cores, commit %s (load average %.1f at the start, %.1f at the end: the cores were shared)" % (commit, load[0], load[1]), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--layouts", default=",".join(LAYOUTS))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--steps-2d", type=int, default=20)
    ap.add_argument("--steps-3d", type=int, default=8)
    ap.add_argument("--quick", action="store_true", help="1 repeat, 2 steps, small lattices (a smoke run)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "scaling"))
    ap.add_argument("--png", default=os.path.join(REPO, "docs", "scaling.png"))
    a = ap.parse_args()
    layouts = a.layouts.split(",")
    for lay in layouts:
        if lay not in LAYOUTS:
            sys.exit("--layouts: %s is not one of %s" % (lay, ", ".join(LAYOUTS)))
    cases = a.cases.split(",")
    for c in cases:
        if c not in CASES:
            sys.exit("--cases: %s is not one of %s" % (c, ", ".join(CASES)))
    if a.quick:
        a.repeats, a.steps_2d, a.steps_3d = 1, 2, 2
        for c in list(CASES):
            d, k, n1, n2 = CASES[c]
            CASES[c] = (d, k, n1 // 4 if d == 2 else n1 // 2, n2 // 4 if d == 2 else n2 // 2)
    commit = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    t_start = time.monotonic()
    load = [os.getloadavg()[0]]
    print("load average (1 min) at the start: %.2f on %d cores" % (load[0], os.cpu_count()), flush=True)
    results, all_runs = [], []
    for c in cases:
        dim, kind, n1, n2 = CASES[c]
        steps = a.steps_2d if dim == 2 else a.steps_3d
        runs = []
        for rep in range(a.repeats):
            for lay in layouts:   # alternating: a slow spell hits every layout
                n = n1 if LAYOUTS[lay] == (1, 1) else n2
                r = one_run(a.spam_ark, lay, dim, n, steps)
                r["case"], r["repeat"] = c, rep
                runs.append(r)
                if r["status"] != "max_steps":
                    print("  %s %s repeat %d failed: %s" % (c, lay, rep, " ".join(r.get("error", []))), flush=True)
        res = summarise(c, [r for r in runs])
        results.append(res)
        all_runs += runs
        print_case(res)
        sys.stdout.flush()
    total = time.monotonic() - t_start
    load.append(os.getloadavg()[0])
    print("total %.0f s, commit %s, load average at the end %.2f" % (total, commit, load[1]))
    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    json.dump({"commit": commit, "command": " ".join(sys.argv), "seconds": total, "load_average": load, "results": results, "runs": all_runs},
              open(a.out + ".json", "w"), indent=1)
    with open(a.out + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "layout", "N", "ms_per_rhs", "ms_per_step", "ratio_rhs", "ratio_step", "kinetic_final", "failed_runs"])
        for res in results:
            for lay, v in res["layouts"].items():
                k = "speedup_" if res["kind"] == "strong" else "weak_efficiency_"
                w.writerow([res["case"], lay, v["N"], v["ms_per_rhs"], v["ms_per_step"], v[k + "rhs"], v[k + "step"], v["kinetic_final"], v["failed"]])
    chart(results, a.png, commit, load)
    # The table bench/README.md quotes, beside the chart with the command and commit.
    sys.path.insert(0, os.path.join(REPO, "examples"))
    import chart_readings
    from scaling_table import table_rows, COLUMNS
    chart_readings.write(a.png, {"table": chart_readings.table(COLUMNS, table_rows(results)), "seconds": total,
                                 "repeats": a.repeats, "load_1min_start": load[0]})
    print("wrote %s.json, %s.csv and %s" % (a.out, a.out, a.png))
    return 1 if any(r["status"] != "max_steps" for r in all_runs) else 0


if __name__ == "__main__":
    sys.exit(main())
