#!/usr/bin/python3
"""ParaView opens a run's outputs unaided: pvpython under xvfb-run reads
snapshots.xmf and grid.xmf with the Xdmf3 reader and with the legacy XDMF reader; at the
last time each gives as many points as the HDF5 file has rows, one vertex cell per particle
(the Xdmf3 reader drew nothing when the Polyvertex topology had no connectivity) or the
grid's cells, and the density range of the HDF5 file (h5dump) to rounding; an elastic
solid's energy and stress come through (Tensor6: 6 components in Xdmf3, 9 in the legacy
reader); the Xdmf3 view of the particles is rendered to a PNG that is not blank. Skips (exit 77) without
pvpython or xvfb-run: `tools/deps.sh --paraview` installs them."""
import json
import os
import re
import shutil
import subprocess
import sys
from spamrun import Checks, arguments, run

SKIP = 77  # SKIP_RETURN_CODE in tests/CMakeLists.txt

# Runs inside pvpython: argv = JSON list of [xmf path, reader name, PNG path or "-"]; prints
# one JSON line per read: the data at the last time (or the error).
PVSCRIPT = r'''
import json, sys
from paraview import simple
for path, reader_name, png in json.loads(sys.argv[1]):
    try:
        # The legacy reader's property is FileNames, the Xdmf3 readers' FileName (5.11).
        reader = getattr(simple, reader_name)(**{"FileNames" if reader_name == "XDMFReader" else "FileName": [path]})
        times = list(reader.TimestepValues)
        reader.UpdatePipeline(times[-1])
        info = reader.GetDataInformation()
        arrays = [reader.PointData.GetArray(i) for i in range(len(reader.PointData))]
        names = [x.GetName() for x in arrays]
        rho = reader.PointData["density" if "density" in names else "rho"]
        out = {"times": times, "points": info.GetNumberOfPoints(), "cells": info.GetNumberOfCells(),
               "range": list(rho.GetRange()), "arrays": names,
               "components": {x.GetName(): x.GetNumberOfComponents() for x in arrays}}
        if png != "-":
            view = simple.CreateView("RenderView")
            view.ViewTime = times[-1]
            view.OrientationAxesVisibility = 0
            d = simple.Show(reader, view)
            simple.ColorBy(d, ("POINTS", "density"))
            d.SetRepresentationType("Points")
            d.PointSize = 4
            view.ResetCamera()
            simple.SaveScreenshot(png, view, ImageResolution=[400, 400])
        simple.Delete(reader)
    except Exception as e:
        out = "%s: %s" % (type(e).__name__, e)
    print("PVJSON " + json.dumps(out), flush=True)
'''


def pv(jobs, tries=2):
    """Each job's read (a dict), or the error text, from one pvpython start. A start that
    dies before its first job reports (pvpython once aborted at start-up, 1 s in, in a full
    ctest -j2 run, and passed on every rerun) is tried once more, and said so: a
    file that crashes the reader crashes the second start too."""
    p = subprocess.run([xvfb, "-a", pvpython, "--force-offscreen-rendering", script, json.dumps(jobs)],
                       capture_output=True, text=True, timeout=600)
    got = [json.loads(l[7:]) for l in p.stdout.splitlines() if l.startswith("PVJSON ")]
    if not got and p.returncode != 0 and tries > 1:
        print(f"note: pvpython exit {p.returncode} before any read ({p.stderr.strip()[-200:]}); starting it again", flush=True)
        return pv(jobs, tries - 1)
    return got + [f"pvpython exit {p.returncode}: {p.stderr.strip()[-300:]}"] * (len(jobs) - len(got))


def h5_values(path, name, kind="-d"):
    """A dataset (-d) or a root attribute (-a) of an HDF5 file, as h5dump prints it."""
    dump = subprocess.run(["h5dump", "-m", "%.17g", kind, name, "-y", "-w", "0", path], capture_output=True, text=True).stdout
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
dims = [int(x) for x in h5_values(os.path.join(run_dir, "grid_00002.h5"), "/dims", "-a")]
cells = 1
for k in dims:
    cells *= k - 1  # the cells between the grid points
c.check(n == 144 and ng == dims[0] * dims[1] and max(rho) > min(rho), f"HDF5 at t = 4: {n} particles, density {min(rho):.6g}..{max(rho):.6g}; grid {dims}: {ng} points, {cells} cells")


