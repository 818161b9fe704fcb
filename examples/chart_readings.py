"""The readings a chart's page quotes, written beside the chart as JSON.

A chart script that draws OUT.png calls write(OUT.png, readings) and OUT.json appears next
to it: the readings (numbers, and tables of formatted cells), the command that made them,
the commit of the repository it ran in (and whether its tree had uncommitted changes), the
time and the machine's load. The pages quote these readings through markers that
tools/docs_numbers.py fills in and checks, so a number beside a chart is never typed by
hand; timings are quoted only with the load that came with them.
"""
import datetime
import json
import os
import shlex
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _git(*args):
    p = subprocess.run(["git", "-C", REPO] + list(args), capture_output=True, text=True)
    return p.stdout.strip() if p.returncode == 0 else ""


def provenance():
    """{"commit", "describe", "dirty"} of the repository the script runs from; a tree with
    uncommitted changes to tracked files other than the pages (docs/, *.md: the charts,
    readings and pages these runs rewrite) is dirty: its results may not be the commit's."""
    dirty = bool(_git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!docs", ":!*.md"))
    return {"commit": _git("rev-parse", "HEAD") or "unknown",
            "describe": (_git("describe", "--always", "--abbrev=12") or "unknown") + ("-dirty" if dirty else ""),
            "dirty": dirty}


def command(argv=None):
    """The command line as run from the repository's root (paths under it made relative)."""
    argv = list(sys.argv if argv is None else argv)

    def rel(w):
        if os.path.exists(w):
            p = os.path.relpath(os.path.abspath(w), REPO)
            return p if not p.startswith("..") else w
        return w
    return " ".join(shlex.quote(rel(w)) if k == 0 else shlex.quote(w) for k, w in enumerate(argv))


def machine():
    """The load the timings were taken under: the 1-minute load average and the cores."""
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = None
    return {"load_1min": load, "cores": os.cpu_count()}


def table(columns, rows):
    """A table reading: its header and its rows of already formatted cells."""
    return {"columns": list(columns), "rows": [[str(c) for c in r] for r in rows]}


def write(png, readings, runs=(), argv=None):
    """Writes PNG's readings to the same path with .json; runs: the run directories (or
    files) read. Returns the path written."""
    return write_json(os.path.splitext(png)[0] + ".json", readings, runs, argv, chart=os.path.basename(png))


def write_json(path, readings, runs=(), argv=None, chart=None):
    """Writes readings with their provenance to path (a study's section has no chart)."""
    doc = {"chart": chart, "command": command(argv)}
    doc.update(provenance())
    doc["made_utc"] = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    doc.update(machine())
    doc["runs"] = [os.path.relpath(os.path.abspath(d), REPO) if not os.path.relpath(os.path.abspath(d), REPO).startswith("..")
                   else d for d in runs]
    doc["readings"] = readings
    with open(path + ".tmp", "w", encoding="utf-8") as fh:
        json.dump(doc, fh, indent=1, sort_keys=False)
        fh.write("\n")
    os.replace(path + ".tmp", path)
    print(f"readings={path}")
    return path


BOOKS = ("n_particles", "steps", "rejected_steps", "rhs_evals", "interpolation_rhs_evals", "rhs_evals_total",
         "energy_rel_drift_max", "momentum_rel_drift_max", "momentum_final", "momentum_scale", "post_step_jumps",
         "wall_time_s", "t_final")


def books(run_dir):
    """The run's counts and drifts from its summary.json (the fields the pages quote)."""
    with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as fh:
        s = json.load(fh)
    return {k: s.get(k) for k in BOOKS}
