#!/usr/bin/python3
"""Fields on a regular grid (-grid_interval; docs/scenes/grid.md).

Particle files of the file scene on a square lattice of spacing a = 1 (mass 1, so the
continuum density is rho0 = m / a^D = 1), Lucy's kernel with h = 3 (1D, 2D) or 2.5 (3D), the
grid written at t = 0 (the first snapshot: the state is exactly the file).

(0) Implementation: rho, S and every interpolant equal a direct O(N M) sum in this script
    (minimum image, rho_j the summed density at the sites) to 1e-12 relative. Derivation:
    each value is a sum of at most ~40 terms of size <= w(0) m / rho_j < 0.2, so round-off
    is below 40 * 2.2e-16 * 0.2 = 2e-15; 1e-12 leaves a factor 500 for the order of the sums.
(a) A uniform lattice at rest: |rho(x) - rho0| <= E_lat, E_lat = max over the unit cell of
    |sum_j m w(x - x_j) - rho0|, the kernel's lattice-sum error, computed here on a 25 x 25
    sampling of the cell, corners included (9^3 in 3D); 2D, h = 3: E_lat = 2.93e-3 (at
    the sites), measured max |rho - 1| = 8.6e-5 at the grid points (none on a site).
    S(x) = rho(x) / rho_site (all sites alike), so |S - 1| <= 2 E_lat / (1 - E_lat);
    measured 3.0e-3 <= 5.9e-3.
    A gas with e_j = 2 everywhere: e(x) / S(x) = 2 and T = (gamma - 1) e to 1e-12.
(b) v_x = sin(k x), k = 2 pi / 16: the grid's v_x is A sin(k x) with A the kernel's Fourier
    transform w^(k) = int w(r) J0(k r) d^2r = sum_n (-1)^n (k/2)^(2n) <r^(2n)> / (n!)^2,
    <r^2> = 5 h^2 / 28, <r^4> = h^4 / 18 for Lucy in 2D (exact moments of the polynomial,
    computed here), so A = 1 - 5 (k h)^2 / 112 + ... = 0.93969 at k h = 1.178 (the
    leading order alone: 0.93804). The lattice sum replaces the integral: by Poisson
    summation it adds the aliases w^(|G +- k|) at the reciprocal vectors G != 0, each as
    small as the lattice-sum error of the constant, and the weights 1 / rho_j differ from 1 / rho0 by <= E_lat: |A_fit - w^(k)| <= 3 E_lat.
    Measured (2D): A_fit = 0.93687, w^(k) = 0.93969, |diff| = 2.8e-3 < 8.8e-3. The
    residual max |v_x - A_fit sin(k x)| <= 3 E_lat, v_y = 0 exactly.
    examples/plot_grid.py --field vx puts the spectrum's peak at k = 2 pi / 16 (within
    half a ring, dk / 2 = pi / 16).
(c) grid.xmf parses (xml.etree); every DataItem's Dimensions equal the grid's dims and
    the HDF5 dataset's shape (h5dump -H); one Grid per grid file, at its time.
(d) The CSV and the HDF5 hold the same values (both printed with 17 digits: equal).
(e) An open box (-periodic 0): at the corner point (0.25, 0.25) the sum is one-sided: rho
    equals the continuum integral of w over the quarter plane x, y > 0 (0.3657 for h = 3)
    within the midpoint rule's bound (a^2/24) int |w_xx| + |w_yy| (0.032; measured 0.3719,
    diff 0.0062), S there is well below 1 (0.61: below 1 - 10 E_lat), and beyond h of the
    faces |S - 1| <= 2 E_lat / (1 - E_lat) as in the periodic box. With walls at y = 0 and
    16 (-wall_ylo/-wall_yhi noslip) rho is the sum over the local particles alone (equal to
    the direct sum, periodic in x and open in y: the wall images are not summed), 0.714 in
    the row y = 0.5, and S there (0.712) is below 1 - 10 E_lat.
(f) 1D and 3D grids: the shapes (1 x 16; 6 x 6 x 6 and velocity 6 x 6 x 6 x 3) and rho
    within their own lattice-sum errors (+1e-12: these grid points sit on the sites, where
    the sampled maximum is attained, so equality holds to round-off).
(g) Bad values refused in one line, exit 2, nothing written: -1, nan, a spacing giving
    more than 1e7 points (the count named), -grid_interval without snapshots.
(h) A failed grid write (SPAM_TEST_FAIL_WRITE) is one line, exit 1, no temporary left; grid
    files of an earlier run are refused without -output_overwrite and removed with it.
"""
import math
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from fractions import Fraction
from spamrun import Checks, arguments, manifest_files, run

