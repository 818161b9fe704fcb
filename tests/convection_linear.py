#!/usr/bin/python3
"""Linear stability of the convection cell (-scene convection) as the scene defines it.

The continuum model of src/scenes/scene_convection.c, linearised about its start:
  * ideal gas, P = rho T, T = (gamma - 1) e (k = m = 1), c_v = 1/(gamma - 1),
    c_p = gamma/(gamma - 1);
  * conduction state T0(y) = T_b - beta y, beta = (T_b - T_t)/H, in hydrostatic balance
    P0' = -rho0 g: rho0 ~ (T0/T_b)^(g/beta - 1) (exp(-g y/T_b) when beta = 0), normalised
    as the scene does: its mean over the lattice rows y = 1/2, 3/2, ... (ny of them) is
    -mass (rho_mean);
  * Newtonian stress sigma = eta (G + G^T - (2/D) div v I) + eta_b div v I with D = 2, so
    div sigma = eta lap v + eta_b grad div v (the 2D shear part has no grad div term);
    eta_b = 0 as the scene leaves it (-viscosity_bulk);
  * Fourier conduction Q = -kappa grad T; eta and kappa constant;
  * walls at y = 0 and y = H (mirror walls lie half a spacing beyond the outer lattice
    rows, docs/walls.md): no-slip u = v = 0, isothermal T' = 0; periodic in x.
  * eta and kappa from Ra and Pr as the scene's ModelDefaults: Ra = g alpha dT H^3/(nu chi)
    with dT = T_b - T_t - g H/c_p (superadiabatic), alpha = 1/T_mean, nu = eta/rho_mean,
    chi = kappa/(rho_mean c_p), Pr = nu/chi.

Perturbations (rho', u, v, T') ~ f(y) exp(i k x + s t):
  s rho' = -rho0' v - rho0 (i k u + v')
  rho0 s u = -i k P' + eta (D^2 - k^2) u + i k eta_b (i k u + v')
  rho0 s v = -D P' - g rho' + eta (D^2 - k^2) v + eta_b D (i k u + v')
  rho0 c_v s T' = -rho0 c_v T0' v - P0 (i k u + v') + kappa (D^2 - k^2) T'
with P' = T0 rho' + rho0 T' (P0 = rho0 T0), by Chebyshev collocation on N + 1
Gauss-Lobatto points in y. The wall values of u, v and T' are zero and are removed from
the unknowns (and their equations' wall rows); rho' has no boundary condition and keeps
its wall rows. The left side is then diagonal, so s are the eigenvalues of one matrix
(numpy.linalg.eig), about 4N unknowns.

Verified (--check): in the Boussinesq limit (dT = 1e-3 T_mean, g H / c_p = dT / 5)
Ra_c = 1707.7617 at k_c H = 3.1163 (the accurate rigid-rigid values are 1707.762 and
3.1163; the usual 3.117 is rounded up), and just above onset the growth rate is
(Ra / Ra_c - 1) / tau0 with Cross & Hohenberg's rigid-wall
tau0 = (Pr + 0.5117) / (19.65 Pr) H^2 / chi to 2e-4 (Pr = 0.5, 1, 7). Resolution: Ra_c of
the scene's cell 1700.96188 (N = 6), 1700.78569 (8), 1700.78925 (10), 1700.788860 (12),
1700.788851 (16, 24, 32, 48): spectral convergence, 1e-8 relative from N = 16; N = 24 is the
default. Ra_c takes about 0.5 s.

The scene's cell (options/convection.opts, 32 x 16, T_b = 1.25, T_t = 0.75, g = 0.0125,
Pr = 1): Ra_c = 1700.789 (-0.41 % from the Boussinesq 1707.76) at k_c H = 3.1209; the
periodic cell's own roll (k = 2 pi / L, k H = pi) sets in at 1700.896.

Usage: /usr/bin/python3 tests/convection_linear.py [scene options] [--n N] [--check]
  scene options as spam-ark takes them: -convection_ra, -convection_prandtl, -convection_g,
  -convection_nx, -convection_ny, -wall_ylo_temperature, -wall_yhi_temperature,
  -gas_gamma, -mass, -viscosity_bulk, or -options_file FILE (later options win).
Prints Ra_c, k_c H, those of the cell's own wavenumbers 2 pi n / L, and the growth rate
at the given Ra. --check runs the Boussinesq limit and the resolution study.
"""
import math
import sys

