"""Times what ParaView's log does not show in a Catalyst step: importing
paraview.simple, importing each pipeline script, and, inside the scripts,
loading plugins, creating views, showing sources and creating extractors.

canopy_bench_image_step installs it once canopy::InSitu is open (Python runs)
and before the first step; wrappers only measure (the same calls run), so the
first step does the work it does in a simulation. Records are written as
'<what>\t<seconds>' lines by dump().
"""
import builtins
import importlib
import sys
import time

_records = []
_clock = time.perf_counter
_original_import = builtins.__import__
_original_import_module = importlib.import_module
_patched_simple = False


def _record(what, seconds):
    _records.append((what, seconds))


def _timed(what, function):
    def timed(*args, **kwargs):
        start = _clock()
        try:
            return function(*args, **kwargs)
        finally:
            _record(what, _clock() - start)
    timed.__wrapped__ = function
    timed.__doc__ = function.__doc__
    return timed


def _patch_simple():
    global _patched_simple
    simple = sys.modules.get("paraview.simple")
    if _patched_simple or simple is None:
        return
    _patched_simple = True
    for name, what in (("LoadPlugin", "plugin load"), ("CreateView", "view creation"),
                       ("Show", "show"), ("CreateExtractor", "extractor creation")):
        setattr(simple, name, _timed(what, getattr(simple, name)))


def _wants_simple(name, fromlist):
    return name == "paraview.simple" or (name == "paraview" and fromlist and "simple" in fromlist)


def _import(name, globals=None, locals=None, fromlist=(), level=0):
    if level == 0 and "paraview.simple" not in sys.modules and _wants_simple(name, fromlist):
        start = _clock()
        module = _original_import(name, globals, locals, fromlist, level)
        _record("import paraview.simple", _clock() - start)
        _patch_simple()
        return module
    return _original_import(name, globals, locals, fromlist, level)


def _import_module(name, package=None):
    fresh = name not in sys.modules
    start = _clock()
    try:
        return _original_import_module(name, package)
    finally:
        if fresh:
            _record("import module " + name, _clock() - start)


def install():
    builtins.__import__ = _import
    importlib.import_module = _import_module
    _patch_simple()  # in case something imported it already


def dump(path):
    with open(path, "w") as out:
        for what, seconds in _records:
            out.write("%s\t%.6f\n" % (what, seconds))
    del _records[:]
