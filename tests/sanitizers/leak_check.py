"""Runs a command whose pipeline leaks on purpose (leaking_script.py) in the
sanitizer build and requires LeakSanitizer to report the planted leak with its
function named: reached from Python (--when execute: 4096 bytes in
catalyst_execute) or from MPI_Finalize (--when finalize: 8192 bytes in
catalyst_finalize of a simulation that forgot close()). A suppression list that
hides a leak because Python or OpenMPI is on its stack fails this test.

Usage: leak_check.py --when execute|finalize -- command...
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import expect, finish, run_command  # noqa: E402

split = sys.argv.index("--")
options = argparse.ArgumentParser()
options.add_argument("--when", choices=("execute", "finalize"), required=True)
args = options.parse_args(sys.argv[1:split])
command = sys.argv[split + 1:]

# Full unwinding and deep stacks: the stack then reaches Python and, at finalize,
# MPI_Finalize (the fast unwinder stops in frames without a frame pointer), so a
# suppression naming either would match.
asan = os.environ.get("ASAN_OPTIONS", "")
code, log = run_command(command, tail=12000, extra_env={
    "ASAN_OPTIONS": (asan + ":" if asan else "") + "fast_unwind_on_malloc=0:malloc_context_size=120",
    "CANOPY_LEAK_WHEN": args.when})
expect(code != 0, "the job fails: a leak was found (exit code %d)" % code)
expect(re.search(r"ERROR: LeakSanitizer: detected memory leaks", log) is not None,
       "LeakSanitizer reports leaks")
size = 4096 if args.when == "execute" else 8192
report = re.search(r"leak of %d byte\(s\) in 1 object\(s\) allocated from:((\n\s+#.*)*)" % size, log)
expect(report is not None, "the %d bytes lost in the script's catalyst_%s are reported"
       % (size, args.when))
if report is not None:
    stack = report.group(1)
    expect("canopy_leak_probe_leak" in stack, "the report names the leaking function")
    if args.when == "finalize":
        expect("FinalizeGuard::onDelete" in stack and "ompi_mpi_finalize" in stack,
               "the report's stack passes through MPI_Finalize and Canopy's FinalizeGuard")
finish()
