#!/usr/bin/env python3
"""Multi-rank runs on paper: the halo volume and the messages per rank of a 3D gas cut
into P pieces along the Hilbert curve, for N up to 1e8 and P up to 1000, and the parallel
efficiency they imply on a stated network, against this machine's measured RHS cost
(bench/README.md, "Multi-rank runs: halo volume and messages").

  /usr/bin/python3 bench/halo_model.py [--alpha-us 1.5] [--beta-gbs 12.5] [--build-every 20]
                                       [--repeats 3] [--out bench/results/halo_model.json]
                                       [--png docs/halo_model.png]

Four parts, in one run:
 1. the RHS cost on this machine: spam-ark's 3D expansion (gamma 5/3, h = 3) on one rank,
    as the benchmarks run it (the chunked pair loops, which a rank with remote ghosts also
    runs), medians of --repeats runs;
 2. the census: bench/halo_census on 2, 4 and 8 ranks (mpiexec --oversubscribe) for two
    lattices, against the formula applied to each rank's own bounding box, and against
    the cut computed without particles (-geometry), which the table uses;
 3. the table for N = 1e5 .. 1e8 and P = 2 .. 1000 from the -geometry cut;
 4. the chart.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from scaling_style import SOURCE_STYLE, N_WIDTH  # noqa: E402

H = 3.0             # Lucy range of the expansion scenes, in lattice spacings
SKIN = 0.1 * H      # the program's default -neighbour_skin
RC = H + SKIN       # list range: what SpamHalo sends within
# What one RHS of the gas path (gamma != 2) exchanges with the halo, in the code since
# dfdefa1: rhs_isentrope.c SpamAccelIsentrope -> SpamNeighboursUpdate (the ghosts'
# positions, neighbours_ghost.c SpamNeighboursMoveGhosts; at a rebuild the build sends
# them instead), then P/rho^2 before the force pass. Masses and inverse masses go once per
# list build (SpamSimGhostMasses), and with gamma = 2 P/rho^2 too. The chunked density
# pass walks a remote ghost for the local particle only and gathers no density. Doubles
# per ghost of each.
EXCHANGES = (("positions", 3), ("P/rho^2", 1))
RHS_ALLREDUCES = 1       # the rebuild decision and non-finite flag (neighbours.c Agree)
STEP_ALLREDUCES = 3      # per step: ARKODE's error norm, the signal agreement, the step bound
RHS_PER_STEP = 6         # Dormand-Prince, FSAL
HALF_PAIRS = 2.0 / 3.0 * math.pi * RC ** 3     # listed pairs per particle (each once), density 1
CROSS_PAIRS_PER_AREA = math.pi * RC ** 4 / 4   # pairs within RC across a unit plane, density 1
LATTICE_INSET = 0.4      # halo_census's lattice: sites 0.5 +- 0.1 inside their cells' faces


def env():
    e = dict(os.environ)
    e.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_pml="ob1",
             OMP_NUM_THREADS="1")
    return e


def steiner(ext, r, L):
    """Volume within r of a box of edges ext in a periodic box of edges L. A direction whose
    box plus 2r covers L wraps onto itself: it contributes L and no extension."""
    free = [a for a, l in zip(ext, L) if a + 2 * r < l]
    span = math.prod(l for a, l in zip(ext, L) if a + 2 * r >= l)
    if len(free) == 0:
        v = 1.0
    elif len(free) == 1:
        v = free[0] + 2 * r
    elif len(free) == 2:
        a, b = free
        v = a * b + 2 * (a + b) * r + math.pi * r * r
    else:
        a, b, c = free
        v = a * b * c + 2 * (a * b + b * c + c * a) * r + math.pi * (a + b + c) * r * r + 4 / 3 * math.pi * r ** 3
    return v * span


def halo_of_box(ext, L, n_own, inset):
    """Particles of other ranks within RC of a rank's bounding box at density 1: everything
    within RC - inset of its cells' box but its own. inset: how far the outermost particles
    sit inside the cells' faces (0 for a disordered gas: the conservative choice)."""
    return max(0.0, steiner(ext, RC - inset, L) - n_own)


