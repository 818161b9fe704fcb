"""The roll of the convection cell and its saturation, for the scripts that run the cell.

roll_amplitudes measures the roll (k = 2 pi / L) in a run's CSV snapshots; saturation and
run_to_saturation are the rule the runs share for the saturated state: a run lasts until its
roll has saturated, and Nu is averaged from one e-folding time after that (nu_from).
tests/run_convection_onset.py (the onset study) and examples/convection_sweep.py (the Nu-Ra
chart, --saturate) both use them."""
import math

import numpy as np

from spamrun import manifest_files


def roll_amplitudes(cell, out, k, y, fields):
    """(t, A_T, A_v, C, phi, H2) in every CSV snapshot of the run in out (cell: the
    convection_linear.Cell it ran; y, fields: the linear mode at k, convection_linear.mode): the roll's amplitude (its peak vertical velocity,
    the eigenfunction's scale) from the projection of T - T0(y) on T'(y) exp(i k x), and from
    that of v_y on v(y) exp(i k x), both mass-weighted. The temperature carries the roll
    more than the sound waves that fill the cell (the eigenfunction's T' peaks at 2.4 x
    its v at 3 Ra_c, a sound wave's T' is (gamma - 1) T v / c_s ~ 0.7 v), and the runs
    show it: A_T's noise floor is about 1e-4, A_v's 1e-3 (the cell's sound at the same k).
    A_T is the measure fitted.
    C and phi tell the disturbance from the linear eigenmode: C the correlation of its
    T - T0 row profile (the complex k-component in each of the cell's ny rows, the
    mass-weighted mean over the row's particles) with the eigenfunction's T' there,
    |<c, T'>| / (|c| |T'|), 1 for the eigenmode at any amplitude and phase; phi the phase
    of A_T's projection (where the roll sits along x), constant for the eigenmode, which is
    stationary. C alone does not tell the mode from the seed's transient (the seed's v
    advecting the mean gradient gives a T' of the same sin-like shape: C 0.99 at 1.2 Ra_c,
    seed 1e-2, while the projection decays and its phase turns by 2 rad); the phase does.
    The v_y profile would tell them apart as well, but its noise floor (the cell's sound)
    keeps its correlation low up to A ~ 1e-3.
    H2, the share of the second harmonic: |k-component of T - T0 at 2k| over |at k| (mass-
    weighted, no profile): the roll's own nonlinear harmonic is of order (A / saturation) x
    its saturated share (0.09 at 1.2 Ra_c), so a larger H2 while A is small is a second
    disturbance (two roll pairs), which the roll's k-component couples to (k x 2k -> k)."""
    wT, wv = fields["T"].real, fields["v"].real
    beta = (cell.t_bottom - cell.t_top) / cell.H
    edges = np.linspace(0.0, cell.H, cell.ny + 1)
    eig = np.interp(0.5 * (edges[1:] + edges[:-1]), y, wT)
    ts, aT, av, cs, phs, h2s = [], [], [], [], [], []
    for path in manifest_files(out, "snapshot_csv"):
        with open(path) as f:
            first = f.readline()
        t = float(first.split("=")[1])
        d = np.genfromtxt(path, delimiter=",", names=True, skip_header=1)
        ph = np.exp(-1j * k * d["x"])
        dT = (cell.gamma - 1.0) * d["e"] - (cell.t_bottom - beta * d["y"])
        pT, pv = np.interp(d["y"], y, wT), np.interp(d["y"], y, wv)
        ts.append(t)
        projT = np.sum(d["m"] * dT * pT * ph)
        aT.append(2 * abs(projT) / np.sum(d["m"] * pT * pT))
        phs.append(float(np.angle(projT)))
        f1, f2 = abs(np.sum(d["m"] * dT * ph)), abs(np.sum(d["m"] * dT * ph * ph))
        h2s.append(f2 / f1 if f1 > 0 else float("nan"))
        av.append(2 * abs(np.sum(d["m"] * d["vy"] * pv * ph)) / np.sum(d["m"] * pv * pv))
        row = np.clip(np.digitize(d["y"], edges) - 1, 0, cell.ny - 1)
        mass = np.maximum(np.bincount(row, d["m"], cell.ny), 1e-300)
        prof = (np.bincount(row, (d["m"] * dT * ph).real, cell.ny) + 1j * np.bincount(row, (d["m"] * dT * ph).imag, cell.ny)) / mass
        norm = math.sqrt(np.sum(abs(prof) ** 2) * np.sum(eig ** 2))
        cs.append(abs(np.sum(prof * eig)) / norm if norm > 0 else 0.0)
    order = np.argsort(ts)
    return tuple(np.array(q)[order] for q in (ts, aT, av, cs, phs, h2s))


