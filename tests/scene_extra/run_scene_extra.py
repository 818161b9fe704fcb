#!/usr/bin/python3
"""A scene added by its file and one row reaches every use of the scene list.

The program under test is spam-ark compiled with the test-only scene test-drift (its file
scene_test_drift.c and its row scene_list_extra.h; nothing else edited). Checked: -help
lists it among the scenes and shows its options with their defaults; -scene test-drift
runs, and its gas keeps its uniform drift U (the uniform lattice's pressure forces cancel,
so every velocity stays U up to round-off); its options are accepted for it and refused for
another scene in one line naming it, and another scene's option is refused for it; its
integer option is range-checked and a misspelling of it is answered with its name, both
derived from its options table."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import spamrun  # noqa: E402

args = spamrun.arguments()
bin_ = args.spam_ark
checks = spamrun.Checks()

# -help: the scene in -scene's list, its options with their defaults.
code, out, err = spamrun.run(bin_, ["-help", "-scene", "test-drift"])
text = out + err
scene_line = [l for l in text.splitlines() if l.strip().startswith("-scene  ")]
checks.check(code == 0 and len(scene_line) == 1 and scene_line[0].rstrip().endswith("cavity, test-drift  [default test-drift]"),
             "-help: -scene lists test-drift last: " + (scene_line[0].strip() if scene_line else spamrun.brief(text)))
checks.check("-testdrift_n  Lattice points per direction of the drifting gas (N = n^D)  [default 8]" in text
             and "-testdrift_speed  Velocity U of every particle along x  [default 0.25]" in text,
             "-help: its options with their defaults and help, from its table")
code, out, err = spamrun.run(bin_, ["-help"])
checks.check(code == 0 and "-testdrift_n  Lattice points" in out + err and "-expansion_n  " in out + err,
             "-help of another scene lists it too, beside the others")

# It runs: the uniform drift is kept up to round-off.
U, t_end = 0.3, 2.0
final = os.path.join(args.workdir, "final.csv")
code, out, err = spamrun.run(bin_, ["-scene", "test-drift", "-testdrift_n", 9, "-testdrift_speed", U, "-ts_max_time", t_end,
                                    "-final_csv", final, "-output_dir", os.path.join(args.workdir, "run")])
ok = code == 0 and os.path.exists(final)
checks.check(ok, f"-scene test-drift -testdrift_n 9 runs to t = {t_end} (exit {code}) {spamrun.brief(err) if not ok else ''}")
if ok:
    cols = spamrun.table(final)
    vx, vy = cols["vx"], cols["vy"]
    # The pressure forces cancel to round-off on the uniform lattice: a drift of U by 1e-12 U
    # over t_end is more than many thousand steps of round-off.
    dv = max(max(abs(v - U) for v in vx), max(abs(v) for v in vy))
    checks.check(len(vx) == 81 and dv < 1e-12 * U, f"81 particles keep v = (U, 0): max deviation {dv:.3g} (< 1e-12 U)")

# Relevance, from the scene tables.
code, out, err = spamrun.run(bin_, ["-scene", "expansion", "-expansion_n", 4, "-testdrift_n", 9])
line = spamrun.one_line(err)
checks.check(code == 2 and line == "spam-ark: error: -testdrift_n = '9': not used: applies to -scene test-drift (this run: -scene expansion)",
             "its option refused for another scene, naming it: " + spamrun.brief(err))
code, out, err = spamrun.run(bin_, ["-scene", "test-drift", "-expansion_n", 4])
line = spamrun.one_line(err)
checks.check(code == 2 and line == "spam-ark: error: -expansion_n = '4': not used: applies to -scene expansion (this run: -scene test-drift)",
             "another scene's option refused for it: " + spamrun.brief(err))
code, out, err = spamrun.run(bin_, ["-scene", "test-drift", "-testdrift_n", 2147483648])
checks.check(code == 2 and "-testdrift_n" in err and "PetscInt is 32-bit" in err,
             "its integer option is range-checked before PETSc reads it: " + spamrun.brief(err))
code, out, err = spamrun.run(bin_, ["-scene", "test-drift", "-testdrift_m", 9])
checks.check(code == 2 and "did you mean -testdrift_n?" in err, "a misspelling names its option: " + spamrun.brief(err))
code, out, err = spamrun.run(bin_, ["-scene", "test-drift", "-testdrift_n", 3])
line = spamrun.one_line(err)
checks.check(code == 2 and line is not None and "-testdrift_n" in line and "2 (h + skin)" in line,
             "its own check refuses in one line: " + spamrun.brief(err))
checks.finish()
