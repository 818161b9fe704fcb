"""The report of run_bench.py: the per-case tables, the summary table, the targets T1-T3
and the -log_view table."""

import math

from bench_common import fnum
from spam_driver import LOG_VIEW_SUBSTRINGS
from bench_cases import solid_reference


NA = object()  # a row that does not apply to that program


def _ms(x):
    return x * 1e3 if x else None


def _mega(x):
    return x / 1e6 if x else None


def _row(label, sv, lv, fmt="%.3f", ratio=False, have_s=True, width=50):
    s = "" if sv is NA else (fnum(sv, fmt) if have_s else "n/a")
    ls = "" if lv is NA else fnum(lv, fmt)
    rr = ""
    if (ratio and sv is not NA and lv is not NA and sv and lv
            and not (isinstance(lv, float) and math.isnan(lv))):
        rr = "%.3f" % (sv / lv)
    print("  %-*s %14s %14s %9s" % (width, label, s, ls, rr))


def print_gas(res, base):
    n = res["n"]
    L, S = res["lammps"], res["spam"]
    have_s = bool(S)
    print()
    print("== %s, N = %d  (%dx%d lattice in a periodic %gx%g box, dt = %g, %d steps)"
          % (res["label"], n, res["nx"], res["nx"], res["box"][0], res["box"][1],
             res["dt"], res["spam_steps"]))
    print("  initial particles: %s" % res["initial_source"])
    print("  pairs i<j with r < h: initial %d (numpy), %d (LAMMPS coord/atom at step 0);"
          % (res["pairs_initial"], res["pairs_lammps_step0"] or -1))
    print("    the gas expands, so the count falls: %d after %d steps; time-mean %.0f "
          "over the LAMMPS window, %.0f over the spam-ark window"
          % (res["pairs_end_lammps_window"], res["lammps_steps"],
             res["pairs_mean_lammps_window"] or float("nan"),
             res["pairs_mean_spam_window"] or float("nan")))

    def row(label, sv, lv, fmt="%.3f", ratio=False):
        _row(label, sv, lv, fmt, ratio, have_s)

    print("  %-50s %14s %14s %9s" % ("", "spam-ark", "LAMMPS", "ratio"))
    row("steps", S.get("steps"), res["lammps_steps"], "%.0f")
    row("force (RHS) evaluations", S.get("rhs_evals"), res["lammps_steps"], "%.0f")
    row("time per force (RHS) evaluation (ms)", _ms(S.get("time_per_eval_s")),
        _ms(L["time_per_eval_s"]), "%.3f", ratio=True)
    row("  LAMMPS Pair section only (ms)", NA, _ms(L["pair_time_per_eval_s"]))
    row("  same, LAMMPS Pair + Neigh sections only", _ms(S.get("time_per_eval_s")),
        _ms(L["pair_neigh_time_per_eval_s"]), "%.3f", ratio=True)
    row("time per step (ms)", _ms(S.get("time_per_step_s")), _ms(L["time_per_step_s"]),
        "%.3f", ratio=True)
    row("particle-steps per second per core (millions)",
        _mega(S.get("particle_steps_per_s")), _mega(L["particle_steps_per_s"]), "%.3f",
        ratio=True)
    row("time per force evaluation / N (ns)",
        S.get("time_per_eval_per_particle_s") and S["time_per_eval_per_particle_s"] * 1e9,
        L["time_per_eval_per_particle_s"] * 1e9, "%.2f", ratio=True)
    row("ns per pair, initial pair count", S.get("ns_per_pair_initial"),
        L["ns_per_pair_initial"], "%.2f", ratio=True)
    row("ns per pair, time-mean pair count", S.get("ns_per_pair_mean"),
        L["ns_per_pair_mean"], "%.2f", ratio=True)
    row("ns per pair, spam-ark's own count", S.get("ns_per_pair_self_reported"), NA, "%.2f")
    row("neighbour list builds", S.get("neighbour_builds"), L["neighbor_builds"], "%.0f")
    row("peak RSS (MiB, ru_maxrss)",
        S.get("ru_maxrss_bytes") and S["ru_maxrss_bytes"] / 2 ** 20,
        L["ru_maxrss_bytes"] / 2 ** 20, "%.1f")
    row("peak RSS / N (bytes, incl. runtime baseline)",
        S.get("rss_per_particle_bytes"), L["rss_per_particle_bytes"], "%.0f")
    row("(peak RSS - 64-particle run) / N (bytes)",
        S.get("rss_minus_baseline_per_particle_bytes"),
        L["rss_minus_baseline_per_particle_bytes"], "%.0f")
    row("  spam-ark peak_rss_bytes / N (self-reported)",
        S.get("self_rss_per_particle_bytes"), NA, "%.0f")
    row("  LAMMPS 'memory allocation' (MiB)", NA, L["lammps_memory_mbytes"], "%.2f")
    if "energy_rel_drift" in L:
        print("  relative energy change over the run: spam-ark %s, LAMMPS %.2e"
              % (fnum(S.get("energy_rel_drift"), "%.2e"), L["energy_rel_drift"]))
    cons = res.get("consistency") or {}
    if "energy_initial_rel_diff" in cons:
        print("  same physics? E(0): spam-ark %.10g, LAMMPS KE+PE+N m^2 w(0)/2 %.10g "
              "(rel diff %.1e)" % (cons["energy_initial_spam"],
                                   cons["energy_initial_lammps_plus_self"],
                                   cons["energy_initial_rel_diff"]))
    if cons.get("kinetic_final_rel_diff") is not None:
        print("                KE at the last step: spam-ark %.10g, LAMMPS %.10g "
              "(rel diff %.1e)" % (cons["kinetic_final_spam"], cons["kinetic_final_lammps"],
                                   cons["kinetic_final_rel_diff"]))
    if S.get("summary_keys_missing"):
        print("  note: spam-ark summary.json lacks %s" % ", ".join(S["summary_keys_missing"]))
    if S.get("loop_wall_note"):
        print("  note: %s" % S["loop_wall_note"])
    if "ratio_time_per_eval" in res:
        print("  spam-ark time per RHS evaluation / LAMMPS time per step = %.3f"
              % res["ratio_time_per_eval"])
    else:
        print("  spam-ark / LAMMPS: not measured (spam-ark not run)")