def cube_halo(n):
    a = n ** (1 / 3)
    return steiner((a, a, a), RC, (1e300,) * 3) - n


def run_json(cmd, timeout=600):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env(), timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
    return json.loads(p.stdout[p.stdout.index("{"):])


def census(exe, P, side, reps):
    return run_json(["mpiexec", "--oversubscribe", "-n", str(P), exe, "-side", str(side), "-reps", str(reps)])


def geometry(exe, side, P):
    return run_json([exe, "-geometry", "-side", str(side), "-pieces", str(P)])


def rhs_cost(spam, repeats, side=40):
    """Seconds per particle per RHS, and ns per listed pair (spam-ark's count), of the 3D
    expansion on one rank with its default pair loops."""
    runs = {"fast": []}
    for _ in range(repeats):
        for name, images in (("fast", "minimum"),):
            with tempfile.TemporaryDirectory() as d:
                cmd = [spam, "-scene", "expansion", "-dim", "3", "-expansion_n", str(side), "-h", "%g" % H,
                       "-arkode_table", "ARKODE_DORMAND_PRINCE_7_4_5", "-arkode_fixed_step", "0.05",
                       "-ts_max_steps", "10", "-ts_max_time", "0.525", "-snapshot_interval", "0",
                       "-output_interval", "0", "-diag_entropy", "0", "-periodic_images", images,
                       "-output_dir", os.path.join(d, "o")]
                subprocess.run(cmd, check=True, capture_output=True, env=env())
                s = json.load(open(os.path.join(d, "o", "summary.json")))
                runs[name].append((s["rhs_time_s"] / s["rhs_evals"] / s["n_particles"], s["ns_per_pair"]))
    out = {"command": " ".join(cmd[:-2]), "N": side ** 3}
    for k, v in runs.items():
        out[k] = {"s_per_particle": statistics.median(x[0] for x in v), "ns_per_pair": statistics.median(x[1] for x in v),
                  "runs": v}
    return out


def check_census(exe, reps):
    """Per rank: the measured remote ghosts against the formula on its own particles' box,
    and the -geometry cut's prediction (cells' boxes) against the same ranks."""
    rows = []
    for side in (48, 40):
        for P in (2, 4, 8):
            c = census(exe, P, side, reps)
            g = geometry(exe, side, P)
            L = (side,) * 3
            per_rank = []
            for r in c["ranks"]:
                ext = [r["hi_" + a] - r["lo_" + a] + 2 * LATTICE_INSET for a in "xyz"]
                per_rank.append((r["remote_ghosts"], halo_of_box(ext, L, r["n"], LATTICE_INSET)))
            geo = [halo_of_box([hi - lo for lo, hi in zip(p["lo"], p["hi"])], L, p["cells"] * math.prod(g["cell_width"]),
                               LATTICE_INSET) for p in g["pieces"]]
            rows.append({
                "side": side, "N": c["N"], "P": P, "cells_per_edge": g["cells"][0],
                "measured_max": max(m for m, _ in per_rank), "measured_sum": sum(m for m, _ in per_rank),
                "own_box_formula_max": max(f for _, f in per_rank), "own_box_formula_sum": sum(f for _, f in per_rank),
                "own_box_worst_ratio": max(f / m for m, f in per_rank if m) if any(m for m, _ in per_rank) else None,
                "own_box_best_ratio": min(f / m for m, f in per_rank if m) if any(m for m, _ in per_rank) else None,
                "geometry_max": max(geo), "geometry_sum": sum(geo),
                "ranks_from_measured_max": max(r["ranks_from"] for r in c["ranks"]),
                "ranks_from_geometry_max": max(p["ranks_from"] for p in g["pieces"]),
                "ghost_pairs_measured_sum": sum(r["ghost_pairs"] for r in c["ranks"]),
                "ghost_pairs_surface_sum": sum(p["surface"] for p in g["pieces"]) * CROSS_PAIRS_PER_AREA,
                "n_max": max(r["n"] for r in c["ranks"]),
                "select_s": c["select_s"], "forward3_s": c["forward3_s"], "forward1_s": c["forward1_s"],
            })
            print("census side %d (%d cells per edge), P = %d: remote ghosts max %d, sum %d; formula on each rank's box max %.0f, sum %.0f "
                  "(per rank %.3f-%.3f of measured); -geometry cut max %.0f, sum %.0f; ranks heard from max %d (geometry %d); "
                  "ghost pairs %d, surface estimate %.0f" % (
                      side, g["cells"][0], P, rows[-1]["measured_max"], rows[-1]["measured_sum"], rows[-1]["own_box_formula_max"],
                      rows[-1]["own_box_formula_sum"], rows[-1]["own_box_best_ratio"] or 0, rows[-1]["own_box_worst_ratio"] or 0,
                      rows[-1]["geometry_max"], rows[-1]["geometry_sum"], rows[-1]["ranks_from_measured_max"],
                      rows[-1]["ranks_from_geometry_max"], rows[-1]["ghost_pairs_measured_sum"], rows[-1]["ghost_pairs_surface_sum"]),
                  flush=True)
    return rows


