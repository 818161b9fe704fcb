#!/usr/bin/python3
"""What a user reads: -help lists every option with its default; timeseries.csv,
steps.csv and summary.json carry the documented fields; HDF5 + XDMF snapshots are
well formed (each XDMF grid points at HDF5 datasets of the right shape); -monitor
prints a line per step; the expansion chart script draws the run."""
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from spamrun import Checks, arguments, manifest, run, summary, table

a = arguments()
c = Checks()
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# -help: every option, each with its default ("[default ...]"), and no run, no files.
code, out, err = run(a.spam_ark, ["-help"], os.path.join(a.workdir, "help"))
options = ["-dim", "-h", "-mass", "-neighbour_skin", "-eos_gamma", "-eos_kappa", "-box_lo", "-box_len", "-periodic",
           "-scene_translate", "-scene", "-expansion_n", "-expansion_amplitude", "-expansion_seed",
           "-expansion_perturb_velocities", "-file_path", "-ts_max_time", "-ts_max_steps", "-ts_dt", "-ts_rtol",
           "-ts_atol", "-arkode_table", "-arkode_adapt", "-arkode_fixed_step", "-arkode_safety", "-arkode_max_growth",
           "-arkode_classic_weights", "-output_dir", "-output_interval", "-snapshot_interval", "-snapshot_hdf5",
           "-snapshot_csv", "-monitor", "-diag_entropy", "-diag_grid_spacing", "-initial_csv", "-final_csv",
           "-output_overwrite", "-snapshot_max"]
missing = [o for o in options if not re.search(r"^\s*" + re.escape(o) + r"  .*\[default [^]]+\]$", out, re.M)]
c.check(code == 0 and not missing, f"-help exits 0 and lists {len(options)} options with defaults (missing: {missing})")
c.check(not os.path.exists(os.path.join(a.workdir, "help")), "-help writes no files")

# -quiet: the run's last line alone on stdout (the same line a run without it ends with).
lines = {}
for flag in ([], ["-quiet"]):
    code, out, err = run(a.spam_ark, ["-expansion_n", 8, "-h", 3, "-ts_max_time", 2] + flag,
                         os.path.join(a.workdir, "quiet" if flag else "loud"))
    lines[bool(flag)] = out.strip().splitlines() if code == 0 else []
q, l = lines[True], lines[False]
c.check(len(q) == 1 and len(l) > 2 and q[0].split(";")[0].split(",")[0] == l[-1].split(";")[0].split(",")[0]
        and q[0].startswith("spam-ark: done"), f"-quiet: {len(q)} line on stdout ({q[:1]}), {len(l)} without it")

# A small run with every output.
run_dir = os.path.join(a.workdir, "run")
code, out, err = run(a.spam_ark, ["-expansion_n", 12, "-h", 3, "-ts_max_time", 12, "-output_interval", 1,
                                  "-snapshot_interval", 4, "-monitor"], run_dir)
c.check(code == 0, f"run exits 0 {err.strip()}")
s = summary(run_dir)
for key in ("status", "method", "rtol", "atol", "steps", "rejected_steps", "rhs_evals", "wall_time_s",
            "pair_interactions_per_s", "energy_initial", "energy_final", "energy_rel_drift_max", "momentum_initial",
            "momentum_final", "momentum_rel_drift_max", "angular_momentum_initial", "angular_momentum_final",
            "angular_momentum_rel_drift_max", "dS_sum_ratio_final", "dS_grid_ratio_final", "sound_traversal_time"):
    c.check(key in s, f"summary.json has {key} = {s.get(key)}")
# Angular momentum is not conserved in a periodic box: no drift figure, the reason instead,
# and the same measure as a change; in the open box it is conserved and its drift is given.
c.check(s["angular_momentum_rel_drift_max"] is None and s["angular_momentum_conserved"] is False
        and s["angular_momentum_not_conserved"] == "not conserved: periodic box"
        and "angular_momentum_rel_drift_max" in s["null_fields"] and s["angular_momentum_rel_change_max"] >= 0,
        f"periodic box: L drift {s['angular_momentum_rel_drift_max']}, conserved {s['angular_momentum_conserved']}, "
        f"reason {s.get('angular_momentum_not_conserved')!r}, change {s['angular_momentum_rel_change_max']}")
open_dir = os.path.join(a.workdir, "open")
code, _, err = run(a.spam_ark, ["-expansion_n", 12, "-h", 3, "-ts_max_time", 4, "-periodic", 0, "-snapshot_interval", 0], open_dir)
so = summary(open_dir) if code == 0 else {}
c.check(code == 0 and so.get("angular_momentum_conserved") is True and "angular_momentum_not_conserved" not in so
        and 0 <= so.get("angular_momentum_rel_drift_max", -1) < 1e-6,
        f"open box: exit {code}, L conserved {so.get('angular_momentum_conserved')}, drift {so.get('angular_momentum_rel_drift_max')} "
        f"(below the default rtol 1e-6: Runge-Kutta keeps the quadratic L to its error only) {err.strip()[:200]}")