def print_solid(res, results):
    n = res["n"]
    S = res["spam"]
    print()
    print("== %s, N = %d  (%dx%d triangular lattice in a periodic %.6gx%.6g box, "
          "dt = %g, %d steps)" % (res["label"], n, res["nx"], res["ny"], res["box"][0],
                                  res["box"][1], res["dt"], res["spam_steps"]))
    print("  pairs i<j with r < h: initial %d, after the run %s (numpy); mean %.0f"
          % (res["pairs_initial"], fnum(res.get("pairs_final"), "%d"),
             res["pairs_mean_spam_window"]))

    def row(label, sv, fmt="%.3f"):
        print("  %-50s %14s" % (label, fnum(sv, fmt)))

    print("  %-50s %14s" % ("", "spam-ark"))
    row("steps", S.get("steps"), "%.0f")
    row("force (RHS) evaluations", S.get("rhs_evals"), "%.0f")
    row("time per force (RHS) evaluation (ms)", _ms(S.get("time_per_eval_s")))
    row("time per step (ms)", _ms(S.get("time_per_step_s")))
    row("particle-steps per second per core (millions)",
        _mega(S.get("particle_steps_per_s")))
    row("time per force evaluation / N (ns)",
        S.get("time_per_eval_per_particle_s") and S["time_per_eval_per_particle_s"] * 1e9,
        "%.2f")
    row("ns per pair, time-mean pair count", S.get("ns_per_pair_mean"), "%.2f")
    row("ns per pair, spam-ark's own count", S.get("ns_per_pair_self_reported"), "%.2f")
    row("neighbour list builds", S.get("neighbour_builds"), "%.0f")
    row("peak RSS (MiB, ru_maxrss)",
        S.get("ru_maxrss_bytes") and S["ru_maxrss_bytes"] / 2 ** 20, "%.1f")
    row("peak RSS / N (bytes, incl. runtime baseline)", S.get("rss_per_particle_bytes"),
        "%.0f")
    row("(peak RSS - 64-particle run) / N (bytes)",
        S.get("rss_minus_baseline_per_particle_bytes"), "%.0f")
    row("  spam-ark peak_rss_bytes / N (self-reported)",
        S.get("self_rss_per_particle_bytes"), "%.0f")
    print("  relative energy (KE + IE) change over the run: %s"
          % fnum(S.get("energy_rel_drift"), "%.2e"))
    ref = solid_reference(res, results)
    res["reference"] = ref
    if ref and ref.get("ratio_time_per_eval"):
        print("  reference cost, not the same dynamics: solid time per RHS evaluation / "
              "LAMMPS gas (%s, N = %d) time per step = %.3f%s"
              % (ref["gas_case"], ref["gas_n"], ref["ratio_time_per_eval"],
                 "" if ref["gas_n"] == n else
                 " (per particle: %.3f)" % ref["ratio_time_per_eval_per_particle"]))
        if ref.get("ratio_to_spam_gas_per_particle"):
            print("    (and per particle against spam-ark's own gas at that N: %.2fx)"
                  % ref["ratio_to_spam_gas_per_particle"])
    else:
        print("  reference cost: no LAMMPS gas run at h = %g to compare with" % res["h"])


