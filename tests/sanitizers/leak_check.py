"""Runs a command whose pipeline leaks on purpose (leaking_script.py) in the
sanitizer build and requires LeakSanitizer to report the planted leak, reached
from Python, with its function named. A suppression list that hides a leak
because Python is on its stack fails this test.

Usage: leak_check.py -- command...
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import expect, finish, run_command  # noqa: E402

command = sys.argv[sys.argv.index("--") + 1:]
# Full unwinding: the stack then reaches Python (the fast unwinder stops in
# frames without a frame pointer), so a suppression naming it would match.
asan = os.environ.get("ASAN_OPTIONS", "")
code, log = run_command(command, tail=8000, extra_env={
    "ASAN_OPTIONS": (asan + ":" if asan else "") + "fast_unwind_on_malloc=0"})
expect(code != 0, "the job fails: a leak was found (exit code %d)" % code)
expect(re.search(r"ERROR: LeakSanitizer: detected memory leaks", log) is not None,
       "LeakSanitizer reports leaks")
expect(re.search(r"leak of 4096 byte\(s\) in 1 object\(s\) allocated from:(\n\s+#.*)*?"
                 r"canopy_leak_probe_leak", log) is not None,
       "the 4096 bytes lost in catalyst_execute (called from Python) are reported")
finish()
