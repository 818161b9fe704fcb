"""Linear theory of one Fourier mode of the SPAM gas on a perfect periodic lattice (unit
spacing, m = 1, Lucy's kernel, summation density), for the run tests of transport.

A mode exp(i k.r) of any per-particle field is an eigenvector of every pair sum on the
lattice, so the SPAM equations linearised about the uniform state reduce to small matrices
whose entries are lattice sums over the offsets s of one particle's neighbours:
  rho      = sum_s w(s)                                  (summed density, self term included)
  K(k)     = -(1/rho) sum_s g(s) s sin(k.s),  g = w'/r   (the SPAM gradient: grad f -> i K f)
  D_ee(k)  = sum_s (1 - cos k.s) e.(grad grad w)(s).e    (the pair-force stiffness)
In the continuum K -> k w^(k) (w^ the kernel's Fourier transform, 1 - k^2 <r^2>/(2D) + ...)
and the lattice sums -> integrals; the difference between the sums and the integrals at
h/spacing = 3 is what stays when k h -> 0 (the floor of the resolution studies).

Derivation (signs of src/pair/*.h: grad_i w_ij = g (r_i - r_j)):
  velocity gradient   (grad v)_ab  -> i K_a v_b
  viscous force       dv/dt        -> i rho q.K,  q = eta (G + G^T - (2/D) div v I)/rho^2
  so a transverse mode (K.v = 0) has dv/dt = -(eta/rho)|K|^2 v; the pressure acts on a
  displaced transverse mode through the stiffness alone (its density change is zero):
  dv/dt -= 2 (gamma - 1) e0 / rho D_ee xi. Longitudinal: rho' = -i rho K.xi, the pressure
  perturbation adds i rho K dq with dq = -(gamma-1)(e'/rho - e0 rho'/rho^2), the work term
  gives de/dt = -i (P/rho) K.u, conduction de/dt = -(gamma-1) kappa |K|^2 e' / rho.
The flow scheme's pair form of viscosity and conduction (src/pair/pair_diffusion.h) puts
K2 = 2 D S1(k) / S0 in place of |K|^2, S1 = sum_s g(s) (1 - cos k.s), S0 = sum_s g(s) |s|^2
(its normalisation -D / tr M makes K2 -> k^2 exactly as k -> 0)."""
import itertools
import math

import numpy as np

LUCY_C = {1: 5.0 / 4.0, 2: 5.0 / math.pi, 3: 105.0 / (16.0 * math.pi)}


def lucy_second_moment(dim, h):
    """<r^2> = integral of r^2 w over D-space (the k^2 coefficient of w^ is -<r^2>/(2D))."""
    shell = {1: 2.0, 2: 2.0 * math.pi, 3: 4.0 * math.pi}[dim]
    s = (np.arange(200000) + 0.5) / 200000
    f = s ** (dim + 1) * (1 + 3 * s) * (1 - s) ** 3
    return shell * LUCY_C[dim] * h * h * f.mean()


def lattice_sums(dim, h, kvec, e_hat):
    """rho, K(k) (vector) and D_ee(k) on the unit simple-cubic lattice in dim dimensions."""
    n = int(math.floor(h))
    s = np.array(list(itertools.product(range(-n, n + 1), repeat=dim)), float)
    r = np.linalg.norm(s, axis=1)
    s, r = s[r < h], r[r < h]
    q, c = r / h, LUCY_C[dim]
    w = c / h**dim * (1 + 3 * q) * (1 - q) ** 3
    g = -12 * c / h ** (dim + 2) * (1 - q) ** 2
    dg = 24 * c / h ** (dim + 3) * (1 - q)  # dg/dr
    rho = w.sum()
    ks = s @ kvec
    K = -(g[:, None] * s * np.sin(ks)[:, None]).sum(0) / rho
    nz = r > 0
    se = s[nz] @ e_hat
    hess = g[nz] * (e_hat @ e_hat) + dg[nz] / r[nz] * se**2
    return rho, K, ((1 - np.cos(ks[nz])) * hess).sum()


