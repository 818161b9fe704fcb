"""Exact solutions of the shock scenes, computed here (no tables): the Riemann problem of an
ideal gas (Sod's tube) and the Sedov-Taylor point blast.

Riemann (Toro, "Riemann Solvers and Numerical Methods for Fluid Dynamics", ch. 4): the
star pressure p* is the root of f_L(p) + f_R(p) + u_R - u_L = 0 (shock branch
f = (p - p_K) sqrt(A_K / (p + B_K)), A = 2/((g+1) rho), B = (g-1)/(g+1) p_K, rarefaction
branch f = 2 c_K/(g-1) ((p/p_K)^((g-1)/(2g)) - 1)), found by Newton's iteration from the
two-rarefaction guess; u* = (u_L + u_R + f_R - f_L)/2; then the star densities (shock
adiabat or isentrope), the wave speeds and the profile at any x/t.

Sedov (Sedov 1959; the equations as in Kamm & Timmes, LA-UR-07-2849): u = R' f(l),
rho = rho0 g(l), p = rho0 R'^2 h(l) with l = r/R, R = xi0 (E t^2/rho0)^(1/(nu+2)),
alpha = 2/(nu+2), nu = 2 (cylinder) or 3 (sphere). Mass, momentum and entropy give
  (f-l) f' + h'/g = -(alpha-1)/alpha f
  g f' + (f-l) g' = -(nu-1) g f/l
  (f-l) (h'/h - gamma g'/g) = -2 (alpha-1)/alpha
from the strong-shock values f = h = 2/(gamma+1), g = (gamma+1)/(gamma-1) at l = 1,
integrated inward (RK4) to l = 1e-3; the energy integral E = sigma alpha^2 xi0^(nu+2)
E I, I = int_0^1 (g f^2/2 + h/(gamma-1)) l^(nu-1) dl, sigma = 2 pi (nu = 2) or 4 pi
(nu = 3), gives xi0 = (sigma alpha^2 I)^(-1/(nu+2)). The inner part l < 1e-3 is
omitted: its share of I is below 1e-6 (h tends to a constant, so it adds about
h(0) l^nu / nu / (gamma-1))."""
import math

import numpy as np


# ---- Riemann problem of the ideal gas -------------------------------------------------

def _pressure_function(p, rho, pk, ck, g):
    """f_K(p) and its derivative for one side."""
    if p > pk:  # shock
        a, b = 2.0 / ((g + 1.0) * rho), (g - 1.0) / (g + 1.0) * pk
        q = math.sqrt(a / (p + b))
        return (p - pk) * q, q * (1.0 - 0.5 * (p - pk) / (b + p))
    r = p / pk  # rarefaction
    return 2.0 * ck / (g - 1.0) * (r ** ((g - 1.0) / (2.0 * g)) - 1.0), 1.0 / (rho * ck) * r ** (-(g + 1.0) / (2.0 * g))


