#!/usr/bin/env python3
"""Regenerate docs/benchmarks.md's tables from the benchmarks' own output.

Every table in docs/benchmarks.md sits between two markers (HTML comments, not
rendered) that say which command printed it:

    <!-- benchmark table wrap: `build/tests/bench/canopy_bench_wrap --max-levels 8` -->
    | storage | cells | ... |
    |---|---:|...|
    | breadth-first | 115608 | ... |
    <!-- end benchmark table wrap -->

A table the command prints as it stands is replaced by that command's table with
the same header: run the command (--run) or give its saved standard output
(--output FILE). A command that prints several tables fills every marked table
with its command at once. A table kept by hand (columns left out, rows of two
runs, figures from prose) says so and why, and is never replaced:

    <!-- benchmark table slices (by hand: three columns left out): `cd build && ...` -->

Nothing outside the markers of the replaced tables changes, byte for byte.

Usage:
  benchmark_tables.py [--doc FILE] --list
  benchmark_tables.py [--doc FILE] --check
  benchmark_tables.py [--doc FILE] --id ID --output FILE [--write-to FILE]
  benchmark_tables.py [--doc FILE] --id ID --run [--build DIR] [--write-to FILE]

--run executes the marker's command with bash in the source directory; --build DIR
makes the command's `build/` (and `cd build`) mean DIR (e.g. another worktree's
build). --write-to writes the result elsewhere instead of over --doc. The exit
status is 1 when a marker is malformed, when the output has no table with the
marked table's header, or when the table is kept by hand; the document is then
left as it was.
"""
import argparse
import os
import re
import subprocess
import sys

BEGIN = re.compile(r"^<!-- benchmark table ([\w.-]+)(?: \(by hand: (.*?)\))?: `([^`]+)` -->$")
END = re.compile(r"^<!-- end benchmark table ([\w.-]+) -->$")
ROW = re.compile(r"^\|.*\|\s*$")
SEPARATOR = re.compile(r"^\|(\s*:?-+:?\s*\|)+\s*$")


class Problem(Exception):
    pass


class Marker:
    def __init__(self, name, hand, command, begin, end):
        self.name = name          # the table's id
        self.hand = hand          # why it is kept by hand, or None
        self.command = command    # the command whose output it is (or was made from)
        self.begin = begin        # index of the begin marker's line
        self.end = end            # index of the end marker's line


def cells(row):
    """The cells of a markdown table row, stripped."""
    return [cell.strip() for cell in row.strip().strip("|").split("|")]


def markers(lines):
    """Every marked table of the document, in order; Problem on a malformed one."""
    found = []
    open_marker = None
    names = set()
    for index, line in enumerate(lines):
        text = line.rstrip("\n")
        if text.startswith("<!-- benchmark table ") or text.startswith("<!-- end benchmark table"):
            begin, end = BEGIN.match(text), END.match(text)
            if begin:
                if open_marker:
                    raise Problem("line %d: table %s opens inside table %s"
                                  % (index + 1, begin.group(1), open_marker.name))
                if begin.group(1) in names:
                    raise Problem("line %d: table %s is marked twice" % (index + 1, begin.group(1)))
                names.add(begin.group(1))
                open_marker = Marker(begin.group(1), begin.group(2), begin.group(3), index, None)
            elif end:
                if not open_marker or end.group(1) != open_marker.name:
                    raise Problem("line %d: end of table %s without its beginning"
                                  % (index + 1, end.group(1)))
                open_marker.end = index
                found.append(open_marker)
                open_marker = None
            else:
                raise Problem("line %d: malformed marker: %s" % (index + 1, text))
    if open_marker:
        raise Problem("table %s (line %d) has no end marker" % (open_marker.name, open_marker.begin + 1))
    for marker in found:
        body = lines[marker.begin + 1:marker.end]
        if len(body) < 2 or not all(ROW.match(line) for line in body) or not SEPARATOR.match(body[1]):
            raise Problem("table %s (line %d): the lines between its markers are not one markdown "
                          "table (header, separator, rows, nothing else)" % (marker.name, marker.begin + 1))
        width = len(cells(body[0]))
        for offset, line in enumerate(body):
            if len(cells(line)) != width:
                raise Problem("table %s: line %d has %d cells, its header %d"
                              % (marker.name, marker.begin + 2 + offset, len(cells(line)), width))
    return found