def allreduce_s(P, alpha):
    return 2 * math.ceil(math.log2(P)) * alpha if P > 1 else 0.0


def model_row(N, P, g, cost, net, box_test_s):
    """Per rank of the -geometry cut g: halo, messages, time; the slowest rank sets T_P."""
    alpha, beta, every = net["alpha_s"], net["beta_Bps"], net["build_every"]
    L = (g["side"],) * 3
    ncomp = sum(c for _, c in EXCHANGES)
    t1 = N * cost["fast"]["s_per_particle"]            # one rank, default loops
    worst = None
    for p in g["pieces"]:
        n = p["cells"] * math.prod(g["cell_width"])
        halo = halo_of_box([hi - lo for lo, hi in zip(p["lo"], p["hi"])], L, n, 0.0)
        msgs = max(p["ranks_from"], p["ranks_to"])
        cross = p["surface"] * CROSS_PAIRS_PER_AREA       # pairs with remote ghosts, walked here too
        work = n + cross / HALF_PAIRS                     # in particles' worth of listed pairs (a cross
                                                          # pair costs about a local one: its term is
                                                          # computed, only particle i's sum taken)
        comm = sum(alpha * msgs + halo * 8 * c / beta for _, c in EXCHANGES)
        comm += RHS_ALLREDUCES * allreduce_s(P, alpha) + STEP_ALLREDUCES * allreduce_s(P, alpha) / RHS_PER_STEP
        build = (box_test_s * n * (P - 1)                      # SpamHaloSelect: every particle against every box
                 + 2 * (P - 1) * alpha + allreduce_s(P, alpha) + 48 * P / beta   # two Alltoall, the Allgather of boxes
                 + 2 * alpha * msgs + halo * 32 / beta)           # PetscSFSetUp, the ghosts' description
        r = {"n": n, "halo": halo, "msgs": msgs, "cross_pairs": cross, "comm_s": comm, "build_s": build,
             "comp_s": work * cost["fast"]["s_per_particle"]}
        r["tp_s"] = r["comp_s"] + comm
        if worst is None or r["tp_s"] > worst["tp_s"]:
            worst = r
    halos = [halo_of_box([hi - lo for lo, hi in zip(p["lo"], p["hi"])], L, p["cells"] * math.prod(g["cell_width"]), 0.0)
             for p in g["pieces"]]
    n_mean = N / P
    tp = worst["tp_s"]
    return {
        "N": N, "P": P, "side": g["side"], "n_per_rank": n_mean,
        "halo_cube": cube_halo(n_mean), "halo_mean": statistics.mean(halos), "halo_max": max(halos),
        "ranks_from_mean": statistics.mean(p["ranks_from"] for p in g["pieces"]),
        "ranks_from_max": max(p["ranks_from"] for p in g["pieces"]),
        "ranks_to_max": max(p["ranks_to"] for p in g["pieces"]),
        "messages_per_rhs_max": len(EXCHANGES) * max(max(p["ranks_from"], p["ranks_to"]) for p in g["pieces"]) + RHS_ALLREDUCES,
        "bytes_in_per_rhs_max": max(halos) * 8 * ncomp,
        "t1_s": t1, "tp_comp_s": worst["comp_s"], "tp_comm_s": worst["comm_s"], "tp_s": tp,
        "efficiency": t1 / (P * tp),
        "efficiency_builds": t1 / (P * (tp + worst["build_s"] / every)),
        "efficiency_compute_only": t1 / (P * worst["comp_s"]),
        "build_s": worst["build_s"], "build_over_rhs": worst["build_s"] / tp,
    }


