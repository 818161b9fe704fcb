#!/usr/bin/python3
"""The pages say what is true of the repository and the program: README.md, CONTRIBUTING.md,
tests/README.md, bench/README.md and every page under docs/.

Commands. Every command a page shows in a shell block (a fenced block marked sh, bash or
shell, or an indented block whose lines start with a command of this project) is split into
its simple commands (&&, ;, |) and checked:
- a script it runs (examples/, bench/, tests/, tools/) exists, is executable and, for Python,
  starts with #!/usr/bin/python3; it is run as itself, not through python3 (one interpreter
  convention: the shebang's);
- a spam-ark command (./build/spam-ark, build/spam-ark, spam-ark, also under mpiexec) gives
  only options that `spam-ark -help` lists or that PETSc reads and spam-ark passes on, and
  the options files and particle files it names exist (or an earlier command of the page
  makes them);
- no command writes into a file or directory git tracks (-o, --out, --chart, --doc,
  -output_dir, -final_csv, --readings), unless its line says it regenerates it;
- the cheap ones run: every spam-ark command of README.md and of the docs/*.md pages (not
  the scene and study pages, whose runs are their tests') is run for zero steps in a
  scratch directory (the files an example script of the page makes are made there first),
  on one rank, and must exit 0: the program itself then checks every option, its value and
  that the run uses it.
Links and paths. Every relative link of a page exists; every repository path a page names in
backticks (src/..., tests/..., examples/..., ...) exists, unless it is a pattern (NAME, *).
History. No page carries a commit hash, an issue number or a CI timing.
Numbers. Every number a page quotes through a marker (<!--num FILE KEY-->, <!--table ...-->,
<!--test ...-->) equals its source, a JSON a chart script wrote beside its chart with the
command and commit that made it (tools/docs_numbers.py --check); a page edited by hand
beside its marker is caught (control); a number typed in a page's prose without a marker
must be a parameter tools/docs_typed_numbers.txt lists for that page, and a new one is caught
(control); the list names no measurement (a 'PAGE measured:' line is refused: control).
README.md is at most 15 KB and starts with exactly two commands, the second being the one
.ci/run runs.
Control: a page with a bad option, a script missing, a script run through python3, a
command that overwrites a tracked chart, a dead link and a commit hash is checked too, and
each must be caught."""
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys

from spamrun import Checks, arguments

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
PAGES = ["README.md", "CONTRIBUTING.md", "tests/README.md", "bench/README.md"] + \
    sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "docs", "**", "*.md"), recursive=True))
# Pages whose spam-ark commands are run for zero steps (quick: small scenes, set-up only).
RUN_PAGES = re.compile(r"^(README\.md|docs/[^/]+\.md)$")
SPAM = {"./build/spam-ark", "build/spam-ark", "spam-ark"}
COMMAND_START = re.compile(r"^\s*(\./build/|build/|spam-ark|examples/|bench/|tests/|tools/|mpiexec|ctest|cmake|"
                           r"python3|/usr/bin/python3|xvfb-run|h5dump)")
# PETSc's own options, which spam-ark passes on (docs/running.md).
PETSC_PASS = re.compile(r"^-(log_\w*|info|malloc\w*|memory_view|objects_dump|checkstack|options_\w*|on_error_\w*|fp_trap|"
                        r"no_signal_handler|\w*debugger\w*|mpi\w*|viewer_\w*|history|skip_petscrc|ts_monitor|ts_view|ts_adapt_\w+|ts_rk_type|ts_ssp_type|ts_basicsymplectic_type|help|version)$")
WRITES = {"-o", "--out", "--chart", "--doc", "-output_dir", "-final_csv", "-initial_csv", "--workdir", "--readings"}
HASH = re.compile(r"(?<![\w/.-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w/.-])")
ISSUE = re.compile(r"\bissues?\s+#?\d+|(?<![\w&])#\d{1,4}\b", re.I)
CI_TIMING = re.compile(r"\bCI\b[^.\n]{0,80}\b\d+(\.\d+)?\s*(s|min|minutes|seconds)\b")
REPO_PATH = re.compile(r"`((?:src|include|tests|examples|bench|tools|options|docs|cmake)/[^`\s]*)`")
LINK = re.compile(r"\]\(([^)\s]+)\)")


def tracked_paths():
    out = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True).stdout.split()
    dirs = {os.path.dirname(p) for p in out}
    for p in list(dirs):
        while p:
            p = os.path.dirname(p)
            dirs.add(p)
    return set(out), dirs - {""}


def help_options(binary):
    p = subprocess.run([binary, "-help"], capture_output=True, text=True, timeout=120)
    return set(re.findall(r"^\s*(-[A-Za-z][\w]*)\b", p.stdout, re.M))


