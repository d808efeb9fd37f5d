"""Runs the stand-in simulation with data_extracts.py, then checks the grid
extracts: the VTKHDF file with h5py (tests/support/vtkhdf_check.py), the
ParaView 5.11 series by opening it in pvpython (paraview511_open.py), and
failed writes (reported with rank and step, every rank skipping the step,
earlier steps intact).

usage: python3 grid_extracts_check.py CHECK OUTPUT_DIR [ARGUMENT] -- COMMAND...
  vtkhdf                    the VTKHDF file holds every step
  paraview511 PVPYTHON      ParaView 5.11 opens the .pvd and .vtm files right
  paraview511_render PVPYTHON WITH_XVFB (no COMMAND) ParaView 5.11 draws OUTPUT_DIR's series
  selection PVPYTHON        selection_extract.py --preserve-topology=1 --selection=range
                            --value-field=refinementLevel --value-range=4,5 (format both):
                            selection.vtkhdf (h5py) and selection.pvd (pvpython) hold the
                            forest with exactly the brute-force selection left unmasked
  disk_full BYTES           OUTPUT_DIR/small_disk holds BYTES per rank (the write-fault
                            shim, tests/support/write_fault_shim.c): steps that do
                            not fit fail, the file keeps the others
  write_fails STEP          writes fail from STEP on (a file-size limit): same
  unwritable                the file's folder cannot be created: every step fails
COMMAND writes into OUTPUT_DIR, with --forest-json. Debian's /usr/bin/python3 (h5py).
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from grid_extract_expectations import failed_steps, load_forests, selected_by_level  # noqa: E402
from output_checks import expect, finish, run_command, write_faults  # noqa: E402
from vtkhdf_check import verify  # noqa: E402



def steps_run(log):
    # Not anchored: a line of ParaView's stderr may run into it.
    return [int(s) for s in re.findall(r"step (\d+) executed", log)]


def check_vtkhdf(code, log, output, _):
    expect(code == 0, "the simulation exits normally")
    expect(failed_steps(log) == [], "no step failed (%s)" % failed_steps(log))
    forests = load_forests(output)
    expect(len(forests) >= 2, "%d steps to check" % len(forests))
    verify(os.path.join(output, "grid.vtkhdf"), forests, expect)


def check_paraview511(code, log, output, pvpython):
    expect(code == 0, "the simulation exits normally")
    expect(failed_steps(log) == [], "no step failed (%s)" % failed_steps(log))
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview511_open.py")
    data = subprocess.run([pvpython, script, output, "data"], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True,
                          env={k: v for k, v in os.environ.items() if k != "DISPLAY"})
    print(data.stdout[-6000:])
    expect(data.returncode == 0, "ParaView 5.11 (pvpython) opens the series and every step "
           "with the simulation's cells and values (exit code %d)" % data.returncode)


def check_selection(code, log, output, pvpython):
    expect(code == 0, "the simulation exits normally")
    expect(failed_steps(log) == [], "no step failed (%s)" % failed_steps(log))
    forests = [selected_by_level(forest, 4, 5) for forest in load_forests(output)]
    expect(len(forests) >= 2, "%d steps to check" % len(forests))
    visible = [sum(tree["mask"].count("0") for tree in forest["trees"]) for forest in forests]
    expect(all(0 < v < sum(len(t["refinement"]) for t in f["trees"])
               for v, f in zip(visible, forests)),
           "the selection keeps some cells and masks others (%s visible)" % visible)
    verify(os.path.join(output, "selection.vtkhdf"), forests, expect)
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview511_open.py")
    data = subprocess.run([pvpython, script, output, "data", "selection", "4,5"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          env={k: v for k, v in os.environ.items() if k != "DISPLAY"})
    print(data.stdout[-6000:])
    expect(data.returncode == 0, "ParaView 5.11 (pvpython) opens selection.pvd with the "
           "selection's mask and the simulation's values (exit code %d)" % data.returncode)


def render_paraview511(output, pvpython, with_xvfb):
    """ParaView 5.11 draws the series of an earlier run (OUTPUT_DIR) in a render
    view, on an X server of its own (tests/support/with_xvfb.sh)."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview511_open.py")
    result = subprocess.run([with_xvfb, pvpython, script, output, "render"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(result.stdout[-3000:])
    expect(result.returncode == 0, "ParaView 5.11 (pvpython) renders the series (exit code %d)"
           % result.returncode)


def check_failed_from(code, log, output, first_failure, message):
    """Steps from `first_failure` on failed on every rank with `message`; the file
    holds exactly the earlier ones."""
    expect(code == 0, "the simulation exits normally, no crash (exit code %d)" % code)
    forests = load_forests(output)
    steps = [forest["step"] for forest in forests]
    want = [step for step in steps if step >= first_failure]
    expect(failed_steps(log) == want and want, "steps %s failed (%s)" % (want, failed_steps(log)))
    first = re.search(r"^  failure: rank 0, step %d: (.*)" % first_failure, log, re.M)
    expect(first is not None and re.search(message, first.group(1)) is not None,
           "step %d's error names the rank and the problem: %s"
           % (first_failure, first.group(1)[:300] if first else None))
    ranks = forests[0]["ranks"]
    reported = set(re.findall(r"failure: rank (\d+), step %d:" % first_failure, log))
    expect(reported == {str(r) for r in range(ranks)},
           "every rank skipped step %d (reports from ranks %s)" % (first_failure, sorted(reported)))
    expect(steps_run(log) == steps, "the simulation went on to its last step")
    kept = [forest for forest in forests if forest["step"] < first_failure]
    path = os.path.join(output, "small_disk", "grid.vtkhdf")
    if not os.path.exists(path):
        path = os.path.join(output, "grid.vtkhdf")
    verify(path, kept, expect)


def check_disk_full(code, log, output, _):
    # The first step that failed is the one that did not fit.
    failed = failed_steps(log)
    expect(bool(failed) and failed[0] > 0, "some steps were written before the disk was full, "
           "then steps failed (%s)" % failed)
    # Refused before anything is written: by the script's check of the step's
    # size (canopy_catalyst) or by the writer's own.
    check_failed_from(code, log, output, failed[0] if failed else -1,
                      r"not enough free (disk )?space in .*small_disk")


def check_write_fails(code, log, output, step):
    check_failed_from(code, log, output, int(step),
                      r"VTKHDF extract .*: step %s \(time [^)]*\) not written: rank \d+: "
                      r"cannot write .*" % step)


def check_unwritable(code, log, output, _):
    expect(code == 0, "the simulation exits normally")
    forests = load_forests(output)
    steps = [forest["step"] for forest in forests]
    expect(failed_steps(log) == steps, "every step failed (%s)" % failed_steps(log))
    for step in steps:
        expect(re.search(r"VTKHDF extract /proc/canopy/grid.vtkhdf: step %d \(time [^)]*\) not "
                         r"written: rank 0: cannot create /proc/canopy/grid.vtkhdf" % step, log)
               is not None, "step %d: reported with rank, step and file" % step)


def main():
    check, output = sys.argv[1], sys.argv[2]
    if check == "paraview511_render":
        render_paraview511(output, sys.argv[3], sys.argv[4])
        finish()
    separator = sys.argv.index("--")
    argument = sys.argv[3] if separator > 3 else None
    command = sys.argv[separator + 1:]
    shutil.rmtree(output, ignore_errors=True)
    os.makedirs(output)
    faults = None
    if check == "disk_full":
        # A disk of `argument` bytes under output/small_disk for the whole run
        # (each rank's process counts its own writes): the write-fault shim.
        disk = os.path.join(output, "small_disk")
        os.makedirs(disk)
        control = output + ".fault"
        with open(control, "w") as out:
            out.write("ENOSPC %d statvfs\n" % int(argument))
        faults = write_faults(disk, control)
    code, log = run_command(command, tail=6000, extra_env=faults)
    with open(os.path.join(output, "run.log"), "w") as out:
        out.write(log)
    globals()["check_" + check](code, log, output, argument)
    finish()


if __name__ == "__main__":
    main()