def print_summary(results):
    print()
    print("Summary (medians; one core per program; 'B/part' = bytes per particle; "
          "ratio = spam-ark time per RHS evaluation / LAMMPS time per step)")
    hdr = ("%-9s %8s %5s %-8s %8s %9s %9s %10s %8s %8s %8s"
           % ("case", "N", "steps", "program", "ns/pair", "ms/force", "ms/step",
              "Mpart-st/s", "B/part", "B/part", "ratio"))
    print("  " + hdr)
    print("  " + ("%-9s %8s %5s %-8s %8s %9s %9s %10s %8s %8s %8s"
                  % ("", "", "", "", "(mean)", "eval", "", "per core", "RSS-base",
                     "self", "")))
    for r in results:
        S = r.get("spam") or {}
        ratio = r.get("ratio_time_per_eval")
        if r.get("kind") == "solid" and r.get("reference"):
            ratio = r["reference"].get("ratio_time_per_eval")
        if S:
            print("  %-9s %8d %5s %-8s %8s %9s %9s %10s %8s %8s %8s%s"
                  % (r["case"], r["n"], fnum(S.get("steps"), "%.0f"), "spam-ark",
                     fnum(S.get("ns_per_pair_mean"), "%.2f"),
                     fnum(_ms(S.get("time_per_eval_s")), "%.3f"),
                     fnum(_ms(S.get("time_per_step_s")), "%.2f"),
                     fnum(_mega(S.get("particle_steps_per_s")), "%.3f"),
                     fnum(S.get("rss_minus_baseline_per_particle_bytes"), "%.0f"),
                     fnum(S.get("self_rss_per_particle_bytes"), "%.0f"),
                     fnum(ratio, "%.3f"),
                     "  (reference cost vs the LAMMPS gas, not the same dynamics)"
                     if r.get("kind") == "solid" and ratio else ""))
        L = r.get("lammps")
        if L:
            print("  %-9s %8d %5d %-8s %8s %9s %9s %10s %8s %8s"
                  % ("" if S else r["case"], r["n"], r["lammps_steps"], "LAMMPS",
                     fnum(L.get("ns_per_pair_mean"), "%.2f"),
                     fnum(_ms(L.get("time_per_eval_s")), "%.3f"),
                     fnum(_ms(L.get("time_per_step_s")), "%.2f"),
                     fnum(_mega(L.get("particle_steps_per_s")), "%.3f"),
                     fnum(L.get("rss_minus_baseline_per_particle_bytes"), "%.0f"), "-"))


PAGE_COLUMNS = ["case", "N", "spam-ark ms/RHS", "LAMMPS ms/step", "ratio", "spam-ark ns/pair", "B/particle (RSS − base)"]