import numpy as np

a = arguments()
c = Checks()
w = a.workdir
HERE = os.path.dirname(os.path.abspath(__file__))
PLOT = os.path.join(HERE, "..", "examples", "plot_grid.py")
FAST = ["-monitor", 0, "-diag_entropy", 0, "-ts_max_time", 1e-4, "-snapshot_interval", 1e-4]
NORM = {1: 5.0 / 4.0, 2: 5.0 / math.pi, 3: 105.0 / (16.0 * math.pi)}  # Lucy: w = C_D / h^D F(s)


def lucy(r, h, dim):
    s = np.minimum(r / h, 1.0)
    return NORM[dim] / h ** dim * (1 + 3 * s) * (1 - s) ** 3


def lattice(n, dim):
    """Sites (i + 1/2) a of an n^dim lattice, x fastest."""
    g = np.indices((n,) * dim)[::-1].reshape(dim, -1).T
    return g + 0.5


def write_file(name, x, cols):
    path = os.path.join(w, name)
    heads = ["x", "y", "z"][: x.shape[1]] + list(cols)
    with open(path, "w") as f:
        f.write(",".join(heads) + "\n")
        for i in range(len(x)):
            f.write(",".join(repr(float(v)) for v in list(x[i]) + [cols[k][i] for k in cols]) + "\n")
    return path


def grid_csv(path):
    with open(path) as f:
        comment = f.readline()
        head = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=2, ndmin=2)
    return comment, {h: data[:, k] for k, h in enumerate(head)}


def pairs(p, x, box, periodic):
    """Distances |p_i - x_j| (minimum image along the directions periodic says: a bool for
    all, or one per direction): [np, nx]."""
    d = p[:, None, :] - x[None, :, :]
    for k in range(x.shape[1]):
        if periodic if isinstance(periodic, bool) else periodic[k]:
            d[:, :, k] -= box[k] * np.rint(d[:, :, k] / box[k])
    return np.sqrt((d ** 2).sum(axis=2))


def reference(points, x, vals, box, h, periodic):
    """rho, S and the interpolants of vals at the points by the direct sums."""
    dim = x.shape[1]
    rho_j = lucy(pairs(x, x, box, periodic), h, dim).sum(axis=1)
    wp = lucy(pairs(points, x, box, periodic), h, dim)
    out = {"rho": wp.sum(axis=1), "S": (wp / rho_j).sum(axis=1)}
    for k, v in vals.items():
        out[k] = (wp * (v / rho_j)).sum(axis=1)
    return out


def lattice_error(h, dim, n):
    """Largest |sum_j w(x - x_j) - 1| over a sampling of the unit cell (a = m = 1)."""
    x = lattice(n, dim)
    m = 24 if dim < 3 else 8
    s = np.indices((m + 1,) * dim).reshape(dim, -1).T / m + n // 2
    return float(np.abs(lucy(pairs(s, x, [n] * dim, True), h, dim).sum(axis=1) - 1).max())


def spam(name, args):
    out = os.path.join(w, name)
    code, so, se = run(a.spam_ark, ["-scene", "file"] + args + FAST, out)
    return out, code, se


def rel_err(got, want):
    return float(np.abs(got - want).max() / max(1e-300, np.abs(want).max()))


def h5_shape(path, dataset):
    p = subprocess.run(["h5dump", "-H", "-d", dataset, path], capture_output=True, text=True)
    m = re.search(r"DATASPACE\s+SIMPLE \{ \( ([0-9, ]+) \)", p.stdout)
    return tuple(int(v) for v in m.group(1).split(",")) if m else None


