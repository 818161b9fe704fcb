#!/usr/bin/python3
"""Numbers in the pages come from generated files: fill them in (--update) or check them (--check).

A page quotes a reading through a marker that names where it comes from; what stands
between the marker and its end is what a reader sees, and is rewritten from the source:

    <!--num FILE KEY [FORMAT]-->0.0123<!--/num-->
        a reading of FILE (a JSON a chart script wrote beside its chart, examples/chart_readings.py;
        the path relative to the page). KEY is a dotted path into its "readings" (list
        items by index), or @NAME for a field of the file itself (@load_1min, @describe).
        FORMAT is a Python format spec (.3g, +.2%, .4f, .2e; exponents are written without
        leading zeros: 7.5e-5), or one ending in x (.2x) for "7.5 × 10⁻⁵"; a leading u
        writes a minus as "−". Default: g.
    <!--table FILE KEY-->
    | ... the table ... |
    <!--/table-->
        a whole table: the reading is {"columns": [...], "rows": [[cell, ...], ...]} of
        formatted cells.
    <!--text FILE KEY-->
    ... generated markdown ...
    <!--/text-->
        a generated section (a study's text, examples/study.py): the reading is the text itself.
    <!--test PATH [TOKEN]-->3%<!--/test-->
        a number a test asserts: PATH (from the repository's root) must be a test ctest runs
        (a tests/run_*.py, or named in tests/CMakeLists.txt), and TOKEN, when given, must occur in it (the
        bound as the test writes it, e.g. 0.03).

A number typed in a page's prose (outside markers, code, option values and links: a decimal,
an exponent, a percentage, a ratio "2.4x", "3 x 10^-5", or a count with a unit, "40 steps",
"12 s") is a parameter, an exact or analytic value, or a measurement that escaped its
marker. Those a page may type are listed in tools/docs_typed_numbers.txt, one line per page,
comma-separated: "PAGE: 0.5, 1e-6, 40 steps". A measurement is never listed: a line
"PAGE measured: ..." (the form the list once had for measurements still typed) is refused.
A number a page types that its line does not list is a problem: put it under a marker if
it was measured, or add it to the page's line if it is a parameter. A listed number the
page no longer types is a problem too (the list says only what the pages type).
--unmarked lists every typed number with its line (* not listed); --allow adds the pages'
unlisted typed numbers to their parameters' line (look first: a measurement goes under a
marker instead); --prune drops the listed numbers the pages no longer type.

--check (the default) lists every marker whose text differs from its source, every
source or key that does not exist, every JSON without its command and commit, every
number typed without a marker that tools/docs_typed_numbers.txt does not list, every
"measured" line of that list, and every
figure a page labels as a hand run or as history (made by no script: regenerate it with one,
or leave it to git's history), and exits 1 if there is one; --update rewrites the pages' marked text from the sources. With paths,
only those pages; otherwise README.md, CONTRIBUTING.md, bench/README.md, tests/README.md
and docs/**/*.md.
"""
import argparse
import glob
import json
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
W = r"((?:(?!-->)\S)+)"  # a word of a marker, which ends at -->
NUM = re.compile(rf"<!--num\s+{W}\s+{W}(?:\s+{W})?\s*-->(.*?)<!--/num-->")
TABLE = re.compile(rf"<!--table\s+{W}\s+{W}\s*-->\n(.*?)<!--/table-->", re.S)
TEXT = re.compile(rf"<!--text\s+{W}\s+{W}\s*-->\n(.*?)<!--/text-->", re.S)
TEST = re.compile(rf"<!--test\s+{W}(?:\s+{W})?\s*-->(.*?)<!--/test-->")
SUPER = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


class Missing(Exception):
    pass


def pages(paths):
    if paths:
        return [os.path.relpath(os.path.abspath(p), ROOT) for p in paths]
    out = [p for p in ("README.md", "CONTRIBUTING.md", "bench/README.md", "tests/README.md")
           if os.path.exists(os.path.join(ROOT, p))]
    out += sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "docs", "**", "*.md"), recursive=True))
    return out


_cache = {}