def page_rows(results):
    """bench/README.md's table (formatted cells): a row per case and size; the solid's ratio
    is against the LAMMPS gas at the same N (a reference cost, marked *)."""
    rows = []
    for r in results:
        S, L = r.get("spam") or {}, r.get("lammps") or {}
        ratio = r.get("ratio_time_per_eval")
        star = ""
        if r.get("kind") == "solid":
            ratio, star = (r.get("reference") or {}).get("ratio_time_per_eval"), "*"
        kind, h = r["case"].split("-h")
        rows.append([f"{kind} h = {h}", str(r["n"]),
                     fnum(_ms(S.get("time_per_eval_s")), "%.3f"), fnum(_ms(L.get("time_per_step_s")), "%.3f") if L else "–",
                     fnum(ratio, "%.3f") + (star if ratio else ""), fnum(S.get("ns_per_pair_mean"), "%.2f"),
                     fnum(S.get("rss_minus_baseline_per_particle_bytes"), "%.0f")])
    return rows


T1_N, T1_H, T1_MAX = 65536, 3.0, 0.5
T2_N0, T2_N1, T2_H, T2_MAX = 16384, 1048576, 3.0, 0.20
T3_H, T3_MAX = 3.0, 1024.0


def _verdict(ok):
    return "met" if ok else "falls short"


