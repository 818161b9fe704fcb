#!/usr/bin/python3
"""-conduction_linear in the implicit part of -ts_type arkode_imex.

The pair conduction's linear correction (src/pair/pair_diffusion.h) is conduction: in
arkode_imex it is in the implicit (diffusion) part with the plain pair form, its heat in
the flow scheme's book there, and the stage preconditioner's Jacobian
(src/physics/diffusion_jacobian.c) carries it exactly: the correction of particle i is
u_i . S_i, u_i = M_i^-1 b_i, S_i the SPAM grad T, linear in the temperatures of i's own
neighbours.

Scene: a disordered periodic gas (16 x 16 unit cells, each coordinate moved by up to 0.2
of a spacing, fixed seed; h = 3, gamma = 1.4, kappa = 1, the flow scheme's pair form),
e = e0 (1 + 0.1 cos(k x)) with e0 = 1e-6: the temperature mode of run_heat_mode.py on
moved particles, where the correction is not zero (on the lattice it is). The sound's
speed is 7.5e-4, so the particles stay where they are and the run is conduction alone,
to t = 8 (about half an e-folding of the mode).

1. Against the explicit method. arkode_imex (ARK436L2SA) and arkode (Dormand-Prince
   5(4)), both -conduction_linear at -ts_rtol 1e-10 (-gas_e0 1e-6: e's error weights are
   rtol e0): e and the book (scheme_energy, per unit mass) agree within the sum of their
   step errors, (steps) rtol e0, as run_imex_order.py's Couette. Without the correction
   (-conduction_linear false) e differs from the corrected run by more than 100 times that
   bound: the comparison sees the correction.
2. The Jacobian carries the correction. GMRES iterations per Newton iteration with the
   correction at most 1.1 times those of the run without it, whose J is exact as well (the
   ratio is above 1 because ARKODE refactors P = I - gamma J only when gamma has moved by
   a fifth). With the correction's entries left out of J (a trial build) the ratio rose
   from 1.36 to 2.14 (without the correction: 1.62), and the test fails.
3. The walls and gravity: the 16 x 8 convection cell (options/convection.opts: isothermal
   walls, whose images' temperatures enter the correction's grad T with their rule,
   -gas_scheme flow -conduction_linear, 2 Ra_c, seed 0.01) to t = 20: arkode_imex against
   arkode at -ts_rtol 1e-9, e and the book per particle within (steps) rtol e (e ~ 1).
   (There the particles have hardly left the lattice, where the correction is small: the
   same GMRES count with and without its entries in J, so it checks the walls, not J.)
4. On 2 ranks (the stage preconditioner block Jacobi, the correction's G through the
   halo) the gas's e equal to one rank's within the bound of 1.

Read, not checked: the mode's decay rate over the run against the ordered lattice's linear
theory (tests/lattice_modes.py), with and without the correction.

Measured: e 1.7e-16 apart against a bound of 5.8e-15, the correction's own effect on e
2.3e-9; the cell's e 5.0e-8 apart against 1.5e-7, its book 3.9e-11 (readings with
--readings).
"""
import csv
import math
import os
import re

import numpy as np

import subprocess

from lattice_modes import heat_mode
from spamrun import Checks, arguments, brief, mpiexec_env, rank_command, summary, table

N, JITTER, H, GAMMA, KAPPA, E0, EPS, T_END = 16, 0.2, 3.0, 1.4, 1.0, 1e-6, 0.1, 8.0
RTOL, CELL_RTOL, CELL_T = 1e-10, 1e-9, 20.0
RATIO_MAX, SENSITIVITY = 1.1, 100.0
OPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "convection.opts")


def write_gas(path):
    rng = np.random.default_rng(7)
    k = 2 * math.pi / N
    with open(path, "w") as f:
        f.write("x,y,vx,vy,m,e\n")
        for j in range(N):
            for i in range(N):
                x, y = (i + 0.5 + JITTER * (2 * rng.random() - 1)), (j + 0.5 + JITTER * (2 * rng.random() - 1))
                f.write(f"{x!r},{y!r},0,0,1,{E0 * (1 + EPS * math.cos(k * x))!r}\n")


def columns(path, names):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    ids = np.array([float(r["id"]) for r in rows])
    order = np.argsort(ids)
    return [np.array([float(r[n]) for r in rows])[order] for n in names]


def counts(stdout):
    """(Newton iterations, GMRES iterations) of ARKStep's statistics table, or (-1, -1)."""
    nw = re.search(r"^NLS iters\s*=\s*(\d+)", stdout, re.M)
    ls = re.search(r"^LS iters\s*=\s*(\d+)", stdout, re.M)
    return (int(nw.group(1)), int(ls.group(1))) if nw and ls else (-1, -1)


def one(a, c, name, args, ranks=1):
    """e (by id), the book at the end, steps and the (Newton, GMRES) counts of one run; None if it failed."""
    out = os.path.join(a.workdir, name)
    last = os.path.join(out, "final.csv")
    cmd, env = rank_command(*mpiexec_env(), ranks, a.spam_ark, args + ["-final_csv", last, "-output_dir", out, "-output_overwrite"])
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    code, so = p.returncode, p.stdout
    if not c.check(code == 0, f"{name}: run completes (exit {code}) {brief(p.stderr)}"):
        return None
    s = summary(out)
    ts = table(os.path.join(out, "timeseries.csv"))
    (e,) = columns(last, ["e"])
    return e, float(ts["scheme_energy"][-1]), int(s["steps"]), counts(so)


