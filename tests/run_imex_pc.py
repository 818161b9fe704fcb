#!/usr/bin/python3
"""-ts_type arkode_imex with its stage preconditioner (-arkode_imex_pc diffusion: GMRES
preconditioned on the right by the assembled diffusion Jacobian, I - gamma J, ILU(0)).

GMRES's products J v may then be the assembled J's too (-arkode_imex_jv assembled; the
default, difference: ARKStep's difference quotient, one evaluation each). Either changes how
the stages' systems are solved, not what they are (Newton's residual is the right-hand
side's own), so:

1. Order and conservation. The temperature mode of the conducting gas at rest (heat mode
   48 x 12, h = 3, as run_imex_order.py), ARK436L2SA at the fixed steps T/4 and T/8 to
   one e-folding T, against ARK548L2SA at T/16 (both preconditioned): the error of the
   finer halving falls by 2^q, q = 4, within 0.2 (run_imex_order.py's bound: the next term
   moves the observed order by less than 0.15 there); the energy drift is round-off (the pair
   form conserves energy pair by pair in every evaluation; bound 1e-11).
2. The same solution as the unpreconditioned method, to the Newton tolerance. Each stage's
   Newton iteration stops when its correction is below nonlin_coef = 0.1 in the weighted
   norm (weights rtol |y| + atol: for e, rtol e0 with -ts_rtol 1e-12), so two solvers of the
   same stage equations differ by at most that per stage, carried by the stable steps: at
   most (stages x steps) x 0.1 x rtol x scale in the max-norm of the rms-weighted
   correction's worst component (sqrt(n nvar) of it at worst; the rms bound is what is
   checked, and the measured differences sit far below it). Heat mode at T/8 (6 stages x 8
   steps): e within 48 x 0.1 x 1e-12 x e0 x sqrt(n nvar). Couette from rest
   (options/couette.opts with nu = 10, walls with a moving lid: the images' rules enter the
   Jacobian), fixed step 0.5 to t = 5, -ts_rtol 1e-9: v within (6 x 10) x 0.1 x 1e-9 x c0 x
   sqrt(n nvar), and the total energy's drift with the walls' books (set by the fixed
   step's own error) the unpreconditioned run's within that bound over c0.
   On 2 ranks (each rank's own rows: block Jacobi) the same, to the same bound.
3. It does its job: GMRES iterations (ARKStep's "LS iters") on Couette at least 3 times
   fewer with the preconditioner (a count, not a timing).
4. The options: -imex_pc_* are refused without the preconditioner, and a misspelt one
   (-imex_pc_pc_typo) with it; with it, -imex_pc_pc_type is accepted (the Couette run).
   The Couette run with the assembled J's products (each stage's first linear solve by the
   difference quotient, the later ones by J, which holds the viscous work and the walls'
   books) equals the unpreconditioned one within the same bound. It takes ten Newton
   iterations a stage: J is the one of ARKODE's last set-up, and beside the moving wall the
   work's derivative, C (v_i - v_j) with v_j the image's 2U - v_s, is a small difference of
   near velocities that changes by its own size within a few steps; at this tolerance three
   iterations of that modified Newton do not converge."""
import csv
import math
import os
import re

import numpy as np

import subprocess

from spamrun import Checks, arguments, check_sanitizers, mpiexec_env, rank_command, run, summary

L, LY, E0, EPS, GAMMA, KAPPA, H = 48, 12, 1e-6, 1e-4, 1.4, 1.0, 3.0
K = 2 * math.pi / L
T = 1 / ((GAMMA - 1) * KAPPA * K * K)
COUETTE_NU, COUETTE_T = 10, 5
HEAT_RTOL, COUETTE_RTOL, COUETTE_C0, NEWTON = 1e-12, 1e-9, math.sqrt(2.0), 0.1
ORDER_TOL, DRIFT_TOL, GMRES_GAIN = 0.2, 1e-11, 3.0
OPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "couette.opts")


def columns(path, names):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return [np.array([float(r[n]) for r in rows]) for n in names]


def gmres(stdout):
    m = re.search(r"^LS iters\s*=\s*(\d+)", stdout, re.M)
    return int(m.group(1)) if m else -1