def h5_values(path, dataset):
    p = subprocess.run(["h5dump", "-y", "-w", "0", "-m", "%.17g", "-d", dataset, path], capture_output=True, text=True)
    body = p.stdout.split("DATA {", 1)[1].split("}", 1)[0]
    return np.array([float(v) for v in re.split(r"[,\s]+", body) if v.strip()])


# ------------------------------------------------------------------ 2D periodic, gas ----
N, H, GAMMA, E0 = 16, 3.0, 1.4, 2.0
K = 2 * math.pi / N
x2 = lattice(N, 2)
vx = np.sin(K * x2[:, 0])
f2 = write_file("mode.csv", x2, {"vx": vx, "vy": np.zeros(len(x2)), "e": np.full(len(x2), E0)})
out, code, se = spam("mode", ["-file_path", f2, "-box_len", "16,16", "-h", H, "-material", "gas", "-gas_gamma", GAMMA, "-grid_interval", 0.5])
c.check(code == 0, f"2D gas run with -grid_interval 0.5: exit {code} {se.strip()[:200]}")
csvs, h5s = manifest_files(out, "grid_csv"), manifest_files(out, "grid_h5")
c.check(len(csvs) == 2 and len(h5s) == 2, f"a grid file per snapshot: {len(csvs)} CSV, {len(h5s)} HDF5 (snapshots at t = 0, 1e-4)")
comment, g = grid_csv(csvs[0])
c.check(comment.startswith("# t=0 ") and "dims=32x32" in comment, f"CSV comment line: {comment.strip()}")
c.check(list(g) == ["x", "y", "rho", "vx", "vy", "e", "T", "S"], f"CSV columns {','.join(g)}")
pts = np.stack([g["x"], g["y"]], axis=1)
ref = reference(pts, x2, {"vx": vx, "vy": np.zeros(len(x2)), "e": np.full(len(x2), E0)}, [N, N], H, True)
direct = 0.0
for k in ("rho", "S", "vx", "e"):
    e = rel_err(g[k], ref[k])
    c.check(e < 1e-12, f"(0) {k} equals the direct sum: max relative difference {e:.2e} < 1e-12")
    direct = max(direct, e)
c.reading("direct_sum_rel", direct)
E_LAT = lattice_error(H, 2, N)
d_rho = float(np.abs(g["rho"] - 1).max())
c.check(d_rho <= E_LAT + 1e-12, f"(a) |rho - 1| = {d_rho:.3e} <= lattice-sum error E_lat = {E_LAT:.3e} (Lucy 2D, h/a = 3)")
d_s = float(np.abs(g["S"] - 1).max())
c.check(d_s <= 2 * E_LAT / (1 - E_LAT), f"(a) |S - 1| = {d_s:.3e} <= 2 E_lat / (1 - E_lat) = {2 * E_LAT / (1 - E_LAT):.3e}")
d_e = float(np.abs(g["e"] / g["S"] - E0).max())
d_t = float(np.abs(g["T"] - (GAMMA - 1) * g["e"]).max())
for k, v in (("E_lat", E_LAT), ("rho_dev", d_rho), ("S_dev", d_s), ("S_bound", 2 * E_LAT / (1 - E_LAT)), ("e_dev", d_e), ("T_dev", d_t)):
    c.reading(k, v)
c.check(d_e < 1e-12 and d_t < 1e-12, f"(a) e / S = {E0} to {d_e:.1e}, T = (gamma - 1) e to {d_t:.1e} (< 1e-12)")


def lucy2d_moment(n):
    """<r^(2n)> / h^(2n) = 10 int_0^1 s^(2n+1) (1 - 6 s^2 + 8 s^3 - 3 s^4) ds, exactly."""
    p = {0: 1, 2: -6, 3: 8, 4: -3}
    return 10 * sum(Fraction(cf, 2 * n + 2 + e) for e, cf in p.items())