def shell_blocks(text):
    """[(first line number, [lines])] of the page's shell blocks, continuation lines joined."""
    blocks, lines = [], text.split("\n")
    i = 0
    while i < len(lines):
        m = re.match(r"^\s*```(\w*)", lines[i])
        if m:
            lang, start, body = m.group(1), i + 1, []
            i += 1
            while i < len(lines) and not lines[i].strip().startswith("```"):
                body.append(lines[i])
                i += 1
            if lang in ("sh", "bash", "shell", "console"):
                blocks.append((start + 1, body))
        elif lines[i].startswith("    ") and COMMAND_START.match(lines[i][4:]) and (i == 0 or not lines[i - 1].strip()):
            start, body = i, []
            while i < len(lines) and lines[i].startswith("    "):
                body.append(lines[i][4:])
                i += 1
            blocks.append((start + 1, body))
            continue
        i += 1
    out = []
    for start, body in blocks:
        joined, cur = [], ""
        for line in body:
            cur += line.rstrip()
            if cur.endswith("\\"):
                cur = cur[:-1] + " "
                continue
            joined.append(cur)
            cur = ""
        if cur:
            joined.append(cur)
        out.append((start, [l for l in joined if l.strip() and not l.lstrip().startswith("#")]))
    return out


def simple_commands(line):
    """The simple commands of one shell line as argv lists (comments dropped)."""
    try:
        words = shlex.split(line, comments=True)
    except ValueError:
        return []
    cmds, cur = [], []
    for w in words:
        if w in ("&&", "||", ";", "|"):
            cmds.append(cur)
            cur = []
        else:
            cur.append(w)
    cmds.append(cur)
    return [c for c in cmds if c]


def placeholder(word):
    """A word standing for the reader's value (DIR, OUT.png, NAME, [--field rho], ...)."""
    return bool(re.search(r"[A-Z]{2,}|[\[\]<>…*]|\.\.\.", word))


def spam_argv(argv):
    """The spam-ark argv inside argv (after mpiexec and its options), or None."""
    if argv[0] in ("mpiexec", "mpirun"):
        k = 1
        while k < len(argv) and argv[k] not in SPAM:
            k += 1
        return argv[k:] if k < len(argv) else None
    return argv if argv[0] in SPAM else None


def check_command(argv, line, made, known, tracked, tracked_dirs):
    """Problems of one simple command (a list of strings)."""
    bad = []
    if argv[0] in ("python3", "/usr/bin/python3", "python") and len(argv) > 1 and argv[1].endswith(".py"):
        bad.append(f"'{argv[0]} {argv[1]}': run the script as itself ({argv[1]}, #!/usr/bin/python3)")
        argv = argv[1:]
    prog = argv[0]
    if re.match(r"^(examples|bench|tests|tools)/", prog) and not placeholder(prog):
        path = os.path.join(ROOT, prog)
        if not os.path.isfile(path):
            bad.append(f"{prog}: no such script")
        else:
            if not os.access(path, os.X_OK):
                bad.append(f"{prog}: not executable")
            if prog.endswith(".py") and open(path, encoding="utf-8").readline().strip() != "#!/usr/bin/python3":
                bad.append(f"{prog}: does not start with #!/usr/bin/python3")
    sa = spam_argv(argv)
    if sa is not None:
        for k, w in enumerate(sa[1:], 1):
            if re.match(r"^--?[A-Za-z]", w) and not placeholder(w):
                name = w.split("=", 1)[0]
                if name.startswith("--") and name not in ("--help", "--version"):
                    bad.append(f"{w}: spam-ark options take one dash")
                elif name not in known and not PETSC_PASS.match(name):
                    bad.append(f"{w}: not an option spam-ark -help lists")
            if k > 1 and sa[k - 1] in ("-options_file", "-file_path") and not placeholder(w):
                if not os.path.exists(os.path.join(ROOT, w)) and w not in made:
                    bad.append(f"{sa[k - 1]} {w}: no such file (and no earlier command of the page makes it)")
    regenerates = "regenerate" in line
    for k, w in enumerate(argv[:-1]):
        if w in WRITES:
            target = os.path.normpath(argv[k + 1])
            made.add(argv[k + 1])
            if (target in tracked or target in tracked_dirs) and not regenerates:
                bad.append(f"{w} {argv[k + 1]}: writes into a tracked {'file' if target in tracked else 'directory'} "
                           "(write into an output directory, or say on the line that it regenerates it)")
    return bad