def gas_args(gas, method, lin, extra=()):
    return ["-scene", "file", "-file_path", gas, "-dim", 2, "-box_lo", "0,0", "-box_len", f"{N},{N}", "-periodic", "true,true",
            "-h", H, "-material", "gas", "-gas_gamma", GAMMA, "-gas_e0", E0, "-conductivity", KAPPA, "-conduction_linear", "true" if lin else "false",
            "-ts_type", method, "-ts_rtol", RTOL, "-ts_atol", 1e-20, "-ts_max_time", T_END, "-output_interval", 0,
            "-sundials_stats"] + list(extra)


def per_newton(got):
    newton, gmres = got[3]
    return gmres / newton if newton > 0 else math.inf


def main():
    a = arguments()
    c = Checks()
    gas = os.path.join(a.workdir, "gas.csv")
    write_gas(gas)
    imex = one(a, c, "gas_imex", gas_args(gas, "arkode_imex", True))
    dp5 = one(a, c, "gas_dp5", gas_args(gas, "arkode", True))
    off = one(a, c, "gas_imex_off", gas_args(gas, "arkode_imex", False))
    two = one(a, c, "gas_imex_2ranks", gas_args(gas, "arkode_imex", True), ranks=2)
    if imex and dp5:
        steps = imex[2] + dp5[2]
        bound = steps * RTOL * E0
        de = float(np.max(np.abs(imex[0] - dp5[0])))
        db = abs(imex[1] - dp5[1]) / (N * N)  # the book per unit mass (unit masses)
        c.check(de < bound, f"gas: max |e imex - e dp5| {de:.1e} within {steps} rtol e0 = {bound:.1e}")
        c.check(db < bound, f"gas: book per unit mass |imex - dp5| {db:.1e} within {bound:.1e} (book {imex[1] / (N * N):.3e})")
        c.reading("gas.de", de)
        c.reading("gas.dbook", db)
        c.reading("gas.bound", bound)
        c.reading("gas.book", imex[1] / (N * N))
    if imex and dp5 and two:
        d2 = float(np.max(np.abs(two[0] - imex[0])))
        c.check(d2 < bound, f"gas on 2 ranks (block Jacobi): max |e - e 1 rank| {d2:.1e} within {bound:.1e}")
        c.reading("gas.de_ranks", d2)
    if imex and off:
        # the mode's decay over the run, with and without the correction, against the
        # ordered lattice's linear theory (a reading: how the correction reads a moved
        # arrangement where there is no mean gradient)
        x0, e_start = np.loadtxt(gas, delimiter=",", skiprows=1, usecols=(0, 5), unpack=True)
        k = 2 * math.pi / N
        a0 = 2 / len(x0) * np.sum((e_start - e_start.mean()) * np.cos(k * x0))
        discrete, _, _ = heat_mode(2, N, H, E0, GAMMA, KAPPA, "pair")
        lattice = -math.log(discrete(T_END)) / T_END
        for key, got in (("on", imex), ("off", off)):
            amp = 2 / len(x0) * np.sum((got[0] - got[0].mean()) * np.cos(k * x0)) / a0
            c.reading(f"gas.rate_over_lattice_{key}", -math.log(amp) / T_END / lattice)
        d_off = float(np.max(np.abs(off[0] - imex[0])))
        c.check(d_off > SENSITIVITY * bound, f"gas: the correction moves e by {d_off:.1e}, more than {SENSITIVITY:g} x the bound")
        c.reading("gas.correction", d_off)
        r_on, r_off = per_newton(imex), per_newton(off)
        c.check(r_on <= RATIO_MAX * r_off, f"gas: GMRES iterations per Newton iteration {r_on:.2f} with the correction, {r_off:.2f} without it (J exact there): within {RATIO_MAX}x")
        c.reading("gas.gmres_per_newton_on", r_on)
        c.reading("gas.gmres_per_newton_off", r_off)
    cell = ["-options_file", OPTS, "-convection_nx", 16, "-convection_ny", 8, "-convection_ra", 2 * 1700.79, "-convection_amplitude", 0.01,
            "-gas_scheme", "flow", "-conduction_linear", "-ts_rtol", CELL_RTOL, "-ts_max_time", CELL_T, "-output_interval", 0,
            "-snapshot_interval", 0, "-sundials_stats"]
    ci = one(a, c, "cell_imex", cell + ["-ts_type", "arkode_imex"])
    cd = one(a, c, "cell_dp5", cell + ["-ts_type", "arkode"])
    if ci and cd:
        steps = ci[2] + cd[2]
        bound = steps * CELL_RTOL
        de = float(np.max(np.abs(ci[0] - cd[0])))
        db = abs(ci[1] - cd[1]) / (16 * 8)
        c.check(de < bound, f"cell: max |e imex - e dp5| {de:.1e} within {steps} rtol e = {bound:.1e}")
        c.check(db < bound, f"cell: book per particle |imex - dp5| {db:.1e} within {bound:.1e} (book {ci[1] / (16 * 8):.3e})")
        c.reading("cell.de", de)
        c.reading("cell.dbook", db)
        c.reading("cell.bound", bound)
    c.finish(a.readings)


if __name__ == "__main__":
    main()
