"""Every writer against a disk that fails on one rank, at one kind of write,
step after step (docs/testing.md, "Write faults"), with no step time limit.

usage: python3 writer_faults_check.py OUTPUT_DIR RANKS -- COMMAND...

COMMAND runs canopy_insitu_run (under with_xvfb.sh and mpirun -np RANKS) into
OUTPUT_DIR with --forest-json and the scripts surface_image.py,
data_extracts.py (--format=both, with the surface) and selection_extract.py.
This checker preloads the write-fault shim (tests/support/write_fault_shim.c)
and adds the fault of each step of PLAN to COMMAND; then, for every step:
- the writers the fault hits fail on every rank, the failure naming the step,
  and nothing of their output of that step is left (no file, no folder, no row
  of the VTKHDF file);
- every other output of the step is there and whole;
- the VTKHDF file holds exactly the steps that did not fail, each with every
  rank's piece and values (h5py, tests/support/vtkhdf_check.py), and the .pvd
  series lists exactly the .htg steps that did not fail;
- the simulation runs to its last step and exits normally.
Debian's /usr/bin/python3 (h5py, ParaView's VTK).
"""
import glob
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from grid_extract_expectations import load_forests  # noqa: E402
from output_checks import (expect, finish, read_htg_pieces, read_png, read_polydata,  # noqa: E402
                           read_unstructured, run_command, write_faults)
from vtkhdf_check import verify  # noqa: E402

# The outputs of a step, by writer: the script that writes it, and its files.
WRITERS = {
    "vtkhdf": "data_extracts.py",     # a step of grid.vtkhdf
    "htg": "data_extracts.py",        # grid_<step>.vtm and its .htg pieces
    "surface": "data_extracts.py",    # grid_surface_<step>.pvtp and its .vtp pieces
    "selection": "selection_extract.py",  # selection_<step>.pvtu and its .vtu pieces
    "image": "surface_image.py",      # surface_<step>.png
}


def plan(ranks):
    """(control line of the step's fault, writers it must fail) per step; None:
    no fault. `last`: a rank that is not rank 0."""
    last = ranks - 1
    hdf = "only=grid.vtkhdf rank=0"
    return [
        None,
        ("EIO 0 %s" % hdf, {"vtkhdf"}),                      # its first write
        None,
        ("EIO 0 %s min=65536" % hdf, {"vtkhdf"}),            # the first large write: data
        None,
        ("EIO 0 %s overwrite" % hdf, {"vtkhdf"}),            # rewriting metadata in place
        ("EIO 0 %s overwrite skip=2" % hdf, {"vtkhdf"}),     # ... after some of it went
        ("EIO 0 %s at=0" % hdf, {"vtkhdf"}),                 # the superblock, at close
        ("EIO 0 %s fsync" % hdf, {"vtkhdf"}),                # making the step durable at close
        ("EIO 100000 %s" % hdf, {"vtkhdf"}),                 # 100 KB into the step
        None,
        ("EIO 0 only=.htg rank=%d" % last, {"htg"}),          # a rank's piece of the series
        ("EIO 0 only=.vtm rank=0", {"htg"}),                  # the step's list of pieces
        ("EIO 0 only=grid.pvd rank=0", {"htg"}),              # the series' list of steps
        None,
        ("EIO 0 only=.vtp rank=%d" % last, {"surface"}),      # a rank's surface piece
        ("EIO 0 only=.pvtp rank=0", {"surface"}),             # the surface's list of pieces
        ("EIO 0 only=.vtu rank=%d" % last, {"selection"}),    # a rank's selected cells
        ("EIO 0 only=.pvtu rank=0", {"selection"}),           # the selection's list of pieces
        ("EIO 0 only=.png rank=0", {"image"}),                # the image
        ("EIO 0 rank=%d" % last, {"htg", "surface", "selection"}),  # every write of a rank
        ("EIO 2000 rank=%d" % last, {"htg", "surface", "selection"}),  # 2 KB into a rank's step
        None,
    ]


def step_outputs(output, writer, step):
    """The files and folders `writer` leaves for `step`."""
    patterns = {
        "htg": ["grid_%06d.vtm", "grid_%06d"],
        "surface": ["grid_surface_%06d.pvtp", "grid_surface_%06d"],
        "selection": ["selection_%06d.pvtu", "selection_%06d"],
        "image": ["surface_%06d.png"],
    }[writer]
    found = []
    for pattern in patterns:
        found += glob.glob(os.path.join(output, pattern % step))
    return sorted(os.path.relpath(p, output) for p in found)