def output_tables(text):
    """The markdown tables a benchmark printed: (header, separator, rows) in order. A
    table runs from a header row followed by a separator to the next table's header;
    lines between its rows that are not rows (each input's fingerprint) are skipped."""
    lines = text.splitlines()
    starts = [i for i in range(len(lines) - 1)
              if ROW.match(lines[i]) and not SEPARATOR.match(lines[i]) and SEPARATOR.match(lines[i + 1])]
    tables = []
    for k, start in enumerate(starts):
        stop = starts[k + 1] if k + 1 < len(starts) else len(lines)
        rows = [line.rstrip() for line in lines[start + 2:stop] if ROW.match(line)]
        tables.append((lines[start].rstrip(), lines[start + 1].rstrip(), rows))
    return tables


def splice(lines, marker, tables):
    """The document's lines with the marked table replaced by the printed table that
    has its header."""
    header = cells(lines[marker.begin + 1])
    chosen = [t for t in tables if cells(t[0]) == header]
    if not chosen:
        printed = "\n".join("  " + t[0] for t in tables) or "  (none)"
        raise Problem("table %s: the output has no table with its header\n  %s\nTables printed:\n%s"
                      % (marker.name, lines[marker.begin + 1].rstrip(), printed))
    if len(chosen) > 1:
        raise Problem("table %s: the output has %d tables with its header" % (marker.name, len(chosen)))
    head, separator, rows = chosen[0]
    if not rows:
        raise Problem("table %s: the output's table has no rows" % marker.name)
    ending = "\n"
    replacement = [head + ending, separator + ending] + [row + ending for row in rows]
    return lines[:marker.begin + 1] + replacement + lines[marker.end:]


def with_build(command, build):
    """The command with its build directory `build/` (and `cd build`) made `build`."""
    build = os.path.abspath(build)
    command = re.sub(r"(?<![\w./-])build/", build + "/", command)
    return re.sub(r"(?<![\w./-])cd build(?=\s|$|;|&)", "cd " + build, command)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    source = os.path.dirname(here)
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--doc", default=os.path.join(source, "docs", "benchmarks.md"))
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--list", action="store_true", help="list the marked tables")
    action.add_argument("--check", action="store_true", help="check every marker and table")
    action.add_argument("--output", help="a saved standard output of the marker's command")
    action.add_argument("--run", action="store_true", help="run the marker's command")
    parser.add_argument("--id", help="the table whose command's output replaces its tables")
    parser.add_argument("--build", help="the build directory the command's build/ means")
    parser.add_argument("--write-to", help="write the document here instead of over --doc")
    args = parser.parse_args()

    with open(args.doc, encoding="utf-8", newline="") as f:
        lines = f.read().splitlines(keepends=True)
    try:
        found = markers(lines)
        if args.list or args.check:
            for marker in found:
                if args.list:
                    print("%-28s %-11s %s" % (marker.name, "by hand" if marker.hand else "regenerated",
                                              marker.command))
                    if marker.hand:
                        print("%-28s   (%s)" % ("", marker.hand))
            if args.check:
                print("%s: %d marked tables (%d regenerated from their command's output, %d by hand)"
                      % (args.doc, len(found), sum(1 for m in found if not m.hand),
                         sum(1 for m in found if m.hand)))
            return 0
        if not args.id:
            raise Problem("--output and --run need --id")
        target = [m for m in found if m.name == args.id]
        if not target:
            raise Problem("no table %s in %s" % (args.id, args.doc))
        if target[0].hand:
            raise Problem("table %s is kept by hand (%s): regenerate it from the output of `%s` "
                          "by hand" % (args.id, target[0].hand, target[0].command))
        command = target[0].command
        if args.output:
            with open(args.output, encoding="utf-8", errors="replace") as f:
                text = f.read()
        else:
            run = with_build(command, args.build) if args.build else command
            print("running: " + run, file=sys.stderr)
            done = subprocess.run(["bash", "-c", run], cwd=source, stdout=subprocess.PIPE,
                                  universal_newlines=True)
            if done.returncode != 0:
                raise Problem("the command failed (exit status %d): %s" % (done.returncode, run))
            text = done.stdout
        tables = output_tables(text)
        replaced = []
        # Every regenerated table with the same command, from the last (indices stay valid).
        for marker in reversed([m for m in found if m.command == command and not m.hand]):
            lines = splice(lines, marker, tables)
            replaced.append(marker.name)
        markers(lines)  # the result is still well-formed
    except Problem as problem:
        print("benchmark_tables.py: %s" % problem, file=sys.stderr)
        return 1
    with open(args.write_to or args.doc, "w", encoding="utf-8", newline="") as f:
        f.write("".join(lines))
    print("replaced table(s) %s in %s" % (", ".join(reversed(replaced)), args.write_to or args.doc))
    return 0


if __name__ == "__main__":
    sys.exit(main())
