"""One colour and marker per method (and per controller or variant) for every chart the
studies draw, so that a method looks the same in every panel and every PNG.

    from chart_style import style, UNSTABLE
    ax.plot(x, y, **style("DP5"), label="DP5")

A label not in the table gets a colour and marker chosen from a hash of the label, so it is
still the same across charts (and across runs of the scripts), though it may share a
colour with another label. Unstable or failed runs are drawn with UNSTABLE, whatever the
method: a hollow red X.
"""
import hashlib

# Adaptive pairs, then the fixed-step methods (symplectic, then Runge-Kutta), then the
# step controllers, the tensile variants and the kernels. Colours are distinct within each chart's set.
STYLES = {
    # adaptive (precision, drift)
    "BS3": ("#1f77b4", "o"),
    "DP5": ("#ff7f0e", "s"),
    "V6": ("#2ca02c", "D"),
    "F8": ("#d62728", "^"),
    "CVODE": ("#9467bd", "v"),
    "rk5dp": ("#8c564b", "<"),
    # IMEX (bench/run_imex.py): GMRES unpreconditioned, preconditioned, and with the
    # assembled Jacobian's products
    "IMEX, unpreconditioned": ("#1f77b4", "o"),
    "IMEX, preconditioned": ("#2ca02c", "D"),
    "IMEX, assembled J v": ("#d62728", "^"),
    # variants of the preconditioned runs (bench/run_imex.py --variants)
    "IMEX, predictor5": ("#9467bd", "v"),
    "IMEX, previous": ("#8c564b", "<"),
    # symplectic, fixed steps (precision, drift, stability)
    "Verlet": ("#e377c2", ">"),
    "Symp3": ("#17becf", "p"),
    "Symp4": ("#000000", "*"),
    # fixed-step Runge-Kutta (stability)
    "euler": ("#7f7f7f", "h"),
    "Heun": ("#bcbd22", "H"),
    "SSP3": ("#aec7e8", "d"),
    "RK4": ("#98df8a", "P"),
    # controllers
    "ARKODE I": ("#1f77b4", "o"),
    "ARKODE PI": ("#ff7f0e", "s"),
    "ARKODE PID": ("#2ca02c", "D"),
    "PETSc basic (rk 5dp)": ("#9467bd", "v"),
    "PETSc dsp (rk 5dp)": ("#8c564b", "<"),
    # tensile variants
    "R0": ("#1f77b4", "o"),
    "R2": ("#ff7f0e", "s"),
    "R0 + viscosity": ("#2ca02c", "D"),
    # kernels (examples/study_shear_mode.py: colour per kernel, marker per variant)
    "lucy": ("#1f77b4", "o"),
    "cubic_spline": ("#ff7f0e", "s"),
    "quintic_spline": ("#2ca02c", "D"),
    "wendland_c2": ("#d62728", "^"),
    "wendland_c4": ("#9467bd", "v"),
    "wendland_c6": ("#8c564b", "<"),
}
_FALLBACK_COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                     "#bcbd22", "#17becf"]
_FALLBACK_MARKERS = "osD^v<>ph*"

# Unstable (exit 3) or failed runs: one look for all methods, named in the legend.
UNSTABLE = {"color": "red", "marker": "X", "mfc": "none", "mec": "red", "ms": 11, "linestyle": "none", "mew": 1.6}


def style(label):
    """{'color': ..., 'marker': ...} of a method label, stable across charts and runs."""
    if label in STYLES:
        colour, marker = STYLES[label]
    else:
        k = int(hashlib.sha1(label.encode()).hexdigest(), 16)
        colour, marker = _FALLBACK_COLOURS[k % len(_FALLBACK_COLOURS)], _FALLBACK_MARKERS[(k // 10) % len(_FALLBACK_MARKERS)]
    return {"color": colour, "marker": marker}
