"""Render a run's last particle snapshot with ParaView, coloured by density.

    xvfb-run -a pvpython --force-offscreen-rendering examples/paraview_last.py RUN_DIR [OUT.png]

(pvpython is ParaView's Python; `tools/deps.sh --paraview` installs it and xvfb-run on Debian
12; on a desktop `pvpython examples/paraview_last.py RUN_DIR` is enough.) Opens
RUN_DIR/snapshots.xmf with the Xdmf3 reader, goes to the last time, shows the particles as
points coloured by `density`, with a colour bar, and writes OUT.png (default
RUN_DIR/paraview.png). The same steps by hand in the ParaView window: File > Open
snapshots.xmf, reader "XDMF Reader (Xdmf3ReaderS)", Apply, representation "Points" (or
"Point Gaussian"), colour by density, last time step.
"""
import os
import sys

from paraview import simple

run_dir = sys.argv[1]
png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(run_dir, "paraview.png")
reader = simple.Xdmf3ReaderS(FileName=[os.path.join(run_dir, "snapshots.xmf")])
times = list(reader.TimestepValues) or [0.0]
view = simple.CreateView("RenderView")
view.ViewTime = times[-1]
display = simple.Show(reader, view)
display.SetRepresentationType("Points")
display.PointSize = 3
simple.ColorBy(display, ("POINTS", "density"))
display.SetScalarBarVisibility(view, True)
simple.GetScalarBar(simple.GetColorTransferFunction("density"), view).Title = "density (reduced units)"
title = simple.Text(Text="spam-ark run %s, particles at t = %g" % (os.path.basename(os.path.abspath(run_dir)), times[-1]))
simple.Show(title, view)
view.ResetCamera()
simple.SaveScreenshot(png, view, ImageResolution=[800, 600])
print("wrote %s" % png)