import numpy as np

RA_BOUSSINESQ = 1707.76   # rigid-rigid onset, Boussinesq (Chandrasekhar; accurately 1707.762)
K_BOUSSINESQ = 3.117      # k_c H there (accurately 3.1163)


class Cell:
    """The scene's parameters (defaults of -scene convection and options/convection.opts)."""

    def __init__(self, nx=32, ny=16, ra=5.0 * RA_BOUSSINESQ, prandtl=1.0, g=None, t_bottom=1.25, t_top=0.75,
                 gamma=2.0, mass=1.0, eta_b=0.0):
        self.nx, self.ny = nx, ny
        self.ra, self.prandtl = ra, prandtl
        self.gamma, self.mass, self.eta_b = gamma, mass, eta_b
        self.t_bottom, self.t_top = t_bottom, t_top
        self.g = 0.1 * self.cp / ny if g is None else g  # the scene's default, 0.1 c_p / H

    @property
    def cp(self):
        return self.gamma / (self.gamma - 1.0)

    @property
    def H(self):
        return float(self.ny)

    @property
    def L(self):
        return float(self.nx)

    def superadiabatic(self):
        return self.t_bottom - self.t_top - self.g * self.H / self.cp

    def transport(self, ra):
        """(eta, kappa) the scene gives the model at this Ra (ModelDefaults)."""
        t_mean = 0.5 * (self.t_bottom + self.t_top)
        dt = self.superadiabatic()
        if dt <= 0.0:
            dt = 0.4 * t_mean
        nu = math.sqrt(self.g * dt / t_mean * self.H ** 3 * self.prandtl / ra)
        return self.mass * nu, self.mass * self.cp * nu / self.prandtl

    def rho_unnormalised(self, y):
        beta = (self.t_bottom - self.t_top) / self.H
        if beta == 0.0:
            return np.exp(-self.g * y / self.t_bottom)
        T = self.t_bottom - beta * y
        return np.exp((self.g / beta) * np.log1p(-beta * y / self.t_bottom)) * self.t_bottom / T

    def base(self, y):
        """T0, T0', rho0, rho0' at heights y (the scene's normalisation of rho)."""
        beta = (self.t_bottom - self.t_top) / self.H
        rows = np.arange(self.ny) + 0.5
        scale = self.mass / np.mean(self.rho_unnormalised(rows))
        T = self.t_bottom - beta * y
        rho = scale * self.rho_unnormalised(y)
        # hydrostatic: (rho T)' = -rho g  =>  rho' = -rho (g - beta) / T
        drho = -rho * (self.g - beta) / T
        return T, np.full_like(y, -beta), rho, drho


def chebyshev(n):
    """Gauss-Lobatto points x_j = cos(pi j / n) and the differentiation matrix (Trefethen)."""
    j = np.arange(n + 1)
    x = np.cos(np.pi * j / n)
    c = np.ones(n + 1)
    c[0] = c[-1] = 2.0
    c *= (-1.0) ** j
    X = np.tile(x, (n + 1, 1)).T
    dX = X - X.T
    D = np.outer(c, 1.0 / c) / (dX + np.eye(n + 1))
    D -= np.diag(D.sum(axis=1))
    return x, D


_GRIDS = {}


def grid(n, H):
    key = (n, H)
    if key not in _GRIDS:
        x, D = chebyshev(n)
        y = 0.5 * H * (1.0 - x)          # j = 0 at the hot wall y = 0, j = n at y = H
        Dy = -2.0 / H * D
        _GRIDS[key] = (y, Dy, Dy @ Dy)
    return _GRIDS[key]


