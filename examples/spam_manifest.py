"""Reading a spam-ark output directory through its manifest.json.

spam-ark lists every file a run wrote in DIR/manifest.json (name, kind, and t for
snapshots) with the run's status: running, ok, max_steps, unstable, interrupted or
failed. Scripts read that list instead of globbing the directory, so a file left by
another run is never picked up.
"""
import functools
import hashlib
import json
import os
import sys

DONE = ("ok", "max_steps")          # the run reached its end (or its step limit)
FINISHED = DONE + ("unstable",)     # ended by itself; its files are complete


class ManifestError(Exception):
    """No usable manifest: a missing, unreadable or malformed manifest.json."""


def read(run_dir):
    """The manifest of run_dir as a dict (raises ManifestError)."""
    path = os.path.join(run_dir, "manifest.json")
    try:
        with open(path, encoding="utf-8") as fh:
            man = json.load(fh)
    except FileNotFoundError:
        raise ManifestError("%s: no manifest.json (not a spam-ark output directory, "
                            "or one written before spam-ark listed its files)" % run_dir)
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise ManifestError("cannot read %s: %s" % (path, exc))
    if (not isinstance(man, dict) or man.get("program") != "spam-ark"
            or not isinstance(man.get("files"), list)):
        raise ManifestError("%s is not a spam-ark manifest" % path)
    return man


def status(run_dir):
    """The run's status, or None when there is no usable manifest."""
    try:
        return read(run_dir).get("status")
    except ManifestError:
        return None


def option(man, name, default):
    """The value of -name in the manifest's option string as a float, else default."""
    words = man.get("options", "").split()
    for k, w in enumerate(words[:-1]):
        if w == "-" + name:
            return float(words[k + 1])
    return default


def files(man, run_dir, kind):
    """[(t, path)] of the files of one kind ("snapshot_csv", "snapshot_h5", "summary",
    "timeseries", ...) in the order written; t is None for files that are not snapshots."""
    out = []
    for e in man["files"]:
        if isinstance(e, dict) and e.get("kind") == kind and isinstance(e.get("name"), str):
            out.append((e.get("t"), os.path.join(run_dir, e["name"])))
    return out


def check(man, run_dir, prog, refuse=("failed",)):
    """Raises ManifestError for a status in refuse; warns (stderr, one line) when the run
    did not reach its end: running (still going, or killed), interrupted, unstable."""
    st = man.get("status")
    if st in refuse:
        raise ManifestError("%s: the run's status is %r (%s)" % (run_dir, st, "see summary.json"))
    if st not in DONE:
        why = {"running": "still running, or killed before it could finish",
               "interrupted": "stopped by a signal before its end",
               "unstable": "stopped when it went unstable"}.get(st, "status unknown")
        sys.stderr.write("%s: warning: %s: the run's status is %r (%s); its files are drawn as "
                         "they are\n" % (prog, run_dir, st, why))
    return st


def open_run(run_dir, prog, scene=None):
    """(manifest, summary) of a run a chart script draws; on any problem, one line naming
    prog on stderr and exit code 2. With scene, summary.json must say the run is of that
    scene (a chart of the wrong scene would look plausible and mean nothing)."""
    try:
        man = read(run_dir)
        check(man, run_dir, prog)
        summary = None
        if scene is not None:
            path = os.path.join(run_dir, "summary.json")
            try:
                with open(path, encoding="utf-8") as fh:
                    summary = json.load(fh)
            except (OSError, UnicodeDecodeError, ValueError) as exc:
                raise ManifestError("cannot read %s: %s" % (path, exc))
            if summary.get("scene") != scene:
                raise ManifestError("%s is a run of -scene %s, not %s" % (run_dir, summary.get("scene"), scene))
    except ManifestError as exc:
        sys.stderr.write("%s: error: %s\n" % (prog, " ".join(str(exc).split())))
        sys.exit(2)
    return man, summary


@functools.lru_cache(maxsize=None)
def binary_id(binary):
    """SHA-1 of the spam-ark executable: a run directory remembers the build that made it."""
    with open(binary, "rb") as f:
        return hashlib.sha1(f.read()).hexdigest()[:16]


def run_options(args):
    """The options of a run as one string: the key a study's cache compares."""
    return " ".join(map(str, args))


def same_build(summary, binary, args=None):
    """Whether a finished run's summary was made by this build of spam-ark and, given args,
    with these options: a study rerun after a change to the program, or with another scene
    or method in the same run directory, must not reuse the old run."""
    if args is not None and summary.get("run_options") != run_options(args):
        return False
    return summary.get("binary_sha1") == binary_id(binary)


def remember_build(run_dir, binary, exit_code, args=None):
    """Records the build, the options (args) and the exit code in run_dir/summary.json (if
    the run wrote one), so that a resumed study can reuse the run without running it again."""
    summ = os.path.join(run_dir, "summary.json")
    if not os.path.exists(summ):
        return
    with open(summ, encoding="utf-8") as fh:
        s = json.load(fh)
    s["exit_code"] = exit_code
    s["binary_sha1"] = binary_id(binary)
    if args is not None:
        s["run_options"] = run_options(args)
    with open(summ + ".tmp", "w", encoding="utf-8") as fh:
        json.dump(s, fh, indent=1)
    os.replace(summ + ".tmp", summ)
