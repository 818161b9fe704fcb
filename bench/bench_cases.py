"""The cases of run_bench.py: which cases, how many steps, the memory baselines, and one case
at one size (gas against LAMMPS, solid alone), each returning a dict of its measurements."""

import json
import math
import re
import time
from pathlib import Path

from bench_common import (DT, REPO_ROOT, count_pairs, lucy_w, med, np, numpy_lattice,
                          read_particles_csv, run_measured, tail,
                          window_mean, write_particles_csv)
from peer_lammps import lammps_run, write_lammps_data, write_table
from spam_driver import (SOLID_PHYSICS, parse_log_view, solid_cmd, solid_shape, spam_make_initial,
                         spam_run, spam_run_cmd)


# Default step counts: STEPS_AT_16384[kind] * (3/h) * 16384/N, clamped to
# [MIN_STEPS, MAX_STEPS]; chosen so that one timed spam-ark run takes a few
# seconds on this machine (1-4 s up to N = 262144, longer at 1048576, where
# MIN_STEPS decides).  The gas does not get more steps: the longer the run,
# the more pairs the expanding gas loses, and the less the cost per particle
# at different N measures the same thing (T2).
STEPS_AT_16384 = {"gas": 160, "solid": 64}
MIN_STEPS = 4
MAX_STEPS = 2000


def parse_cases(text):
    """'gas-h3,gas-h6,solid-h3' -> list of case dicts (name, kind, h, label)."""
    cases = []
    for tok in (t.strip() for t in text.split(",")):
        if not tok:
            continue
        m = re.fullmatch(r"(gas|solid)-h(\d+(?:\.\d*)?|\.\d+)", tok)
        if not m:
            raise SystemExit("--cases: %r is not gas-hH or solid-hH (e.g. gas-h3, "
                             "solid-h3)" % tok)
        kind, h = m.group(1), float(m.group(2))
        if h <= 0:
            raise SystemExit("--cases: %r needs h > 0" % tok)
        label = ("gas h=%g (isentrope P = rho^2/2; LAMMPS pair_style table)" % h
                 if kind == "gas" else
                 "solid h=%g (elastic, continuity density, R2; spam-ark only)" % h)
        cases.append({"name": "%s-h%g" % (kind, h), "kind": kind, "h": h,
                      "label": label})
    if not cases:
        raise SystemExit("--cases: no case given")
    # A solid's reference is the LAMMPS gas at the same h: run gases first.
    return sorted(cases, key=lambda c: (c["kind"] != "gas", c["h"]))


def steps_for(case, n, args):
    """(LAMMPS steps, spam-ark steps) for a case and size.

    Default: STEPS_AT_16384[kind] * (3/h) * 16384/N, at least MIN_STEPS and
    at most MAX_STEPS, so that one timed spam-ark run takes a few seconds.
    """
    if args.steps is not None:
        base = args.steps
    else:
        k = STEPS_AT_16384[case["kind"]] * (3.0 / case["h"])
        base = int(min(MAX_STEPS, max(MIN_STEPS, round(k * 16384 / n))))
    ls = args.lammps_steps if args.lammps_steps is not None else base
    ss = args.spam_steps if args.spam_steps is not None else base
    return ls, ss


def per_particle(x, base, n):
    """(x - base) / n, or None when either is unknown."""
    if not x or not base or not n:
        return None
    return (x - base) / n