def page_problems(page, text, known, tracked, tracked_dirs):
    """(problems, [(line, argv, made)] of the spam-ark commands to run) of one page."""
    problems, runnable = [], []
    here = os.path.dirname(os.path.join(ROOT, page))
    made, before = set(), []  # files the page's commands make, and its commands so far
    for start, lines in shell_blocks(text):
        for line in lines:
            for argv in simple_commands(line):
                for p in check_command(argv, line, made, known, tracked, tracked_dirs):
                    problems.append(f"{page}: block at line {start}: {p}")
                sa = spam_argv(argv)
                if sa is not None:
                    runnable.append((start, sa, set(made), list(before)))
            before.append(line)
    for m in LINK.finditer(text):
        target = m.group(1)
        if re.match(r"^(https?:|mailto:|#)", target):
            continue
        path = os.path.normpath(os.path.join(here, target.split("#", 1)[0]))
        if not os.path.exists(path):
            problems.append(f"{page}: link to {target}: no such file")
    for m in REPO_PATH.finditer(text):
        p = m.group(1).rstrip(".,;:)")
        # Patterns, and what runs write (git-ignored output directories).
        if placeholder(p) or re.search(r"NAME|LAW|_NNNNN|<|\{", p) or p.startswith("bench/results/"):
            continue
        if not glob.glob(os.path.join(ROOT, p)):
            problems.append(f"{page}: names {p}: no such file or directory")
    for k, line in enumerate(text.split("\n"), 1):
        for pat, what in ((HASH, "a commit hash"), (ISSUE, "an issue number"), (CI_TIMING, "a CI timing")):
            m = pat.search(line)
            if m:
                problems.append(f"{page}:{k}: {what}: {m.group(0)!r}")
    return problems, runnable


def run_zero_steps(binary, scratch, sa, earlier):
    """Runs a spam-ark command of a page for zero steps in scratch (which links the
    repository's directories), after the example scripts before it that make files."""
    for line in earlier:
        for argv in simple_commands(line):
            if re.match(r"^examples/make_\w+\.py$", argv[0]) and "-o" in argv:
                subprocess.run([os.path.join(ROOT, argv[0])] + argv[1:], cwd=scratch, capture_output=True, timeout=120)
    args = list(sa[1:])
    if "-restart" in args:
        return None  # continues a run the block made; docs/checkpoints.md's test is run_restart
    if "-help" in args or "-version" in args or "--version" in args:
        pass
    else:
        if "-ts_max_steps" in args:
            k = args.index("-ts_max_steps")
            del args[k:k + 2]
        args += ["-ts_max_steps", "0"]
        if "-output_overwrite" not in args:
            args.append("-output_overwrite")
    p = subprocess.run([binary] + args, cwd=scratch, capture_output=True, text=True, timeout=300)
    return p


def numbers_control(c, workdir):
    """A page whose marked number was edited by hand, or whose source lacks the reading, is
    caught by tools/docs_numbers.py --check; --update puts the number back."""
    d = os.path.join(workdir, "numbers")
    os.makedirs(d)
    with open(os.path.join(d, "chart.json"), "w") as f:
        f.write('{"command": "x", "commit": "y", "readings": {"l2": 0.012345, "rows": [1, 2]}}')
    page = os.path.join(d, "page.md")
    with open(page, "w") as f:
        f.write("L2 <!--num chart.json l2 .3g-->0.0124<!--/num--> and <!--num chart.json rows.5-->3<!--/num-->\n")
    tool = [sys.executable, os.path.join(ROOT, "tools", "docs_numbers.py")]
    p = subprocess.run(tool + ["--check", page], capture_output=True, text=True)
    c.check(p.returncode == 1 and "'0.0124'" in p.stdout and "no reading rows.5" in p.stdout,
            f"control: a hand-edited number and a missing reading are caught ({p.stdout.strip()[-200:]})")
    subprocess.run(tool + ["--update", page], capture_output=True, text=True)
    c.check("-->0.0123<!--" in open(page).read(), "control: --update writes the file's reading into the page")
    typed = os.path.join(d, "typed.md")
    with open(typed, "w") as f:
        f.write("At rtol `1e-6` the error is 3.2e-5 in 40 steps.\n\n```sh\nspam-ark -ts_rtol 1e-6\n```\n")
    p = subprocess.run(tool + ["--check", typed], capture_output=True, text=True)
    c.check(p.returncode == 1 and "typed.md:1: 3.2e-5 typed without a marker" in p.stdout
            and "40 steps typed" in p.stdout and "1e-6 typed" not in p.stdout,
            f"control: a number typed in prose without a marker is caught, not one in code ({p.stdout.strip()[-300:]})")
    listed = os.path.join(d, "typed_numbers.txt")
    with open(listed, "w") as f:
        f.write(f"{os.path.relpath(typed, ROOT)}: 40 steps\n{os.path.relpath(typed, ROOT)} measured: 3.2e-5\n")
    p = subprocess.run(tool + ["--check", "--list", listed, typed], capture_output=True, text=True)
    c.check(p.returncode == 1 and "a 'measured' line for" in p.stdout and "typed without a marker" not in p.stdout,
            f"control: a measurement on the list ('PAGE measured:') is refused ({p.stdout.strip()[-300:]})")