kh = K * H
w_hat = float(sum((-1) ** n * Fraction(kh / 2) ** (2 * n) * lucy2d_moment(n) / math.factorial(n) ** 2 for n in range(12)))
s_k = np.sin(K * g["x"])
A = float((g["vx"] * s_k).sum() / (s_k ** 2).sum())
c.check(abs(float(lucy2d_moment(1)) - 5 / 28) < 1e-15 and abs(float(lucy2d_moment(2)) - 1 / 18) < 1e-15, "(b) Lucy 2D moments <r^2> = 5 h^2/28, <r^4> = h^4/18")
c.check(abs(A - w_hat) <= 3 * E_LAT, f"(b) v_x amplitude {A:.5f} vs w^(k) = {w_hat:.5f} (leading order 1 - 5 (kh)^2/112 = {1 - 5 * kh ** 2 / 112:.5f}): |diff| {abs(A - w_hat):.2e} <= 3 E_lat = {3 * E_LAT:.2e}")
resid = float(np.abs(g["vx"] - A * s_k).max())
for k, v in (("amplitude", A), ("w_hat", w_hat), ("leading_order", 1 - 5 * kh ** 2 / 112), ("residual", resid)):
    c.reading(k, v)
c.check(resid <= 3 * E_LAT and float(np.abs(g["vy"]).max()) == 0.0, f"(b) max |v_x - A sin kx| = {resid:.2e} <= 3 E_lat, v_y = 0")
p = subprocess.run([sys.executable, PLOT, out, "--field", "vx", "--time", "0", "-o", os.path.join(w, "mode_vx.png")], capture_output=True, text=True)
m = re.search(r"peak_k=([0-9.eE+-]+)", p.stdout)
peak = float(m.group(1)) if m else float("nan")
c.reading("peak_k", peak)
c.reading("mode_k", K)
c.check(p.returncode == 0 and abs(peak - K) <= 0.5 * (2 * math.pi / N), f"(b) plot_grid.py spectrum peak k = {peak:.5f}, mode k = {K:.5f} (within dk/2 = {math.pi / N:.4f}) {p.stderr.strip()[:200]}")

# --------------------------------------------------------------- (c) XDMF and shapes ----
try:
    root = ET.parse(os.path.join(out, "grid.xmf")).getroot()
    grids = root.findall("./Domain/Grid/Grid")
    ok = len(grids) == len(h5s)
    bad = []
    for gr in grids:
        topo = gr.find("Topology").get("Dimensions")
        ok = ok and topo == "32 32" and gr.find("Topology").get("TopologyType") == "2DCoRectMesh"
        for att in gr.findall("Attribute"):
            item = att.find("DataItem")
            fname, dset = item.text.strip().split(":")
            want = tuple(int(v) for v in item.get("Dimensions").split())
            got = h5_shape(os.path.join(out, fname), dset)
            if got != want or want[:2] != (32, 32):
                bad.append(f"{fname}:{dset} {got} vs {want}")
    c.check(ok and not bad, f"(c) grid.xmf: {len(grids)} grids, 2DCoRectMesh 32 32, every dataset's shape as declared {bad[:3]}")
    times = [float(gr.find("Time").get("Value")) for gr in grids]
    c.check(times == [0.0, 1e-4], f"(c) grid.xmf times {times}")
except (ET.ParseError, AttributeError, OSError) as e:
    c.check(False, f"(c) grid.xmf does not parse: {e}")
# ------------------------------------------------------------- (d) CSV equals HDF5 ----
for k in ("rho", "vx", "T", "S"):
    hv = h5_values(h5s[0], "/" + k)
    c.check(hv.shape == g[k].shape and np.array_equal(hv, g[k]), f"(d) /{k} of the HDF5 equals the CSV column ({hv.size} values)")

# --------------------------------------------------------------- (e) an open box ----
fo = write_file("rest.csv", x2, {"vx": np.zeros(len(x2)), "vy": np.zeros(len(x2))})
out, code, se = spam("open", ["-file_path", fo, "-box_len", "16,16", "-h", H, "-periodic", 0, "-grid_interval", 0.5])
_, go = grid_csv(manifest_files(out, "grid_csv")[0]) if code == 0 else (None, {"S": np.zeros(1024), "rho": np.zeros(1024), "x": np.zeros(1024), "y": np.zeros(1024)})
corner, rho_c = float(go["S"][0]), float(go["rho"][0])
c.reading("corner_rho", rho_c)
c.reading("corner_S", corner)


