"""ParaView opens a run's outputs unaided (issue 17 point 3): pvpython under xvfb-run reads
snapshots.xmf and grid.xmf with the Xdmf3 reader and with the legacy XDMF reader; at the
last time each gives as many points as the HDF5 file has rows, one vertex cell per particle
(the Xdmf3 reader drew nothing when the Polyvertex topology had no connectivity) or the
grid's cells, and the density range of the HDF5 file (h5dump) to rounding; the Xdmf3
view of the particles is rendered to a PNG that is not blank. Skips (exit 77) without
pvpython or xvfb-run: `tools/deps.sh --paraview` installs them."""
import json
import os
import re
import shutil
import subprocess
import sys
from spamrun import Checks, arguments, run

SKIP = 77  # SKIP_RETURN_CODE in tests/CMakeLists.txt

# Runs inside pvpython: argv = xmf path, reader name, PNG path or "-"; prints one JSON line.
PVSCRIPT = r'''
import json, sys
from paraview import simple
path, reader_name, png = sys.argv[1:4]
reader = getattr(simple, reader_name)(FileName=[path] if reader_name != "XDMFReader" else path)
times = list(reader.TimestepValues)
reader.UpdatePipeline(times[-1])
info = reader.GetDataInformation()
names = [reader.PointData.GetArray(i).GetName() for i in range(len(reader.PointData))]
rho = reader.PointData["density"] if "density" in names else reader.PointData["rho"]
out = {"times": times, "points": info.GetNumberOfPoints(), "cells": info.GetNumberOfCells(),
       "range": list(rho.GetRange()), "arrays": names}
if png != "-":
    view = simple.CreateView("RenderView")
    view.ViewSize = [400, 400]
    view.Background = [1, 1, 1]
    view.ViewTime = times[-1]
    d = simple.Show(reader, view)
    simple.ColorBy(d, ("POINTS", "density"))
    d.SetRepresentationType("Points")
    d.PointSize = 4
    view.ResetCamera()
    simple.SaveScreenshot(png, view, ImageResolution=[400, 400])
print("PVJSON " + json.dumps(out))
'''


def pv(xmf, reader, png="-"):
    """The reader's view of xmf at its last time (a dict), or the error text."""
    p = subprocess.run([xvfb, "-a", pvpython, "--force-offscreen-rendering", script, xmf, reader, png],
                       capture_output=True, text=True, timeout=300)
    line = [l for l in p.stdout.splitlines() if l.startswith("PVJSON ")]
    return json.loads(line[0][7:]) if p.returncode == 0 and line else f"exit {p.returncode}: {p.stderr.strip()[-300:]}"


def h5_values(path, dataset):
    dump = subprocess.run(["h5dump", "-m", "%.17g", "-d", dataset, "-y", "-w", "0", path], capture_output=True, text=True).stdout
    return [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e[-+]?\d+)?", dump.split("DATA {")[1].split("}")[0])]


pvpython, xvfb = shutil.which("pvpython"), shutil.which("xvfb-run")
if not (pvpython and xvfb):
    print(f"SKIP: {'pvpython' if not pvpython else 'xvfb-run'} not installed (tools/deps.sh --paraview installs ParaView and xvfb)")
    sys.exit(SKIP)

a = arguments()
c = Checks()
script = os.path.join(a.workdir, "pv_read.py")
with open(script, "w") as f:
    f.write(PVSCRIPT)

# A 2D gas of 144 particles, snapshots at t = 0, 2, 4 and the fields on a grid beside them.
run_dir = os.path.join(a.workdir, "run")
code, _, err = run(a.spam_ark, ["-expansion_n", 12, "-h", 3, "-ts_max_time", 4, "-snapshot_interval", 2,
                                "-grid_interval", 1], run_dir)
c.check(code == 0, f"run exits 0 {err.strip()[:200]}")
if code:
    c.finish()
rho = h5_values(os.path.join(run_dir, "snap_00002.h5"), "/density")
grid_rho = h5_values(os.path.join(run_dir, "grid_00002.h5"), "/rho")
n, ng = len(rho), len(grid_rho)
c.check(n == 144 and ng > 1 and max(rho) > min(rho), f"HDF5 at t = 4: {n} particles, density {min(rho):.6g}..{max(rho):.6g}; {ng} grid points")


def agree(got, want):
    """Rounding only: ParaView reads the same doubles."""
    return all(abs(g - w) <= 1e-12 * abs(w) for g, w in zip(got, want))


png = os.path.join(a.workdir, "snapshots_xdmf3.png")
for reader, image in (("Xdmf3ReaderS", png), ("XDMFReader", "-")):
    r = pv(os.path.join(run_dir, "snapshots.xmf"), reader, image)
    ok = isinstance(r, dict)
    c.check(ok and r["times"] == [0, 2, 4] and r["points"] == n and r["cells"] == n
            and agree(r["range"], [min(rho), max(rho)]) and {"velocity", "density", "mass", "id"} <= set(r["arrays"]),
            f"{reader} on snapshots.xmf: {r if not ok else {k: r[k] for k in ('times', 'points', 'cells', 'range')}}"
            f" (want {n} points and vertex cells, density {min(rho):.17g}..{max(rho):.17g})")
    g = pv(os.path.join(run_dir, "grid.xmf"), reader)
    ok = isinstance(g, dict)
    c.check(ok and g["points"] == ng and g["cells"] > 0 and agree(g["range"], [min(grid_rho), max(grid_rho)]),
            f"{reader} on grid.xmf: {g if not ok else {k: g[k] for k in ('points', 'cells', 'range')}} (want {ng} points,"
            f" rho {min(grid_rho):.17g}..{max(grid_rho):.17g})")

# The render: a PNG with particles drawn (pixels other than the white background).
drawn = 0
if os.path.exists(png):
    import matplotlib.image
    img = matplotlib.image.imread(png)
    drawn = int((img[:, :, :3].min(axis=2) < 0.9).sum())
c.check(drawn > 100, f"{png} rendered with {drawn} non-background pixels")
c.finish()