def taylor_green(dim, L, h, eta, e0, gamma, stiffness=True, form="gradient"):
    """The Taylor-Green mode k = (2 pi/L)(1, 1[, 1]) with velocity along (1, -1, 0):
    v'' + a v' + w2 v = 0 with a = (eta/rho)|K|^2, w2 = 2 (gamma-1) e0 D_ee / rho (0 without
    the pressure's stiffness: the gas flow scheme takes the uniform pressure out of the
    momentum equation, and this mode changes no density to first order).
    Returns (a, w2, rho, ke(t)), ke the kinetic energy relative to t = 0 for v(0) = v0,
    xi(0) = 0: v(t) = v0 (l1 e^{l1 t} - l2 e^{l2 t}) / (l1 - l2)."""
    k = 2 * math.pi / L
    kvec = np.full(dim, k)
    e_hat = np.zeros(dim)
    e_hat[0], e_hat[1] = 1.0, -1.0
    e_hat /= np.linalg.norm(e_hat)
    rho, K, dee = lattice_sums(dim, h, kvec, e_hat)
    a = eta / rho * diffusion_k2(form, dim, h, kvec, K)
    w2 = 2 * (gamma - 1) * e0 / rho * dee if stiffness else 0.0
    d = math.sqrt(a * a - 4 * w2)
    l1, l2 = (-a - d) / 2, (-a + d) / 2

    def ke(t):
        v = (l1 * np.exp(l1 * np.asarray(t)) - l2 * np.exp(l2 * np.asarray(t))) / (l1 - l2)
        return v * v
    return a, w2, rho, ke


def pair_laplacian(dim, h, kvec):
    """K2 of the pair form (the module's docstring) on the unit simple-cubic lattice."""
    n = int(math.floor(h))
    s = np.array(list(itertools.product(range(-n, n + 1), repeat=dim)), float)
    r = np.linalg.norm(s, axis=1)
    keep = (r < h) & (r > 0)
    s, r = s[keep], r[keep]
    g = -12 * LUCY_C[dim] / h ** (dim + 2) * (1 - r / h) ** 2
    return 2 * dim * (g * (1 - np.cos(s @ kvec))).sum() / (g * r * r).sum()


def diffusion_k2(form, dim, h, kvec, K):
    """What multiplies nu (or the conduction's (gamma - 1) kappa / rho) in a mode's decay:
    |K|^2 of the gradient form, or the pair form's K2."""
    return pair_laplacian(dim, h, kvec) if form == "pair" else K @ K


def heat_mode_matrix(K2, stiff, rho, e0, gamma, kappa, K2c=None):
    """The longitudinal mode's matrix for (xi, u, e') with K2 = |K|^2 (or k^2 in the
    continuum), stiff the displacement stiffness (D_xx pressure term or its continuum
    value), rho the density, K2c the conduction's (K2 when None, the gradient form):
    d/dt (xi, u, e') = M (xi, u, e')."""
    K = math.sqrt(K2)
    sig = (gamma - 1) * kappa * (K2 if K2c is None else K2c) / rho
    return np.array([[0, 1, 0],
                     [-stiff + (gamma - 1) * e0 * K2, 0, -1j * (gamma - 1) * K],
                     [0, -1j * (gamma - 1) * e0 * K, -sig]], complex)


def heat_mode(dim, L, h, e0, gamma, kappa, form="gradient"):
    """The temperature mode e = e0 + de cos(2 pi x / L), gas at rest.
    Returns (discrete, continuum), each a function t -> e'(t)/e'(0) (real part of the
    mode evolved by the 3 x 3 matrix), and the continuum's thermal root (the slowest
    decay rate of the cubic l^3 + s l^2 + c^2 k^2 l + s c_T^2 k^2 = 0, s = (gamma-1)
    kappa k^2 / rho, c^2 = gamma (gamma-1) e0, c_T^2 = (gamma-1) e0), with rho = 1."""
    k = 2 * math.pi / L
    kvec = np.zeros(dim)
    kvec[0] = k
    e_hat = np.zeros(dim)
    e_hat[0] = 1.0
    rho, K, dee = lattice_sums(dim, h, kvec, e_hat)
    disc = heat_mode_matrix(K @ K, 2 * (gamma - 1) * e0 / rho * dee, rho, e0, gamma, kappa, diffusion_k2(form, dim, h, kvec, K))
    # Continuum: the displacement term of the pair force is 2 (P/rho^2) rho k^2 = 2 c_T^2 k^2.
    cont = heat_mode_matrix(k * k, 2 * (gamma - 1) * e0 * k * k, 1.0, e0, gamma, kappa)

    def evolve(M):
        lam, V = np.linalg.eig(M)
        c0 = np.linalg.solve(V, np.array([0, 0, 1], complex))

        def e_of_t(t):
            t = np.asarray(t, float)
            return np.real(np.einsum("j,j,...j->...", V[2], c0, np.exp(np.multiply.outer(t, lam))))
        return e_of_t, lam
    fd, _ = evolve(disc)
    fc, lam_c = evolve(cont)
    thermal = -max((l for l in lam_c if abs(l.imag) < 1e-12 * abs(l)), key=lambda l: l.real).real
    return fd, fc, thermal