def source(page, name):
    """The JSON document name (relative to page) as a dict; raises Missing."""
    path = os.path.normpath(os.path.join(ROOT, os.path.dirname(page), name))
    if path not in _cache:
        try:
            with open(path, encoding="utf-8") as fh:
                doc = json.load(fh)
        except (OSError, ValueError) as exc:
            raise Missing(f"{name}: {exc}")
        lacks = [k for k in ("command", "commit", "readings") if k not in doc]
        if lacks:
            raise Missing(f"{name}: no {', '.join(lacks)} (not written by examples/chart_readings.py)")
        _cache[path] = doc
    return _cache[path]


def lookup(doc, key):
    if key.startswith("@"):
        if key[1:] not in doc:
            raise Missing(f"no field {key[1:]}")
        return doc[key[1:]]
    v = doc["readings"]
    for part in key.split("."):
        if isinstance(v, list) and re.fullmatch(r"-?\d+", part) and -len(v) <= int(part) < len(v):
            v = v[int(part)]
        elif isinstance(v, dict) and part in v:
            v = v[part]
        else:
            raise Missing(f"no reading {key}")
    return v


def fmt(value, spec):
    """value written as spec says (see the module's text)."""
    spec = spec or "g"
    uminus = spec.startswith("u")
    if uminus:
        spec = spec[1:]
    if isinstance(value, str):
        s = value
    elif spec.endswith("x"):
        m, e = format(float(value), spec[:-1] + "e").split("e")
        s = f"{m} × 10{str(int(e)).translate(SUPER)}"
    else:
        s = format(value, spec)
        s = re.sub(r"e([+-])0*(\d)", lambda m: "e" + ("-" if m.group(1) == "-" else "") + m.group(2), s)
    return s.replace("-", "−") if uminus else s


def render_table(t):
    if not isinstance(t, dict) or "columns" not in t or "rows" not in t:
        raise Missing("not a table reading (columns, rows)")
    lines = ["| " + " | ".join(t["columns"]) + " |", "|" + "---|" * len(t["columns"])]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in t["rows"]]
    return "\n".join(lines) + "\n"


def registered_tests():
    try:
        return open(os.path.join(ROOT, "tests", "CMakeLists.txt"), encoding="utf-8").read()
    except OSError:
        return ""


def process(page, text, problems):
    """text with every marker's text rewritten from its source; problems appended."""
    def num(m):
        name, key, spec, shown = m.groups()
        try:
            want = fmt(lookup(source(page, name), key), spec)
        except (Missing, ValueError, TypeError) as exc:
            problems.append(f"{page}: <!--num {name} {key}-->: {exc}")
            return m.group(0)
        if want != shown:
            problems.append(f"{page}: {name} {key}: the page says {shown!r}, the file {want!r}")
        return m.group(0)[:m.start(4) - m.start(0)] + want + "<!--/num-->"

    def table(m):
        name, key, shown = m.groups()
        try:
            want = render_table(lookup(source(page, name), key))
        except Missing as exc:
            problems.append(f"{page}: <!--table {name} {key}-->: {exc}")
            return m.group(0)
        if want != shown:
            problems.append(f"{page}: table {name} {key} differs from the file")
        return m.group(0)[:m.start(3) - m.start(0)] + want + "<!--/table-->"

    def text_(m):
        name, key, shown = m.groups()
        try:
            want = lookup(source(page, name), key)
        except Missing as exc:
            problems.append(f"{page}: <!--text {name} {key}-->: {exc}")
            return m.group(0)
        if want != shown:
            problems.append(f"{page}: text {name} {key} differs from the file")
        return m.group(0)[:m.start(3) - m.start(0)] + want + "<!--/text-->"

    cmake = registered_tests()

    def test(m):
        path, token, _ = m.groups()
        full = os.path.join(ROOT, path)
        if not os.path.isfile(full):
            problems.append(f"{page}: <!--test {path}-->: no such test")
        elif not (re.fullmatch(r"tests/run_\w+\.py", path)  # ctest runs every tests/run_*.py
                  or re.search(r"\b%s\b" % re.escape(os.path.splitext(os.path.basename(path))[0]), cmake)):
            problems.append(f"{page}: <!--test {path}-->: not a test tests/CMakeLists.txt runs")
        elif token and token not in open(full, encoding="utf-8").read():
            problems.append(f"{page}: <!--test {path} {token}-->: the test does not say {token}")
        return m.group(0)

    text = TEXT.sub(text_, text)
    text = TABLE.sub(table, text)
    text = NUM.sub(num, text)
    return TEST.sub(test, text)