# Saturation, for Nu: the roll's amplitude has saturated at t_sat, the first snapshot where
# A reaches SAT_LEVEL x its mean over the run's last e-folding time 1/s; Nu is averaged from
# t_sat + 1/s (one e-folding time to settle) to the end, over at least NU_WINDOW / s. A run
# whose end comes sooner is continued from its last checkpoint (taken every 1/s) to
# t_sat + (1 + NU_WINDOW) / s and looked at again, up to MAX_EXTENSIONS times; then its Nu
# is flagged "not saturated". The runs' sized end times assume the roll grows from t = 0;
# a seed whose disturbance first decays (1.2 Ra_c, seed 1e-2: for about 3000 time units)
# ends during the rise, and its Nu, averaged over the last 3 / s, took in part of it
# (1.214 against 1.223-1.229 at saturation).
SAT_LEVEL, NU_WINDOW, MAX_EXTENSIONS = 0.9, 3.0, 4


def saturation(t, A, s):
    """(t_sat, A_end): t_sat the first time A reaches SAT_LEVEL x A_end, the mean of A over the
    run's last 1/s."""
    a_end = float(np.mean(A[t >= t[-1] - 1.0 / s]))
    i = next((i for i in range(len(t)) if t[i] > 0 and A[i] >= SAT_LEVEL * a_end), len(t) - 1)
    return float(t[i]), a_end


def nu_from(t, A, s):
    """The time Nu's average starts: one e-folding time 1/s after saturation (saturation)."""
    return saturation(t, A, s)[0] + 1.0 / s


def grew(t, A):
    """Whether the roll grew: its end value (the mean over the last tenth of the run) is 3 x or
    more its minimum after t = 0 up to its peak (the seed is velocity only, so A starts from 0
    at t = 0). exponential_fit of tests/run_convection_onset.py calls the other case "none"."""
    pos = t > 0
    t, A = t[pos], A[pos]
    if len(A) < 2:
        return False
    a_min = float(np.min(A[: int(np.argmax(A)) + 1]))
    return float(np.mean(A[t >= t[-1] - 0.1 * (t[-1] - t[0])])) >= 3.0 * a_min


def run_to_saturation(t_end, s, amplitudes, extend, log=print):
    """(t_end, series, extensions, saturated) of a run that reached t_end, its roll growing at
    the linear rate s > 0: while its end comes before t_sat + (1 + NU_WINDOW) / s (saturation
    of series = amplitudes(), whose first two entries are t and A), extend(t) continues it from
    its checkpoint to that time (True: continued, False: the continuation failed, None: no
    checkpoint) and amplitudes() is read again, up to MAX_EXTENSIONS times; saturated is False
    when the run still ends too soon."""
    series, extensions = amplitudes(), 0
    while True:
        t_sat, a_end = saturation(series[0], series[1], s)
        t_need = t_sat + (1.0 + NU_WINDOW) / s
        if t_end >= t_need * (1 - 1e-9):
            return t_end, series, extensions, True
        if extensions == MAX_EXTENSIONS:
            return t_end, series, extensions, False
        log(f"A reaches {SAT_LEVEL} x its end value {a_end:.3g} at t = {t_sat:.0f}: continued to {t_need:.0f}")
        done = extend(t_need)
        if done is None:
            return t_end, series, extensions, False
        extensions += 1
        if not done:
            return t_need, series, extensions, False
        t_end, series = t_need, amplitudes()