def evaluate_targets(results):
    gas = sorted([r for r in results if r.get("kind") == "gas" and r.get("h") == T1_H
                  and r.get("spam", {}).get("time_per_eval_s")], key=lambda r: r["n"])
    t = {}
    lines = []

    # T1: spam-ark time per force evaluation <= 0.5 x LAMMPS time per step.
    rec = {"target": "spam-ark time per force evaluation <= %.1f x LAMMPS time per "
                     "step at N = %d, h = %g" % (T1_MAX, T1_N, T1_H),
           "n_wanted": T1_N}
    cands = [r for r in gas if r.get("lammps", {}).get("time_per_step_s")]
    if cands:
        r = min(cands, key=lambda r: abs(math.log(r["n"] / T1_N)))
        s_ev, l_st = r["spam"]["time_per_eval_s"], r["lammps"]["time_per_step_s"]
        ratio = s_ev / l_st
        rec.update({"n": r["n"], "spam_time_per_eval_s": s_ev,
                    "lammps_time_per_step_s": l_st, "ratio": ratio,
                    "met": ratio <= T1_MAX, "at_wanted_n": r["n"] == T1_N})
        lines.append("T1  %s: spam-ark %.3f ms per force evaluation, LAMMPS %.3f ms per "
                     "step, ratio %.3f (target <= %.1f): %s%s"
                     % ("N = %d, h = %g" % (r["n"], T1_H), s_ev * 1e3, l_st * 1e3, ratio,
                        T1_MAX, _verdict(rec["met"]),
                        "" if rec["at_wanted_n"] else
                        "  [measured at N = %d, not %d]" % (r["n"], T1_N)))
    else:
        rec["met"] = None
        lines.append("T1  not measured (no gas run at h = %g with both programs)" % T1_H)
    t["T1"] = rec

    # T2: cost per particle-step grows by < 20 % from N = 16384 to N = 1048576.
    rec = {"target": "spam-ark time per RHS evaluation / N grows by less than %d%% "
                     "from N = %d to N = %d, gas h = %g"
                     % (round(T2_MAX * 100), T2_N0, T2_N1, T2_H)}
    if len(gas) >= 2:
        hi = gas[-1]
        lo = next((r for r in gas if r["n"] == T2_N0 and r["n"] < hi["n"]), gas[0])
        if hi["n"] > lo["n"]:
            c0 = lo["spam"]["time_per_eval_s"] / lo["n"]
            c1 = hi["spam"]["time_per_eval_s"] / hi["n"]
            g = c1 / c0 - 1.0
            p0, p1 = lo["spam"].get("ns_per_pair_mean"), hi["spam"].get("ns_per_pair_mean")
            rec.update({"n_from": lo["n"], "n_to": hi["n"],
                        "ns_per_particle_eval_from": c0 * 1e9,
                        "ns_per_particle_eval_to": c1 * 1e9, "growth": g,
                        "met": g < T2_MAX, "to_wanted_n": hi["n"] == T2_N1,
                        "ns_per_pair_from": p0, "ns_per_pair_to": p1,
                        "ns_per_pair_growth": (p1 / p0 - 1.0) if p0 and p1 else None})
            note = []
            if lo["n"] != T2_N0:
                note.append("from N = %d, the smallest size run" % lo["n"])
            if hi["n"] != T2_N1:
                note.append("to N = %d, the largest size run, not %d" % (hi["n"], T2_N1))
            lines.append("T2  gas h = %g: time per RHS evaluation / N = %.2f ns at N = %d, "
                         "%.2f ns at N = %d: growth %+.1f%% (target < %d%%): %s%s"
                         % (T2_H, c0 * 1e9, lo["n"], c1 * 1e9, hi["n"], 100 * g,
                            round(T2_MAX * 100), _verdict(rec["met"]),
                            "  [%s]" % "; ".join(note) if note else ""))
            if rec["ns_per_pair_growth"] is not None:
                lines.append("      (per pair within h, time-mean: %.2f -> %.2f ns, %+.1f%%%s)"
                             % (p0, p1, 100 * rec["ns_per_pair_growth"],
                                "; the runs cover different physical times (%d and %d "
                                "steps), so the pairs per particle differ"
                                % (lo["spam_steps"], hi["spam_steps"])
                                if lo["spam_steps"] != hi["spam_steps"] else ""))
        else:
            rec["met"] = None
    if "growth" not in rec:
        rec["met"] = None
        lines.append("T2  not measured (needs the gas at h = %g at two sizes)" % T2_H)
    t["T2"] = rec

    # T3: (peak RSS - baseline) / N <= 1 KiB for the gas, at the largest size run.
    rec = {"target": "(peak RSS - 64-particle baseline) / N <= %d bytes for the "
                     "isentropic gas with Dormand-Prince, at the largest size run"
                     % T3_MAX}
    mem = [r for r in gas if r["spam"].get("rss_minus_baseline_per_particle_bytes")]
    if mem:
        r = mem[-1]
        b = r["spam"]["rss_minus_baseline_per_particle_bytes"]
        selfb = r["spam"].get("self_rss_per_particle_bytes")
        rec.update({"n": r["n"], "h": r["h"], "bytes_per_particle": b,
                    "self_reported_bytes_per_particle": selfb, "met": b <= T3_MAX,
                    "lammps_bytes_per_particle":
                        r["lammps"].get("rss_minus_baseline_per_particle_bytes")})
        lines.append("T3  gas h = %g, N = %d: (peak RSS - baseline) / N = %.0f bytes "
                     "(target <= %d): %s   [self-reported peak_rss_bytes / N = %s, "
                     "LAMMPS %s]"
                     % (T3_H, r["n"], b, T3_MAX, _verdict(rec["met"]),
                        fnum(selfb, "%.0f"),
                        fnum(rec["lammps_bytes_per_particle"], "%.0f")))
    else:
        rec["met"] = None
        lines.append("T3  not measured (no gas run at h = %g with a memory baseline)" % T3_H)
    t["T3"] = rec
    return t, lines


def print_log_view(rec):
    print()
    print("PETSc -log_view (untimed spam-ark run, gas h = %g, N = %d, %d steps): %s"
          % (rec["h"], rec["n"], rec["steps"], rec["file"]))
    if rec.get("error"):
        print("  %s" % rec["error"])
        return
    print("  events whose name contains %s; total time %s s, spam-ark RHS time %s s "
          "over %s evaluations"
          % (" or ".join('"%s"' % s for s in LOG_VIEW_SUBSTRINGS),
             fnum(rec.get("total_time_s"), "%.3f"), fnum(rec.get("rhs_time_s"), "%.3f"),
             rec.get("rhs_evals")))
    print("  %-24s %9s %11s %13s %6s %9s" % ("event", "count", "time (s)", "ms per call",
                                             "%T", "Mflop/s"))
    for e in rec.get("events", []):
        print("  %-24s %9d %11.4e %13.4f %6.0f %9.0f"
              % (e["event"], e["count"], e["time_s"],
                 1e3 * e["time_s"] / e["count"] if e["count"] else float("nan"),
                 e["pct_time"], e["mflops"]))
    if not rec.get("events"):
        print("  (no matching events in the table)")