def heat(a, c, table, n, pc):
    """e(T) and x(0) of one heat-mode run at the fixed step T/n; None if it failed."""
    name = f"heat_{table}_{n}_{pc}"
    out = os.path.join(a.workdir, name)
    first, last = os.path.join(out, "initial.csv"), os.path.join(out, "final.csv")
    args = ["-dim", 2, "-scene", "heat-mode", "-heatmode_n", L, "-heatmode_ny", LY, "-h", H, "-gas_gamma", GAMMA,
            "-gas_e0", E0, "-heatmode_eps", EPS, "-conductivity", KAPPA, "-ts_max_time", T, "-ts_type", "arkode_imex",
            "-arkode_imex_table", table, "-arkode_imex_pc", pc, "-arkode_fixed_step", T / n, "-ts_rtol", HEAT_RTOL,
            "-ts_atol", 1e-20, "-output_interval", 0, "-initial_csv", first, "-final_csv", last]
    code, _, err = run(a.spam_ark, args, out)
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {err.strip()[-300:]}"):
        return None
    s = summary(out)
    c.check(abs(s["energy_rel_drift_max"]) < DRIFT_TOL, f"{name}: energy drift {s['energy_rel_drift_max']:.1e} (bound {DRIFT_TOL:g})")
    (x0,) = columns(first, ["x"])
    (e,) = columns(last, ["e"])
    return x0, e


def amplitude(run_xe):
    x0, e = run_xe
    return 2 / len(e) * np.sum((e - e.mean()) * np.cos(K * x0)) / (E0 * EPS)


def couette(a, c, pc, ranks=1, extra=()):
    """Couette from rest at fixed steps: (vx by id), GMRES iterations (rank 0's), drift, steps,
    particles; None if it failed."""
    out = os.path.join(a.workdir, "_".join(["couette", pc, str(ranks)] + [str(e).lstrip("-") for e in extra]))
    last = os.path.join(out, "final.csv")
    cmd, env = rank_command(*mpiexec_env(), ranks, a.spam_ark, ["-options_file", OPTS, "-ts_type", "arkode_imex", "-arkode_imex_pc", pc, "-viscosity_shear", COUETTE_NU, "-arkode_fixed_step", 0.5,
                                     "-ts_rtol", COUETTE_RTOL, "-ts_max_time", COUETTE_T, "-output_interval", 0, "-snapshot_interval", 0,
                                     "-final_csv", last, "-sundials_stats", "-output_dir", out, "-output_overwrite"] + list(extra))
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    code, so, err = check_sanitizers(cmd, p.returncode, p.stdout, p.stderr)
    if not c.check(code == 0, f"couette {pc} on {ranks} rank(s): run completes (exit {code}) {err.strip()[-300:]}"):
        return None
    s = summary(out)
    vx, e, ids = columns(last, ["vx", "e", "id"])
    order = np.argsort(ids)
    reused = re.search(r"^Diffusion fields reused\s*=\s*(\d+) of (\d+)", so, re.M)
    return (vx[order], e[order]), gmres(so), s["energy_rel_drift_max"], s["steps"], s["n_particles"], (int(reused.group(1)), int(reused.group(2))) if reused else None


a = arguments()
c = Checks()
ref = heat(a, c, "ARK548L2SA", 16, "diffusion")
runs = {n: heat(a, c, "ARK436L2SA", n, "diffusion") for n in (4, 8)}
plain = heat(a, c, "ARK436L2SA", 8, "none")
if ref is not None and all(r is not None for r in runs.values()):
    aref = amplitude(ref)
    err = [abs(amplitude(runs[n]) - aref) for n in (4, 8)]
    orders = [math.log2(err[0] / err[1])]
    print(f"     ARK436L2SA preconditioned: errors T/4 {err[0]:.3e}, T/8 {err[1]:.3e}; order {orders[0]:.2f}")
    c.check(abs(orders[-1] - 4) < ORDER_TOL, f"preconditioned ARK436L2SA: order {orders[-1]:.2f} from T/4 to T/8 (nominal 4, within {ORDER_TOL})")
    c.reading("heat.order", orders[0])
    if plain is not None:
        nvar = 5  # x, y, vx, vy, e
        bound = 6 * 8 * NEWTON * HEAT_RTOL * E0 * math.sqrt(len(plain[1]) * nvar)
        de = float(np.max(np.abs(runs[8][1] - plain[1])))
        c.check(de < bound, f"heat T/8: max |e pc - e none| {de:.1e} within the Newton tolerance's {bound:.1e}")
        c.reading("heat.de", de)
