#!/usr/bin/python3
"""Chart one grid-field file of a spam-ark run (-grid_interval, docs/scenes/grid.md).

Usage:
    examples/plot_grid.py DIR [--field rho] [--time INDEX] [-o OUT.png]

DIR is the output directory of a run with -grid_interval dx and CSV snapshots (the
default); the grid files are those manifest.json lists (kind grid_csv), never a glob of
the directory. INDEX counts them from 0 in time order (negative: from the end; default
-1, the last). FIELD is a column of the file: rho, vx, vy, (vz), e, T, sxx.., S.

The figure (default DIR/grid_<field>_<index>.png) has two panels:
  * left:  filled contours of the field over the grid (a 3D grid: its mid-plane
           z = z[nz/2]; a 1D grid: the field against x);
  * right: the power spectrum of that (2D) field, |FFT|^2 / N^2 of the field minus its
           mean, summed over rings of width dk = 2 pi / max(Lx, Ly) and drawn against
           the ring's wavenumber k on log-log axes. The FFT treats the grid as periodic:
           in a direction with walls or free surfaces the jump at the edge adds power at
           every k.

One line goes to stdout:
    field=<f> t=<t> peak_k=<k> peak_wavelength=<2 pi/k> png=<path>
where peak_k is the centre of the ring with the most power (k > 0). On a missing or
malformed input the script prints one line to stderr and exits with status 2.
Needs numpy and matplotlib.
"""

import argparse
import json
import math
import os
import sys

EXIT_INPUT = 2

UNITS = {"rho": "mass / length^D", "vx": "length / time", "vy": "length / time", "vz": "length / time",
         "e": "energy / mass", "T": "energy / k_B", "S": "1 (Shepard sum)"}


class InputError(Exception):
    """A missing or malformed input; reported as one line, exit status 2."""


def fail(message):
    sys.stderr.write("plot_grid: error: %s\n" % " ".join(str(message).split()))
    sys.exit(EXIT_INPUT)


def grid_files(d):
    """(time, path) of the grid CSV files the manifest lists, in time order."""
    try:
        with open(os.path.join(d, "manifest.json")) as f:
            manifest = json.load(f)
    except (OSError, ValueError) as e:
        raise InputError("cannot read %s/manifest.json: %s" % (d, e))
    files = [(e.get("t"), os.path.join(d, e["name"])) for e in manifest.get("files", []) if e.get("kind") == "grid_csv"]
    if not files:
        raise InputError("%s lists no grid_csv file: run with -grid_interval and CSV snapshots" % d)
    return sorted(files, key=lambda x: (x[0], x[1]))


def scene_name(d):
    try:
        with open(os.path.join(d, "summary.json")) as f:
            return json.load(f).get("scene", "spam-ark")
    except (OSError, ValueError):
        return "spam-ark"


def read_grid(path):
    """The grid of a grid_NNNNN.csv: (t, dims [nx, ny, nz], header, data [npoints, ncol])."""
    import numpy as np
    with open(path) as f:
        comment = f.readline()
        header = f.readline().strip().split(",")
    if not comment.startswith("# "):
        raise InputError("%s: no '# t=...' line" % path)
    meta = dict(kv.split("=", 1) for kv in comment[2:].split())
    dims = [int(n) for n in meta["dims"].split("x")]
    data = np.loadtxt(path, delimiter=",", skiprows=2, ndmin=2)
    if data.shape != (int(np.prod(dims)), len(header)):
        raise InputError("%s: %s values, the header and dims %s say %d x %d" % (path, data.shape, dims, np.prod(dims), len(header)))
    return float(meta["t"]), dims + [1] * (3 - len(dims)), header, data


def plane(dims, header, data, field):
    """The field and the coordinates as [ny, nx] arrays (3D: the mid-plane in z)."""
    if field not in header:
        raise InputError("no column %r; the file has %s" % (field, ",".join(header)))
    nx, ny, nz = dims
    shape = (nz, ny, nx)
    k = nz // 2
    f = data[:, header.index(field)].reshape(shape)[k]
    x = data[:, 0].reshape(shape)[k]
    y = data[:, 1].reshape(shape)[k] if "y" in header[:3] else None
    zmid = data[:, 2].reshape(shape)[k, 0, 0] if "z" in header[:3] else None
    return x, y, f, zmid


