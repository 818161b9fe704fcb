#!/usr/bin/python3
"""docs/options.md is current: tools/options_page.py, run on this build, writes it byte for
byte (the page and -help have one source, the option tables of the code). A changed option,
default or help text fails here until the page is written again:
  tools/options_page.py --spam-ark build/spam-ark
The page must also list the options users meet first, with the defaults -help gives; -help
itself stays at most 400 lines of spam-ark's options (PETSc's under -help petsc)."""
import os
import subprocess
from spamrun import Checks, arguments

a = arguments()
c = Checks()
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
os.makedirs(a.workdir, exist_ok=True)
fresh = os.path.join(a.workdir, "options.md")
p = subprocess.run([os.path.join(ROOT, "tools", "options_page.py"), "--spam-ark", a.spam_ark, "-o", fresh],
                   capture_output=True, text=True, timeout=300)
if c.check(p.returncode == 0, f"tools/options_page.py: exit {p.returncode} {p.stderr.strip()}"):
    new, old = open(fresh).read(), open(os.path.join(ROOT, "docs", "options.md")).read()
    diff = [(i + 1, x, y) for i, (x, y) in enumerate(zip(old.splitlines(), new.splitlines())) if x != y]
    c.check(new == old, f"docs/options.md is what -help says today ({len(new.splitlines())} lines; first difference "
            f"{diff[:1] or 'in length'}; rerun tools/options_page.py --spam-ark build/spam-ark)")
    for opt, default in (("-scene", "expansion"), ("-kernel", "lucy"), ("-ts_rtol", None), ("-output_dir", None),
                         ("-quiet", "false"), ("-error_norm", "rms")):
        row = next((l for l in new.splitlines() if l.startswith(f"| `{opt}` |")), None)
        c.check(row is not None and (default is None or f"| `{default}` |" in row), f"{opt} on the page: {row}")
# -help is read by a person: spam-ark's options only (PETSc's under -help petsc), at most 400
# lines, no line pointing elsewhere for its meaning.
p = subprocess.run([a.spam_ark, "-help"], capture_output=True, text=True, timeout=60)
lines = (p.stdout + p.stderr).splitlines()
c.check(p.returncode == 0 and len(lines) <= 400 and not any(l.rstrip().endswith("(README)") for l in lines)
        and not any("-ksp_type" in l for l in lines),
        f"-help: exit {p.returncode}, {len(lines)} lines (at most 400), lines ending in (README): "
        f"{sum(l.rstrip().endswith('(README)') for l in lines)}, KSP's options listed: {any('-ksp_type' in l for l in lines)}")
p = subprocess.run([a.spam_ark, "-help", "petsc"], capture_output=True, text=True, timeout=60)
c.check(p.returncode == 0 and "-ksp_type" in p.stdout + p.stderr, f"-help petsc: exit {p.returncode}, lists PETSc's KSP options: {'-ksp_type' in p.stdout + p.stderr}")
c.finish()