none = couette(a, c, "none")
pre = couette(a, c, "diffusion", extra=("-imex_pc_pc_type", "ilu"))  # its KSP's options accepted
pre2 = couette(a, c, "diffusion", ranks=2)
asm = couette(a, c, "diffusion", extra=("-arkode_imex_jv", "assembled", "-arkode_imex_max_nonlin_iters", 10))
fresh = couette(a, c, "diffusion", extra=("-imex_pc_pc_type", "ilu", "-arkode_imex_reuse_fields", "false"))
if pre and fresh:
    # the diffusion part's kept densities and moments give the bits computed afresh
    same = bool(np.array_equal(pre[0][0], fresh[0][0]) and np.array_equal(pre[0][1], fresh[0][1]))
    c.check(same and pre[5] is not None and pre[5][0] > 0 and fresh[5] == (0, 0),
            f"couette: the reused diffusion fields ({pre[5]} evaluations) give the same bits as computed afresh ({fresh[5]}): {same}")
if none and pre:
    (v0, e0), it0, drift0, steps, n, _ = none
    (v1, e1), it1, drift, _, _, _ = pre
    newton = 6 * steps * NEWTON * COUETTE_RTOL * math.sqrt(n * 5)
    dv = float(np.max(np.abs(v1 - v0)))
    c.check(dv < newton * COUETTE_C0, f"couette: max |vx pc - vx none| {dv:.1e} within the Newton tolerance's {newton * COUETTE_C0:.1e} ({steps} steps)")
    c.check(abs(drift - drift0) < newton, f"couette: energy drift with the walls' books {drift:.3e}, unpreconditioned {drift0:.3e} (the steps' own error), equal within the Newton tolerance's {newton:.1e}")
    c.check(it1 > 0 and it1 * GMRES_GAIN < it0, f"couette: GMRES iterations {it0} unpreconditioned, {it1} preconditioned (at least {GMRES_GAIN:g}x fewer)")
    c.reading("couette.dv", dv)
    if asm:
        dva = float(np.max(np.abs(asm[0][0] - v0)))
        c.check(dva < newton * COUETTE_C0, f"couette, J v of the assembled J (-arkode_imex_jv assembled): max |vx - vx none| {dva:.1e} within the Newton tolerance's {newton * COUETTE_C0:.1e}")
        c.reading("couette.dv_assembled", dva)
    if pre2:
        dv2 = float(np.max(np.abs(pre2[0][0] - v1)))
        c.check(dv2 < newton * COUETTE_C0, f"couette on 2 ranks (block Jacobi: each rank's rows): max |vx - vx 1 rank| {dv2:.1e} within the Newton tolerance's {newton * COUETTE_C0:.1e} (GMRES iterations {pre2[1]} against {it1})")
        c.reading("couette.dv_ranks", dv2)
    c.reading("couette.gmres_none", it0)
    c.reading("couette.gmres_pc", it1)
# the options: refused where they do not apply, and a misspelt one where they do
code, _, err = run(a.spam_ark, ["-options_file", OPTS, "-ts_type", "arkode_imex", "-arkode_imex_pc", "none", "-ts_max_steps", 0, "-imex_pc_pc_type", "lu"], os.path.join(a.workdir, "refused"))
c.check(code != 0 and "applies to the stage preconditioner" in err, f"-imex_pc_pc_type without -arkode_imex_pc diffusion refused (exit {code}: {err.strip()[-160:]})")
code, _, err = run(a.spam_ark, ["-options_file", OPTS, "-ts_type", "arkode_imex", "-arkode_imex_pc", "diffusion", "-ts_max_steps", 0, "-imex_pc_pc_typo", "lu"], os.path.join(a.workdir, "typo"))
c.check(code != 0 and "imex_pc_pc_typo" in err, f"-imex_pc_pc_typo refused (exit {code}: {err.strip()[-160:]})")
c.finish(a.readings)