class Riemann:
    """The exact solution of (rho_L, u_L, p_L) | (rho_R, u_R, p_R) at x = 0, t = 0."""

    def __init__(self, left, right, gamma):
        self.g = g = gamma
        self.rl, self.ul, self.pl = left
        self.rr, self.ur, self.pr = right
        self.cl = math.sqrt(g * self.pl / self.rl)
        self.cr = math.sqrt(g * self.pr / self.rr)
        z = (g - 1.0) / (2.0 * g)
        p = ((self.cl + self.cr - 0.5 * (g - 1.0) * (self.ur - self.ul)) / (self.cl / self.pl ** z + self.cr / self.pr ** z)) ** (1.0 / z)
        for _ in range(100):  # Newton
            fl, dl = _pressure_function(p, self.rl, self.pl, self.cl, g)
            fr, dr = _pressure_function(p, self.rr, self.pr, self.cr, g)
            step = (fl + fr + self.ur - self.ul) / (dl + dr)
            p = max(p - step, 1e-12 * p)
            if abs(step) < 1e-15 * p:
                break
        fl, _ = _pressure_function(p, self.rl, self.pl, self.cl, g)
        fr, _ = _pressure_function(p, self.rr, self.pr, self.cr, g)
        self.p_star = p
        self.u_star = 0.5 * (self.ul + self.ur + fr - fl)
        gm = (g - 1.0) / (g + 1.0)
        self.left_shock = p > self.pl
        self.right_shock = p > self.pr
        if self.left_shock:
            self.rho_star_l = self.rl * (p / self.pl + gm) / (gm * p / self.pl + 1.0)
        else:
            self.rho_star_l = self.rl * (p / self.pl) ** (1.0 / g)
        if self.right_shock:
            self.rho_star_r = self.rr * (p / self.pr + gm) / (gm * p / self.pr + 1.0)
        else:
            self.rho_star_r = self.rr * (p / self.pr) ** (1.0 / g)
        self.c_star_l = math.sqrt(g * p / self.rho_star_l)
        self.c_star_r = math.sqrt(g * p / self.rho_star_r)

    def speeds(self):
        """Wave speeds: left wave (head, tail; equal for a shock), contact, right wave (tail, head)."""
        g = self.g
        if self.left_shock:
            s = self.ul - self.cl * math.sqrt((g + 1) / (2 * g) * self.p_star / self.pl + (g - 1) / (2 * g))
            left = (s, s)
        else:
            left = (self.ul - self.cl, self.u_star - self.c_star_l)
        if self.right_shock:
            s = self.ur + self.cr * math.sqrt((g + 1) / (2 * g) * self.p_star / self.pr + (g - 1) / (2 * g))
            right = (s, s)
        else:
            right = (self.u_star + self.c_star_r, self.ur + self.cr)
        return {"left_head": left[0], "left_tail": left[1], "contact": self.u_star, "right_tail": right[0], "right_head": right[1]}

    def sample(self, xi):
        """(rho, u, p) at x/t = xi (arrays)."""
        g = self.g
        xi = np.asarray(xi, dtype=float)
        rho, u, p = np.empty_like(xi), np.empty_like(xi), np.empty_like(xi)
        s = self.speeds()
        for k, q in enumerate(xi.flat):
            if q < s["contact"]:
                if q < s["left_head"]:
                    st = (self.rl, self.ul, self.pl)
                elif q > s["left_tail"]:
                    st = (self.rho_star_l, self.u_star, self.p_star)
                else:  # inside the left fan
                    uu = 2 / (g + 1) * (self.cl + (g - 1) / 2 * self.ul + q)
                    cc = 2 / (g + 1) * (self.cl + (g - 1) / 2 * (self.ul - q))
                    rr = self.rl * (cc / self.cl) ** (2 / (g - 1))
                    st = (rr, uu, self.pl * (cc / self.cl) ** (2 * g / (g - 1)))
            else:
                if q > s["right_head"]:
                    st = (self.rr, self.ur, self.pr)
                elif q < s["right_tail"]:
                    st = (self.rho_star_r, self.u_star, self.p_star)
                else:  # inside the right fan
                    uu = 2 / (g + 1) * (-self.cr + (g - 1) / 2 * self.ur + q)
                    cc = 2 / (g + 1) * (self.cr - (g - 1) / 2 * (self.ur - q))
                    rr = self.rr * (cc / self.cr) ** (2 / (g - 1))
                    st = (rr, uu, self.pr * (cc / self.cr) ** (2 * g / (g - 1)))
            rho.flat[k], u.flat[k], p.flat[k] = st
        return rho, u, p


def sod(gamma=1.4):
    """Sod's tube: (1, 0, 1) | (0.125, 0, 0.1)."""
    return Riemann((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), gamma)


# ---- Sedov-Taylor blast ---------------------------------------------------------------

