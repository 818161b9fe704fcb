#!/usr/bin/python3
"""docs/options.md is current: tools/options_page.py, run on this build, writes it byte for
byte (the page and -help have one source, the option tables of the code). A changed option,
default or help text fails here until the page is written again:
  tools/options_page.py --spam-ark build/spam-ark
The page must also list the options users meet first, with the defaults -help gives."""
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
c.finish()
