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