def _sedov_rates(l, y, nu, gamma):
    f, g, h = y
    a = 2.0 / (nu + 2.0)
    m = np.array([[f - l, 0.0, 1.0 / g],
                  [g, f - l, 0.0],
                  [0.0, -gamma * (f - l) / g, (f - l) / h]])
    rhs = np.array([-(a - 1.0) / a * f, -(nu - 1.0) * g * f / l, -2.0 * (a - 1.0) / a])
    return np.linalg.solve(m, rhs)


def sedov_profile(nu, gamma, steps=4000, l_min=1e-3):
    """(l, f, g, h) from l = 1 (shock) inward to l_min, on a grid uniform in ln l."""
    ls = np.exp(np.linspace(0.0, math.log(l_min), steps + 1))
    y = np.array([2.0 / (gamma + 1.0), (gamma + 1.0) / (gamma - 1.0), 2.0 / (gamma + 1.0)])
    out = [y.copy()]
    for k in range(steps):
        l0, dl = ls[k], ls[k + 1] - ls[k]
        k1 = _sedov_rates(l0, y, nu, gamma)
        k2 = _sedov_rates(l0 + dl / 2, y + dl / 2 * k1, nu, gamma)
        k3 = _sedov_rates(l0 + dl / 2, y + dl / 2 * k2, nu, gamma)
        k4 = _sedov_rates(l0 + dl, y + dl * k3, nu, gamma)
        y = y + dl / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(y.copy())
    out = np.array(out)
    return ls, out[:, 0], out[:, 1], out[:, 2]


def sedov_energy_density(nu, gamma, profile):
    """The blast's energy (kinetic + internal, the ambient's zero) per unit l = r/R in
    similarity variables: (g f^2/2 + h/(gamma - 1)) l^(nu-1), along the profile's l."""
    l, f, g, h = profile
    return (0.5 * g * f * f + h / (gamma - 1.0)) * l ** (nu - 1)


def sedov_xi0(nu, gamma):
    """xi0 of R = xi0 (E t^2/rho0)^(1/(nu+2)) from the energy integral."""
    prof = sedov_profile(nu, gamma)
    i = -np.trapz(sedov_energy_density(nu, gamma, prof), prof[0])  # l decreases along the arrays
    a = 2.0 / (nu + 2.0)
    sigma = {2: 2.0 * math.pi, 3: 4.0 * math.pi}[nu]
    return (sigma * a * a * i) ** (-1.0 / (nu + 2.0))


def sedov_energy_fraction(nu, gamma, l_cut=0.5, profile=None):
    """(fraction, slope): the share of the blast's energy inside r < l_cut R in the
    self-similar solution, and its derivative d(fraction)/dl at l_cut (the energy density
    there over the total: what a shift or a smearing of the cut by dl costs). The integral
    is cut exactly at l_cut (the profile interpolated linearly in l there)."""
    prof = profile if profile is not None else sedov_profile(nu, gamma)
    l, eps = prof[0][::-1], sedov_energy_density(nu, gamma, prof)[::-1]  # l increasing
    total = np.trapz(eps, l)
    x = np.concatenate([l[l < l_cut], [l_cut]])
    return float(np.trapz(np.interp(x, l, eps), x) / total), float(np.interp(l_cut, l, eps) / total)


if __name__ == "__main__":
    r = sod()
    print("Sod: p* %.6f u* %.6f rho*L %.6f rho*R %.6f" % (r.p_star, r.u_star, r.rho_star_l, r.rho_star_r), r.speeds())
    for nu in (2, 3):
        for gam in (1.4, 5.0 / 3.0):
            print(f"Sedov nu={nu} gamma={gam:.4f}: xi0 = {sedov_xi0(nu, gam):.5f}")


# ---- what a kernel of range h makes of a profile ---------------------------------------

