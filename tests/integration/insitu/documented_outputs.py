"""Runs a pipeline script in one or more configurations, then checks that the
files it wrote are exactly the ones its docstring's "Writes" section lists, and
that docs/insitu.md's table row for the script names every file outside the
piece folders.

usage: python3 documented_outputs.py SCRIPT DOCS_MD OUTPUT_ROOT -- COMMAND... [--then COMMAND...]...

Each COMMAND (canopy_insitu_run under mpirun / xvfb-run) must write into the
folder given by the token {output}: OUTPUT_ROOT/run_<n>. File names become
patterns: the 6-digit step becomes <step>, the rank of a piece <rank>; the
docstring writes <prefix> for the script's default file_prefix.
"""
import ast
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from output_checks import expect, finish, run_command  # noqa: E402

# Written by the stand-in simulation and by this checker, not by the script.
NOT_THE_SCRIPTS = {"expected.json", "run.log"}


def documented_patterns(script):
    """The docstring's "Writes" section, up to the next blank line: a line
    indented by two spaces starts with a file name pattern (deeper indented
    lines continue a description), <prefix> being the default file_prefix."""
    with open(script) as source:
        text = source.read()
    docstring = ast.get_docstring(ast.parse(text)) or ""
    prefix = re.search(r"file_prefix=\"(\w+)\"", text)
    lines = docstring.splitlines()
    start = next((i for i, line in enumerate(lines) if line.startswith("Writes")), None)
    if start is None:
        return set()
    patterns = set()
    for line in lines[start + 1:]:
        if not line.strip():
            break
        if not re.match(r"  \S", line):
            continue
        word = line.split()[0]
        patterns.add(word.replace("<prefix>", prefix.group(1)) if prefix else word)
    return patterns


def produced_patterns(directory):
    patterns = set()
    for root, _, files in os.walk(directory):
        for name in files:
            relative = os.path.relpath(os.path.join(root, name), directory)
            if relative in NOT_THE_SCRIPTS:
                continue
            pattern = re.sub(r"\d{6}", "<step>", relative)
            pattern = re.sub(r"_<step>_\d+\.", "_<step>_<rank>.", pattern)
            patterns.add(pattern)
    return patterns


def is_piece(pattern):
    return "_<rank>." in pattern


def docs_row(docs, script):
    with open(docs) as source:
        for line in source:
            if line.startswith("| `%s` |" % script):
                return line
    return ""


def main():
    separator = sys.argv.index("--")
    script, docs, root = sys.argv[1:separator]
    commands = [[]]
    for word in sys.argv[separator + 1:]:
        if word == "--then":
            commands.append([])
        else:
            commands[-1].append(word)
    shutil.rmtree(root, ignore_errors=True)
    produced = set()
    for number, command in enumerate(commands):
        output = os.path.join(root, "run_%d" % number)
        os.makedirs(output)
        code, log = run_command([word.replace("{output}", output) for word in command])
        with open(os.path.join(output, "run.log"), "w") as out:
            out.write(log)
        found = produced_patterns(output)
        expect(code == 0 and "failures 0" in log and found,
               "run %d exits normally, without failures, and writes %s" % (number, sorted(found)))
        produced |= found

    name = os.path.basename(script)
    documented = documented_patterns(script)
    expect(documented == produced,
           "%s's docstring lists exactly the files it writes (not written: %s; not listed: %s)"
           % (name, sorted(documented - produced), sorted(produced - documented)))
    row = docs_row(docs, name)
    missing = sorted(p for p in produced if not is_piece(p) and "`%s`" % p not in row)
    expect(row and not missing,
           "docs/insitu.md's table row for %s names every file but the pieces (missing: %s)"
           % (name, missing))
    finish()


if __name__ == "__main__":
    main()
