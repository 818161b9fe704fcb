#!/usr/bin/python3
"""-error_norm rms|max: the norm in which every adaptive method holds its
weighted error estimate to 1.

1. Under the max norm the largest particle error at t_end scales with rtol at every N, on the
   free expansion at t = 4 (its front, a few spacings wide, carries the error; the interior
   is at rest), against a Dormand-Prince reference (max norm, rtol 1e-11):
   - the exponent of a fit of log(error) against log(rtol) over rtol 1e-4, 1e-6, 1e-8 lies
     in [0.5, 1]. Derived from the order: Lucy's force is only C^1 at r = h, so once every
     step holds a pair crossing the local error is third order in dt, the step goes as
     rtol^(1/3), and the error at t_end, summed over ~rtol^(-1/3) steps, as rtol^(2/3); a
     smooth force would give Dormand-Prince's tolerance proportionality, rtol^1. The lower
     bound leaves 25% of 2/3 for the scatter of a fit over three runs.
   - error / (rtol h) at each rtol varies by less than a factor 2 from N = 16^2 to 64^2:
     the max norm holds every particle's local error to rtol h whatever N is (the rms norm
     lets an error at a few particles through sqrt(4N) times larger); the factor 2 allows
     for the different step sequences.
   (That rms and max are equal for an error at one particle scaled by sqrt(L), and for a
   uniform one, is test_error_norm, the unit test of the norm.)
2. It means the same for every adaptive method: arkode, cvode and PETSc's rk (basic and dsp
   adaptors) each need more RHS evaluations under max than under rms (max >= rms for every
   error vector, equal only for an error spread evenly over all components, which the
   expansion's is not), and run to the end.
3. Refused (exit 2, one line naming -error_norm): fixed-step runs (arkode with a fixed step,
   rk without an adaptor, euler, basicsymplectic) and bad values (naming rms and max); a
   -ts_adapt_wnormtype that disagrees with it is refused, one that agrees runs."""
import math
import os

import numpy as np
from spamrun import Checks, Runner, arguments, manifest_files, summary

a = arguments()
runner = Runner(a.spam_ark, a.workdir)  # each run a forked child of the fork server
c = Checks()
W = a.workdir
H, T_END = 3.0, 4.0
SIZES = (16, 32, 64)
TOLS = (1e-4, 1e-6, 1e-8)


def scene(n):
    return ["-scene", "expansion", "-expansion_n", n, "-h", H, "-ts_max_time", T_END, "-output_interval", T_END,
            "-snapshot_interval", T_END, "-snapshot_hdf5", "false", "-diag_entropy", "false"]


def tol(rtol):
    return ["-ts_rtol", rtol, "-ts_atol", rtol * 1e-3]  # rtol alone sets every weight


def go(args, name):
    d = os.path.join(W, name)
    code, _, err = runner.run(args, d)
    if code != 0:
        c.check(False, f"{name}: exit {code}: {err.strip().splitlines()[-1:]}")
        return None
    return d


def final(d):
    return np.loadtxt(manifest_files(d, "snapshot_csv")[-1], delimiter=",", skiprows=2, ndmin=2)[:, :3]


def largest_error(d, ref):
    box = summary(ref)["box_len"]
    dx = final(d) - final(ref)
    for k in range(3):  # minimum image across the periodic faces
        if box[k] > 0:
            dx[:, k] -= box[k] * np.round(dx[:, k] / box[k])
    return float(np.sqrt(np.sum(dx * dx, 1)).max())


# 1. tolerance proportionality of the max norm at every N
ratio = {}
for n in SIZES:
    ref = go(scene(n) + tol(1e-11) + ["-error_norm", "max"], f"ref_{n}")
    errs = []
    for rtol in TOLS:
        d = go(scene(n) + tol(rtol) + ["-error_norm", "max"], f"max_{n}_{rtol:g}")
        if ref and d:
            errs.append(largest_error(d, ref))
            ratio[(n, rtol)] = errs[-1] / (rtol * H)
    if len(errs) == len(TOLS):
        q = float(np.polyfit(np.log(TOLS), np.log(errs), 1)[0])
        c.check(0.5 <= q <= 1.0, f"N = {n}^2, max norm: largest particle error "
                + ", ".join(f"{e:.2e}" for e in errs) + f" at rtol {', '.join(f'{t:g}' for t in TOLS)}: "
                f"goes as rtol^{q:.2f}, in [0.5, 1] (2/3 for Lucy's C^1 force, 1 for a smooth one)")
