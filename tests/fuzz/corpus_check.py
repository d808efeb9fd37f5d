"""What both corpus scripts (make_corpus.py, make_filter_corpus.py) do with their
seeds: write them, and check that the committed corpus is exactly what the
script writes and that the fuzzer runs every file as its name says.

A script gives its seeds (name -> bytes), the line prefix its fuzzer prints for
a described input (CANOPY_FUZZ_DESCRIBE=1), and a judge of that line.
"""
import os
import subprocess
import sys


def check(fuzzer, directory, seeds, script, prefix, judge, all_ok):
    """Checks `directory` against `seeds` and runs each of its files through
    `fuzzer`. judge(name, last described line or None) returns None when the
    file's run is right, else what is wrong. Returns the exit code."""
    failures = []
    for name, data in seeds.items():
        path = os.path.join(directory, name)
        if not os.path.exists(path) or open(path, "rb").read() != data:
            failures.append("%s differs from what %s writes (rerun it)" % (name, script))
    for name in sorted(os.listdir(directory)):
        env = dict(os.environ, CANOPY_FUZZ_DESCRIBE="1")
        result = subprocess.run([fuzzer, os.path.join(directory, name)], env=env, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        lines = [l for l in result.stdout.splitlines() if l.startswith(prefix)]
        line = lines[-1] if lines else None
        problem = "exit code %d" % result.returncode if result.returncode != 0 else None
        problem = problem or judge(name, line)
        print(("ok:     " if problem is None else "FAILED: ") + "%s: %s" % (
            name, line if line else result.stdout[-2000:]))
        if problem is not None:
            failures.append("%s: %s" % (name, problem))
    print("\n".join(failures) if failures else all_ok)
    return 1 if failures else 0


def main(usage, write, check_directory):
    """`script <corpus dir>` writes the seeds; `script --check <fuzzer> <corpus dir>`
    checks them (check_directory(fuzzer, directory) -> exit code)."""
    if len(sys.argv) == 4 and sys.argv[1] == "--check":
        sys.exit(check_directory(sys.argv[2], sys.argv[3]))
    if len(sys.argv) != 2:
        sys.exit(usage)
    write(sys.argv[1])