def lucy_projected(dim, h, s):
    """Lucy's kernel of range h in dim dimensions integrated over the dim-1 directions
    across a line: the weight with which a plane (a thin shell, R >> h) at distance s
    enters a summed density. Normalised numerically to unit integral."""
    s = np.abs(np.asarray(s, dtype=float))
    y = np.linspace(0.0, h, 801)
    q = np.sqrt(s[:, None] ** 2 + y[None, :] ** 2) / h
    w = np.where(q < 1.0, (1 + 3 * q) * (1 - q) ** 3, 0.0)
    if dim == 2:
        prof = 2.0 * np.trapz(w, y, axis=1)
    else:  # the plane across: rings of radius y
        prof = 2.0 * math.pi * np.trapz(w * y[None, :], y, axis=1)
    return prof


def sedov_smoothed_density(r, radius, nu, gamma, h, profile=None):
    """The self-similar density rho/rho0 at shock radius `radius`, averaged across r by the
    projected kernel (the summed density SPH would give of the exact field in the planar
    approximation, curvature neglected: an error of order h/R)."""
    l, f, g, hh = profile if profile is not None else sedov_profile(nu, gamma)
    ds = h / 100.0
    s = np.arange(-h, h + ds / 2, ds)
    k = lucy_projected(nu, h, s)
    k /= np.trapz(k, s)
    out = []
    for rr in np.atleast_1d(r):
        rp = rr - s
        lam = rp / radius
        rho = np.where(lam >= 1.0, 1.0, np.interp(np.clip(lam, l[-1], 1.0), l[::-1], g[::-1]))
        out.append(np.trapz(rho * k, s))
    return np.array(out)


def half_level_radius(r, rho, ambient=1.0):
    """Outer radius where a profile with a peak falls to (peak + ambient)/2 (linear
    interpolation): the shock-position estimator used on SPH and smoothed exact alike."""
    r, rho = np.asarray(r), np.asarray(rho)
    k = int(np.nanargmax(rho))
    lvl = 0.5 * (rho[k] + ambient)
    j = k + int(np.argmax(rho[k:] < lvl))
    return r[j - 1] + (lvl - rho[j - 1]) * (r[j] - r[j - 1]) / (rho[j] - rho[j - 1]), rho[k]


def lucy(dim, h, s):
    """Lucy's kernel of range h, normalised in dim dimensions (5/(pi h^2), 105/(16 pi h^3))."""
    q = np.abs(np.asarray(s, dtype=float)) / h
    norm = 5.0 / (math.pi * h * h) if dim == 2 else 105.0 / (16.0 * math.pi * h ** 3)
    return np.where(q < 1.0, norm * (1 + 3 * q) * (1 - q) ** 3, 0.0)


def kernel_shape(name, dim, q):
    """The shape F(q) of the kernel -kernel calls name (src/kernels/), q = r/h, range h."""
    q = np.abs(np.asarray(q, dtype=float))
    t = np.clip(1.0 - q, 0.0, None)
    if name == "lucy" or (name == "wendland_c2" and dim == 1):
        return (1 + 3 * q) * t ** 3
    if name == "wendland_c2":
        return (1 + 4 * q) * t ** 4
    if name == "wendland_c4":
        return (1 + 6 * q + 35.0 / 3.0 * q * q) * t ** 6 if dim > 1 else (1 + 5 * q + 8 * q * q) * t ** 5
    if name == "wendland_c6":
        return (1 + 8 * q + 25 * q * q + 32 * q ** 3) * t ** 8 if dim > 1 else (1 + 7 * q + 19 * q * q + 21 * q ** 3) * t ** 7
    if name == "cubic_spline":
        return 2 * t ** 3 - np.clip(1.0 - 2.0 * q, 0.0, None) ** 3
    if name == "quintic_spline":
        return t ** 5 - 6 * np.clip(2.0 / 3.0 - q, 0.0, None) ** 5 + 15 * np.clip(1.0 / 3.0 - q, 0.0, None) ** 5
    raise ValueError("unknown kernel " + name)