def operator(cell, k, ra, n=24):
    """The collocated matrix M (s q = M q) at wavenumber k (1/length) and Rayleigh number
    ra, the rest of the parameters from cell, with the indices of its unknowns in the
    full list [rho'(y_0..y_n), u(...), v(...), T'(...)]."""
    y, D1, D2 = grid(n, cell.H)
    T0, dT0, r0, dr0 = cell.base(y)
    eta, kappa = cell.transport(ra)
    eb, g, cv = cell.eta_b, cell.g, 1.0 / (cell.gamma - 1.0)
    m = n + 1
    I = np.eye(m)
    ik = 1j * k
    lap = D2 - k * k * I
    R0, T0d = np.diag(r0), np.diag(T0)
    # rows: continuity, x, y momentum (divided by rho0), energy (divided by rho0 c_v);
    # columns: rho', u, v, T'
    A = np.zeros((4 * m, 4 * m), complex)
    blk = lambda a, b: (slice(a * m, (a + 1) * m), slice(b * m, (b + 1) * m))
    A[blk(0, 1)] = -ik * R0
    A[blk(0, 2)] = -(np.diag(dr0) + R0 @ D1)
    inv = np.diag(1.0 / r0)
    A[blk(1, 0)] = inv @ (-ik * T0d)
    A[blk(1, 1)] = inv @ (eta * lap - eb * k * k * I)
    A[blk(1, 2)] = inv @ (ik * eb * D1)
    A[blk(1, 3)] = inv @ (-ik * R0)
    A[blk(2, 0)] = inv @ (-D1 @ T0d - g * I)
    A[blk(2, 1)] = inv @ (ik * eb * D1)
    A[blk(2, 2)] = inv @ (eta * lap + eb * D2)
    A[blk(2, 3)] = inv @ (-D1 @ R0)
    P0 = np.diag(r0 * T0)
    invc = np.diag(1.0 / (r0 * cv))
    A[blk(3, 1)] = invc @ (-ik * P0)
    A[blk(3, 2)] = invc @ (-cv * np.diag(r0 * dT0) - P0 @ D1)
    A[blk(3, 3)] = invc @ (kappa * lap)
    # u, v, T' vanish at the walls: drop their wall unknowns and wall equations
    walls = [b * m + j for b in (1, 2, 3) for j in (0, n)]
    keep = np.setdiff1d(np.arange(4 * m), walls)
    return A[np.ix_(keep, keep)], keep


def spectrum(cell, k, ra, n=24):
    """All eigenvalues s at wavenumber k and Rayleigh number ra."""
    return np.linalg.eigvals(operator(cell, k, ra, n)[0])


def mode(cell, k, ra, n=24):
    """The fastest-growing mode at (k, ra): (s, y, fields) with fields a dict of the
    complex profiles rho', u, v, T' on the collocation points y (zero at the walls for
    u, v, T'), scaled so that max |v| = 1."""
    M, keep = operator(cell, k, ra, n)
    s, vec = np.linalg.eig(M)
    i = np.argmax(s.real)
    full = np.zeros(4 * (n + 1), complex)
    full[keep] = vec[:, i]
    m = n + 1
    f = {name: full[b * m:(b + 1) * m] for b, name in enumerate(("rho", "u", "v", "T"))}
    scale = f["v"][np.argmax(abs(f["v"]))]
    f = {name: v / scale for name, v in f.items()}
    return s[i], grid(n, cell.H)[0], f


def growth(cell, k, ra, n=24):
    """(Re s, Im s) of the fastest-growing mode at wavenumber k and Rayleigh number ra."""
    s = spectrum(cell, k, ra, n)
    i = np.argmax(s.real)
    return s[i].real, abs(s[i].imag)


def neutral_ra(cell, k, n=24, ra0=RA_BOUSSINESQ, tol=1e-9):
    """Ra at which the fastest mode at wavenumber k has Re s = 0: a bracket in log Ra
    (Re s grows with Ra), then regula falsi with the Illinois step."""
    f = lambda lr: growth(cell, k, math.exp(lr), n)[0]
    a, b = math.log(ra0), math.log(ra0 * 1.02)
    fa, fb = f(a), f(b)
    while fa > 0:
        b, fb = a, fa
        a -= 0.2
        fa = f(a)
    while fb < 0:
        a, fa = b, fb
        b += 0.2
        fb = f(b)
    side = 0
    for _ in range(100):
        c = b - fb * (b - a) / (fb - fa)
        fc = f(c)
        if fc == 0.0:
            return math.exp(c)
        if fc > 0:
            b, fb = c, fc
            if side == 1:
                fa *= 0.5
            side = 1
        else:
            a, fa = c, fc
            if side == -1:
                fb *= 0.5
            side = -1
        if b - a < tol:
            break
    return math.exp(0.5 * (a + b))