for rtol in TOLS:
    r = [ratio[(n, rtol)] for n in SIZES if (n, rtol) in ratio]
    if len(r) == len(SIZES):
        c.check(max(r) / min(r) < 2.0, f"rtol {rtol:g}, max norm: largest particle error / (rtol h) = "
                + ", ".join(f"{x:.2f}" for x in r) + f" at N = {', '.join(f'{n}^2' for n in SIZES)}: "
                f"within a factor 2 ({max(r) / min(r):.2f}) whatever N is")

# 2. the same option for every adaptive method
METHODS = [("arkode", []), ("cvode", ["-ts_type", "cvode"]), ("rk 5dp basic", ["-ts_type", "rk", "-ts_rk_type", "5dp"]),
           ("rk 3bs basic", ["-ts_type", "rk", "-ts_rk_type", "3bs"]),
           ("rk 5dp dsp", ["-ts_type", "rk", "-ts_rk_type", "5dp", "-ts_adapt_type", "dsp"])]
for label, opts in METHODS:
    rhs = {}
    for norm in ("rms", "max"):
        d = go(scene(32) + tol(1e-6) + opts + ["-error_norm", norm], f"{label.replace(' ', '_')}_{norm}")
        if d:
            s = summary(d)
            rhs[norm] = s["rhs_evals"] if s["status"] == "ok" else None
    if len(rhs) == 2 and None not in rhs.values():
        c.check(rhs["max"] > rhs["rms"], f"{label}: {rhs['max']} RHS evaluations under -error_norm max, more than "
                f"{rhs['rms']} under rms (both runs to t = {T_END:g})")

# 3. refusals
SMALL = ["-expansion_n", 8, "-h", 3, "-ts_max_time", 1]


def refused(name, args, needles):
    d = os.path.join(W, "refused_" + name)
    code, _, err = runner.run(SMALL + args, d)
    lines = err.strip().splitlines()
    ok = code == 2 and len(lines) == 1 and lines[0].startswith("spam-ark: error: ") and all(x in lines[0] for x in needles)
    c.check(ok and not os.path.exists(d), f"{name}: exit {code}, stderr {lines}, no output directory")


for name, args in [("arkode fixed step", ["-arkode_fixed_step", 0.1]),
                   ("rk without adaptor", ["-ts_type", "rk", "-ts_rk_type", "4", "-ts_adapt_type", "none"]),
                   ("euler", ["-ts_type", "euler"]), ("basicsymplectic", ["-ts_type", "basicsymplectic"])]:
    for norm in ("rms", "max"):
        refused(f"{name} -error_norm {norm}", args + ["-error_norm", norm], ["-error_norm", "adaptive steps"])
for value in ("inf", "MAX", "l2", "0"):
    refused(f"-error_norm {value}", ["-error_norm", value], ["-error_norm", f"'{value}'", "rms, max"])
refused("rk -ts_adapt_wnormtype infinity under rms", ["-ts_type", "rk", "-ts_adapt_wnormtype", "infinity"],
        ["-ts_adapt_wnormtype", "-error_norm rms"])
refused("rk -ts_adapt_wnormtype 2 under max", ["-ts_type", "rk", "-ts_adapt_wnormtype", "2", "-error_norm", "max"],
        ["-ts_adapt_wnormtype", "-error_norm max"])
code, _, err = runner.run(SMALL + ["-ts_type", "rk", "-ts_adapt_wnormtype", "infinity", "-error_norm", "max"], os.path.join(W, "agree"))
c.check(code == 0, f"rk -ts_adapt_wnormtype infinity -error_norm max (they agree) runs: exit {code} {err.strip().splitlines()[-1:]}")
c.finish()