def kernel_w(name, dim, h, s):
    """The kernel called name, range h, normalised in dim dimensions (numerically: its
    integral over the ball of radius h by 20000 trapezoids; Lucy's kernel is lucy())."""
    if name == "lucy":
        return lucy(dim, h, s)
    q = np.linspace(0.0, 1.0, 20001)
    c = 1.0 / np.trapz(kernel_shape(name, dim, q) * (2.0 * math.pi * q if dim == 2 else 4.0 * math.pi * q * q), q)
    return c / h ** dim * kernel_shape(name, dim, np.asarray(s, dtype=float) / h)


def sedov_gathered_density(r, radius, nu, gamma, h, profile=None, ns=120, na=360, kernel="lucy"):
    """The self-similar density rho/rho0 (shock at `radius`) averaged by Lucy's kernel of
    range h about the points at distance r from the centre, in the blast's own geometry
    (circles in 2D, spheres in 3D; no planar approximation; another kernel by its -kernel
    name): what a summed density at h makes of the exact field, sum_j m_j W(r_ij, h) -> int rho(x') W(|x - x'|, h) dx'.
    The point x at (r, 0); x' = x + s e(angle): 2D int_0^h W s ds int_0^2pi rho(|x'|) dphi,
    3D int_0^h W s^2 ds 2 pi int_-1^1 rho(|x'|) dmu (midpoint rules, ns x na nodes)."""
    l, f, g, hh = profile if profile is not None else sedov_profile(nu, gamma)
    s = (np.arange(ns) + 0.5) * h / ns
    a = (np.arange(na) + 0.5) / na
    c = np.cos(2.0 * math.pi * a) if nu == 2 else 2.0 * a - 1.0
    ws = kernel_w(kernel, nu, h, s) * (2.0 * math.pi * s * h / ns if nu == 2 else 4.0 * math.pi * s * s * h / ns)
    out = []
    for rr in np.atleast_1d(np.asarray(r, dtype=float)):
        d = np.sqrt(np.maximum(rr * rr + s[:, None] ** 2 + 2.0 * rr * s[:, None] * c[None, :], 0.0))
        lam = d / radius
        rho = np.where(lam >= 1.0, 1.0, np.interp(np.clip(lam, l[-1], 1.0), l[::-1], g[::-1]))
        out.append(float(np.sum(ws * rho.mean(axis=1))))
    return np.array(out)


def sedov_gathered_adaptive(r, radius, nu, gamma, eta, bounds, profile=None, nh=24, kernel="lucy"):
    """The same average at each point's own gather range h(r), the root of
    rho_bar(r, h) h^D = eta^D m (m = 1: the relation the adaptive particles solve), held at
    a bound (bounds = (h_lo, h_hi), absolute) where no root lies between them: rho_bar
    tabulated on nh ranges, the root interpolated linearly in h. Returns (rho_bar, h)."""
    hs = np.linspace(bounds[0], bounds[1], nh)
    table = np.array([sedov_gathered_density(r, radius, nu, gamma, hv, profile, kernel=kernel) for hv in hs])
    fz = table * hs[:, None] ** nu - eta ** nu
    rho_out, h_out = np.empty(table.shape[1]), np.empty(table.shape[1])
    for k in range(table.shape[1]):
        sgn = np.where(np.diff(np.sign(fz[:, k])) != 0)[0]
        if len(sgn) == 0:
            j = 0 if fz[0, k] > 0 else -1
            rho_out[k], h_out[k] = table[j, k], hs[j]
            continue
        j = sgn[0]
        w = fz[j, k] / (fz[j, k] - fz[j + 1, k])
        rho_out[k] = (1 - w) * table[j, k] + w * table[j + 1, k]
        h_out[k] = (1 - w) * hs[j] + w * hs[j + 1]
    return rho_out, h_out