def summarize_spam(spam, n, pairs_mean, pairs0, baseline_rss):
    """Medians over the spam-ark runs of one case and size."""
    def sget(r, key):
        v = r["summary"].get(key)
        return float(v) if isinstance(v, (int, float)) else None

    S = {}
    per_eval, per_step = [], []
    for r in spam:
        rt, ne, ns = sget(r, "rhs_time_s"), sget(r, "rhs_evals"), sget(r, "steps")
        per_eval.append(rt / ne if rt is not None and ne else None)
        loop = r.get("loop_wall_s")
        if loop is None:
            loop = sget(r, "wall_time_s")
        per_step.append(loop / ns if loop is not None and ns else None)
    S["time_per_eval_s"] = med(per_eval)
    S["time_per_step_s"] = med(per_step)
    S["time_per_eval_s_runs"] = per_eval
    S["time_per_step_s_runs"] = per_step
    S["rhs_evals"] = med([sget(r, "rhs_evals") for r in spam])
    S["steps"] = med([sget(r, "steps") for r in spam])
    S["rhs_evals_per_step"] = (S["rhs_evals"] / S["steps"]
                               if S["rhs_evals"] and S["steps"] else None)
    S["wall_time_s"] = med([sget(r, "wall_time_s") for r in spam])
    S["loop_wall_s"] = med([r.get("loop_wall_s") for r in spam])
    S["rhs_time_s"] = med([sget(r, "rhs_time_s") for r in spam])
    S["ns_per_pair_self_reported"] = med([sget(r, "ns_per_pair") for r in spam])
    S["pair_interactions_per_s"] = med([sget(r, "pair_interactions_per_s") for r in spam])
    S["peak_rss_bytes_self_reported"] = med([sget(r, "peak_rss_bytes") for r in spam])
    S["neighbour_builds"] = med([sget(r, "neighbour_builds") for r in spam])
    S["n_particles"] = med([sget(r, "n_particles") for r in spam])
    S["ru_maxrss_bytes"] = med([r["ru_maxrss_bytes"] for r in spam])
    te, ts = S["time_per_eval_s"], S["time_per_step_s"]
    S["time_per_eval_per_particle_s"] = te / n if te else None
    S["particle_steps_per_s"] = n / ts if ts else None
    S["ns_per_pair_initial"] = te / pairs0 * 1e9 if te and pairs0 else None
    S["ns_per_pair_mean"] = te / pairs_mean * 1e9 if te and pairs_mean else None
    S["rss_per_particle_bytes"] = S["ru_maxrss_bytes"] / n if S["ru_maxrss_bytes"] else None
    S["rss_minus_baseline_per_particle_bytes"] = per_particle(
        S["ru_maxrss_bytes"], baseline_rss, n)
    S["self_rss_per_particle_bytes"] = (S["peak_rss_bytes_self_reported"] / n
                                        if S["peak_rss_bytes_self_reported"] else None)
    missing = [k for k in ("rhs_evals", "steps", "wall_time_s", "rhs_time_s",
                           "pair_interactions_per_s", "ns_per_pair",
                           "peak_rss_bytes", "n_particles", "neighbour_builds")
               if k not in spam[0]["summary"]]
    if missing:
        S["summary_keys_missing"] = missing
    if not all(r.get("loop_wall_s") is not None for r in spam):
        S["loop_wall_note"] = "timeseries.csv wall_s missing; used summary wall_time_s"
    s0 = spam[0]["summary"]
    if isinstance(s0.get("energy_rel_drift_final"), (int, float)):
        S["energy_rel_drift"] = float(s0["energy_rel_drift_final"])
    return S


