#!/usr/bin/python3
"""The adaptive Sedov front's lead against the width of the shock's viscous layer.

Usage:
    /usr/bin/python3 examples/sedov_layer_width.py [--readings FILE]

Reads the 2D 64^2, t = 4 readings of docs/scenes/sedov_lead_64.json (R_front - R) and
docs/scenes/sedov_lead_causes_64.json (the mass front - R), one change per run, and tests
the two scalings a viscous layer's width has:
- the kernel's range: at fixed viscosity the layer is a fixed number of particle ranges
  h_i = eta (m/rho_i)^(1/D) wide, so a lead that is the layer's is proportional to eta
  (lead / eta the same at eta = 2.4, 3, 3.6);
- the quadratic term: a steady shock held by q = beta rho (h div v)^2 alone (the von
  Neumann-Richtmyer viscosity; at the front of a strong blast the cold gas ahead makes the
  linear alpha c term negligible) is pi h (2 beta / (gamma + 1))^(1/2) wide, whatever the
  shock's strength, so the lead is a + b beta^(1/2) (fitted at beta = 1, 2, 4; a: what the
  range alone gives).
Writes the ratios, the fits and their residuals (lattice spacings).
"""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

import chart_readings  # noqa: E402

SCENES = os.path.join(HERE, "..", "docs", "scenes")
ETAS = (("eta2_4", 2.4), ("default", 3.0), ("eta3_6", 3.6))
BETAS = (("beta1", 1.0), ("default", 2.0), ("beta4", 4.0))


def leads(name, key, t="t4"):
    with open(os.path.join(SCENES, name), encoding="utf-8") as fh:
        r = json.load(fh)["readings"]
    return {run: r[run]["at"][t][key] for run in r if t in r[run].get("at", {})}


def scalings(lead):
    """lead / eta at the three ranges, and the fit a + b beta^(1/2) at the three betas."""
    out = {"over_eta": {run: lead[run] / eta for run, eta in ETAS}}
    ratios = np.array(list(out["over_eta"].values()))
    out["over_eta_spread"] = float((ratios.max() - ratios.min()) / ratios.mean())
    s = np.array([np.sqrt(b) for _, b in BETAS])
    y = np.array([lead[run] for run, _ in BETAS])
    b, a = np.polyfit(s, y, 1)
    out["beta_fit"] = {"a": float(a), "b": float(b), "rms": float(np.sqrt(np.mean((a + b * s - y) ** 2)))}
    lin = np.polyfit([bb for _, bb in BETAS], y, 1)
    out["beta_linear_rms"] = float(np.sqrt(np.mean((np.polyval(lin, [bb for _, bb in BETAS]) - y) ** 2)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--readings")
    a = ap.parse_args()
    out = {"front": scalings(leads("sedov_lead_64.json", "front_lead")),
           "mass": scalings(leads("sedov_lead_causes_64.json", "mass_lead"))}
    for k, v in out.items():
        f = v["beta_fit"]
        print(f"{k}: lead/eta {', '.join(f'{x:.3f}' for x in v['over_eta'].values())} (spread {v['over_eta_spread']:.1%}); "
              f"lead = {f['a']:.3f} + {f['b']:.3f} beta^1/2 (rms {f['rms']:.3f}; linear in beta: rms {v['beta_linear_rms']:.3f})")
    if a.readings:
        chart_readings.write_json(a.readings, out)


if __name__ == "__main__":
    main()