# What a page says of a figure no script makes: a hand run, or history.
UNGENERATED = re.compile(r"\bhand[- ]runs?\b|not regenerated|\(history\b|\bhistory:|kept as history|are history", re.I)


def ungenerated(page, text, problems):
    for n, line in enumerate(text.splitlines(), 1):
        m = UNGENERATED.search(line)
        if m:
            problems.append(f"{page}:{n}: a figure labelled '{m.group(0)}': made by no script")


# What is not prose: fenced code, markers and comments, sections a script wrote between
# <!-- NAME --> and <!-- /NAME --> (examples/study.py, study_shear_mode.py --doc), inline
# code, link targets.
FENCE = re.compile(r"^([ \t]*)(```|~~~).*?^\1\2[^\n]*$", re.S | re.M)
NOT_PROSE = [re.compile(r"<!--(num|table|text|test)\b.*?<!--/\1-->", re.S),
             re.compile(r"<!-- ([\w:.-]+) -->.*?<!-- /\1 -->", re.S),  # a section a script wrote (study.md)
             re.compile(r"<!--.*?-->", re.S),
             re.compile(r"`(?:[^`\n]|\n(?![ \t]*\n))*`"),  # inline code, which may wrap within its paragraph
             re.compile(r"\]\([^)\s]*\)"), re.compile(r"<[a-z]+ [^>\n]*>")]
UNIT = r"(?:s|ms|min|minutes|seconds|h|hours|steps|RHS evaluations|evaluations|rejections|rejected steps|KB|MB|GB|MiB|GiB|bytes)"
TYPED = re.compile(r"(?<![\w.⁻^/-])(\d+\s+%s\b|\d+(?:\.\d+)?\s*×\s*10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+|\d+(?:\.\d+)?e[-+]?\d+"
                   r"|\d+(?:\.\d+)?\s*(?:%%|×(?!\s*\d)|x(?![\w\d]))|\d+\.\d+)" % UNIT)
ALLOWED = os.path.join(ROOT, "tools", "docs_typed_numbers.txt")


def blank(m):
    return re.sub(r"[^\n]", " ", m.group(0))


def typed_numbers(text):
    """[(line, number, the line's text)] of the numbers text types in its prose."""
    prose = FENCE.sub(blank, text)
    for r in NOT_PROSE:
        prose = r.sub(blank, prose)
    out = []
    lines = text.splitlines()
    for n, (line, orig) in enumerate(zip(prose.splitlines(), lines), 1):
        if indented_code(lines, n - 1):
            continue
        for m in TYPED.finditer(line):
            out.append((n, re.sub(r"\s+", " ", m.group(1)), orig.strip()))
    return out


def indented_code(lines, i):
    """Whether lines[i] belongs to an indented code block: indented by 4 or more, after a
    blank line that follows a paragraph, not a list item (whose continuation it would be)."""
    if not re.match(r"^( {4,}|\t)\S", lines[i]):
        return False
    blank = False
    for j in range(i - 1, -1, -1):
        if not lines[j].strip():
            blank = True
        elif not re.match(r"^( {4,}|\t)", lines[j]):
            return blank and not re.match(r"^\s*([-*+]|\d+\.)\s", lines[j])
    return blank


def allowed_numbers(path=ALLOWED):
    """{page: set of numbers it may type}, {page: the measured ones among them} from the list
    (tools/docs_typed_numbers.txt)."""
    out, measured = {}, {}
    try:
        lines = open(path, encoding="utf-8").read().splitlines()
    except OSError:
        return out, measured
    for line in lines:
        if line.strip() and not line.startswith("#"):
            head, _, rest = line.partition(": ")
            page = head.strip()
            nums = {t.strip() for t in rest.split(",") if t.strip()}  # a count keeps its unit: "40 steps"
            if page.endswith(" measured"):
                page = page[:-len(" measured")]
                measured.setdefault(page, set()).update(nums)
            out.setdefault(page, set()).update(nums)
    return out, measured