def quadrant(p, h, d=0.01):
    """The continuum density at (p, p) of the quarter plane x, y > 0 (the lattice's cells),
    int w d^2x, and the midpoint rule's error bound (a^2 / 24) int |w_xx| + |w_yy| d^2x:
    the lattice sum is the midpoint rule of that integral over the unit cells."""
    u = np.arange(d / 2, p + h, d)
    X, Y = np.meshgrid(u - p, u - p)
    f = lambda x, y: lucy(np.sqrt(x * x + y * y), h, 2)
    e = 1e-3
    wxx = (f(X + e, Y) - 2 * f(X, Y) + f(X - e, Y)) / e ** 2
    wyy = (f(X, Y + e) - 2 * f(X, Y) + f(X, Y - e)) / e ** 2
    return float(f(X, Y).sum() * d * d), float((np.abs(wxx) + np.abs(wyy)).sum() * d * d / 24)


I_q, B_q = quadrant(0.25, H)
c.reading("quarter_plane", I_q)
c.reading("quarter_plane_bound", B_q)
ref = reference(np.stack([go["x"], go["y"]], axis=1), x2, {}, [N, N], H, False) if code == 0 else {"S": go["S"]}
c.check(code == 0 and abs(rho_c - I_q) <= B_q and rel_err(go["S"], ref["S"]) < 1e-12,
        f"(e) open box, corner point (0.25, 0.25): rho = {rho_c:.4f} vs the quarter-plane integral {I_q:.4f} (|diff| {abs(rho_c - I_q):.4f} <= midpoint bound {B_q:.4f}); S equals the direct sum")
c.check(corner < 1 - 10 * E_LAT, f"(e) open box: S = {corner:.3f} at the corner point, below 1 - 10 E_lat = {1 - 10 * E_LAT:.3f}: the one-sided sum shows")
inner = (go["x"] > H) & (go["x"] < N - H) & (go["y"] > H) & (go["y"] < N - H)
d_in = float(np.abs(go["S"][inner] - 1).max())
c.reading("interior_S_dev", d_in)
c.check(d_in <= 2 * E_LAT / (1 - E_LAT), f"(e) open box interior (beyond h of the faces): |S - 1| = {d_in:.2e}")

# ------------------------------------------------------------- (e) walls at y = 0, 16 ----
out, code, se = spam("walls", ["-file_path", fo, "-box_len", "16,16", "-h", H, "-wall_ylo", "noslip", "-wall_yhi", "noslip", "-grid_interval", 1])
_, gw = grid_csv(manifest_files(out, "grid_csv")[0]) if code == 0 else (None, {"rho": np.zeros(256), "S": np.zeros(256), "x": np.zeros(256), "y": np.zeros(256)})
pw = np.stack([gw["x"], gw["y"]], axis=1)
rw = lucy(pairs(pw, x2, [N, N], [True, False]), H, 2).sum(axis=1)
row0 = gw["y"] < 1
c.reading("wall_row_rho", float(gw["rho"][row0].mean()))
c.reading("wall_row_S", float(gw["S"][row0].mean()))
c.check(code == 0 and rel_err(gw["rho"], rw) < 1e-12 and float(gw["S"][row0].max()) < 1 - 10 * E_LAT,
        f"(e) walls at y = 0 and 16 (-wall_ylo/-wall_yhi noslip): rho is the local particles' sum (no wall images), "
        f"rho = {float(gw['rho'][row0].mean()):.3f} and S = {float(gw['S'][row0].mean()):.3f} in the row y = 0.5")

