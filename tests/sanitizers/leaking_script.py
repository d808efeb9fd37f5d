# script-version: 2
"""A pipeline script that calls a planted leak (tests/sanitizers/LeakProbe.cxx,
through ctypes; its path in CANOPY_LEAK_PROBE) at its first step: 4096 bytes lost
from inside catalyst_execute. The sanitizer run must report it
(tests/sanitizers/leak_check.py)."""
import ctypes
import os

_probe = ctypes.CDLL(os.environ["CANOPY_LEAK_PROBE"])
_done = False


def catalyst_execute(info):
    global _done
    if not _done:
        _probe.canopy_leak_probe_leak(4096)
        _done = True