c.check(s["status"] == "ok" and s["steps"] > 0 and s["rhs_evals"] >= 6 * s["steps"], f"DP costs at least 6 RHS per step ({s['rhs_evals']} for {s['steps']} steps)")
steplines = [l for l in out.splitlines() if l.startswith("step ")]
c.check(len(steplines) == s["steps"], f"-monitor printed {len(steplines)} step lines for {s['steps']} steps")
ts = table(os.path.join(run_dir, "timeseries.csv"))
c.check(len(ts["t"]) == 13 and abs(ts["t"][-1] - 12) < 1e-9, f"timeseries.csv has a row per output time ({len(ts['t'])} rows)")
c.check(abs(ts["mass"][0] - 144) < 1e-9 and max(ts["mass"]) == min(ts["mass"]), "mass is N m at every row")
m = manifest(run_dir)
names = sorted(e["name"] for e in m["files"])
present = sorted(n for n in os.listdir(run_dir) if n != "manifest.json")
kinds = {e["kind"] for e in m["files"]}
c.check(m["program"] == "spam-ark" and m["status"] == "ok" and names == present and "-expansion_n 12" in m["options"]
        and [e["t"] for e in m["files"] if e["kind"] == "snapshot_h5"] == [0, 4, 8, 12]
        and kinds == {"snapshot_h5", "snapshot_csv", "xdmf_index", "summary", "timeseries", "steps"},
        f"manifest.json: status {m['status']}, lists every file of the run ({len(names)}) with its kind and snapshot times")
st = table(os.path.join(run_dir, "steps.csv"))
c.check(len(st["dt"]) == s["steps"] and abs(sum(st["dt"]) - 12) < 1e-9, "steps.csv: one row per step, steps add up to the end time")

# XDMF index and HDF5 datasets.
xmf = os.path.join(run_dir, "snapshots.xmf")
grids = ET.parse(xmf).getroot().findall(".//Grid[@GridType='Uniform']")
times = [float(g.find("Time").get("Value")) for g in grids]
c.check(times == [0.0, 4.0, 8.0, 12.0], f"XDMF lists the snapshots at {times}")
items = [d.text.strip() for g in grids for d in g.iter("DataItem")]
c.check(all(os.path.exists(os.path.join(run_dir, i.split(":")[0])) for i in items), f"every XDMF DataItem names an existing HDF5 file ({len(items)} items)")
if shutil.which("h5ls"):
    listing = subprocess.run(["h5ls", os.path.join(run_dir, "snap_00003.h5")], capture_output=True, text=True).stdout
    c.check(re.search(r"positions\s+Dataset \{144, 3\}", listing) and re.search(r"density\s+Dataset \{144\}", listing),
            f"HDF5 datasets have the shapes XDMF declares: {listing.split()}")
else:
    c.check(False, "h5ls (hdf5-tools) is installed")

# An elastic solid's snapshots also carry its energy and stress (Tensor6 for ParaView), and
# the CSV and HDF5 copies of one snapshot hold the same numbers.
solid_dir = os.path.join(a.workdir, "solid")
code, _, err = run(a.spam_ark, ["-scene", "rotor", "-rotor_n", 2, "-ts_max_time", 1, "-snapshot_interval", 1,
                                "-snapshot_csv", "-output_dir", solid_dir], solid_dir)
attrs = {e.get("Name"): e.get("AttributeType") for e in ET.parse(os.path.join(solid_dir, "snapshots.xmf")).getroot().iter("Attribute")} if code == 0 else {}
c.check(attrs == {"velocity": "Vector", "density": "Scalar", "mass": "Scalar", "id": "Scalar", "energy": "Scalar", "stress": "Tensor6"}, f"solid XDMF attributes {attrs} {err.strip()}")
if code == 0 and shutil.which("h5dump"):
    dump = subprocess.run(["h5dump", "-m", "%.17g", "-d", "/stress", "-y", "-w", "0", os.path.join(solid_dir, "snap_00001.h5")], capture_output=True, text=True).stdout
    h5 = [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e[-+]?\d+)?", dump.split("DATA {")[1].split("}")[0])]
    rows = open(os.path.join(solid_dir, "particles_00001.csv")).read().splitlines()[1:]
    cols = rows[0].split(",")
    # The CSV holds the 2D state's components (the file-scene format); xz, yz, zz are 0.
    csv6 = [float(r.split(",")[cols.index(k)]) if k in cols else 0.0 for r in rows[1:] for k in ("sxx", "sxy", "sxz", "syy", "syz", "szz")]
    c.check(len(h5) == len(csv6) == 6 * 19 and max(abs(u - w) for u, w in zip(h5, csv6)) < 1e-12 and max(map(abs, csv6)) > 0,
            f"stress of {len(csv6) // 6} particles, HDF5 = CSV, max |sigma| {max(map(abs, csv6)) if csv6 else 0:.3g}")

# Read alone (h5py, h5dump): the columns of the [n][k] datasets are named, and the units.
if code == 0 and shutil.which("h5dump"):
    h5 = os.path.join(solid_dir, "snap_00001.h5")
    named = {d: subprocess.run(["h5dump", "-a", f"{d}/components", h5], capture_output=True, text=True).stdout
             for d in ("/positions", "/velocities", "/stress")}
    units = subprocess.run(["h5dump", "-a", "units_convention", h5], capture_output=True, text=True).stdout
    c.check('"x,y,z' in named["/positions"] and '"vx,vy,vz' in named["/velocities"] and '"sxx,sxy,sxz,syy,syz,szz' in named["/stress"]
            and "reduced units" in units, f"HDF5 datasets name their components and the file its units: {units.split('(0): ')[-1][:60]}...")

# The chart of the run.
png = os.path.join(run_dir, "expansion.png")
p = subprocess.run([sys.executable, os.path.join(root, "examples", "plot_expansion.py"), run_dir, "-o", png],
                   capture_output=True, text=True)
with open(png, "rb") as f:
    magic = f.read(8)
c.check(p.returncode == 0 and magic == b"\x89PNG\r\n\x1a\n", f"plot_expansion.py draws the run: {p.stdout.strip()} {p.stderr.strip()}")
c.finish()
