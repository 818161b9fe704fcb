#!/usr/bin/python3
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
    lattices, against two formulas: the halo the selection by occupied cells makes (each
    piece dilated by rc, computed by -geometry) and the halo of a rank's bounding box
    (Steiner's formula: an upper bound); and the selection's cost: per box
    test (occupied cell, other rank) bounded by three runs with a cell per particle (h =
    0.5), per particle looked up and per item fitted to the census runs;
 3. the table for N = 1e5 .. 1e8 and P = 2 .. 1000 from the -geometry cut;
 4. the chart, bench/results/halo_model.json and .md (the README's tables, as printed).
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from scaling_style import SOURCE_STYLE, N_WIDTH  # noqa: E402

H = 3.0             # Lucy range of the expansion scenes, in lattice spacings
SKIN = 0.1 * H      # the program's default -neighbour_skin
RC = H + SKIN       # list range: what SpamHalo sends within
# What one RHS of the gas path (gamma != 2) exchanges with the halo, in the code:
# rhs_isentrope.c SpamAccelIsentrope -> SpamNeighboursUpdate (the ghosts'
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
CELL_BYTES = 56          # a selection cell sent: its key and its particles' box, 7 doubles
# Runs that make the box tests of the selection weigh (rc = 0.55 < the lattice spacing: a
# cell per particle, no pairs, no items), beside the census runs, for the fit of its cost.
CALIBRATION = ((40, 0.5, 2), (40, 0.5, 8), (40, 0.5, 16))


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


def census(exe, P, side, reps, h=H):
    return run_json(["mpiexec", "--oversubscribe", "-n", str(P), exe, "-side", str(side), "-reps", str(reps),
                     "-h", "%g" % h, "-skin", "%g" % (0.1 * h), "-inset", "%g" % min(LATTICE_INSET, 0.5 * h)])


def geometry(exe, side, P, inset=0.0):
    return run_json([exe, "-geometry", "-side", str(side), "-pieces", str(P), "-inset", "%g" % inset])


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
    """Per rank: the measured remote ghosts against the formula on the selection's halo
    (its piece of the ranks' own cut dilated by rc - inset, computed by the census) and
    against the one on its own particles' bounding box; the selection's cells against
    those of -geometry's cut (of equal cell counts: the ranks' own where the cells hold
    equal counts, 16 per edge)."""
    rows = []
    for side in (48, 40):
        for P in (2, 4, 8):
            c = census(exe, P, side, reps)
            g = geometry(exe, side, P)
            L = (side,) * 3
            boxf = []
            for r in c["ranks"]:
                ext = [r["hi_" + a] - r["lo_" + a] + 2 * LATTICE_INSET for a in "xyz"]
                boxf.append(halo_of_box(ext, L, r["n"], LATTICE_INSET))
            meas = [r["remote_ghosts"] for r in c["ranks"]]
            cellf = [r["halo_cells_formula"] for r in c["ranks"]]
            cpu = min(c["ranks"], key=lambda r: r["select_cpu_s"])
            row = {
                "side": side, "N": c["N"], "P": P, "h": H, "cells_per_edge": g["cells"][0], "select_cells_per_edge": g["select_cells"],
                "measured_max": max(meas), "measured_sum": sum(meas),
                "cells_formula_max": max(cellf), "cells_formula_sum": sum(cellf),
                "cells_ratio": [min(f / m for f, m in zip(cellf, meas)), max(f / m for f, m in zip(cellf, meas))],
                "box_formula_max": max(boxf), "box_formula_sum": sum(boxf),
                "box_ratio": [min(f / m for f, m in zip(boxf, meas)), max(f / m for f, m in zip(boxf, meas))],
                "ranks_from_measured_max": max(r["ranks_from"] for r in c["ranks"]),
                "ranks_from_cells_max": max(p["ranks_from_cells"] for p in g["pieces"]),
                "occupied_measured_max": max(r["occupied_cells"] for r in c["ranks"]),
                "occupied_geometry_max": max(p["occupied_cells"] for p in g["pieces"]),
                "cells_sent_measured_sum": sum(r["cells_sent"] for r in c["ranks"]),
                "cells_sent_geometry_sum": sum(p["cells_sent"] for p in g["pieces"]),
                "ghost_pairs_measured_sum": sum(r["ghost_pairs"] for r in c["ranks"]),
                "ghost_pairs_surface_sum": sum(p["surface"] for p in g["pieces"]) * CROSS_PAIRS_PER_AREA,
                "n_max": max(r["n"] for r in c["ranks"]),
                "select_s": c["select_s"], "forward3_s": c["forward3_s"], "forward1_s": c["forward1_s"],
                "fit_point": fit_point(cpu, P), "ranks": c["ranks"],
            }
            rows.append(row)
            print("census side %d (%d cells per edge, %d selection cells), P = %d: remote ghosts max %d, sum %d | cell formula max %.0f, "
                  "sum %.0f, per rank %s of measured | box formula (upper bound) max %.0f, sum %.0f, per rank %.3f-%.3f | ranks heard from "
                  "max %d (cells: %d) | occupied cells max %d (geometry %d), cells sent %d (geometry %d) | ghost pairs %d, surface "
                  "estimate %.0f | selection %.2f ms wall, least-loaded rank %.2f ms CPU" % (
                      side, row["cells_per_edge"], row["select_cells_per_edge"], P, row["measured_max"], row["measured_sum"],
                      row["cells_formula_max"], row["cells_formula_sum"],
                      "%.3f-%.3f" % tuple(row["cells_ratio"]),
                      row["box_formula_max"], row["box_formula_sum"], row["box_ratio"][0], row["box_ratio"][1],
                      row["ranks_from_measured_max"], row["ranks_from_cells_max"], row["occupied_measured_max"],
                      row["occupied_geometry_max"], row["cells_sent_measured_sum"], row["cells_sent_geometry_sum"],
                      row["ghost_pairs_measured_sum"], row["ghost_pairs_surface_sum"], row["select_s"] * 1e3,
                      row["fit_point"]["cpu_s"] * 1e3), flush=True)
    return rows


def fit_point(r, P):
    """What a rank's selection did, and its CPU time: particles looked up, box tests of its
    occupied cells against the other ranks' boxes, items sent plus ghost slots made."""
    return {"P": P, "n": r["n"], "tests": r["occupied_cells"] * (P - 1), "items": r["items_sent"] + r["remote_ghosts"],
            "cpu_s": r["select_cpu_s"]}


def calibration(exe, reps):
    pts = []
    for side, h, P in CALIBRATION:
        c = census(exe, P, side, reps, h)
        r = min(c["ranks"], key=lambda r: r["select_cpu_s"])
        pts.append(dict(fit_point(r, P), side=side, h=h))
        print("calibration side %d h %g P %d: least-loaded rank %d particles, %d box tests, %d items: %.2f ms CPU (wall %.2f ms)" % (
            side, h, P, r["n"], pts[-1]["tests"], pts[-1]["items"], r["select_cpu_s"] * 1e3, c["select_s"] * 1e3), flush=True)
    return pts


def fit_selection(census_points, calibration_points):
    """The selection's cost on a rank: c_look n + c_box tests + c_item items (CPU time).
    c_box: the smallest upper bound of the calibration runs (the whole selection's CPU time
    over its box tests: there the tests are 1 to 15 per particle and no items are made).
    c_look, c_item: least squares on the relative residuals of the census runs (h = 3, the
    model's scale) once the box tests at c_box are taken off, both >= 0."""
    import numpy as np
    c_box = min(p["cpu_s"] / p["tests"] for p in calibration_points)
    rows = [p for p in census_points]
    A = np.array([[p["n"] / p["cpu_s"], p["items"] / p["cpu_s"]] for p in rows])
    y = np.array([1.0 - c_box * p["tests"] / p["cpu_s"] for p in rows])
    best = None
    for sub in ((0, 1), (0,), (1,)):
        c, *_ = np.linalg.lstsq(A[:, sub], y, rcond=None)
        if (c < 0).any():
            continue
        res = float(np.sqrt(np.mean((A[:, sub] @ c - y) ** 2)))
        if best is None or res < best[0]:
            full = np.zeros(2)
            full[list(sub)] = c
            best = (res, full)
    res, (c_look, c_item) = best
    for p in rows + calibration_points:
        p["fit_cpu_s"] = c_look * p["n"] + c_box * p["tests"] + c_item * p["items"]
    return {"c_look_s": c_look, "c_box_s": c_box, "c_item_s": c_item, "rel_rms": res, "points": rows + calibration_points}


def allreduce_s(P, alpha):
    return 2 * math.ceil(math.log2(P)) * alpha if P > 1 else 0.0


def exchanges_s(halo, msgs, alpha, beta):
    """The forward exchanges of one RHS: a message to each neighbour rank, the bytes in."""
    return sum(alpha * msgs + halo * 8 * c / beta for _, c in EXCHANGES)


def build_s(n, halo, p, P, sel, alpha, beta):
    """One list build's halo selection on a rank (halo_select.c, halo.c, neighbours.c), as
    the code does it: the lookups of its n particles, the box tests of its
    occupied cells against the P - 1 other ranks' boxes, the items and ghost slots (sorted,
    described), and the collectives."""
    msgs = max(p["ranks_from_cells"], p["ranks_to_cells"])
    work = sel["c_look_s"] * n + sel["c_box_s"] * p["occupied_cells"] * (P - 1) + sel["c_item_s"] * 2 * halo
    coll = (2 * allreduce_s(P, alpha)                                   # WrapAll; the walls' depth
            + math.ceil(math.log2(P)) * alpha + 48 * P / beta           # MPI_Allgather of the boxes
            + 3 * (P - 1) * alpha                                       # MPI_Alltoall: cell counts; item counts, offsets
            + alpha * max(p["ranks_sent_cells"], p["ranks_from"]) + CELL_BYTES * p["cells_received"] / beta  # Alltoallv of cells
            + 2 * alpha * msgs + allreduce_s(P, alpha)                  # PetscSFSetUp (two-sided set-up)
            + alpha * msgs + halo * 32 / beta                           # the ghosts' description, 4 doubles
            + 2 * (alpha * msgs + halo * 8 / beta))                     # masses and inverse masses
    return work + coll


def model_row(N, P, g, cost, net, sel):
    """Per rank of the -geometry cut g: halo, messages, time; the slowest rank sets T_P. The
    halo is the selection's (the piece dilated by rc); the bounding box's gives the bound."""
    alpha, beta, every = net["alpha_s"], net["beta_Bps"], net["build_every"]
    L = (g["side"],) * 3
    ncomp = sum(c for _, c in EXCHANGES)
    t1 = N * cost["fast"]["s_per_particle"]            # one rank, default loops
    fixed = RHS_ALLREDUCES * allreduce_s(P, alpha) + STEP_ALLREDUCES * allreduce_s(P, alpha) / RHS_PER_STEP
    ranks = []
    for p in g["pieces"]:
        n = p["cells"] * math.prod(g["cell_width"])
        halo = p["halo_cells"]
        box = halo_of_box([hi - lo for lo, hi in zip(p["lo"], p["hi"])], L, n, 0.0)
        cross = p["surface"] * CROSS_PAIRS_PER_AREA       # pairs with remote ghosts, walked here too
        comp = (n + cross / HALF_PAIRS) * cost["fast"]["s_per_particle"]  # a cross pair costs about a local
                                                          # one: its term is computed, only i's sum taken
        msgs = max(p["ranks_from_cells"], p["ranks_to_cells"])
        r = {"n": n, "halo": halo, "halo_box": box, "msgs": msgs, "comp_s": comp,
             "comm_s": exchanges_s(halo, msgs, alpha, beta) + fixed,
             "comm_box_s": exchanges_s(box, max(p["ranks_from"], p["ranks_to"]), alpha, beta) + fixed,
             "build_s": build_s(n, halo, p, P, sel, alpha, beta), "tests": p["occupied_cells"] * (P - 1)}
        r["tp_s"] = comp + r["comm_s"]
        r["tpb_s"] = r["tp_s"] + r["build_s"] / every
        r["tp_box_s"] = comp + r["comm_box_s"]
        ranks.append(r)
    worst = max(ranks, key=lambda r: r["tp_s"])
    worst_b = max(ranks, key=lambda r: r["tpb_s"])
    tp = worst["tp_s"]
    return {
        "N": N, "P": P, "side": g["side"], "n_per_rank": N / P,
        "halo_cube": cube_halo(N / P),
        "halo_mean": statistics.mean(r["halo"] for r in ranks), "halo_max": max(r["halo"] for r in ranks),
        "halo_box_mean": statistics.mean(r["halo_box"] for r in ranks), "halo_box_max": max(r["halo_box"] for r in ranks),
        "ranks_from_mean": statistics.mean(p["ranks_from_cells"] for p in g["pieces"]),
        "ranks_from_max": max(p["ranks_from_cells"] for p in g["pieces"]),
        "ranks_from_box_max": max(p["ranks_from"] for p in g["pieces"]),
        "messages_per_rhs_max": len(EXCHANGES) * max(r["msgs"] for r in ranks) + RHS_ALLREDUCES,
        "messages_per_rhs_box_max": len(EXCHANGES) * max(max(p["ranks_from"], p["ranks_to"]) for p in g["pieces"]) + RHS_ALLREDUCES,
        "bytes_in_per_rhs_max": max(r["halo"] for r in ranks) * 8 * ncomp,
        "t1_s": t1, "tp_comp_s": worst["comp_s"], "tp_comm_s": worst["comm_s"], "tp_s": tp,
        "efficiency": t1 / (P * tp),
        "efficiency_builds": t1 / (P * worst_b["tpb_s"]),
        "efficiency_box": t1 / (P * max(r["tp_box_s"] for r in ranks)),
        "efficiency_compute_only": t1 / (P * max(r["comp_s"] for r in ranks)),
        "build_s": worst_b["build_s"], "build_over_rhs": worst_b["build_s"] / worst_b["tp_s"],
        "box_tests_max": max(r["tests"] for r in ranks),
        "cells_received_max": max(p["cells_received"] for p in g["pieces"]),
    }


def chart(rows, census_rows, net, cost, sel, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(18, 6))
    Ns = sorted({r["N"] for r in rows})

    def line(a, key, P, ys, lw, plot):
        st = SOURCE_STYLE[key]
        getattr(a, plot)(P, ys, color=st["color"], marker=st["marker"], ls=st["linestyle"], lw=lw, ms=4)

    for iN, N in enumerate(Ns):
        rs = sorted((r for r in rows if r["N"] == N), key=lambda r: r["P"])
        P = [r["P"] for r in rs]
        lw = N_WIDTH.get(N, 1.0)
        tag = " N = 1e%d" % round(math.log10(N))
        line(ax[0], "cube", P, [r["halo_cube"] / r["n_per_rank"] for r in rs], lw, "loglog")
        line(ax[0], "hilbert", P, [r["halo_box_max"] / r["n_per_rank"] for r in rs], lw, "loglog")
        line(ax[0], "cells", P, [r["halo_max"] / r["n_per_rank"] for r in rs], lw, "loglog")
        ax[0].annotate(tag, (P[-1], rs[-1]["halo_max"] / rs[-1]["n_per_rank"]), fontsize=7, xytext=(3, 6 * iN - 12), textcoords="offset points")
        line(ax[1], "hilbert", P, [r["messages_per_rhs_box_max"] for r in rs], lw, "semilogx")
        line(ax[1], "cells", P, [r["messages_per_rhs_max"] for r in rs], lw, "semilogx")
        line(ax[2], "hilbert", P, [r["efficiency_box"] for r in rs], lw, "semilogx")
        line(ax[2], "cells", P, [r["efficiency"] for r in rs], lw, "semilogx")
        line(ax[2], "cells_builds", P, [r["efficiency_builds"] for r in rs], lw, "semilogx")
        ax[2].annotate(tag, (P[-1], rs[-1]["efficiency_builds"]), fontsize=7, xytext=(3, 7 * iN - 10), textcoords="offset points")
    st = SOURCE_STYLE["census"]
    for c in census_rows:
        ax[0].loglog(c["P"], c["measured_max"] / (c["N"] / c["P"]), color=st["color"], marker=st["marker"], ls="", ms=8)
        ax[0].annotate("%d, %d cells/edge" % (c["N"], c["cells_per_edge"]), (c["P"], c["measured_max"] / (c["N"] / c["P"])),
                       fontsize=6, color=st["color"], xytext=(5, 2 if c["side"] == 40 else -8), textcoords="offset points")
        ax[1].semilogx(c["P"], len(EXCHANGES) * c["ranks_from_measured_max"] + RHS_ALLREDUCES, color=st["color"], marker=st["marker"], ls="", ms=8)
    ax[1].axhline(len(EXCHANGES) * 26 + RHS_ALLREDUCES, color=SOURCE_STYLE["cube"]["color"], ls=SOURCE_STYLE["cube"]["linestyle"])
    ax[0].set(xlabel="ranks P", ylabel="remote ghosts per rank / particles per rank (largest rank)",
              title="3D gas (density 1, h = 3): halo per rank, list range %.1f" % RC)
    ax[1].set(xlabel="ranks P", ylabel="messages sent per rank per RHS (largest rank)",
              title="3D gas: %d halo exchanges per RHS x neighbour ranks + 1 allreduce" % len(EXCHANGES))
    ax[2].set(xlabel="ranks P", ylabel="parallel efficiency T1 / (P T_P)", ylim=(0, 1.05),
              title="3D gas: efficiency at latency %.1f us, %.1f GB/s" % (net["alpha_s"] * 1e6, net["beta_Bps"] / 1e9))
    ax[2].text(0.02, 0.02, "T1: this machine's RHS, %.0f ns per particle (one rank, measured);\nbuilds (every %d RHS): %.0f ns per lookup, "
               "%.1f ns per box test (bound),\n%.0f ns per item (fit to the census), collectives at the latency above" % (
                   cost["fast"]["s_per_particle"] * 1e9, net["build_every"], sel["c_look_s"] * 1e9, sel["c_box_s"] * 1e9,
                   sel["c_item_s"] * 1e9), transform=ax[2].transAxes, fontsize=7, va="bottom")
    handles = [plt.Line2D([], [], color=s["color"], marker=s["marker"], ls=s["linestyle"] or "", label=s["label"])
               for s in SOURCE_STYLE.values()]
    handles += [plt.Line2D([], [], color="black", lw=N_WIDTH[n], label="N = 1e%d (line width)" % round(math.log10(n))) for n in Ns if n in N_WIDTH]
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=8)
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=110)