def critical(cell, n=24, kh=(2.0, 4.5), tol=1e-5):
    """(Ra_c, k_c H): the minimum over k of the neutral Ra (golden section in k H)."""
    H = cell.H
    r = 0.5 * (math.sqrt(5.0) - 1.0)
    a, b = kh
    c, d = b - r * (b - a), a + r * (b - a)
    fc, fd = neutral_ra(cell, c / H, n), neutral_ra(cell, d / H, n)
    while b - a > tol:
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - r * (b - a)
            fc = neutral_ra(cell, c / H, n, fd)
        else:
            a, c, fc = c, d, fd
            d = a + r * (b - a)
            fd = neutral_ra(cell, d / H, n, fc)
    kc = 0.5 * (a + b)
    return neutral_ra(cell, kc / H, n, min(fc, fd)), kc


def cell_modes(cell, kmax_h=12.0):
    """The wavenumbers 2 pi j / L the periodic cell holds, up to k H = kmax_h."""
    ks = []
    j = 1
    while 2 * math.pi * j / cell.L * cell.H <= kmax_h:
        ks.append(2 * math.pi * j / cell.L)
        j += 1
    return ks


def cell_critical(cell, n=24):
    """(Ra_c, j) of the periodic cell: the lowest neutral Ra over its own wavenumbers."""
    best = None
    for j, k in enumerate(cell_modes(cell, 8.0), 1):
        ra = neutral_ra(cell, k, n)
        if best is None or ra < best[0]:
            best = (ra, j)
    return best


def cell_growth(cell, ra, n=24):
    """(s, frequency, j) of the fastest mode the cell holds at ra (k = 2 pi j / L)."""
    best = None
    for j, k in enumerate(cell_modes(cell), 1):
        s, w = growth(cell, k, ra, n)
        if best is None or s > best[0]:
            best = (s, w, j)
    return best


def boussinesq_cell(eps, ny=16, prandtl=1.0):
    """A cell near the Boussinesq limit: T_b - T_t = eps T_mean, adiabatic difference
    g H / c_p = eps / 5 (the scene's ratio), so g H / T_mean = 0.4 eps."""
    return Cell(nx=2 * ny, ny=ny, prandtl=prandtl, g=0.2 * eps * 2.0 / ny, t_bottom=1.0 + 0.5 * eps, t_top=1.0 - 0.5 * eps)


def parse(argv):
    """Scene options (as spam-ark takes them, -options_file included) into a Cell;
    returns (cell, n, check)."""
    opts, n, check = {}, 24, False

    def take(tokens):
        i = 0
        while i < len(tokens):
            t = tokens[i]
            if t == "-options_file":
                with open(tokens[i + 1]) as f:
                    take([w for line in f for w in line.split("#")[0].split()])
                i += 2
            elif t.startswith("-") and i + 1 < len(tokens) and not tokens[i + 1].startswith("-") or \
                    (t.startswith("-") and i + 1 < len(tokens) and _number(tokens[i + 1])):
                opts[t] = tokens[i + 1]
                i += 2
            else:
                opts[t] = None
                i += 1

    args = list(argv)
    if "--n" in args:
        k = args.index("--n")
        n = int(args[k + 1])
        del args[k:k + 2]
    if "--check" in args:
        check = True
        args.remove("--check")
    take(args)
    num = lambda key, d: float(opts[key]) if opts.get(key) is not None else d
    ny = int(num("-convection_ny", 16))
    gamma = num("-gas_gamma", 2.0)
    cell = Cell(nx=int(num("-convection_nx", 32)), ny=ny, ra=num("-convection_ra", 5.0 * RA_BOUSSINESQ),
                prandtl=num("-convection_prandtl", 1.0), g=num("-convection_g", None),
                t_bottom=num("-wall_ylo_temperature", 1.25), t_top=num("-wall_yhi_temperature", 0.75),
                gamma=gamma, mass=num("-mass", 1.0), eta_b=num("-viscosity_bulk", 0.0))
    return cell, n, check


