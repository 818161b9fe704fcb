#!/usr/bin/python3
"""Install like a library of its field: `cmake --install` into a
temporary prefix, then, from other directories and without LD_LIBRARY_PATH:
- the installed spam-ark runs the README's usage line on an installed options file
  (`-options_file options/expansion.opts`, found in PREFIX/share/spam, and saying so),
  while a file of that name in the working directory wins and a missing one is refused;
- it needs no library of this project at run time (libspam is static), and libspam.a
  defines no global symbol outside the Spam prefix;
- a small consumer program (C, -Wall -Wextra -Werror) built against the installed package
  with find_package(spam) and with pkg-config (spam.pc) prints the version and Lucy's
  kernel, checked against the closed forms: w(0) = 5 / (pi h^2) in 2D and
  w(h/2) = w(0) (1 + 3/2) (1/2)^3; both are a few operations, so round-off (1e-14) bounds
  the difference;
- the examples (executable) and the documentation are installed in PREFIX/share/spam, and
  the installed examples/plot_run.py draws the installed binary's run;
- every relative link of every installed page (README.md, CONTRIBUTING.md, docs/**,
  tests/README.md, bench/README.md: Markdown links and images) names a file or directory
  inside PREFIX/share/spam, so that an installed copy has no dead link; a control page with
  a link into the source tree only is caught."""
import glob
import math
import os
import re
import shutil
import subprocess

from spamrun import Checks, arguments

CONSUMER_C = r"""/* A program using the installed libspam: its version and Lucy's kernel in 2D. */
#include <spam/kernel.h>
#include <spam/version.h>
#include <stdio.h>

int main(int argc, char **argv)
{
  SpamKernel k;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(SpamKernelCreate("lucy", 2, 3.0, &k));
  printf("%s %.17g %.17g\n", SPAM_VERSION, SpamKernelW(&k, 0.0), SpamKernelW(&k, 1.5 * 1.5));
  PetscCall(PetscFinalize());
  return 0;
}
"""

CONSUMER_CMAKE = """cmake_minimum_required(VERSION 3.25)
project(spam_consumer LANGUAGES C)
find_package(spam 0.1 REQUIRED)
add_executable(consumer main.c)
target_compile_options(consumer PRIVATE -Wall -Wextra -Werror)
target_link_libraries(consumer PRIVATE spam::spam)
"""

H = 3.0
LINK = re.compile(r"\]\(([^)\s]+)\)")


def sh(cmd, cwd=None, env=None, timeout=600):
    p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def dead_links(share, pages):
    """[(page, target)] of the relative links of pages (paths under share) that name nothing
    inside share: a link that leaves the install, or one to a file not installed."""
    dead = []
    for page in pages:
        with open(page, encoding="utf-8") as f:
            text = f.read()
        for m in LINK.finditer(text):
            target = m.group(1)
            if re.match(r"^(https?:|mailto:|#)", target):
                continue
            path = os.path.normpath(os.path.join(os.path.dirname(page), target.split("#", 1)[0]))
            if os.path.relpath(path, share).startswith("..") or not os.path.exists(path):
                dead.append((os.path.relpath(page, share), target))
    return dead


def check_kernel_line(c, how, code, out, err, version):
    if not c.check(code == 0, f"{how}: the consumer runs (exit {code}) {err.strip()[-300:]}"):
        return
    fields = out.split()
    w0_exact = 5.0 / (math.pi * H * H)
    w_half_exact = w0_exact * 2.5 * 0.125
    c.check(len(fields) == 3 and fields[0] == version, f"{how}: version {fields[:1]} is spam-ark's {version}")
    if len(fields) == 3:
        w0, w_half = float(fields[1]), float(fields[2])
        c.check(abs(w0 - w0_exact) <= 1e-14 * w0_exact, f"{how}: w(0) = {w0:.17g}, 5/(pi h^2) = {w0_exact:.17g}")
        c.check(abs(w_half - w_half_exact) <= 1e-14 * w0_exact, f"{how}: w(h/2) = {w_half:.17g}, closed form {w_half_exact:.17g}")


a = arguments()
c = Checks()
build = os.path.dirname(os.path.abspath(a.spam_ark))
prefix = os.path.join(a.workdir, "prefix")
# The environment of a user who has not pointed the loader anywhere.
env = {k: v for k, v in os.environ.items() if k not in ("LD_LIBRARY_PATH", "PKG_CONFIG_PATH", "CMAKE_PREFIX_PATH")}