def markdown(rows, census_rows, cost, sel, net, stamp):
    """The README's tables, as this run computed them."""
    ratio = lambda r: "%.3f-%.3f" % tuple(r)
    out = ["Census (%s): remote ghosts per rank measured (SpamHalo, selection by occupied cells) against the selection's halo "
           "(each rank's piece of the cut dilated by rc - %.1f, the lattice's inset) and against the formula on each rank's own "
           "bounding box (an upper bound); the selection's cells measured and computed:" % (stamp, LATTICE_INSET), "",
           "| N | cells per edge (cut / selection) | P | measured max | cells formula: max (per-rank ratio) | box bound: max (per-rank ratio) | measured sum | cells formula sum | ranks heard from (measured / cells) | occupied cells max (measured / geometry) | cells sent, sum (measured / geometry) | ghost pairs: measured / surface estimate |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in census_rows:
        out.append("| %d | %d / %d | %d | %d | %.0f (%s) | %.0f (%s) | %d | %.0f | %d / %d | %d / %d | %d / %d | %.3f |" % (
            c["N"], c["cells_per_edge"], c["select_cells_per_edge"], c["P"], c["measured_max"], c["cells_formula_max"],
            ratio(c["cells_ratio"]), c["box_formula_max"], ratio(c["box_ratio"]), c["measured_sum"], c["cells_formula_sum"],
            c["ranks_from_measured_max"], c["ranks_from_cells_max"], c["occupied_measured_max"], c["occupied_geometry_max"],
            c["cells_sent_measured_sum"], c["cells_sent_geometry_sum"], c["ghost_pairs_measured_sum"] / c["ghost_pairs_surface_sum"]))
    out += ["", "The selection's cost (%s): %.1f ns per box test (the smallest upper bound of the h = 0.5 runs: CPU time over box "
            "tests); %.0f ns per particle looked up and %.0f ns per item or ghost slot, fitted to the census runs (least-loaded rank's "
            "CPU time less the box tests; relative rms residual %.2f):" % (
                stamp, sel["c_box_s"] * 1e9, sel["c_look_s"] * 1e9, sel["c_item_s"] * 1e9, sel["rel_rms"]), "",
            "| run (side, h, P) | particles | box tests | items + ghosts | CPU ms | model ms |", "|---|---|---|---|---|---|"]
    for q in sel["points"]:
        out.append("| %d, %g, %d | %d | %d | %d | %.2f | %.2f |" % (q["side"], q["h"], q["P"], q["n"], q["tests"], q["items"],
                                                                q["cpu_s"] * 1e3, q["fit_cpu_s"] * 1e3))
    out += ["", "Model (%s; latency %.1f us, %.1f GB/s, a list build every %d RHS; RHS %.0f ns per particle):" % (
                stamp, net["alpha_s"] * 1e6, net["beta_Bps"] / 1e9, net["build_every"], cost["fast"]["s_per_particle"] * 1e9), "",
            "| N | P | particles per rank | halo, cubes | halo, cells: mean / max | max / particles | halo, box bound: max | ranks heard from, mean / max | messages per RHS (max) | MB in per RHS (max) | comm / T_P | E | E with builds | E, box-bound halo | E, pair work only | a build in RHS |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append("| 1e%d | %d | %.0f | %.0f | %.0f / %.0f | %.2f | %.0f | %.1f / %d | %d | %.2f | %.1f %% | %.3f | %.3f | %.3f | %.3f | %.1f |" % (
            round(math.log10(r["N"])), r["P"], r["n_per_rank"], r["halo_cube"], r["halo_mean"], r["halo_max"],
            r["halo_max"] / r["n_per_rank"], r["halo_box_max"], r["ranks_from_mean"], r["ranks_from_max"], r["messages_per_rhs_max"],
            r["bytes_in_per_rhs_max"] / 1e6, 100 * r["tp_comm_s"] / r["tp_s"], r["efficiency"], r["efficiency_builds"],
            r["efficiency_box"], r["efficiency_compute_only"], r["build_over_rhs"]))
    out += [""] + readings(rows, census_rows, sel)
    return "\n".join(out) + "\n"


