#!/usr/bin/python3
"""One colour and marker per source or run layout, shared by the charts of halo_model.py
and run_scaling.py, so that a layout or a source looks the same in every panel."""

# The halo model's sources (halo_model.py).
SOURCE_STYLE = {
    "cube": {"color": "tab:gray", "marker": "", "linestyle": "--",
             "label": "ideal cubes of N/P (formula)"},
    "cells": {"color": "tab:green", "marker": "s", "linestyle": "-",
              "label": "Hilbert cut, halo of the selection by cells (-geometry)"},
    "cells_builds": {"color": "tab:purple", "marker": "v", "linestyle": ":",
                     "label": "the same, list builds included"},
    "hilbert": {"color": "tab:blue", "marker": "o", "linestyle": "-.",
                "label": "Hilbert cut, bounding-box halo (upper bound)"},
    "census": {"color": "tab:red", "marker": "x", "linestyle": "",
               "label": "SpamHalo on P ranks (measured, halo_census)"},
}

# Particle counts of the model's table: one line width per N (the colour is the source's).
N_WIDTH = {10 ** 5: 0.8, 10 ** 6: 1.3, 10 ** 7: 1.8, 10 ** 8: 2.4}

# Run layouts of run_scaling.py: ranks x threads.
LAYOUT_STYLE = {
    "1x1": {"color": "black", "marker": "s", "label": "1 rank x 1 thread"},
    "1x2": {"color": "tab:orange", "marker": "D", "label": "1 rank x 2 threads (-threads 2)"},
    "2x1": {"color": "tab:blue", "marker": "o", "label": "2 ranks x 1 thread (mpiexec -n 2)"},
}
FAILED_STYLE = {"color": "red", "marker": "X", "markerfacecolor": "none", "markersize": 11, "linestyle": ""}
