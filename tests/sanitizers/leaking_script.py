# script-version: 2
"""A pipeline script that calls a planted leak (tests/sanitizers/LeakProbe.cxx,
through ctypes; its path in CANOPY_LEAK_PROBE). CANOPY_LEAK_WHEN says where:
"execute" loses 4096 bytes inside catalyst_execute at the first step;
"finalize" loses 8192 bytes inside catalyst_finalize, which a simulation that
forgot close() reaches from MPI_Finalize (FinalizeGuard). The sanitizer run must
report it (tests/sanitizers/leak_check.py)."""
import ctypes
import os

_probe = ctypes.CDLL(os.environ["CANOPY_LEAK_PROBE"])
_when = os.environ.get("CANOPY_LEAK_WHEN", "execute")
_done = False


def catalyst_execute(info):
    global _done
    if _when == "execute" and not _done:
        _probe.canopy_leak_probe_leak(4096)
        _done = True


def catalyst_finalize():
    if _when == "finalize":
        _probe.canopy_leak_probe_leak(8192)