def bench_gas(n, case, args, workdir, pin, spam_ok, table_cache, base):
    nx = int(round(math.sqrt(n)))
    if nx * nx != n:
        raise SystemExit("gas size %d is not a perfect square NX^2" % n)
    h = case["h"]
    box = np.array([2.0 * nx, 2.0 * nx])
    lsteps, ssteps = steps_for(case, n, args)
    res = {"case": case["name"], "kind": "gas", "label": case["label"],
           "n": n, "nx": nx, "box": box.tolist(), "h": h, "dt": DT,
           "lammps_steps": lsteps, "spam_steps": ssteps}

    # ---- initial particles -------------------------------------------------
    if spam_ok and not args.numpy_initial:
        csv, res["initial_cmd"] = spam_make_initial(args.spam_ark, nx, h, workdir)
        res["initial_source"] = "spam-ark -initial_csv"
    else:
        csv = workdir / ("initial_%d_numpy.csv" % nx)
        if not csv.exists():
            write_particles_csv(csv, *numpy_lattice(nx))
        res["initial_source"] = "numpy lattice (not spam-ark's -initial_csv)"
    pos, vel, mass, header = read_particles_csv(csv)
    res["csv_header"] = header
    if len(pos) != n:
        print("  note: initial CSV has %d particles, expected %d" % (len(pos), n))
    inside = bool(np.all((pos >= 0) & (pos <= box)))
    res["initial_inside_box"] = inside
    lo, hi = pos.min(axis=0), pos.max(axis=0)
    res["initial_extent"] = [lo.tolist(), hi.tolist()]
    if not inside or np.any(hi - lo < nx - 2) or np.any(hi - lo > nx + 1):
        print("  WARNING: the initial particles do not look like a %dx%d lattice of "
              "spacing 1 inside the box: x in [%g, %g], y in [%g, %g]"
              % (nx, nx, lo[0], hi[0], lo[1], hi[1]))
        res["initial_looks_wrong"] = True
    m0 = float(mass[0])
    if not np.allclose(mass, m0):
        print("  note: masses differ (min %g max %g); LAMMPS uses their mean"
              % (mass.min(), mass.max()))
        m0 = float(mass.mean())
    res["mass"] = m0
    # With mass m the SPAM force is m^2 * (-grad w) and the acceleration
    # m * (-grad w): pair potential m^2 w with atom mass m.
    scale = m0 * m0
    key = (h, scale)
    if key not in table_cache:
        table = workdir / ("table_h%g_m%g.dat" % (h, m0))
        table_cache[key] = (table, write_table(table, h, args.table_points,
                                               args.table_rlo, scale))
    table, tcheck = table_cache[key]
    res["table_check"] = tcheck
    data = workdir / ("lammps_%d_h%g.data" % (nx, h))
    write_lammps_data(data, pos, vel, box, m0)

    t0 = time.perf_counter()
    pairs0 = count_pairs(pos, box, h)
    res["pairs_initial"] = pairs0
    res["pair_count_time_s"] = time.perf_counter() - t0
    del vel

    # ---- pair census along the trajectory (LAMMPS, untimed) ----------------
    horizon = max(lsteps, ssteps)
    every = max(1, min(lsteps, ssteps) // 20)
    horizon = int(math.ceil(horizon / every) * every)
    tag = "%d_h%g" % (nx, h)
    cen = lammps_run(args.lmp, data, table, h, args.skin, horizon, args.table_points,
                     workdir, "census_%s" % tag, [], thermo_every=every, census=True)
    samples = [(int(r["Step"]), r["c_cs"] / 2.0) for r in cen["thermo"]]
    res["pair_census"] = samples
    res["pairs_lammps_step0"] = samples[0][1] if samples else None
    res["pairs_mean_lammps_window"] = window_mean(samples, lsteps)
    res["pairs_mean_spam_window"] = window_mean(samples, ssteps)
    res["pairs_end_lammps_window"] = [v for s, v in samples if s <= lsteps][-1]

    # ---- timed runs, each process alone, alternating -----------------------
    lam = []
    spam = []
    for k in range(args.repeats):
        lam.append(lammps_run(args.lmp, data, table, h, args.skin, lsteps,
                              args.table_points, workdir, "%s_r%d" % (tag, k), pin))
        if spam_ok:
            spam.append(spam_run(args.spam_ark, csv, box, h, ssteps, workdir,
                                 "%s_r%d" % (tag, k), pin))
    res["lammps_runs"] = lam
    res["spam_runs"] = spam
    res["timed_seconds"] = sum(r["process_wall_s"] for r in lam + spam)

    L = {}
    L["time_per_eval_s"] = med([r["loop_time_s"] / r["steps"] for r in lam])
    L["time_per_eval_s_runs"] = [r["loop_time_s"] / r["steps"] for r in lam]
    # velocity Verlet: one force evaluation per step
    L["time_per_step_s"] = L["time_per_eval_s"]
    L["particle_steps_per_s"] = n / L["time_per_step_s"] if L["time_per_step_s"] else None
    L["time_per_eval_per_particle_s"] = L["time_per_eval_s"] / n
    L["pair_time_per_eval_s"] = med([r.get("pair_time_s", float("nan")) / r["steps"]
                                     for r in lam])
    L["pair_neigh_time_per_eval_s"] = med([(r.get("pair_time_s", float("nan"))
                                            + r.get("neigh_time_s", float("nan")))
                                           / r["steps"] for r in lam])
    L["neighbor_builds"] = med([r.get("neighbor_builds") for r in lam])
    L["dangerous_builds"] = max(r.get("dangerous_builds", 0) for r in lam)
    L["ru_maxrss_bytes"] = med([r["ru_maxrss_bytes"] for r in lam])
    L["rss_per_particle_bytes"] = L["ru_maxrss_bytes"] / n if L["ru_maxrss_bytes"] else None
    L["rss_minus_baseline_per_particle_bytes"] = per_particle(
        L["ru_maxrss_bytes"], base.get("lammps_ru_maxrss_bytes"), n)
    L["lammps_memory_mbytes"] = med([r.get("lammps_memory_mbytes") for r in lam])
    th = lam[0]["thermo"]
    if len(th) >= 2 and th[0].get("TotEng"):
        L["energy_rel_drift"] = (th[-1]["TotEng"] - th[0]["TotEng"]) / abs(th[0]["TotEng"])
    L["ns_per_pair_initial"] = L["time_per_eval_s"] / pairs0 * 1e9 if pairs0 else None
    pm = res["pairs_mean_lammps_window"]
    L["ns_per_pair_mean"] = L["time_per_eval_s"] / pm * 1e9 if pm else None
    L["pair_only_ns_per_pair_mean"] = (L["pair_time_per_eval_s"] / pm * 1e9
                                       if pm and L["pair_time_per_eval_s"] else None)
    res["lammps"] = L

    S = {}
    if spam:
        S = summarize_spam(spam, n, res["pairs_mean_spam_window"], pairs0,
                           base.get("spam_ru_maxrss_bytes"))
        # Same physics?  SPAM energy = KE + sum_i m rho_i / 2 (P = rho^2/2)
        # = LAMMPS (KE + PE) + N m^2 w(0) / 2; KE at the end should agree to
        # integrator accuracy when both ran the same steps.
        th0 = lam[0]["thermo"]
        s0 = spam[0]["summary"]
        cons = {}
        if th0 and isinstance(s0.get("energy_initial"), (int, float)):
            e_l = th0[0]["TotEng"] + len(pos) * scale * float(lucy_w(0.0, h)) / 2
            cons["energy_initial_spam"] = float(s0["energy_initial"])
            cons["energy_initial_lammps_plus_self"] = e_l
            cons["energy_initial_rel_diff"] = (float(s0["energy_initial"]) - e_l) / abs(e_l)
        if (th0 and lsteps == ssteps and len(th0) >= 2
                and isinstance(s0.get("kinetic_final"), (int, float))):
            ke_l = th0[-1]["KinEng"]
            cons["kinetic_final_spam"] = float(s0["kinetic_final"])
            cons["kinetic_final_lammps"] = ke_l
            cons["kinetic_final_rel_diff"] = ((float(s0["kinetic_final"]) - ke_l)
                                              / abs(ke_l) if ke_l else None)
        eos = (s0.get("eos_gamma"), s0.get("eos_kappa"))
        cons["eos_gamma_kappa"] = eos
        if eos != (None, None) and eos != (2, 0.5):
            print("  WARNING: spam-ark ran with eos gamma %s kappa %s; the LAMMPS "
                  "equivalence needs P = rho^2/2 (gamma 2, kappa 0.5)" % eos)
        res["consistency"] = cons
        if S["time_per_eval_s"] and L["time_per_eval_s"]:
            res["ratio_time_per_eval"] = S["time_per_eval_s"] / L["time_per_eval_s"]
        if S["time_per_step_s"] and L["time_per_step_s"]:
            res["ratio_time_per_step"] = S["time_per_step_s"] / L["time_per_step_s"]
    res["spam"] = S
    return res


def bench_solid(n, case, args, workdir, pin, base):
    h = case["h"]
    nx, ny = solid_shape(n)
    ns = nx * ny
    _, steps = steps_for(case, n, args)
    res = {"case": case["name"], "kind": "solid", "label": case["label"],
           "n_requested": n, "n": ns, "nx": nx, "ny": ny, "h": h, "dt": DT,
           "spam_steps": steps}
    if ns != n:
        print("  note: solid lattice %dx%d has N = %d (requested %d)" % (nx, ny, ns, n))

    # ---- initial particles (for the pair count and the box) ----------------
    tag = "solid_%dx%d_h%g" % (nx, ny, h)
    init_dir = workdir / ("init_%s" % tag)
    init_dir.mkdir(parents=True, exist_ok=True)
    csv0 = workdir / ("initial_%s.csv" % tag)
    cmd = ([args.spam_ark] + SOLID_PHYSICS
           + ["-planewave_nx", nx, "-planewave_ny", ny, "-h", h,
              "-initial_csv", csv0, "-ts_max_steps", 0, "-output_dir", init_dir, "-output_overwrite"])
    log = workdir / ("init_%s.log" % tag)
    rc, _, _ = run_measured(cmd, REPO_ROOT, log)
    if rc != 0 or not csv0.exists() or not (init_dir / "summary.json").exists():
        raise RuntimeError("spam-ark solid initial-state run failed (rc=%d):\n  %s\n%s"
                           % (rc, " ".join(map(str, cmd)), tail(log)))
    res["initial_cmd"] = " ".join(map(str, cmd))
    s_init = json.loads((init_dir / "summary.json").read_text())
    box = np.array([float(v) for v in s_init.get("box_len", [0, 0])[:2]])
    lo = np.array([float(v) for v in s_init.get("box_lo", [0, 0])[:2]])
    res["box"] = box.tolist()
    pos = read_particles_csv(csv0)[0] - lo
    t0 = time.perf_counter()
    pairs0 = count_pairs(pos, box, h)
    res["pair_count_time_s"] = time.perf_counter() - t0
    res["pairs_initial"] = pairs0
    del pos
    csv0.unlink()

    # ---- timed runs (the first also writes the final particles) ------------
    spam = []
    csv1 = workdir / ("final_%s.csv" % tag)
    for k in range(args.repeats):
        extra = ["-final_csv", csv1] if k == 0 else []
        spam.append(spam_run_cmd(lambda d: solid_cmd(args.spam_ark, nx, ny, h, steps, d),
                                 workdir, "%s_r%d" % (tag, k), pin, extra))
    res["spam_runs"] = spam
    res["timed_seconds"] = sum(r["process_wall_s"] for r in spam)
    pairs1 = None
    if csv1.exists():
        pos1 = read_particles_csv(csv1)[0] - lo
        pairs1 = count_pairs(pos1, box, h)
        del pos1
        csv1.unlink()
    res["pairs_final"] = pairs1
    # The solid barely moves: the mean of the two counts is the time-mean.
    pm = 0.5 * (pairs0 + pairs1) if pairs1 is not None else pairs0
    res["pairs_mean_spam_window"] = pm
    res["spam"] = summarize_spam(spam, ns, pm, pairs0, base.get("spam_ru_maxrss_bytes"))
    return res


def solid_reference(res, results):
    """The solid's cost against the LAMMPS gas at the nearest N and the same h
    (a reference cost, not the same dynamics)."""
    gases = [r for r in results if r.get("kind") == "gas" and r.get("h") == res["h"]
             and r.get("lammps", {}).get("time_per_step_s")]
    if not gases:
        return None
    g = min(gases, key=lambda r: (abs(math.log(r["n"] / res["n"])), -r["n"]))
    S = res["spam"]
    ref = {"gas_case": g["case"], "gas_n": g["n"],
           "lammps_gas_time_per_step_s": g["lammps"]["time_per_step_s"],
           "lammps_gas_time_per_step_per_particle_s": g["lammps"]["time_per_step_s"] / g["n"]}
    te = S.get("time_per_eval_s")
    if te:
        ref["ratio_time_per_eval"] = te / g["lammps"]["time_per_step_s"]
        # per particle, in case the two N differ
        ref["ratio_time_per_eval_per_particle"] = ((te / res["n"])
                                                   / ref["lammps_gas_time_per_step_per_particle_s"])
        gs = g.get("spam", {}).get("time_per_eval_s")
        if gs:
            ref["spam_gas_time_per_eval_s"] = gs
            ref["ratio_to_spam_gas_per_particle"] = (te / res["n"]) / (gs / g["n"])
    return ref


def baselines(args, workdir, pin, spam_ok, case):
    """Peak RSS of each program on a 64-particle problem of this case (the
    runtime baseline: libraries, MPI, PETSc, ...)."""
    h = case["h"]
    out = {}
    if case["kind"] == "solid":
        if not spam_ok:
            return out
        # 8 x 8 unless the box (NX by NY sqrt(3)/2) must be wider than 2.2 h.
        nx = max(8, int(math.ceil(2.2 * h)))
        ny = max(8, 2 * int(math.ceil(2.2 * h / math.sqrt(3))))
        out["n"] = nx * ny
        try:
            r = spam_run_cmd(lambda d: solid_cmd(args.spam_ark, nx, ny, h, 1, d),
                             workdir, "baseline_%s" % case["name"], pin)
            out["spam_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
        except RuntimeError as exc:
            print("  (spam-ark solid baseline failed: %s)" % str(exc).splitlines()[0])
        return out
    nx = 8
    side = max(2.0 * nx, 2.0 * math.ceil(1.1 * h + 1.0))
    box = np.array([side, side])
    pos, vel, mass = numpy_lattice(nx)
    out["n"] = len(pos)
    table = workdir / ("table_baseline_h%g.dat" % h)
    write_table(table, h, args.table_points, args.table_rlo)
    data = workdir / ("baseline_h%g.data" % h)
    write_lammps_data(data, pos, vel, box, 1.0)
    try:
        r = lammps_run(args.lmp, data, table, h, args.skin, 1, args.table_points,
                       workdir, "baseline_%s" % case["name"], pin)
        out["lammps_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
    except RuntimeError as exc:
        print("  (LAMMPS baseline failed: %s)" % str(exc).splitlines()[0])
    if spam_ok:
        csv = workdir / ("baseline_h%g.csv" % h)
        write_particles_csv(csv, pos, vel, mass)
        try:
            r = spam_run(args.spam_ark, csv, box, h, 1, workdir,
                         "baseline_%s" % case["name"], pin)
            out["spam_ru_maxrss_bytes"] = r["ru_maxrss_bytes"]
        except RuntimeError as exc:
            print("  (spam-ark baseline failed: %s)" % str(exc).splitlines()[0])
    return out


def log_view_run(args, workdir, pin, path, spam_ok):
    n, h = args.log_view_size, 3.0
    nx = int(round(math.sqrt(n)))
    if nx * nx != n:
        raise SystemExit("--log-view-size %d is not a perfect square" % n)
    case = {"name": "gas-h3", "kind": "gas", "h": h}
    _, steps = steps_for(case, n, args)
    rec = {"n": n, "h": h, "steps": steps, "file": str(path)}
    if not spam_ok:
        rec["error"] = "spam-ark not usable"
        return rec
    csv, _ = spam_make_initial(args.spam_ark, nx, h, workdir)
    box = np.array([2.0 * nx, 2.0 * nx])
    r = spam_run(args.spam_ark, csv, box, h, steps, workdir, "logview_%d" % nx, pin,
                 extra=["-log_view", ":%s" % path])
    rec["cmd"] = r["cmd"]
    rec["rhs_evals"] = r["summary"].get("rhs_evals")
    rec["rhs_time_s"] = r["summary"].get("rhs_time_s")
    try:
        text = Path(path).read_text(errors="replace")
    except OSError as exc:
        rec["error"] = "no -log_view output: %s" % exc
        return rec
    rows, total = parse_log_view(text)
    rec["total_time_s"] = total
    rec["events"] = rows
    return rec