def chart(rows, census_rows, net, cost, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(17, 5.6))
    Ns = sorted({r["N"] for r in rows})
    for iN, N in enumerate(Ns):
        rs = sorted((r for r in rows if r["N"] == N), key=lambda r: r["P"])
        P = [r["P"] for r in rs]
        lw = N_WIDTH.get(N, 1.0)
        tag = " N = 1e%d" % round(math.log10(N))
        st = SOURCE_STYLE["cube"]
        ax[0].loglog(P, [r["halo_cube"] / r["n_per_rank"] for r in rs], color=st["color"], ls=st["linestyle"], lw=lw)
        st = SOURCE_STYLE["hilbert"]
        ax[0].loglog(P, [r["halo_max"] / r["n_per_rank"] for r in rs], color=st["color"], marker=st["marker"], ls=st["linestyle"], lw=lw, ms=4)
        ax[0].annotate(tag, (P[-1], rs[-1]["halo_max"] / rs[-1]["n_per_rank"]), fontsize=7, xytext=(3, 7 * iN - 10), textcoords="offset points")
        ax[1].semilogx(P, [r["messages_per_rhs_max"] for r in rs], color=st["color"], marker=st["marker"], ls=st["linestyle"], lw=lw, ms=4)
        ax[2].semilogx(P, [r["efficiency"] for r in rs], color=st["color"], marker=st["marker"], ls=st["linestyle"], lw=lw, ms=4)
        ax[2].annotate(tag, (P[-1], rs[-1]["efficiency"]), fontsize=7, xytext=(3, 7 * iN - 10), textcoords="offset points")
        s2 = SOURCE_STYLE["hilbert_builds"]
        ax[2].semilogx(P, [r["efficiency_builds"] for r in rs], color=s2["color"], marker=s2["marker"], ls=s2["linestyle"], lw=lw, ms=4)
    st = SOURCE_STYLE["census"]
    for c in census_rows:
        ax[0].loglog(c["P"], c["measured_max"] / (c["N"] / c["P"]), color=st["color"], marker=st["marker"], ls="", ms=8)
        ax[0].annotate("N = %d (%d cells/edge)" % (c["N"], c["cells_per_edge"]), (c["P"], c["measured_max"] / (c["N"] / c["P"])),
                       fontsize=6, color=st["color"], xytext=(4, -3), textcoords="offset points")
        ax[1].semilogx(c["P"], len(EXCHANGES) * c["ranks_from_measured_max"] + RHS_ALLREDUCES, color=st["color"], marker=st["marker"], ls="", ms=8)
    ax[1].axhline(len(EXCHANGES) * 26 + RHS_ALLREDUCES, color=SOURCE_STYLE["cube"]["color"], ls=SOURCE_STYLE["cube"]["linestyle"])
    ax[0].set(xlabel="ranks P", ylabel="remote ghosts per rank / particles per rank (largest rank)",
              title="3D gas, h = 3, list range %.1f: halo per rank" % RC)
    ax[1].set(xlabel="ranks P", ylabel="messages sent per rank per RHS (largest rank)",
              title="messages: %d halo exchanges per RHS x neighbour ranks + 1 allreduce" % len(EXCHANGES))
    ax[2].set(xlabel="ranks P", ylabel="parallel efficiency T1 / (P T_P)", ylim=(0, 1.05),
              title="efficiency at latency %.1f us, %.1f GB/s" % (net["alpha_s"] * 1e6, net["beta_Bps"] / 1e9))
    ax[2].text(0.02, 0.02, "T1: this machine's RHS, %.0f ns per particle (one rank, measured);\nsolid: RHS exchanges; "
               "dotted: with a list build every %d RHS evaluations" % (cost["fast"]["s_per_particle"] * 1e9, net["build_every"]),
               transform=ax[2].transAxes, fontsize=7, va="bottom")
    handles = [plt.Line2D([], [], color=s["color"], marker=s["marker"], ls=s["linestyle"] or "", label=s["label"])
               for s in SOURCE_STYLE.values()]
    handles += [plt.Line2D([], [], color="black", lw=N_WIDTH[n], label="N = 1e%d (line width)" % round(math.log10(n))) for n in Ns if n in N_WIDTH]
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=8)
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=110)


