#!/usr/bin/python3
"""The gallery cannot go stale unnoticed (examples/study.py gallery --small): every study
writes its CSV, its charts and its section of study.md; each section names the command
that made it; study.md holds
no absolute path; and the numbers its readings print are the ones recomputed here from the
CSVs the same run wrote (to the digits printed), so a reading typed by hand or left from
another run would fail."""
import csv
import math
import os
import re
import subprocess
import sys

from spamrun import Checks, arguments

a = arguments()
c = Checks()
here = os.path.dirname(os.path.abspath(__file__))
study = os.path.join(here, "..", "examples", "study.py")
out = os.path.join(a.workdir, "gallery")
p = subprocess.run([sys.executable, study, "gallery", "--small", "--out", out, "--spam-ark", a.spam_ark],
                   capture_output=True, text=True)
c.check(p.returncode == 0, f"study.py gallery --small runs (exit {p.returncode}) {p.stderr.strip()[-300:]}")


def rows(name, sub=""):
    with open(os.path.join(out, sub, name)) as f:
        return list(csv.DictReader(f))


def num(x):
    try:
        return float(x)
    except ValueError:
        return float("nan")


def section(md, part):
    m = re.search(rf"<!-- {part} -->\n(.*?)<!-- /{part} -->", md, re.S)
    return m.group(1) if m else ""


FILES = {"precision": ["precision.csv", "error_vs_rhs.png", "error_vs_wall.png", "energy_drift_vs_tol.png",
                       "angmom_drift_vs_tol.png", "steps_vs_tol.png"],
         "stability": ["stability.csv", "stability.png"], "controller": ["controllers.csv", "controllers.png"],
         "entropy": ["entropy.csv", "entropy.png"], "tensile": ["tensile.csv", "tensile.png"],
         "drift": ["drift.csv", "drift.png"]}
# An absolute path: a slash that starts a word (after a space, quote, backtick, bracket or
# '=') and continues with a directory name and another slash.
ABSOLUTE = re.compile(r"(?:^|[\s`'\"(\[=])/[\w.+-]+/", re.M)
# The provenance line names the command (the pages name no commit: git's history does).
MADE = re.compile(r"\*Made by `(examples/study\.py gallery --small [^`]*)`")
mds = {}
for sub, parts in (("", ["precision", "stability", "controller", "entropy", "tensile", "drift"]),
                   ("planewave", ["precision", "planewave"])):
    path = os.path.join(out, sub, "study.md")
    md = open(path).read() if os.path.exists(path) else ""
    mds[sub] = md
    for part in parts:
        body = section(md, part)
        files = FILES.get(part, []) if sub == "" or part == "precision" else []
        missing = [f for f in files if not (os.path.exists(os.path.join(out, sub, f))
                                            and os.path.getsize(os.path.join(out, sub, f)) > (1000 if f.endswith(".png") else 100))]
        c.check(bool(body) and not missing, f"{sub or '.'}/{part}: section in study.md, files written (missing: {missing or 'none'})")
        m = MADE.search(body)
        c.check(m is not None, f"{sub or '.'}/{part}: names its command ({m.group(1) if m else 'absent'})")
    bad = ABSOLUTE.findall(md)
    c.check(not bad and os.path.abspath(here + "/..") not in md and a.workdir not in md,
            f"{sub or '.'}/study.md: no absolute path ({bad[:3] or 'none'})")


def check_precision(sub):
    """The reading 'to reach 1e-6 in position, M needs the fewest RHS evaluations (N at ...)'
    and 'the most accurate run is M at ... (E)', recomputed from precision.csv."""
    rs = [r for r in rows("precision.csv", sub) if r["status"] == "ok" and math.isfinite(num(r["err_x_final"]))]
    body = section(mds[sub], "precision")
    reach = [r for r in rs if num(r["err_x_final"]) <= 1e-6]
    best = min(rs, key=lambda r: num(r["err_x_final"]))
    if reach:
        w = min(reach, key=lambda r: int(r["rhs_evals"]))
        c.check(f"{w['method']} needs the fewest RHS evaluations ({w['rhs_evals']} at " in body,
                f"{sub or '.'}: cheapest to 1e-6 is {w['method']} with {w['rhs_evals']} RHS evaluations, as the reading says")
    else:
        c.check("no run reached 1e-6" in body, f"{sub or '.'}: no run reached 1e-6, as the reading says")
    c.check(f"most accurate {'run is ' if reach else 'is '}{best['method']} at" in body
            and f"({num(best['err_x_final']):.1e})" in body,
            f"{sub or '.'}: most accurate run {best['method']} ({num(best['err_x_final']):.1e}), as the reading says")
    return rs


