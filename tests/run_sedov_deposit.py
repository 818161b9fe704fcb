#!/usr/bin/python3
"""-sedov_deposit_radius: the blast's energy weighted by the model's kernel at another range.

The scene puts e_i = e0 + E0 w(r_i, R_d) / sum_j m_j w(r_j, R_d) on the lattice, r_i the
distance from the box centre (a cell corner), w the model's kernel, R_d = -h by default.
2D Sedov 16^2, -h 2, E0 = 1e4, the initial snapshot only (-ts_max_time 1e-3; each run a
fraction of a CPU-second):
- the default and -sedov_deposit_radius 2 (= -h) give the same energies bit for bit (the
  option changes nothing unless given another range);
- -sedov_deposit_radius 3.5: sum_i m_i (e_i - e0) = E0 to 1e-12 relative (the sum's
  rounding); e_i = e0 exactly at r_i >= 3.5 and above it inside; (e_i - e0) / w(r_i, 3.5)
  the same for every particle inside to 1e-12 (Lucy's kernel at range 3.5, computed here);
  more particles heated than at -h;
- refused (exit 2, one line naming the option): 0.5 (below the nearest particles'
  distance sqrt(2)/2, nobody would take the energy), 4 (not below n/4 = 4) and -1; and
  under -scene sod (not the scene's option).
"""
import math
import os

import numpy as np

from spamrun import Checks, arguments, manifest_files, run

a = arguments()
c = Checks()
N, H, E0, E_AMB = 16, 2.0, 1e4, 1e-3
COMMON = ["-scene", "sedov", "-dim", 2, "-sedov_n", N, "-h", H, "-sedov_energy", E0, "-gas_e0", E_AMB, "-material", "gas",
          "-ts_max_time", 1e-3, "-snapshot_interval", 1e-3, "-snapshot_hdf5", 0, "-quiet"]


def initial(out):
    """(r from the centre, m, e) of the snapshot at t = 0."""
    path = manifest_files(out, "snapshot_csv")[0]
    with open(path) as fh:
        fh.readline()
        cols = fh.readline().strip().split(",")
        rows = np.array([[float(v) for v in line.split(",")] for line in fh if line.strip()])
    x = rows[:, [cols.index("x"), cols.index("y")]] - 0.5 * N
    return np.hypot(x[:, 0], x[:, 1]), rows[:, cols.index("m")], rows[:, cols.index("e")]


def lucy(r, h):
    q = np.minimum(r / h, 1.0)
    return 5.0 / (math.pi * h * h) * (1.0 + 3.0 * q) * (1.0 - q) ** 3


got = {}
for name, extra in (("default", []), ("same", ["-sedov_deposit_radius", H]), ("wide", ["-sedov_deposit_radius", 3.5])):
    out = os.path.join(a.workdir, name)
    code, _, err = run(a.spam_ark, COMMON + extra, out)
    if not c.check(code == 0, f"{name}: run exits 0 ({err.strip()[-300:]})"):
        c.finish()
    got[name] = initial(out)
c.check(np.array_equal(got["default"][2], got["same"][2]), "-sedov_deposit_radius 2 (= -h) gives the default's energies bit for bit")
r, m, e = got["wide"]
de = e - E_AMB
rel = abs(float(np.sum(m * de)) / E0 - 1.0)
c.check(rel < 1e-12, f"range 3.5: the deposit sums to E0 within {rel:.1e} (bound 1e-12)")
inside = r < 3.5
c.check(bool(np.all(e[~inside] == E_AMB)) and bool(np.all(de[inside] > 0.0)),
        f"range 3.5: {int(inside.sum())} particles heated, all inside r < 3.5; the others keep e0 exactly")
ratio = de[inside] / lucy(r[inside], 3.5)
spread = float(np.max(ratio) / np.min(ratio) - 1.0)
c.check(spread < 1e-12, f"range 3.5: e - e0 proportional to Lucy's w(r, 3.5) within {spread:.1e} (bound 1e-12)")
n_default = int(np.sum(got["default"][2] > E_AMB))
c.check(int(inside.sum()) > n_default, f"range 3.5 heats {int(inside.sum())} particles, the default range 2 heats {n_default}")
for val in ("0.5", "4", "-1"):
    code, _, err = run(a.spam_ark, COMMON + ["-sedov_deposit_radius", val], os.path.join(a.workdir, "bad"))
    c.check(code == 2 and "-sedov_deposit_radius" in err, f"-sedov_deposit_radius {val} refused with exit 2 naming the option (exit {code}: {err.strip()[-200:]})")
code, _, err = run(a.spam_ark, ["-scene", "sod", "-sedov_deposit_radius", 6, "-quiet"], os.path.join(a.workdir, "sod"))
c.check(code == 2 and "sedov_deposit_radius" in err, f"-sedov_deposit_radius under -scene sod refused with exit 2 (exit {code}: {err.strip()[-200:]})")
c.finish(a.readings)