code, out, err = sh(["cmake", "--install", build, "--prefix", prefix])
if not c.check(code == 0, f"cmake --install {build} --prefix {prefix} (exit {code}) {err.strip()}"):
    c.finish()
exe = os.path.join(prefix, "bin", "spam-ark")
configs = glob.glob(os.path.join(prefix, "lib*", "**", "spamConfig.cmake"), recursive=True)
pcs = glob.glob(os.path.join(prefix, "lib*", "**", "pkgconfig", "spam.pc"), recursive=True)
for rel in ("bin/spam-ark", "include/spam/kernel.h", "include/spam/version.h",
            "include/spam/internal/kernels/kernel_shape.h", "share/spam/options/expansion.opts"):
    c.check(os.path.isfile(os.path.join(prefix, rel)), f"installed: {rel}")
c.check(len(glob.glob(os.path.join(prefix, "lib*", "**", "libspam.a"), recursive=True)) == 1, "installed: libspam.a")
c.check(len(configs) == 1 and len(pcs) == 1, f"installed: spamConfig.cmake {configs}, spam.pc {pcs}")

# Nothing of this project is loaded at run time, and no path into the build tree is kept.
code, out, err = sh(["readelf", "-d", exe])
needed = [line for line in out.splitlines() if "(NEEDED)" in line]
c.check(code == 0 and needed and not any("spam" in line for line in needed),
        f"installed spam-ark needs no libspam: {len(needed)} NEEDED entries")
c.check(build not in out and a.workdir not in out, "installed spam-ark has no RPATH into the build tree or prefix")

# libspam's namespace: every symbol it defines for other objects is Spam* (the rest is
# static), so linking it cannot clash with a consumer's or a dependency's names.
libs = glob.glob(os.path.join(prefix, "lib*", "**", "libspam.a"), recursive=True)
code, out, err = sh(["nm", "-g", "--defined-only", libs[0]] if libs else ["false"])
symbols = [f[2] for f in (line.split() for line in out.splitlines()) if len(f) == 3]
foreign = sorted({s for s in symbols if not s.startswith("Spam")})
c.check(code == 0 and symbols and not foreign, f"libspam.a defines {len(symbols)} global symbols, none outside Spam*: {foreign[:5]}")

# The README's usage line from an empty directory: the installed options file is read.
elsewhere = os.path.join(a.workdir, "elsewhere")
os.makedirs(elsewhere)
tiny = ["-expansion_n", "32", "-ts_max_time", "1"]
code, out, err = sh([exe, "-options_file", "options/expansion.opts"] + tiny, cwd=elsewhere, env=env)
said = [line.split("reading the installed ", 1)[1] for line in err.splitlines() if "reading the installed " in line]
installed_opts = os.path.join(prefix, "share", "spam", "options", "expansion.opts")
c.check(code == 0, f"installed spam-ark -options_file options/expansion.opts from another directory (exit {code}) {err.strip()[-300:]}")
c.check(len(said) == 1 and os.path.realpath(said[0]) == os.path.realpath(installed_opts),
        f"it says which file it read: {said}")
rows = glob.glob(os.path.join(elsewhere, "out", "expansion", "*.csv"))
c.check(len(rows) > 0, f"the run wrote its outputs to the -output_dir of the options file: {[os.path.basename(r) for r in rows]}")

# The user's side is installed too: the examples (executable, with their shebang's Python)
# and the documentation; the installed generic chart script draws the run just made.
for rel in ("share/spam/README.md", "share/spam/docs/README.md", "share/spam/docs/equations.md",
            "share/spam/examples/spamread.py", "share/spam/examples/particles/two_drops.csv"):
    c.check(os.path.isfile(os.path.join(prefix, rel)), f"installed: {rel}")
plot_run = os.path.join(prefix, "share", "spam", "examples", "plot_run.py")
c.check(os.access(plot_run, os.X_OK), "installed: share/spam/examples/plot_run.py, executable")
c.check(not glob.glob(os.path.join(prefix, "share", "spam", "docs", "gallery", "runs")),
        "the gallery's run directories are not installed")
chart = os.path.join(elsewhere, "run.png")
code, out, err = sh([plot_run, os.path.join(elsewhere, "out", "expansion"), "-o", chart], cwd=elsewhere, env=env)
c.check(code == 0 and os.path.getsize(chart) > 10000 if os.path.exists(chart) else False,
        f"the installed plot_run.py draws the installed binary's run (exit {code}) {err.strip()[-200:]}")

