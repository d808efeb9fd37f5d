"""scripts/benchmark_tables.py replaces exactly the marked tables a benchmark's output
fills and nothing else, on a fixture page and a saved output (no benchmark runs):

- the two tables of the fixture's command get the output's rows (chosen by header, the
  output's fingerprint and prose lines skipped), every other byte of the page is kept
  (the lines outside those tables' markers, the page's missing last newline), and a
  second splice of the same output changes nothing;
- a table kept by hand, a table of another command and a malformed page are refused with
  status 1, and a refused page is left as it was;
- docs/benchmarks.md itself: every marker is well formed, and splicing each regenerated
  table's own rows back in (as a benchmark would print them, with a fingerprint line)
  gives the page back byte for byte.

Usage: benchmark_tables_test.py <source dir>
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

root = os.path.abspath(sys.argv[1])
script = os.path.join(root, "scripts", "benchmark_tables.py")
fixtures = os.path.join(root, "tests", "docs", "fixtures")
page = os.path.join(fixtures, "benchmark_tables_doc.md")
output = os.path.join(fixtures, "benchmark_tables_output.txt")
problems = []


def run(*args):
    done = subprocess.run([sys.executable, script] + list(args), stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, universal_newlines=True)
    return done.returncode, done.stdout + done.stderr


def read(path):
    with open(path, "rb") as f:
        return f.read()


def check(condition, what):
    if not condition:
        problems.append(what)


def outside(text, names):
    """The page without the bodies of the named tables (markers kept)."""
    lines, kept, skipping = text.split(b"\n"), [], False
    for line in lines:
        if any(line.startswith(b"<!-- end benchmark table " + n.encode() + b" ") for n in names):
            skipping = False
        if not skipping:
            kept.append(line)
        if any(line.startswith(b"<!-- benchmark table " + n.encode() + b":") for n in names):
            skipping = True
    return b"\n".join(kept)


work = tempfile.mkdtemp(prefix="benchmark_tables_test.")
try:
    # 1. The fixture's two tables of fake_bench, from its saved output.
    result = os.path.join(work, "result.md")
    status, said = run("--doc", page, "--id", "first", "--output", output, "--write-to", result)
    check(status == 0, "splicing the fixture failed: " + said)
    before = read(page)
    after = read(result) if status == 0 else b""
    check(outside(before, ["first", "second"]) == outside(after, ["first", "second"]),
          "bytes outside the replaced tables changed")
    check(not after.endswith(b"\n"), "the page's missing last newline was added")
    first = b"\n".join([b"| size | time s | speedup |", b"|---:|---:|---:|",
                        b"| 10 | 0.40 | 2.5x |", b"| 20 | 0.80 | 2.6x |", b"| 40 | 1.70 | 2.7x |"])
    second = b"\n".join([b"| size | bytes/cell |", b"|---:|---:|", b"| 10 | 3.5 |", b"| 20 | 3.4 |"])
    check(b"`build/tests/bench/fake_bench --size 3` -->\n" + first + b"\n<!-- end benchmark table first -->"
          in after, "table first is not the output's first table")
    check(b"`build/tests/bench/fake_bench --size 3` -->\n" + second + b"\n<!-- end benchmark table second -->"
          in after, "table second is not the output's second table")
    check(b"| 10 | 0.50 | 0.55 |" in after and b"| a | 1.0 |" in after,
          "the table kept by hand or the other command's table changed")
    check(b"fingerprint" not in after and b"not a row" not in after,
          "a line of the output that is not a table row reached the page")
    if after:
        again = os.path.join(work, "again.md")
        status, said = run("--doc", result, "--id", "second", "--output", output, "--write-to", again)
        check(status == 0 and read(again) == after,
              "a second splice of the same output changed the page: " + said)

    # 2. Refusals leave the page as it was (written over in place if not refused).
    copy = os.path.join(work, "copy.md")
    shutil.copyfile(page, copy)
    for args, why in ((["--id", "other", "--output", output], "no table with its header"),
                      (["--id", "by-hand", "--output", output], "a table kept by hand"),
                      (["--id", "missing", "--output", output], "an unknown table")):
        status, said = run("--doc", copy, *args)
        check(status == 1, "%s was not refused (status %d): %s" % (why, status, said))
        check(read(copy) == before, "a refused splice (%s) changed the page" % why)
    broken = os.path.join(work, "broken.md")
    with open(broken, "wb") as f:
        f.write(before.replace(b"<!-- end benchmark table second -->\n", b""))
    status, said = run("--doc", broken, "--check")
    check(status == 1 and "opens inside table second" in said,
          "a table without its end marker passed --check: " + said)
    with open(broken, "wb") as f:
        f.write(before.replace(b"| 20 | 0.90 | 2.2x |", b"| 20 | 0.90 |"))
    status, said = run("--doc", broken, "--check")
    check(status == 1 and "cells" in said, "a row with a missing cell passed --check: " + said)

    # 3. docs/benchmarks.md: markers well formed; each command's regenerated tables,
    # printed back as a benchmark prints them, give the page back byte for byte.
    doc = os.path.join(root, "docs", "benchmarks.md")
    status, said = run("--doc", doc, "--check")
    check(status == 0, "docs/benchmarks.md's markers: " + said)
    text = read(doc).decode("utf-8")
    commands = {}
    for match in re.finditer(r"^<!-- benchmark table ([\w.-]+): `([^`]+)` -->\n(.*?)"
                             r"^<!-- end benchmark table \1 -->$", text, re.M | re.S):
        commands.setdefault(match.group(2), []).append((match.group(1), match.group(3)))
    names = [name for tables in commands.values() for name, _ in tables]
    check(len(names) >= 5, "docs/benchmarks.md has %d regenerated tables" % len(names))
    for command, tables in commands.items():
        printed = os.path.join(work, tables[0][0] + ".txt")
        with open(printed, "w", encoding="utf-8") as f:
            for name, body in tables:
                rows = body.splitlines()
                f.write("\n## a heading\n\n" + "\n".join(rows[:2] + ["input a forest: fingerprint 0"]
                                                        + rows[2:]) + "\n")
        same = os.path.join(work, tables[0][0] + ".md")
        status, said = run("--doc", doc, "--id", tables[0][0], "--output", printed, "--write-to", same)
        check(status == 0 and read(same) == read(doc),
              "docs/benchmarks.md's tables %s do not round-trip: %s"
              % (", ".join(name for name, _ in tables), said))
finally:
    shutil.rmtree(work)

if problems:
    print("scripts/benchmark_tables.py:")
    for problem in problems:
        print("  " + problem)
    sys.exit(1)
print("scripts/benchmark_tables.py splices the fixture's tables and nothing else, refuses what "
      "it must, and docs/benchmarks.md's %d regenerated tables round-trip" % len(names))
