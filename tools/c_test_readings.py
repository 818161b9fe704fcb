#!/usr/bin/python3
"""The readings the C tests print, gathered into a readings JSON the pages quote.

A C test prints a value a page quotes as a line "reading KEY VALUE" (TestReading in
tests/test_util.c). This runs the named tests through ctest, one at a time, and writes
{"TEST": {"KEY": VALUE}} as the readings of OUT (examples/chart_readings.py: with the
command and the commit). A key a test prints several times (one per case, lattice or
controller) becomes its range, {"min": ..., "max": ..., "n": ...}, and "all" holds every
key's range over all the tests named (the same test on 2, 3 and 4 ranks); a test that fails,
or prints no reading, writes nothing.

    tools/c_test_readings.py --build build --out tests/c_test_readings.json \\
        test_walls test_migrate_np4 ...
"""
import argparse
import os
import re
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "examples"))
import chart_readings  # noqa: E402

LINE = re.compile(r"^(?:\d+: )?reading (\S+) (\S+)\s*$")


def summary(values):
    return values[0] if len(values) == 1 else {"min": min(values), "max": max(values), "n": len(values)}


def printed(build, test):
    """{key: [values]} the test printed; exits when the test fails."""
    p = subprocess.run(["ctest", "--test-dir", build, "-R", f"^{re.escape(test)}$", "-V"],
                       capture_output=True, text=True)
    if p.returncode != 0 or "No tests were found" in p.stdout + p.stderr:
        sys.exit(f"c_test_readings: {test} failed or does not exist (ctest exit {p.returncode}):\n"
                 + (p.stdout + p.stderr)[-3000:])
    seen = {}
    for line in p.stdout.splitlines():
        m = LINE.match(line)
        if m:
            seen.setdefault(m.group(1), []).append(float(m.group(2)))
    if not seen:
        sys.exit(f"c_test_readings: {test} printed no reading")
    return seen


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build", help="the build directory ctest runs in")
    ap.add_argument("--out", required=True, help="the readings JSON to write")
    ap.add_argument("tests", nargs="+", help="ctest names of C tests that print readings")
    a = ap.parse_args()
    seen = {t: printed(a.build, t) for t in a.tests}
    every = {}
    for values in seen.values():
        for k, v in values.items():
            every.setdefault(k, []).extend(v)
    readings = {t: {k: summary(v) for k, v in values.items()} for t, values in seen.items()}
    readings["all"] = {k: {"min": min(v), "max": max(v), "n": len(v)} for k, v in every.items()}
    chart_readings.write_json(a.out, readings)


if __name__ == "__main__":
    main()
