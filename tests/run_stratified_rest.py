#!/usr/bin/python3
"""A gas at rest between mirror walls stays at rest in the flow scheme: stratified, and seeded.

The convection cell (options/convection.opts: 32 x 16 unit lattice, T_b = 1.25, T_t = 0.75,
g = 0.0125, h = 3) at Ra = 0.1 Ra_c, where the conduction state is stable, with no seed,
`-gas_scheme flow -kernel wendland_c2`, run to t = 300 (about two sound crossings of the
cell's width per 100). Regime: Ra / Ra_c = 0.1, c h / nu = 11-14 (nu = 0.35 from Pr = 1 at this Ra),
Mach 0 at the start.

A mirror image of a gas particle carries its source's volume and the density of its own
place, rho_g = rho_i (T_i + g.(x_g - x_i)) / T_g (src/physics/gas_images.c). The wall rows'
summed density is then the interior's field continued to first order: what is left is the
second-order term of the continuation over the kernel's range h, at most
    delta = (g h / T_w)^2 / 2    (4.5e-4 at the hot wall, 1.25e-3 at the cold one),
the relative error of a first-order continuation of exp(-g s / T) over s = h.
Checked at t = 0: the volume m / rho of each wall row against the linear extrapolation of
the next two rows' volumes, relative, within delta of its wall.

The transport shift reads a volume error delta as a drift of at most C c delta (C = 0.1,
the shift coefficient; c the sound speed, largest at the hot wall, sqrt(gamma T_b)), and the
drift starts sound of at most the same speed. Checked at t = 300: every particle's speed
within 2 C c_b max(delta) = 4.0e-4.

Measured: wall rows' volume error -2.8e-5 (hot) and -8.3e-5 (cold); max speed 1.9e-4 (1.7e-4
with -shift_compression false, before B's work on the shift's compression was the flow
scheme's default in a stratified cell).
With the images' masses and densities copied from their sources (as before the images had
a place): -3.7e-3 and +6.4e-3, max speed 2.4e-3 (both checks fail). For scale, the plain
scheme at rest reaches 2.9e-3 (Wendland C2) and 5.0e-2 (Lucy) in the same time."""
import csv
import os

import numpy as np

from spamrun import Checks, arguments, manifest_files, run, table

OPTIONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "options", "convection.opts")
G, TB, TT, H, GAMMA, C_SHIFT, RA_C = 0.0125, 1.25, 0.75, 3.0, 2.0, 0.1, 1707.76


def columns(path):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("y", "vx", "vy", "m", "rho_sum")}


def row_volumes(c):
    """Mean m / rho of each lattice row (rows at y = k + 1/2)."""
    r = np.floor(c["y"]).astype(int)
    return np.array([(c["m"][r == k] / c["rho_sum"][r == k]).mean() for k in range(r.max() + 1)])


def main():
    a = arguments()
    chk = Checks()
    out = a.workdir + "/rest"
    code, _, err = run(a.spam_ark, ["-options_file", OPTIONS, "-gas_scheme", "flow", "-kernel", "wendland_c2",
                                    "-convection_ra", 0.1 * RA_C, "-convection_amplitude", 0, "-ts_max_time", 300,
                                    "-output_interval", 300, "-snapshot_interval", 300], out)
    if not chk.check(code == 0, f"the cell at rest runs to t = 300 (exit {code}) {err.strip()[-300:]}"):
        chk.finish()
    snaps = sorted(manifest_files(out, "snapshot_csv"))
    first, last = columns(snaps[0]), columns(snaps[-1])
    V = row_volumes(first)
    for name, wall, inner, Tw in (("hot", 0, (1, 2), TB), ("cold", len(V) - 1, (len(V) - 2, len(V) - 3), TT)):
        delta = 0.5 * (G * H / Tw) ** 2
        err = (V[wall] - (2 * V[inner[0]] - V[inner[1]])) / V[inner[0]]
        chk.check(abs(err) <= delta, f"{name} wall row's volume continues the interior's: relative error {err:.2e}, bound (g h / T_w)^2 / 2 = {delta:.2e}")
    bound = 2 * C_SHIFT * np.sqrt(GAMMA * TB) * 0.5 * (G * H / TT) ** 2
    speed = np.hypot(last["vx"], last["vy"]).max()
    chk.check(speed <= bound, f"the gas stays at rest: max speed at t = 300 {speed:.2e}, bound 2 C c_b delta = {bound:.2e}")
    seeded_uniform_gas(a, chk)
    chk.finish()


def seeded_uniform_gas(a, chk):
    """A uniform gas (T = 1, no gravity) between the same walls, Lucy's kernel (the
    default), seeded with random velocities of 1e-3: its kinetic energy must decay. The
    slowest mode the walls allow, k = pi / H (H = 16), loses its kinetic energy at
    2 nu k^2 as shear and at about half that as sound (Pr = 1, no bulk viscosity), so
    after t = 600 at most KE0 exp(-nu k^2 t) = 3e-4 KE0 is left. With Lucy's own gradient
    in the transport shift it kept 1.8e-4 of 3.4e-4 (the shift, a number-density diffusion,
    runs backwards where the kernel's Fourier transform is negative); measured now 6e-9."""
    nu, t_end, height = 0.35, 600.0, 16.0
    out = a.workdir + "/seeded"
    code, _, err = run(a.spam_ark, ["-options_file", OPTIONS, "-gas_scheme", "flow", "-convection_g", 1e-12, "-gravity", "0,0",
                                    "-viscosity_shear", nu, "-conductivity", 2 * nu, "-wall_ylo_temperature", 1, "-wall_yhi_temperature", 1,
                                    "-convection_amplitude", 1e-3, "-ts_max_time", t_end, "-output_interval", 100, "-snapshot_interval", 0], out)
    if not chk.check(code == 0, f"the seeded uniform gas runs to t = {t_end:g} (exit {code}) {err.strip()[-300:]}"):
        return
    ke = table(out + "/timeseries.csv")["kinetic"]
    bound = ke[0] * np.exp(-nu * (np.pi / height) ** 2 * t_end)
    chk.check(ke[-1] <= bound, f"seeded uniform gas at rest (Lucy): KE {ke[0]:.2e} -> {ke[-1]:.2e} at t = {t_end:g}, bound KE0 exp(-nu k^2 t) = {bound:.2e}")


main()
