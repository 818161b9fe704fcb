#!/usr/bin/python3
"""Writes docs/options.md, the reference of every option, from `spam-ark -help`: the page and
-help have one source (the option tables in the code) and cannot disagree. run_options_page
checks that the committed page is what this script writes today.

  tools/options_page.py --spam-ark build/spam-ark [-o docs/options.md]
"""
import argparse
import re
import subprocess
import sys

HEAD = """# Options

Every option of spam-ark with its default, grouped as `spam-ark -help` groups them. This page
is written by `tools/options_page.py --spam-ark build/spam-ark` from the program's own
`-help` (a test checks that it is current). Defaults are those of the default scene
(`-scene expansion`); a scene may set its own (its options file says which), and
`spam-ark -options_file options/NAME.opts -help` shows them for that scene. How options
are given, refused and reported: [running.md](running.md). PETSc's general options:
`spam-ark -help petsc`.
"""


# PETSc 3.18 prints an uninitialised value as the default of -ts_time_span (6.9e-310 in one
# build, 0 in another): a row that would make the page differ between builds.
UNSTABLE = {"-ts_time_span"}


def blocks(text):
    """[(title, [(option, meaning, default)])] in the order -help prints them."""
    out, title, rows = [], None, []
    for line in text.splitlines():
        m = re.match(r"^  (-[A-Za-z]\w*)  (.*?)  \[default (.*?)(; this run .*)?\]$", line)
        if m and m.group(1) in UNSTABLE:
            continue
        if m:
            rows.append((m.group(1), m.group(2), m.group(3)))
        elif line and not line.startswith(" ") and line.endswith(":"):
            if title is not None and rows:
                out.append((title, rows))
            title, rows = line[:-1], []
    if title is not None and rows:
        out.append((title, rows))
    return out


def cell(s):
    return s.replace("|", "\\|")


def page(text):
    lines = [HEAD]
    for title, rows in blocks(text):
        lines += [f"## {cell(title)}", "", "| option | default | meaning |", "|---|---|---|"]
        lines += [f"| `{o}` | `{cell(d)}` | {cell(m)} |" for o, m, d in rows]
        lines.append("")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--spam-ark", required=True)
    p.add_argument("-o", default="docs/options.md")
    a = p.parse_args()
    r = subprocess.run([a.spam_ark, "-help"], capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        sys.exit(f"{a.spam_ark} -help: exit {r.returncode}: {r.stderr.strip()}")
    with open(a.o, "w") as f:
        f.write(page(r.stdout))


if __name__ == "__main__":
    main()