def unmarked(page, text, allowed, problems):
    found = typed_numbers(text)
    for n, num, _ in found:
        if num not in allowed.get(page, ()):
            problems.append(f"{page}:{n}: {num} typed without a marker (a measurement goes under a marker; "
                            f"a parameter into tools/docs_typed_numbers.txt)")
    for num in sorted(allowed.get(page, set()) - {num for _, num, _ in found}):
        problems.append(f"{page}: {num} listed in tools/docs_typed_numbers.txt but no longer typed "
                        f"(tools/docs_numbers.py --prune {page})")


def _order(t):
    m = re.match(r"[\d.]+(?:e[-+]?\d+)?", t)
    try:
        return (float(m.group(0)), t)
    except (AttributeError, ValueError):
        return (0.0, t)


def write_allowed(allowed, measured, path=ALLOWED):
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("# The numbers each page may type in its prose without a marker (tools/docs_numbers.py --check):\n"
                 "# parameters, exact and analytic values only, 'PAGE: 0.25, 1e-6, 40 steps'. A measurement goes\n"
                 "# under a marker (a 'PAGE measured:' line is refused). Comma-separated.\n")
        for page in sorted(allowed):
            params = allowed[page] - measured.get(page, set())
            if params:
                fh.write(f"{page}: " + ", ".join(sorted(params, key=_order)) + "\n")
            if measured.get(page):
                fh.write(f"{page} measured: " + ", ".join(sorted(measured[page], key=_order)) + "\n")


def count(text):
    return sum(len(r.findall(text)) for r in (NUM, TABLE, TEXT, TEST))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--update", action="store_true", help="rewrite the marked text from the sources")
    ap.add_argument("--check", action="store_true", help="fail when a marked text differs (the default)")
    ap.add_argument("--unmarked", action="store_true",
                    help="list every number typed outside a marker (* before those the list does not allow)")
    ap.add_argument("--allow", action="store_true",
                    help="add the pages' typed numbers to tools/docs_typed_numbers.txt")
    ap.add_argument("--prune", action="store_true",
                    help="drop from tools/docs_typed_numbers.txt the numbers the pages no longer type")
    ap.add_argument("--list", default=ALLOWED, help="the list of the numbers pages may type "
                    "(default tools/docs_typed_numbers.txt; another for the docs check's controls)")
    ap.add_argument("pages", nargs="*")
    a = ap.parse_args()
    problems, markers, changed = [], 0, []
    allowed, measured = allowed_numbers(a.list)
    if a.prune:
        for page in pages(a.pages):
            typed = {num for _, num, _ in typed_numbers(open(os.path.join(ROOT, page), encoding="utf-8").read())}
            for d in (allowed, measured):
                if page in d:
                    d[page] &= typed
        write_allowed(allowed, measured, a.list)
        sys.exit(0)
    if a.unmarked or a.allow:
        total = debt = 0
        for page in pages(a.pages):
            found = typed_numbers(open(os.path.join(ROOT, page), encoding="utf-8").read())
            total += len(found)
            if a.allow:
                allowed.setdefault(page, set()).update(num for _, num, _ in found)
            else:
                for n, num, line in found:
                    tag = "m" if num in measured.get(page, ()) else " " if num in allowed.get(page, ()) else "*"
                    debt += tag == "m"
                    print(f"{tag} {page}:{n}: {num:10s} | {line[:140]}")
        if a.allow:
            write_allowed(allowed, measured, a.list)
        print(f"{total} typed numbers, {debt} of them on a 'measured' line (refused by --check)")
        sys.exit(0)
    for page in sorted(p for p in measured if measured[p]):
        problems.append(f"{os.path.relpath(a.list, ROOT)}: a 'measured' line for {page} "
                        f"({', '.join(sorted(measured[page], key=_order))}): a measurement goes under a "
                        f"marker, or away; the list names parameters only")
    for page in pages(a.pages):
        path = os.path.join(ROOT, page)
        text = open(path, encoding="utf-8").read()
        markers += count(text)
        before = len(problems)
        new = process(page, text, problems)
        ungenerated(page, text, problems)
        if a.update and new != text:
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(new)
            changed.append(page)
            del problems[before:]
            process(page, new, problems)  # what remains: missing sources or keys
            ungenerated(page, new, problems)
        unmarked(page, new if a.update else text, allowed, problems)
    for p in problems:
        print(p)
    if a.update:
        print(f"{markers} markers; rewrote {len(changed)} page(s): {' '.join(changed) or '-'}")
    else:
        print(f"{markers} markers, {len(problems)} problem(s)")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