# ------------------------------------------------------------------ (f) 1D and 3D ----
x1 = lattice(16, 1)
out, code, se = spam("line", ["-dim", 1, "-file_path", write_file("line.csv", x1, {"vx": np.zeros(16)}), "-box_len", 16, "-h", H, "-grid_interval", 1])
ok = code == 0 and h5_shape(manifest_files(out, "grid_h5")[0], "/rho") == (1, 16)
_, g1 = grid_csv(manifest_files(out, "grid_csv")[0]) if ok else (None, {"rho": np.zeros(1)})
e1 = lattice_error(H, 1, 16)
c.reading("E_lat_1d", e1)
c.check(ok and float(np.abs(g1["rho"] - 1).max()) <= e1 + 1e-12, f"(f) 1D: /rho shape (1, 16), |rho - 1| <= E_lat = {e1:.2e}")
x3 = lattice(6, 3)
z3 = np.zeros(len(x3))
out, code, se = spam("cube", ["-dim", 3, "-file_path", write_file("cube.csv", x3, {"vx": z3, "vy": z3, "vz": z3}), "-box_len", "6,6,6", "-h", 2.5, "-grid_interval", 1])
ok = code == 0 and h5_shape(manifest_files(out, "grid_h5")[0], "/rho") == (6, 6, 6) and h5_shape(manifest_files(out, "grid_h5")[0], "/velocity") == (6, 6, 6, 3)
_, g3 = grid_csv(manifest_files(out, "grid_csv")[0]) if ok else (None, {"rho": np.zeros(1)})
e3 = lattice_error(2.5, 3, 6)
c.reading("E_lat_3d", e3)
c.check(ok and float(np.abs(g3["rho"] - 1).max()) <= e3 + 1e-12, f"(f) 3D: /rho (6, 6, 6), /velocity (6, 6, 6, 3), |rho - 1| <= E_lat = {e3:.2e}")

# ------------------------------------------------------- (h) failed write, earlier run ----
env = dict(os.environ, SPAM_TEST_FAIL_WRITE="grid_00000.h5:2")
fail_dir = os.path.join(w, "fail")
args = ["-scene", "file", "-file_path", fo, "-box_len", "16,16", "-h", H] + FAST + ["-grid_interval", 1, "-output_dir", fail_dir]
p = subprocess.run([a.spam_ark] + [str(v) for v in args], capture_output=True, text=True, env=env)
left = [n for n in os.listdir(fail_dir) if n.endswith(".tmp") or n.startswith("grid_")] if os.path.isdir(fail_dir) else []
c.check(p.returncode == 1 and p.stderr.strip().count("\n") == 0 and "grid_00000.h5" in p.stderr and not left,
        f"(h) a failed grid write (injected ENOSPC): exit {p.returncode}, one line {p.stderr.strip()[:120]!r}, no temporary or grid file left {left}")
out = os.path.join(w, "open")   # keep only the open-box run's grid files
for n in os.listdir(out):
    if not n.startswith("grid"):
        os.remove(os.path.join(out, n))
code, so, se = run(a.spam_ark, ["-scene", "file", "-file_path", fo, "-box_len", "16,16", "-h", H] + FAST, out)
c.check(code == 2 and "grid" in se and "-output_overwrite" in se, f"(h) grid files alone are an earlier run's files: refused without -output_overwrite: {se.strip()[:140]}")
code, so, se = run(a.spam_ark, ["-scene", "file", "-file_path", fo, "-box_len", "16,16", "-h", H, "-output_overwrite"] + FAST, out)
c.check(code == 0 and not [n for n in os.listdir(out) if n.startswith("grid")], "(h) -output_overwrite removes them")

# --------------------------------------------------------------------- (g) refusals ----
for value, extra, words in (("-1", [], "positive"), ("nan", [], "positive"), ("1e-4", [], "2.56e+10 grid points"),
                            ("0.5", ["-snapshot_interval", 0], "-snapshot_interval is 0")):
    args = ["-file_path", fo, "-box_len", "16,16", "-h", H] + FAST + extra + ["-grid_interval", value]
    outdir = os.path.join(w, "refused")
    code, so, se = run(a.spam_ark, ["-scene", "file"] + args, outdir)
    lines = se.strip().splitlines()
    c.check(code == 2 and len(lines) == 1 and "-grid_interval" in lines[0] and words in lines[0] and not os.path.exists(outdir),
            f"(g) -grid_interval {value} {' '.join(map(str, extra))}: exit {code}, {lines[:2]}")
c.finish(a.readings)