rs = check_precision("")
check_precision("planewave")
# The fitted orders of the fixed-step series.
orders = {}
for r in rs:
    if math.isfinite(num(r["dt"])) and num(r["err_x_final"]) > 1e-12:
        orders.setdefault(r["method"], []).append((math.log(num(r["dt"])), math.log(num(r["err_x_final"]))))
for m, pts in orders.items():
    (x0, y0), (x1, y1) = sorted(pts)[0], sorted(pts)[-1]
    if len(pts) == 2:
        c.check(f"{m} {(y1 - y0) / (x1 - x0):.2f}" in section(mds[""], "precision"),
                f"fitted order of {m}: {(y1 - y0) / (x1 - x0):.2f}, as the reading says")
c.check(any(math.isfinite(num(r["dt"])) and r["method"] == "Verlet" for r in rs),
        "the work-precision study holds the fixed-step Verlet series")
pw = rows("precision.csv", "planewave")
c.check(any(r["status"] == "refused" and r["method"] == "Verlet" for r in pw)
        and "Refused by spam-ark on this scene (exit 2): Verlet" in section(mds["planewave"], "precision"),
        "plane wave: the symplectic split refused (elastic state) and said so")

# Stability: every table row's limit is the CSV's.
body = section(mds[""], "stability")
for r in rows("stability.csv"):
    c.check(f"| {r['scene']} | {r['method']} | {r['force_evals_per_step']} | {num(r['dt_limit']):.4f} |" in body,
            f"stability {r['scene']} {r['method']}: limit {num(r['dt_limit']):.4f} in the table")

# Controllers: the count of unstable runs and the table.
cr = rows("controllers.csv")
body = section(mds[""], "controller")
nun = sum(1 for r in cr if r["exit_code"] == "3")
c.check(f"Reading: {nun} of {len(cr)} controllers ended unstable" in body, f"controllers: {nun} of {len(cr)} unstable, as the reading says")
for r in cr:
    c.check(f"| {r['controller']} | {r['status']} |" in body and f"| {r['rejected']} |" in body,
            f"controller {r['controller']}: {r['status']}, {r['rejected']} rejected in the table")

# Entropy: the final ratios.
body = section(mds[""], "entropy")
for r in rows("entropy.csv"):
    c.check(f"| {num(r['dS_sum_final']):.4f} | {num(r['dS_grid_final']):.4f} |" in body,
            f"entropy N = {r['N']}: {num(r['dS_sum_final']):.4f} (sum), {num(r['dS_grid_final']):.4f} (grid) in the table")

# Tensile: the rates.
body = section(mds[""], "tensile")
tr = rows("tensile.csv")
for r in tr:
    c.check(f"{num(r['rate']):.4f}" in body, f"tensile {r['variant']} sigma0 {r['sigma0']}: rate {num(r['rate']):.4f} in the table")
grow = sum(1 for r in tr if num(r["rate"]) > 0.01)
c.check(f"Reading: {grow} of {len(tr)} runs grow" in body, f"tensile: {grow} of {len(tr)} runs grow, as the reading says")

# Drift: the exponents and the nearest-cost pair.
body = section(mds[""], "drift")
dr = rows("drift.csv")
fixed = [r for r in dr if math.isfinite(num(r["dt"])) and r["status"] == "ok"]
adaptive = [r for r in dr if math.isfinite(num(r["rtol"])) and r["status"] == "ok"]
c.check(bool(fixed) and bool(adaptive), f"drift: {len(fixed)} symplectic and {len(adaptive)} adaptive runs finished")
if fixed and adaptive:
    pf = max(num(r["drift_exponent"]) for r in fixed)
    pa = min(num(r["drift_exponent"]) for r in adaptive)
    c.check(f"at most {pf:.2f}" in body and f"at least {pa:.2f}" in body,
            f"drift: envelope exponents at most {pf:.2f} (symplectic), at least {pa:.2f} (adaptive), as the reading says")
    for r in dr:
        c.check(f"| {num(r['energy_err_max']):.2e} | {num(r['energy_err_final']):.2e} | {num(r['drift_exponent']):.2f} |" in body,
                f"drift {r['method']}: max {num(r['energy_err_max']):.2e}, final {num(r['energy_err_final']):.2e} in the table")
c.finish()
