#!/usr/bin/python3
"""Read a spam-ark output directory from Python: numpy arrays, no ParaView needed.

    import sys; sys.path.insert(0, "examples")      # or the installed share/spam/examples
    import spamread
    run = spamread.Run("out/expansion")
    run.summary["energy_rel_drift_final"]           # summary.json as a dict
    ts = run.timeseries()                           # timeseries.csv: {column: array}
    ts["t"], ts["total"]
    steps = run.steps()                             # steps.csv: every accepted step
    for t, p in run.snapshots():                    # every particle snapshot, in time order
        p["x"], p["vx"], p["m"]                     # {column: array}, one row per particle id

Snapshots are read from the CSV copies (particles_NNNNN.csv), which need numpy alone; with
h5py installed, run.snapshots(hdf5=True) reads snap_NNNNN.h5 instead. The files a run wrote
are taken from its manifest.json, never by listing the directory, so a file left by another
run is not read. As a script, `examples/spamread.py DIR` prints what a run holds.
"""
import csv
import json
import os
import sys

import numpy as np


class RunError(Exception):
    """A directory that is not a readable spam-ark run."""


def _columns(path, comment="#"):
    """A CSV with a header line as {name: float array}; lines starting with comment skipped.
    Text cells (steps.csv's `limit`) stay strings."""
    with open(path, encoding="utf-8") as fh:
        rows = [r for r in csv.reader(line for line in fh if line.strip() and not line.startswith(comment))]
    if not rows:
        raise RunError("%s: empty" % path)
    head, body = rows[0], rows[1:]
    out = {}
    for k, name in enumerate(head):
        cells = [r[k] for r in body]
        try:
            out[name] = np.array([float(c) for c in cells])
        except ValueError:
            out[name] = np.array(cells)
    return out


def read_particles(path):
    """A particle CSV (a snapshot, -final_csv, or a file for -scene file) as
    ({column: array}, t); t is the `# t=` comment's time or None."""
    t = None
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if line.startswith("# t="):
                t = float(line[4:])
                break
            if line.strip() and not line.startswith("#"):
                break
    return _columns(path), t


def write_particles(path, columns):
    """Writes {name: array} as a particle CSV that `-scene file -file_path path` reads.
    Names: x y z vx vy vz m e rho sxx sxy syy sxz syz szz id (positions required)."""
    names = list(columns)
    n = len(columns[names[0]])
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(",".join(names) + "\n")
        for i in range(n):
            fh.write(",".join(repr(float(columns[c][i])) if c != "id" else str(int(columns[c][i]))
                              for c in names) + "\n")


class Run:
    """One output directory of spam-ark (the -output_dir of a run)."""

    def __init__(self, path):
        self.path = path
        try:
            with open(os.path.join(path, "manifest.json"), encoding="utf-8") as fh:
                self.manifest = json.load(fh)
        except (OSError, ValueError) as exc:
            raise RunError("%s: no readable manifest.json (%s)" % (path, exc))
        if self.manifest.get("program") != "spam-ark":
            raise RunError("%s: manifest.json is not spam-ark's" % path)
        self.status = self.manifest.get("status")
        try:
            with open(os.path.join(path, "summary.json"), encoding="utf-8") as fh:
                self.summary = json.load(fh)
        except (OSError, ValueError):
            self.summary = {}     # a run still under way has none yet

    def files(self, kind):
        """[(t, path)] of the manifest's files of one kind, in the order written (kinds:
        timeseries, steps, summary, snapshot_csv, snapshot_h5, xdmf_index, grid_csv, ...)."""
        return [(e.get("t"), os.path.join(self.path, e["name"]))
                for e in self.manifest.get("files", []) if e.get("kind") == kind]

    def timeseries(self):
        """timeseries.csv: a row per output time, {column: array} (nan where undefined)."""
        return _columns(os.path.join(self.path, "timeseries.csv"))

    def steps(self):
        """steps.csv: every accepted step (step, t, dt, rejected, rhs_evals, limit)."""
        return _columns(os.path.join(self.path, "steps.csv"))

    def snapshots(self, hdf5=False):
        """[(t, {column: array})] of every particle snapshot, in time order."""
        if not hdf5:
            return [(t, read_particles(p)[0]) for t, p in self.files("snapshot_csv")]
        import h5py  # optional: Debian's python3-h5py
        out = []
        for t, p in self.files("snapshot_h5"):
            with h5py.File(p, "r") as f:
                d = {"m": f["mass"][()], "id": f["id"][()]}
                for ds, axes in (("positions", "x y z"), ("velocities", "vx vy vz")):
                    for k, name in enumerate(axes.split()[:f.attrs["dim"]]):
                        d[name] = f[ds][()][:, k]
                for extra in ("density", "energy"):
                    if extra in f:
                        d[extra] = f[extra][()]
                out.append((float(f.attrs["time"]), d))
        return out


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: examples/spamread.py RUN_DIR\n")
        return 2
    try:
        run = Run(argv[1])
        ts = run.timeseries()
    except (RunError, OSError) as exc:
        sys.stderr.write("spamread.py: error: %s\n" % exc)
        return 2
    s = run.summary
    print("%s: status %s, scene %s, %sD, %s particles, model %s" % (
        run.path, run.status, s.get("scene"), s.get("dim"), s.get("n_particles"),
        s.get("model")))
    print("timeseries.csv: %d rows, t = %g to %g; columns: %s" % (
        len(ts["t"]), ts["t"][0], ts["t"][-1], " ".join(ts)))
    snaps = run.files("snapshot_csv")
    print("particle snapshots (CSV): %d%s" % (len(snaps), (" at t = " + ", ".join("%g" % t for t, _ in snaps)) if snaps else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