def spectrum(f, dx, dy):
    """Ring-summed power |FFT|^2 / N^2 of f - mean: (k centres, power), k > 0 rings only."""
    import numpy as np
    ny, nx = f.shape
    F = np.fft.fft2(f - f.mean()) / f.size
    p = np.abs(F) ** 2
    kx = 2 * math.pi * np.fft.fftfreq(nx, dx)
    ky = 2 * math.pi * np.fft.fftfreq(ny, dy) if ny > 1 else np.zeros(1)
    kk = np.sqrt(kx[None, :] ** 2 + ky[:, None] ** 2)
    dk = 2 * math.pi / max(nx * dx, ny * dy if ny > 1 else 0.0)
    ring = np.rint(kk / dk).astype(int)
    power = np.bincount(ring.ravel(), weights=p.ravel())
    kc = dk * np.arange(len(power))
    return kc[1:], power[1:]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--field", default="rho")
    ap.add_argument("--time", type=int, default=-1, help="index of the grid file in time order (default -1: the last)")
    ap.add_argument("-o", "--output")
    a = ap.parse_args()
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    try:
        files = grid_files(a.dir)
        if not -len(files) <= a.time < len(files):
            raise InputError("--time %d: the run has %d grid files (0..%d)" % (a.time, len(files), len(files) - 1))
        index = a.time % len(files)
        t, dims, header, data = read_grid(files[index][1])
        x, y, f, zmid = plane(dims, header, data, a.field)
    except (InputError, OSError, ValueError, KeyError) as e:
        fail(e)
    dx = x[0, 1] - x[0, 0] if dims[0] > 1 else 1.0
    dy = y[1, 0] - y[0, 0] if y is not None and dims[1] > 1 else dx
    k, p = spectrum(f, dx, dy)
    # Power below round-off of the field's size (a uniform field) is not drawn.
    good = p > 1e-24 * max(float(np.abs(f).max()) ** 2, 1e-300)
    peak = k[np.argmax(p)] if good.any() else float("nan")
    unit = UNITS.get(a.field, "stress (energy / length^D)" if a.field.startswith("s") else "")
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.6))
    if y is None or dims[1] == 1:
        ax0.plot(x[0], f[0], "-", color="tab:blue")
        ax0.set_xlabel("x (reduced length)")
        ax0.set_ylabel("%s (%s)" % (a.field, unit))
    else:
        cs = ax0.contourf(x, y, f, levels=24, cmap="viridis")
        bar = fig.colorbar(cs, ax=ax0, label="%s (%s)" % (a.field, unit))
        bar.formatter.set_useOffset(False)
        bar.update_ticks()
        ax0.set_aspect("equal")
        ax0.set_xlabel("x (reduced length)")
        ax0.set_ylabel("y (reduced length)")
    where = "" if zmid is None else ", mid-plane z = %.4g" % zmid
    ax0.set_title("%s on the %s grid%s" % (a.field, "x".join(str(n) for n in dims[:len([c for c in header[:3] if c in "xyz"])]), where))
    if good.any():
        ax1.loglog(k[good], p[good], "o-", color="tab:red", ms=3, label="ring sum of |FFT|^2 / N^2")
        ax1.axvline(peak, color="grey", ls=":", label="peak k = %.4g" % peak)
        ax1.legend(loc="best", fontsize=8)
    else:
        ax1.text(0.5, 0.5, "%s is uniform to round-off:\nno power at k > 0" % a.field, ha="center", va="center", transform=ax1.transAxes)
    ax1.set_xlabel("wavenumber k (1 / reduced length)")
    ax1.set_ylabel("power of %s ((%s)^2)" % (a.field, unit))
    ax1.set_title("power spectrum of %s - mean" % a.field)
    fig.suptitle("%s: grid fields at t = %.4g (grid file %d of %d)" % (scene_name(a.dir), t, index, len(files)))
    fig.tight_layout()
    out = a.output or os.path.join(a.dir, "grid_%s_%05d.png" % (a.field, index))
    fig.savefig(out, dpi=110)
    print("field=%s t=%.10g peak_k=%.10g peak_wavelength=%.10g png=%s" % (a.field, t, peak, 2 * math.pi / peak if peak > 0 else float("nan"), out))
    readings = {"field": a.field, "t": t, "peak_k": float(peak), "dims": dims}
    if "rho" in header and "S" in header:  # the grid integral of rho (the mass) and the Shepard sum's range
        cell = float(np.prod([s for s in (dx, dy, dx) [:sum(1 for d in dims if d > 1)]]))
        rho, S = data[:, header.index("rho")], data[:, header.index("S")]
        high = S > 1.05
        readings.update(rho_integral=float(rho.sum() * cell), S_min=float(S.min()), S_max=float(S.max()),
                        points_S_above_1_05=int(high.sum()), rho_mean_S_above_1_05=float(rho[high].mean()) if high.any() else None)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import chart_readings
    chart_readings.write(out, readings, runs=[a.dir])


if __name__ == "__main__":
    main()