def _number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


def convergence(cell, ns=(8, 12, 16, 24, 32)):
    """Ra_c and k_c H at each resolution."""
    return [(n,) + critical(cell, n) for n in ns]


def growth_table(cell, ra_c, kc, factors, n=24):
    """Rows (Ra/Ra_c, Ra, s at k_c, s of the cell's fastest mode, its j) at Ra = f Ra_c."""
    rows = []
    for f in factors:
        s_kc = growth(cell, kc / cell.H, f * ra_c, n)[0]
        s, w, j = cell_growth(cell, f * ra_c, n)
        rows.append((f, f * ra_c, s_kc, s, j))
    return rows


def report(cell, n, factors=(1.2, 1.5, 2.0, 3.0)):
    import time
    t0 = time.time()
    ra_c, kc = critical(cell, n)
    ra_cell, j = cell_critical(cell, n)
    eta, kappa = cell.transport(cell.ra)
    print(f"cell {cell.nx} x {cell.ny}: T_b = {cell.t_bottom:g}, T_t = {cell.t_top:g}, g = {cell.g:.6g}, gamma = {cell.gamma:g}, "
          f"Pr = {cell.prandtl:g}, superadiabatic dT = {cell.superadiabatic():.6g}, N = {n} Chebyshev intervals")
    print(f"Ra_c = {ra_c:.6f} (Boussinesq {RA_BOUSSINESQ}: {100 * (ra_c / RA_BOUSSINESQ - 1):+.3f} %), "
          f"k_c H = {kc:.5f} (Boussinesq {K_BOUSSINESQ})")
    print(f"the periodic cell (k = 2 pi j / L): Ra_c = {ra_cell:.6f} at j = {j} (k H = {2 * math.pi * j / cell.L * cell.H:.4f})")
    s, w, jj = cell_growth(cell, cell.ra, n)
    print(f"at Ra = {cell.ra:.6g} (eta = {eta:.6g}, kappa = {kappa:.6g}; {cell.ra / ra_c:.4g} Ra_c): "
          f"fastest mode of the cell j = {jj}, s = {s:.6g} (frequency {w:.3g}), e-folding time {1 / s if s > 0 else math.inf:.5g}")
    print("Ra/Ra_c   Ra          s(k_c)       s(cell)      j  e-folding 1/s(cell)")
    for f, ra, s_kc, s, j in growth_table(cell, ra_c, kc, factors, n):
        print(f"{f:<8.3g}  {ra:<10.6g}  {s_kc:<11.5g}  {s:<11.5g}  {j}  {1 / s if s > 0 else math.inf:.5g}")
    print(f"({time.time() - t0:.2f} s)")


def main():
    cell, n, check = parse(sys.argv[1:])
    if check:
        print("Boussinesq limit (dT = eps T_mean, g H / c_p = eps / 5):")
        for eps in (1e-2, 1e-3, 1e-4):
            b = boussinesq_cell(eps)
            ra, kc = critical(b, n)
            print(f"  eps = {eps:g}: Ra_c = {ra:.6f}, k_c H = {kc:.5f}")
        b = boussinesq_cell(1e-3)
        ra, kc = critical(b, n)
        for eps in (1e-2, 1e-3):
            sg = growth(b, kc / b.H, ra * (1 + eps), n)[0]
            chi = b.transport(ra * (1 + eps))[1] / (b.mass * b.cp)
            print(f"  growth at Ra = {1 + eps:g} Ra_c: s H^2 / (chi eps) = {sg * b.H ** 2 / (chi * eps):.5f} "
                  f"(Cross & Hohenberg's 1 / tau0 = 19.65 Pr / (Pr + 0.5117) = {19.65 * b.prandtl / (b.prandtl + 0.5117):.5f})")
        print("resolution (the scene's cell):")
        for nn, ra, kc in convergence(cell):
            print(f"  N = {nn}: Ra_c = {ra:.8f}, k_c H = {kc:.6f}")
    report(cell, n)


if __name__ == "__main__":
    main()
