#!/usr/bin/python3
"""Velocity Verlet in spam-ark against velocity Verlet in LAMMPS.

spam-ark runs `-ts_type basicsymplectic -ts_basicsymplectic_type kdk -ts_dt 0.05` (the
kick-drift-kick scheme spam-ark registers with PETSc's basicsymplectic TS, stepped by
spam-ark's own step on the state vector); LAMMPS runs
`fix nve` (the same kick-drift-kick) at timestep 0.05, from the same particles (the 2D
expansion lattice, h = 3), for 200 steps. For P = rho^2/2 the SPAM force is the force of the
pair potential w(r) (see bench/README.md), so both integrate the same dynamics with the same
scheme: the kinetic energies at the end must agree to 1e-9 relative (what is left is the
LAMMPS table interpolation and round-off), spam-ark must spend 200 + 1 force evaluations,
and the ratio of the times per step is printed (target <= 1.0), and the ratio of the
whole processes' wall times (start-up, reading the particles or the table, set-up, the run
and the final output: what a user waits for). run_bench.py calls measure() for its
whole-process row (N = 65536, 200 steps).

This is a measurement, not a test. Usage (spam-ark built in build/):
    /usr/bin/python3 bench/run_verlet.py [--n 16384] [--steps 200] [--repeats 5]
"""
import argparse
import datetime
import json
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_common as bc  # noqa: E402  (re-executes under /usr/bin/python3 if numpy is missing)
import peer_lammps as pl  # noqa: E402
import spam_driver as sd  # noqa: E402

np = bc.np


def lammps_input(data, table, h, skin, steps, table_n, dt):
    return "\n".join([
        "units lj", "dimension 2", "atom_style atomic", "boundary p p p",
        "read_data %s" % data,
        "pair_style table linear %d" % table_n,
        "pair_coeff 1 1 %s SPAM %.17g" % (table, h),
        "neighbor %.17g bin" % skin,
        "neigh_modify every 1 delay 0 check yes",
        "fix 1 all nve", "fix 2 all enforce2d",
        "timestep %.17g" % dt,
        "thermo_style custom step pe ke etotal", "thermo_modify norm no", "thermo 0",
        "run %d" % steps,
        "write_dump all custom final.txt id vx vy modify sort id format float %.17g",
    ]) + "\n"


def kinetic(vel, mass):
    return 0.5 * float(np.sum(mass[:, None] * vel * vel))


def measure(spam_ark, lmp, n, h=3.0, dt=0.05, steps=200, repeats=5, table_points=200000, skin=1.0, pin=(), work=None):
    """Alternating whole runs of both programs on the same particles (the expansion lattice
    of N = n, a perfect square): per run the run loop's time (spam-ark's summary wall_time_s,
    LAMMPS's Loop time) and the whole process's wall time (start-up, input, set-up and the
    final output included), the end kinetic energies, spam-ark's force evaluations. Returns
    the medians and ratios (dict; the runs themselves under spam_runs and lammps_runs)."""
    nx = int(round(n ** 0.5))
    assert nx * nx == n, "n must be a perfect square"
    work = Path(work) if work else Path(tempfile.mkdtemp(prefix="spam_verlet_"))
    work.mkdir(parents=True, exist_ok=True)
    pin = list(pin)
    csv, _ = sd.spam_make_initial(spam_ark, nx, h, work)
    pos, vel, mass, _ = bc.read_particles_csv(csv)
    box = (2.0 * nx, 2.0 * nx)
    pl.write_lammps_data(work / "data.lmp", pos, vel, box, float(mass[0]))
    pl.write_table(work / "lucy.table", h, table_points, 1e-10)
    (work / "in.lmp").write_text(lammps_input("data.lmp", "lucy.table", h, skin, steps, table_points, dt))

    spam, lammps = [], []
    for k in range(repeats):
        out = work / ("spam_%d" % k)
        final = work / ("spam_final_%d.csv" % k)
        cmd = pin + [spam_ark, "-scene", "file", "-file_path", csv, "-dim", 2, "-box_lo", "0,0",
                     "-box_len", "%.17g,%.17g" % box, "-h", h,
                     "-ts_type", "basicsymplectic", "-ts_basicsymplectic_type", "kdk", "-ts_dt", dt,
                     "-ts_max_steps", steps, "-ts_max_time", "%.17g" % ((steps + 0.5) * dt),
                     "-snapshot_interval", 0, "-output_interval", 0, "-diag_entropy", 0,
                     "-final_csv", final, "-output_dir", out, "-output_overwrite"]
        rc, wall, rss = bc.run_measured(cmd, bc.REPO_ROOT, work / ("spam_%d.log" % k))
        if rc != 0:
            raise RuntimeError("spam-ark failed:\n" + bc.tail(work / ("spam_%d.log" % k)))
        s = json.loads((out / "summary.json").read_text())
        _, v, m, _ = bc.read_particles_csv(final)
        spam.append({"loop_s": s["wall_time_s"], "process_s": wall, "rhs_evals": s["rhs_evals"],
                     "steps": s["steps"], "ke": kinetic(v, m), "rss": rss})
        log = work / ("lammps_%d.log" % k)
        rc, wall, rss = bc.run_measured(pin + [lmp, "-in", "in.lmp", "-log", "none", "-nocite"], work, log)
        res = pl.parse_lammps_log(log.read_text(errors="replace"))
        if rc != 0 or "loop_time_s" not in res:
            raise RuntimeError("LAMMPS failed:\n" + bc.tail(log))
        d = np.loadtxt(work / "final.txt", skiprows=9)
        lammps.append({"loop_s": res["loop_time_s"], "process_s": wall,
                       "ke": kinetic(d[:, 1:3], np.full(len(d), float(mass[0]))), "rss": rss})

    ke_s, ke_l = spam[0]["ke"], lammps[0]["ke"]
    t_s = bc.med([r["loop_s"] for r in spam]) / steps
    t_l = bc.med([r["loop_s"] for r in lammps]) / steps
    p_s = bc.med([r["process_s"] for r in spam])
    p_l = bc.med([r["process_s"] for r in lammps])
    return {"n": n, "h": h, "dt": dt, "steps": steps, "repeats": repeats, "table_points": table_points,
            "ke_spam": ke_s, "ke_lammps": ke_l, "ke_rel_diff": abs(ke_s - ke_l) / abs(ke_l),
            "force_evals": spam[0]["rhs_evals"], "spam_steps": spam[0]["steps"],
            "ms_per_step_spam": 1e3 * t_s, "ms_per_step_lammps": 1e3 * t_l, "ratio": t_s / t_l,
            "process_s_spam": p_s, "process_s_lammps": p_l, "process_ratio": p_s / p_l,
            "spam_runs": spam, "lammps_runs": lammps}