def markdown(rows, census_rows, cost, box_test_s, net, commit):
    """The README's tables, as this run computed them."""
    out = ["Census (commit %s): remote ghosts per rank measured by SpamHalo against the formula on each rank's own "
           "bounding box and against the -geometry cut (lattice inset %.1f):" % (commit, LATTICE_INSET), "",
           "| N | cells per edge | P | measured max | formula, own box: max (per-rank ratio) | -geometry: max | measured sum | -geometry sum | ranks heard from (measured / geometry) | ghost pairs: measured / surface estimate |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for c in census_rows:
        out.append("| %d | %d | %d | %d | %.0f (%.3f-%.3f) | %.0f | %d | %.0f | %d / %d | %.3f |" % (
            c["N"], c["cells_per_edge"], c["P"], c["measured_max"], c["own_box_formula_max"], c["own_box_best_ratio"],
            c["own_box_worst_ratio"], c["geometry_max"], c["measured_sum"], c["geometry_sum"], c["ranks_from_measured_max"],
            c["ranks_from_geometry_max"], c["ghost_pairs_measured_sum"] / c["ghost_pairs_surface_sum"]))
    out += ["", "Model (commit %s; latency %.1f us, %.1f GB/s, a list build every %d RHS; RHS %.0f ns per particle; "
            "box test %.0f ns per (particle, other rank)):" % (
                commit, net["alpha_s"] * 1e6, net["beta_Bps"] / 1e9, net["build_every"], cost["fast"]["s_per_particle"] * 1e9,
                box_test_s * 1e9), "",
            "| N | P | particles per rank | halo, cubes | halo, Hilbert mean / max | max / particles | ranks heard from, mean / max | messages per RHS (max) | MB in per RHS (max) | comm / T_P | E | E with builds | E, pair work only | a build in RHS |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append("| 1e%d | %d | %.0f | %.0f | %.0f / %.0f | %.2f | %.1f / %d | %d | %.2f | %.1f %% | %.3f | %.3f | %.3f | %.1f |" % (
            round(math.log10(r["N"])), r["P"], r["n_per_rank"], r["halo_cube"], r["halo_mean"], r["halo_max"],
            r["halo_max"] / r["n_per_rank"], r["ranks_from_mean"], r["ranks_from_max"], r["messages_per_rhs_max"],
            r["bytes_in_per_rhs_max"] / 1e6, 100 * r["tp_comm_s"] / r["tp_s"], r["efficiency"], r["efficiency_builds"],
            r["efficiency_compute_only"], r["build_over_rhs"]))
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spam-ark", default=os.path.join(REPO, "build", "spam-ark"))
    ap.add_argument("--census", default=os.path.join(REPO, "build", "bench", "halo_census"))
    ap.add_argument("--alpha-us", type=float, default=1.5, help="latency per message, microseconds (default 1.5)")
    ap.add_argument("--beta-gbs", type=float, default=12.5, help="bandwidth per rank, GB/s (default 12.5)")
    ap.add_argument("--build-every", type=int, default=20, help="RHS evaluations per list build (default 20)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--sizes", default="1e5,1e6,1e7,1e8")
    ap.add_argument("--ranks", default="2,8,27,64,100,216,512,1000")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "halo_model.json"))
    ap.add_argument("--png", default=os.path.join(REPO, "docs", "halo_model.png"))
    a = ap.parse_args()
    net = {"alpha_s": a.alpha_us * 1e-6, "beta_Bps": a.beta_gbs * 1e9, "build_every": a.build_every}

    cost = rhs_cost(a.spam_ark, a.repeats)
    print("RHS on this machine, 3D expansion N = %d, one rank: %.1f ns per particle (%.2f ns per pair); runs %s" % (
              cost["N"], cost["fast"]["s_per_particle"] * 1e9, cost["fast"]["ns_per_pair"],
              ", ".join("%.0f" % (x[0] * 1e9) for x in cost["fast"]["runs"])), flush=True)
    census_rows = check_census(a.census, a.repeats)
    # The box tests of a selection cost c n (P - 1) on a rank of n particles. Each census
    # run's whole selection time (slowest rank, its Alltoalls, SF set-up and the
    # oversubscription of 2 cores included) divided by n (P - 1) bounds c from above: the
    # smallest of these bounds is taken.
    best = min(census_rows, key=lambda c: c["select_s"] / (c["n_max"] * (c["P"] - 1)))
    box_test_s = best["select_s"] / (best["n_max"] * (best["P"] - 1))
    print("halo selection: %.3f ms on %d ranks of up to %d particles (side %d): %.1f ns per (particle, other rank), "
          "taken as the box-test cost (the smallest upper bound of the census runs)" % (
              best["select_s"] * 1e3, best["P"], best["n_max"], best["side"], box_test_s * 1e9))

    rows = []
    for N in (int(float(x)) for x in a.sizes.split(",")):
        side = round(N ** (1 / 3))
        for P in (int(x) for x in a.ranks.split(",")):
            g = geometry(a.census, side, P)
            g["side"] = side
            r = model_row(side ** 3, P, g, cost, net, box_test_s)
            r["N_nominal"] = N
            rows.append(r)
            print("N %.0e P %4d: n/rank %9.0f halo cube %8.0f Hilbert mean %8.0f max %8.0f (max/n %.2f) | ranks heard from mean %.1f max %d | "
                  "msgs/RHS %d | bytes in/RHS %.2e | T1 %.3e s TP %.3e s (comm %.1f%%) E %.3f, with builds %.3f, compute only %.3f | build = %.1f RHS" % (
                      N, P, r["n_per_rank"], r["halo_cube"], r["halo_mean"], r["halo_max"], r["halo_max"] / r["n_per_rank"],
                      r["ranks_from_mean"], r["ranks_from_max"], r["messages_per_rhs_max"], r["bytes_in_per_rhs_max"], r["t1_s"], r["tp_s"],
                      100 * r["tp_comm_s"] / r["tp_s"], r["efficiency"], r["efficiency_builds"], r["efficiency_compute_only"], r["build_over_rhs"]), flush=True)
    for r in rows:
        r["N"] = r["N_nominal"]
    commit = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    json.dump({"commit": commit, "command": " ".join(sys.argv), "h": H, "skin": SKIN, "rc": RC, "network": net,
               "exchanges": EXCHANGES, "rhs_cost": cost, "box_test_s": box_test_s, "census": census_rows, "table": rows},
              open(a.out, "w"), indent=1)
    chart(rows, census_rows, net, cost, a.png)
    with open(os.path.splitext(a.out)[0] + ".md", "w") as f:
        f.write(markdown(rows, census_rows, cost, box_test_s, net, commit))
    print("wrote %s, %s.md and %s (commit %s)" % (a.out, os.path.splitext(a.out)[0], a.png, commit))


if __name__ == "__main__":
    main()