def readings(rows, census_rows, sel):
    """The figures the README's findings quote, computed here from the tables above."""
    def at(N, P):
        return next((r for r in rows if r["N"] == N and r["P"] == P), None)
    out = ["Readings (computed from the tables above):", ""]
    out.append("- census, the cells formula over the measured halo, rank by rank: %.3f-%.3f (sums %.3f-%.3f); the bounding-box "
               "formula: %.3f-%.3f" % (
                   min(c["cells_ratio"][0] for c in census_rows), max(c["cells_ratio"][1] for c in census_rows),
                   min(c["cells_formula_sum"] / c["measured_sum"] for c in census_rows),
                   max(c["cells_formula_sum"] / c["measured_sum"] for c in census_rows),
                   min(c["box_ratio"][0] for c in census_rows), max(c["box_ratio"][1] for c in census_rows)))
    out.append("- the selection's cells, measured / -geometry: occupied (largest rank) %s; sent (sum over ranks) %s" % (
        ", ".join("%d/%d" % (c["occupied_measured_max"], c["occupied_geometry_max"]) for c in census_rows),
        ", ".join("%d/%d" % (c["cells_sent_measured_sum"], c["cells_sent_geometry_sum"]) for c in census_rows)))
    big = at(10 ** 8, 1000)
    if big:
        out.append("- N = 1e8, P = 1000: E %.3f, with builds %.3f (a build costs %.1f RHS evaluations of the slowest rank: %d box "
                   "tests at %.1f ns, %.0f particles at %.0f ns); with the bounding-box halo E %.3f; halo max %.0f (cells) against "
                   "%.0f (box bound), %.2f and %.2f times the particles per rank; ranks heard from max %d (box: %d)" % (
                       big["efficiency"], big["efficiency_builds"], big["build_over_rhs"], big["box_tests_max"], sel["c_box_s"] * 1e9,
                       big["n_per_rank"], sel["c_look_s"] * 1e9, big["efficiency_box"], big["halo_max"], big["halo_box_max"],
                       big["halo_max"] / big["n_per_rank"], big["halo_box_max"] / big["n_per_rank"], big["ranks_from_max"],
                       big["ranks_from_box_max"]))
    if big:
        out.append("- N = 1e8, P = 1000: the cells halo is %.2f (mean) and %.2f (largest rank) times the ideal cube's %.0f; the "
                   "bounding-box bound %.1f times; messages per RHS (largest rank) %d, %d with the bounding boxes, %d for cubes" % (
                       big["halo_mean"] / big["halo_cube"], big["halo_max"] / big["halo_cube"], big["halo_cube"],
                       big["halo_box_max"] / big["halo_cube"], big["messages_per_rhs_max"], big["messages_per_rhs_box_max"],
                       len(EXCHANGES) * 26 + RHS_ALLREDUCES))
    worst = max(rows, key=lambda r: r["build_over_rhs"])
    out.append("- a build costs at most %.1f RHS evaluations (N = 1e%d, P = %d); E with builds is within %.3f of E everywhere "
               "(largest gap at N = 1e%d, P = %d)" % (
                   worst["build_over_rhs"], round(math.log10(worst["N"])), worst["P"],
                   max(r["efficiency"] - r["efficiency_builds"] for r in rows),
                   round(math.log10(max(rows, key=lambda r: r["efficiency"] - r["efficiency_builds"])["N"])),
                   max(rows, key=lambda r: r["efficiency"] - r["efficiency_builds"])["P"]))
    small = [r for r in rows if r["tp_comm_s"] / r["tp_s"] < 0.10]
    if small:
        out.append("- communication under 10 %% of T_P down to %.0f particles per rank (the smallest such row: N = 1e%d, P = %d)" % (
            min(r["n_per_rank"] for r in small), round(math.log10(min(small, key=lambda r: r["n_per_rank"])["N"])),
            min(small, key=lambda r: r["n_per_rank"])["P"]))
    hb = [r["halo_box_max"] / r["halo_max"] for r in rows if r["P"] >= 8]
    out.append("- the bounding-box bound over the cells halo (largest rank), P >= 8: %.1f-%.1f times" % (min(hb), max(hb)))
    return out


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
    t0, load0 = time.time(), os.getloadavg()

    cost = rhs_cost(a.spam_ark, a.repeats)
    print("RHS on this machine, 3D expansion N = %d, one rank: %.1f ns per particle (%.2f ns per pair); runs %s" % (
              cost["N"], cost["fast"]["s_per_particle"] * 1e9, cost["fast"]["ns_per_pair"],
              ", ".join("%.0f" % (x[0] * 1e9) for x in cost["fast"]["runs"])), flush=True)
    census_rows = check_census(a.census, a.repeats)
    # The selection's cost. The box tests weigh only where P is large, which no run on 2
    # cores reaches; and the CPU time of an oversubscribed rank includes its MPI polling for
    # descheduled peers (least on the least-loaded rank, which each run's point takes). A
    # least-squares fit of all three constants could not pin c_box on the shared machine
    # (0 to 15 ns in three runs), so c_box is bounded from above by runs made of box tests
    # (h = 0.5: a cell per particle, no items) and the rest fitted to the census runs.
    sel = fit_selection([dict(c["fit_point"], side=c["side"], h=H) for c in census_rows], calibration(a.census, a.repeats))
    print("halo selection: %.2f ns per box test (occupied cell, other rank; the smallest upper bound of the h = 0.5 runs); "
          "fit to the %d census runs: %.1f ns per particle looked up, %.1f ns per item or ghost slot; relative rms residual %.2f" % (
              sel["c_box_s"] * 1e9, len(census_rows), sel["c_look_s"] * 1e9, sel["c_item_s"] * 1e9, sel["rel_rms"]), flush=True)

    rows = []
    for N in (int(float(x)) for x in a.sizes.split(",")):
        side = round(N ** (1 / 3))
        for P in (int(x) for x in a.ranks.split(",")):
            g = geometry(a.census, side, P)
            g["side"] = side
            r = model_row(side ** 3, P, g, cost, net, sel)
            r["N_nominal"] = N
            rows.append(r)
            print("N %.0e P %4d: n/rank %9.0f halo cube %8.0f cells mean %8.0f max %8.0f (max/n %.2f), box bound max %8.0f | ranks heard "
                  "from mean %.1f max %d (box %d) | msgs/RHS %d | bytes in/RHS %.2e | T1 %.3e s TP %.3e s (comm %.1f%%) E %.3f, with builds "
                  "%.3f, box-bound halo %.3f, compute only %.3f | build = %.1f RHS (box tests %d)" % (
                      N, P, r["n_per_rank"], r["halo_cube"], r["halo_mean"], r["halo_max"], r["halo_max"] / r["n_per_rank"],
                      r["halo_box_max"], r["ranks_from_mean"], r["ranks_from_max"], r["ranks_from_box_max"], r["messages_per_rhs_max"],
                      r["bytes_in_per_rhs_max"], r["t1_s"], r["tp_s"], 100 * r["tp_comm_s"] / r["tp_s"], r["efficiency"],
                      r["efficiency_builds"], r["efficiency_box"], r["efficiency_compute_only"], r["build_over_rhs"], r["box_tests_max"]),
                  flush=True)
    for r in rows:
        r["N"] = r["N_nominal"]
    commit = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    load = (load0, os.getloadavg())
    # The stamp is copied into bench/README.md, which names no commit (the JSON keeps it).
    stamp = "`%s`, %.0f s, load average %.1f at the start and %.1f at the end on %d cores" % (
        " ".join(["bench/halo_model.py"] + sys.argv[1:]),
        time.time() - t0, load[0][0], load[1][0], os.cpu_count())
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    json.dump({"commit": commit, "stamp": stamp, "command": " ".join(sys.argv), "h": H, "skin": SKIN, "rc": RC, "network": net,
               "exchanges": EXCHANGES, "rhs_cost": cost, "selection_fit": sel, "load": load, "census": census_rows, "table": rows},
              open(a.out, "w"), indent=1)
    chart(rows, census_rows, net, cost, sel, a.png)
    # The readings bench/README.md quotes, beside the chart with the command and commit.
    sys.path.insert(0, os.path.join(REPO, "examples"))
    import chart_readings
    chart_readings.write(a.png, {"readings": "\n".join(readings(rows, census_rows, sel)[2:]) + "\n",
                                 "rhs_ns_per_particle": cost["fast"]["s_per_particle"] * 1e9,
                                 "seconds": time.time() - t0, "load_1min_start": load[0][0]})
    with open(os.path.splitext(a.out)[0] + ".md", "w") as f:
        f.write(markdown(rows, census_rows, cost, sel, net, stamp))
    print("wrote %s, %s.md and %s (%s)" % (a.out, os.path.splitext(a.out)[0], a.png, stamp))

if __name__ == "__main__":
    main()
