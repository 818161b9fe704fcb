"""Period of a standing wave from the kinetic-energy series KE = K sin^2(omega t): KE has
its minima every half period; each is refined by a parabola through the three samples
around it, and the period is twice the slope of a line through the minima times."""
import re

import numpy as np


def predicted_periods(stdout):
    """(linearised SPAM period, continuum period) printed by the planewave scene."""
    m = re.search(r"predicted period ([0-9.eE+-]+) \(linearised SPAM\), continuum period ([0-9.eE+-]+)", stdout)
    return float(m.group(1)), float(m.group(2))


def measured_period(t, ke):
    t, ke = np.asarray(t), np.asarray(ke)
    mins = []
    for i in range(1, len(ke) - 1):
        if ke[i] < ke[i - 1] and ke[i] <= ke[i + 1]:
            c = np.polyfit(t[i - 1:i + 2] - t[i], ke[i - 1:i + 2], 2)
            mins.append(t[i] - c[1] / (2 * c[0]))
    n = np.arange(1, len(mins) + 1)
    return 2 * np.polyfit(n, mins, 1)[0], len(mins)


def mode_amplitude(path, ny, longitudinal):
    """(t, a) of a particle snapshot CSV: a = (2/N) sum_i u_i sin(k y0_i), the amplitude of
    the standing wave's displacement u (along x or y) about the unit triangular lattice of
    the scene (rows at y0 = (j + 1/2) sqrt(3)/2, x0 = i + 1/4 + (j mod 2)/2); each particle's
    site is the nearest one, as |u| < 1/2 row spacing."""
    with open(path) as f:
        t = float(f.readline().split("=")[1])
    d = np.loadtxt(path, delimiter=",", skiprows=2, usecols=(0, 1))
    ry = np.sqrt(3.0) / 2
    k = 2 * np.pi / (ny * ry)
    row = np.round(d[:, 1] / ry - 0.5)
    y0 = ry * (row + 0.5)
    shift = 0.25 + 0.5 * (row.astype(int) % 2)
    u = d[:, 1] - y0 if longitudinal else d[:, 0] - (np.round(d[:, 0] - shift) + shift)
    return t, 2.0 / len(d) * np.sum(u * np.sin(k * y0))


def half_cycles(t, a):
    """Times between successive zero crossings of a(t); each crossing is the root of a
    cubic through the four samples around it."""
    t, a = np.asarray(t), np.asarray(a)
    crossings = []
    for n in range(1, len(a) - 2):
        if a[n] * a[n + 1] < 0:
            c = np.polyfit(t[n - 1:n + 3] - t[n], a[n - 1:n + 3], 3)
            roots = [z.real for z in np.roots(c) if abs(z.imag) < 1e-12 and 0 <= z.real <= t[n + 1] - t[n]]
            crossings.append(t[n] + roots[0])
    return np.diff(crossings)