def report_lines(res, process_goal=None):
    """The lines run_verlet.py prints (and run_bench.py's whole-process row, with its goal;
    the 1e-9 energy check holds for run_verlet.py's fine table only)."""
    rel, evals, steps = res["ke_rel_diff"], res["force_evals"], res["steps"]
    check = "  [%s: <= 1e-9]" % ("PASS" if rel <= 1e-9 else "FALL SHORT") if res["table_points"] >= 200000 else \
        "  (LAMMPS table of %d points)" % res["table_points"]
    lines = ["Velocity Verlet, N = %d, h = %g, dt = %g, %d steps, one core, median of %d"
             % (res["n"], res["h"], res["dt"], steps, res["repeats"]),
             "  kinetic energy at the end: spam-ark %.15e  LAMMPS %.15e  relative difference %.2e%s"
             % (res["ke_spam"], res["ke_lammps"], rel, check),
             "  spam-ark force evaluations: %d for %d steps  [%s: %d]"
             % (evals, res["spam_steps"], "PASS" if evals == steps + 1 else "FALL SHORT", steps + 1),
             "  time per step (run loops): spam-ark %.3f ms  LAMMPS %.3f ms  ratio %.3f  [%s: <= 1.0]"
             % (res["ms_per_step_spam"], res["ms_per_step_lammps"], res["ratio"],
                "PASS" if res["ratio"] <= 1.0 else "FALL SHORT")]
    line = ("  whole process (start-up, input and output included): spam-ark %.3f s  LAMMPS %.3f s  ratio %.3f"
            % (res["process_s_spam"], res["process_s_lammps"], res["process_ratio"]))
    if process_goal is not None:
        line += "  [%s: <= %g]" % ("met" if res["process_ratio"] <= process_goal else "falls short", process_goal)
    lines.append(line)
    return lines


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spam-ark", default=str(bc.REPO_ROOT / "build" / "spam-ark"))
    p.add_argument("--lmp", default="lmp")
    p.add_argument("--n", type=int, default=16384, help="particles (a perfect square)")
    p.add_argument("--h", type=float, default=3.0)
    p.add_argument("--dt", type=float, default=0.05)
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--table-points", type=int, default=200000,
                   help="LAMMPS table points: its linear interpolation error must stay below 1e-9")
    p.add_argument("--skin", type=float, default=1.0)
    p.add_argument("--cpu", type=int, default=0)
    p.add_argument("--no-pin", action="store_true")
    p.add_argument("--out", default=None, help="JSON results (default bench/results/verlet_<date>.json)")
    p.add_argument("--readings", default=None, help="also write the figures bench/README.md quotes to this JSON")
    a = p.parse_args()
    if int(round(a.n ** 0.5)) ** 2 != a.n:
        sys.exit("--n must be a perfect square")
    try:
        res = measure(a.spam_ark, a.lmp, a.n, a.h, a.dt, a.steps, a.repeats, a.table_points, a.skin,
                      bc.pin_prefix(a.cpu, not a.no_pin))
    except RuntimeError as exc:
        sys.exit(str(exc))
    print("\n".join(report_lines(res)))
    out = Path(a.out) if a.out else bc.BENCH_DIR / "results" / ("verlet_%s.json" % datetime.date.today().isoformat())
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(res, indent=1))
    print("  results in %s" % out)
    if a.readings:
        bc.page_readings(a.readings, {k: v for k, v in res.items() if not k.endswith("_runs")})


if __name__ == "__main__":
    main()