def failures(log):
    """{step: {scripts reported failed on some rank}} (the driver agrees a failure
    over ranks: every rank skips the step, and rank 0's report lists each rank's
    reason)."""
    found = {}
    for step, script in re.findall(
            r"^  failure: rank \d+, step (\d+): the script '[^']*?([a-z_]+\.py)'", log, re.M):
        found.setdefault(int(step), set()).add(script)
    return found


def whole(output, writer, step):
    """Whether `writer`'s output of `step` is there and readable, and what it holds."""
    if writer == "htg":
        pieces = read_htg_pieces(output, "grid", step)
        return bool(pieces) and all(p.GetNumberOfCells() > 0 for p in pieces), len(pieces)
    if writer == "surface":
        cells = read_polydata(os.path.join(output, "grid_surface_%06d.pvtp" % step)).GetNumberOfCells()
        return cells > 0, cells
    if writer == "selection":
        cells = read_unstructured(os.path.join(output, "selection_%06d.pvtu" % step)).GetNumberOfCells()
        return cells > 0, cells
    pixels = read_png(os.path.join(output, "surface_%06d.png" % step))
    covered = int((pixels.min(axis=2) < 250).sum())
    return covered > 1000, covered


def main():
    output, ranks = sys.argv[1], int(sys.argv[2])
    command = sys.argv[sys.argv.index("--") + 1:]
    steps = plan(ranks)
    for step, fault in enumerate(steps):
        if fault:
            command += ["--write-fault-step", str(step), "--write-fault", fault[0]]
    command += ["--steps", str(len(steps))]
    shutil.rmtree(output, ignore_errors=True)
    os.makedirs(output)
    control = output + ".fault"
    if os.path.exists(control):
        os.remove(control)
    code, log = run_command(command, tail=3000, extra_env=write_faults(output, control))
    with open(os.path.join(output, "run.log"), "w") as out:
        out.write(log)

    expect(code == 0, "the simulation exits normally, no crash, no time limit (exit code %d)"
           % code)
    expect(not re.search(r"munmap_chunk|SIGABRT|SIGSEGV|Segmentation fault", log), "no crash")
    expect("\x1b[" not in log, "the log, not a terminal, holds no colour codes (%d)"
           % log.count("\x1b["))
    ran = [int(s) for s in re.findall(r"^step (\d+) executed", log, re.M)]
    expect(ran == list(range(len(steps))), "every step ran (%s)" % ran)
    reported = failures(log)
    forests = {forest["step"]: forest for forest in load_forests(output)}
    for step, fault in enumerate(steps):
        failing = fault[1] if fault else set()
        scripts = {WRITERS[w] for w in failing}
        got = reported.get(step, set())
        expect(got == scripts, "step %d (%s): %s reported failed (%s)"
               % (step, fault[0] if fault else "no fault", sorted(scripts) or "nothing",
                  sorted(got)))
        for writer in ("htg", "surface", "selection", "image"):
            left = step_outputs(output, writer, step)
            ok, size = whole(output, writer, step) if left else (False, 0)
            if writer in failing:
                expect(left == [], "step %d: nothing of the failed %s output is left (%s)"
                       % (step, writer, left))
            elif WRITERS[writer] in scripts:
                # A failed script stops at its first failed extract: the others of
                # its step are whole or absent, never partial.
                expect(ok or left == [], "step %d: the %s output of the failed script is "
                       "whole or absent (%s, %s)" % (step, writer, left, size))
            else:
                expect(ok, "step %d: the %s output is whole (%s)" % (step, writer, size))
    kept = [forests[s] for s, fault in enumerate(steps) if not fault or "vtkhdf" not in fault[1]]
    expect(len(forests) == len(steps), "the simulation described every step (%d)" % len(forests))
    verify(os.path.join(output, "grid.vtkhdf"), kept, expect)
    with open(os.path.join(output, "grid.pvd")) as series:
        listed = re.findall(r'file="grid_(\d{6})\.vtm"', series.read())
    want = ["%06d" % s for s, fault in enumerate(steps) if not fault or "htg" not in fault[1]]
    expect(listed == want, "grid.pvd lists the .htg steps that did not fail: %s" % listed)
    finish()


if __name__ == "__main__":
    main()