# The installed pages' links: every relative one resolves inside the installed share/spam.
share = os.path.join(prefix, "share", "spam")
pages = sorted(glob.glob(os.path.join(share, "**", "*.md"), recursive=True))
names = {os.path.relpath(p, share) for p in pages}
c.check({"README.md", "CONTRIBUTING.md", "docs/README.md", "tests/README.md", "bench/README.md"} <= names,
        f"installed pages: {len(pages)}, the front page, the docs' map and the tests' and benchmarks' pages among them")
dead = dead_links(share, pages)
nlinks = sum(len(LINK.findall(open(p, encoding="utf-8").read())) for p in pages)
c.check(len(pages) > 20 and not dead, f"every relative link of the {len(pages)} installed pages ({nlinks} links) resolves "
        f"inside the prefix; dead: {dead[:8]}")
# Control: a page linking to what only the source tree holds is caught.
control = os.path.join(a.workdir, "control", "share", "spam")
os.makedirs(os.path.join(control, "docs"))
with open(os.path.join(control, "docs", "page.md"), "w", encoding="utf-8") as f:
    f.write("[kept](page.md) [source](../src/app/main.c) [outside](../../../README.md#x) [web](https://example.org)\n")
dead = dead_links(control, [os.path.join(control, "docs", "page.md")])
c.check([t for _, t in dead] == ["../src/app/main.c", "../../../README.md#x"],
        f"control: links to files not installed are caught: {dead}")

# A file of that name in the working directory wins, silently as before.
local = os.path.join(a.workdir, "local")
os.makedirs(os.path.join(local, "options"))
shutil.copy(os.path.join(prefix, "share", "spam", "options", "expansion.opts"), os.path.join(local, "options"))
code, out, err = sh([exe, "-options_file", "options/expansion.opts"] + tiny, cwd=local, env=env)
c.check(code == 0 and "installed" not in err, f"a local options/expansion.opts is read first (exit {code}) {err.strip()[-200:]}")
# A name found in neither place is bad input, as before.
code, out, err = sh([exe, "-options_file", "options/no_such.opts"], cwd=elsewhere, env=env)
c.check(code == 2 and "no_such.opts" in err, f"a missing options file: exit {code}, {err.strip()}")

version = sh([exe, "-version"], env=env)[1].split()[-1]

# A consumer built with find_package(spam).
src = os.path.join(a.workdir, "consumer")
os.makedirs(src)
with open(os.path.join(src, "main.c"), "w") as f:
    f.write(CONSUMER_C)
with open(os.path.join(src, "CMakeLists.txt"), "w") as f:
    f.write(CONSUMER_CMAKE)
cbuild = os.path.join(a.workdir, "consumer-build")
code, out, err = sh(["cmake", "-S", src, "-B", cbuild, f"-DCMAKE_PREFIX_PATH={prefix}"], env=env)
if c.check(code == 0, f"find_package(spam): configure (exit {code}) {err.strip()[-500:]}"):
    code, out, err = sh(["cmake", "--build", cbuild], env=env)
    if c.check(code == 0, f"find_package(spam): build (exit {code}) {(out + err).strip()[-800:]}"):
        check_kernel_line(c, "find_package(spam)", *sh([os.path.join(cbuild, "consumer")], cwd=elsewhere, env=env), version)

# The same program built with pkg-config alone.
pc_env = dict(env, PKG_CONFIG_PATH=os.path.dirname(pcs[0]) if pcs else "")
code, cflags, err = sh(["pkg-config", "--cflags", "spam"], env=pc_env)
code2, libs, err2 = sh(["pkg-config", "--libs", "spam"], env=pc_env)
if c.check(code == 0 and code2 == 0, f"pkg-config --cflags/--libs spam (exit {code}, {code2}) {err.strip()} {err2.strip()}"):
    pc_exe = os.path.join(a.workdir, "consumer-pc")
    code, out, err = sh(["cc", "-std=c11", "-Wall", "-Wextra", "-Werror"] + cflags.split() +
                        [os.path.join(src, "main.c"), "-o", pc_exe] + libs.split(), env=env)
    if c.check(code == 0, f"pkg-config: build (exit {code}) {err.strip()[-800:]}"):
        check_kernel_line(c, "pkg-config", *sh([pc_exe], cwd=elsewhere, env=env), version)
c.finish()