def agree(got, want):
    """Rounding only: ParaView reads the same doubles."""
    return all(abs(g - w) <= 1e-12 * abs(w) for g, w in zip(got, want))


# An elastic solid (the 2D rotor, 19 particles) also carries energy and the stress (Tensor6).
solid_dir = os.path.join(a.workdir, "solid")
code, _, err = run(a.spam_ark, ["-scene", "rotor", "-rotor_n", 2, "-ts_max_time", 1, "-snapshot_interval", 1], solid_dir)
c.check(code == 0, f"solid run exits 0 {err.strip()[:200]}")
solid_xmf = os.path.join(solid_dir, "snapshots.xmf")
solid_rho = h5_values(os.path.join(solid_dir, "snap_00001.h5"), "/density") if code == 0 else []

# The index as it once was (Polyvertex without connectivity): the control that
# shows the cell count can fail. The Xdmf3 reader makes no cells of it.
xmf = os.path.join(run_dir, "snapshots.xmf")
old_xmf = os.path.join(run_dir, "snapshots_noconnectivity.xmf")
with open(xmf) as f:
    text = f.read()
with open(old_xmf, "w") as f:
    f.write(re.sub(r'(<Topology [^>]*)>\s*<DataItem[^<]*</DataItem>\s*</Topology>', r"\1/>", text))

png = os.path.join(a.workdir, "snapshots_xdmf3.png")
grid_xmf = os.path.join(run_dir, "grid.xmf")
jobs = [[xmf, "Xdmf3ReaderS", png], [grid_xmf, "Xdmf3ReaderS", "-"], [xmf, "XDMFReader", "-"], [grid_xmf, "XDMFReader", "-"],
        [old_xmf, "Xdmf3ReaderS", "-"], [solid_xmf, "Xdmf3ReaderS", "-"], [solid_xmf, "XDMFReader", "-"]]
reads = pv(jobs)
for (path, reader, _), r in zip(jobs[:4], reads):
    ok = isinstance(r, dict)
    brief = {k: r[k] for k in ("times", "points", "cells", "range")} if ok else r
    if path == xmf:
        c.check(ok and r["times"] == [0, 2, 4] and r["points"] == n and r["cells"] == n
                and agree(r["range"], [min(rho), max(rho)]) and {"velocity", "density", "mass", "id"} <= set(r["arrays"]),
                f"{reader} on snapshots.xmf: {brief} (want times 0, 2, 4, {n} points and vertex cells,"
                f" density {min(rho):.17g}..{max(rho):.17g}, arrays velocity, density, mass, id)")
    else:
        c.check(ok and r["times"] == [0, 2, 4] and r["points"] == ng and r["cells"] == cells and agree(r["range"], [min(grid_rho), max(grid_rho)]),
                f"{reader} on grid.xmf: {brief} (want {ng} points, {cells} cells, rho {min(grid_rho):.17g}..{max(grid_rho):.17g})")
r = reads[4]
c.check(isinstance(r, dict) and r["points"] == n and r["cells"] == 0,
        f"control: Xdmf3ReaderS on the index without connectivity reads {r if not isinstance(r, dict) else r['cells']} cells (0 expected: the empty view)")

# The Xdmf3 reader keeps the 6 components of a Tensor6, the legacy reader makes the full 3 x 3.
for r, reader, stress in zip(reads[5:], ("Xdmf3ReaderS", "XDMFReader"), (6, 9)):
    ok = isinstance(r, dict)
    c.check(ok and r["times"] == [0, 1] and r["points"] == r["cells"] == len(solid_rho) == 19
            and agree(r["range"], [min(solid_rho), max(solid_rho)])
            and r["components"].get("energy") == 1 and r["components"].get("stress") == stress,
            f"{reader} on the solid's snapshots.xmf: {({k: r[k] for k in ('times', 'points', 'cells', 'components')} if ok else r)}"
            f" (want 19 points and cells, energy, stress of {stress} components)")

# The render: the particles drawn, i.e. pixels other than the background (the corner's colour);
# a particle is 4 x 4 pixels, so at least one pixel each even where they overlap.
drawn = 0
if os.path.exists(png):
    import matplotlib.image
    img = matplotlib.image.imread(png)[:, :, :3]
    drawn = int((abs(img - img[0, 0]).max(axis=2) > 0.02).sum())
c.check(drawn >= n, f"{png} rendered: {drawn} pixels of particles (at least {n})")
c.finish()