def main():
    a = arguments()
    c = Checks()
    binary = os.path.abspath(a.spam_ark)
    known = help_options(binary)
    c.check(len(known) > 100 and "-scene" in known and "-ts_rtol" in known, f"spam-ark -help lists {len(known)} options")
    tracked, tracked_dirs = tracked_paths()
    c.check(len(tracked) > 100, f"git lists {len(tracked)} tracked files")

    # README: size, and its first block is the two commands, the second the one CI runs.
    readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    c.check(len(readme.encode()) <= 15 * 1024, f"README.md is {len(readme.encode())} bytes (at most 15 KB)")
    first = re.match(r"^# [^\n]*\n+```sh\n(.*?)\n```", readme, re.S)
    cmds = first.group(1).split("\n") if first else []
    ci = open(os.path.join(ROOT, ".ci", "run"), encoding="utf-8").read()
    c.check(len(cmds) == 2 and cmds[0].startswith("tools/deps.sh &&") and "./build/spam-ark" in cmds[0],
            f"README.md starts with two commands, the first installing, building and running the main job: {cmds[:1]}")
    c.check(len(cmds) == 2 and cmds[1] in ci, f"the second is the command .ci/run runs: {cmds[1:]}")

    scratch = os.path.join(a.workdir, "scratch")
    os.makedirs(scratch)
    for d in ("build", "options", "examples", "tools", "bench", "tests", "docs"):
        os.symlink(os.path.join(ROOT, d) if d != "build" else os.path.dirname(binary), os.path.join(scratch, d))
    ran = failed = 0
    for page in PAGES:
        text = open(os.path.join(ROOT, page), encoding="utf-8").read()
        problems, runnable = page_problems(page, text, known, tracked, tracked_dirs)
        c.check(not problems, f"{page}: commands, links, paths and history" +
                ("" if not problems else ":\n      " + "\n      ".join(problems)))
        if not RUN_PAGES.match(page):
            continue
        for start, sa, made, earlier in runnable:
            p = run_zero_steps(binary, scratch, sa, earlier)
            if p is None:
                continue
            ran += 1
            if p.returncode != 0:
                failed += 1
                c.check(False, f"{page}: block at line {start}: {' '.join(sa)} (zero steps) exits {p.returncode}: "
                        f"{p.stderr.strip()[-300:]}")
    c.check(ran >= 10 and failed == 0, f"{ran} spam-ark commands of README.md and docs/*.md ran for zero steps, {failed} failed")

    # Numbers: the marked numbers equal their generated sources.
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "docs_numbers.py"), "--check"],
                       capture_output=True, text=True, timeout=120)
    c.check(p.returncode == 0, "tools/docs_numbers.py --check: " + p.stdout.strip().replace("\n", "\n      "))
    numbers_control(c, a.workdir)

    # Control: each kind of fault in a page is caught.
    fake = ("# x\n\n```sh\n./build/spam-ark -options_file options/expansion.opts -ts_rtoll 1e-6\n"
            "examples/no_such_plot.py out/x\n/usr/bin/python3 examples/plot_run.py out/x\n"
            "examples/plot_gresho.py out/gresho -o docs/scenes/gresho.png\n"
            "./build/spam-ark -options_file options/no_such.opts\n```\n\n[dead](docs/no_such_page.md)\n"
            "Made at 1d6cf8f for issue 16.\n")
    problems, _ = page_problems("README.md", fake, known, tracked, tracked_dirs)
    for what in ("-ts_rtoll", "no_such_plot.py: no such script", "run the script as itself",
                 "writes into a tracked file", "options/no_such.opts: no such file", "link to docs/no_such_page.md",
                 "a commit hash", "an issue number"):
        c.check(any(what in p for p in problems), f"control: a page with a fault is caught ({what})")
    p = run_zero_steps(binary, scratch, ["./build/spam-ark", "-options_file", "options/expansion.opts",
                                         "-viscosity_shear", "1"], [])
    c.check(p.returncode == 2, f"control: a zero-step run of an option the run does not use exits 2 ({p.returncode})")
    shutil.rmtree(scratch, ignore_errors=True)
    c.finish()


if __name__ == "__main__":
    main()
