"""Runs the mini-app (or README's main job), then checks what it left, by content.

usage: python3 miniapp_check.py CHECK OUTPUT_DIR -- COMMAND...
CHECK: insitu (images, selection, HTG and surface extracts against the
simulation's own final state, arrays untouched) or same_answer (COMMAND is run
at 1, 2 and 4 ranks; final states must agree).
"""
import glob
import os
import re
import shutil
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import (cell_array, expect, finish, read_htg_pieces, read_png,  # noqa: E402
                           read_polydata, read_unstructured, run_command)


def run(command):
    return run_command(command, tail=3000)


def read_dump(path):
    rows = {}
    with open(path) as source:
        for line in source:
            level, x, y, z, value = line.split()
            rows[(int(level), int(x), int(y), int(z))] = float(value)
    return rows


def check_insitu(output, command):
    shutil.rmtree(output, ignore_errors=True)
    code, log = run(command + ["--dump", os.path.join(output, "final.txt")])
    expect(code == 0, "the mini-app exits normally")
    expect("simulation arrays untouched by Canopy: yes" in log, "Canopy left the arrays untouched")
    expect(re.search(r"0 pipeline failure\(s\)", log) is not None, "no pipeline failed")
    noisy = [line for line in log.splitlines() if re.search(r"WARN|Warning|ERROR", line)]
    expect(not noisy, "no warning or error in the output (%d line(s)%s)"
           % (len(noisy), (": " + noisy[0].strip()) if noisy else ""))
    worst = float(re.search(r"worst relative mass change ([0-9.e+-]+)", log).group(1))
    expect(worst < 1e-12, "mass conserved to %.1e" % worst)
    steps = [int(s) for s in re.findall(r"^step\s+(\d+)", log, re.M)]
    last = steps[-1]
    cells = int(re.findall(r"^step\s+%d\s.*cells\s+(\d+)" % last, log, re.M)[0])
    leaves = int(re.findall(r"^step\s+%d\s.*leaves\s+(\d+)" % last, log, re.M)[0])
    final = read_dump(os.path.join(output, "final.txt"))
    expect(len(final) == leaves, "the dump holds the %d leaves" % leaves)

    images = sorted(glob.glob(os.path.join(output, "surface_*.png")))
    expect(len(images) >= 2, "%d images" % len(images))
    for name in images:
        pixels = read_png(name)
        height, width, _ = pixels.shape
        colors = len(numpy.unique(pixels.reshape(-1, 3), axis=0))
        dark = int((pixels.max(axis=2) < 100).sum())  # cell edges (the colormap is brighter)
        expect(colors > 50 and dark > 0.01 * width * height,
               "%s: the field in %d colors and the mesh's edges (%d dark pixels)"
               % (os.path.basename(name), colors, dark))

    # The zoomed view (a camera on the region the sphere sweeps): culled, so it
    # draws fewer quads than the grid has leaves; the step line says both.
    zoomed = sorted(glob.glob(os.path.join(output, "zoom_*.png")))
    expect(len(zoomed) == len(images), "a zoomed image beside each of the %d images (%d)"
           % (len(images), len(zoomed)))
    drawn = re.findall(r"^step\s+(\d+)\s.*leaves\s+(\d+)\s.*quads: surface (\d+), zoom (\d+)$",
                       log, re.M)
    expect(len(drawn) == len(images), "%d step lines say the quads drawn, one per image"
           % len(drawn))
    for step, step_leaves, surface_quads, zoom_quads in drawn:
        expect(0 < int(zoom_quads) < int(step_leaves) and 0 < int(surface_quads) <= int(step_leaves),
               "step %s: %s quads in the image, %s in the zoomed view, %s leaves"
               % (step, surface_quads, zoom_quads, step_leaves))

    # The selection (scalar >= 0.5) at the last step is the dump's leaves >= 0.5.
    selection = read_unstructured(os.path.join(output, "selection_%06d.pvtu" % last))
    want = sum(1 for value in final.values() if value >= 0.5)
    expect(selection.GetNumberOfCells() == want and want > 0,
           "selection at step %d: %d cells, %d leaves have scalar >= 0.5"
           % (last, selection.GetNumberOfCells(), want))
    values = cell_array(selection, "scalar")
    expect(sorted(values.tolist()) == sorted(v for v in final.values() if v >= 0.5),
           "with the simulation's own values")

    # The .htg pieces hold every node; the full 2D surface one quad per leaf.
    nodes = sum(grid.GetNumberOfCells() for grid in read_htg_pieces(output, "grid", last))
    expect(nodes == cells, "HTG extract at step %d: %d nodes (the simulation has %d)"
           % (last, nodes, cells))
    surface = read_polydata(os.path.join(output, "grid_surface_%06d.pvtp" % last))
    expect(surface.GetNumberOfCells() == leaves, "surface extract: %d quads for %d leaves"
           % (surface.GetNumberOfCells(), leaves))
    scalar = cell_array(surface, "scalar")
    expect(abs(float(scalar.sum()) - sum(final.values())) < 1e-9 * max(1.0, sum(final.values())),
           "the surface carries the leaves' values")


def check_same_answer_repartitioning(output, command):
    """As same_answer, and the 4-rank run must have repartitioned."""
    check_same_answer(output, command, require_repartition=True)


def check_same_answer(output, command, require_repartition=False):
    """The same run on 1, 2 and 4 ranks: the same leaves and values. The update is a
    per-leaf gather in a fixed face order, so values agree to the last bit; the
    stated tolerance is 1e-12."""
    shutil.rmtree(output, ignore_errors=True)
    os.makedirs(output)
    dumps = {}
    for ranks in (1, 2, 4):
        code, log = run(["mpirun", "--oversubscribe", "-np", str(ranks)] + command +
                        ["--dump", os.path.join(output, "np%d.txt" % ranks)])
        expect(code == 0, "np %d runs" % ranks)
        if ranks == 4 and require_repartition:
            repartitions = int(re.search(r"(\d+) repartition", log).group(1))
            expect(repartitions > 0, "np 4 repartitioned (%d times): trees moved between "
                   "ranks with their values" % repartitions)
        dumps[ranks] = read_dump(os.path.join(output, "np%d.txt" % ranks))
    for ranks in (2, 4):
        expect(dumps[ranks].keys() == dumps[1].keys(), "np %d: the same %d leaves"
               % (ranks, len(dumps[1])))
        worst = max(abs(dumps[ranks][k] - dumps[1][k]) for k in dumps[1])
        expect(worst <= 1e-12, "np %d: values within 1e-12 of np 1 (largest difference %.1e)"
               % (ranks, worst))


if __name__ == "__main__":
    separator = sys.argv.index("--")
    check, output = sys.argv[1], sys.argv[2]
    globals()["check_" + check](output, sys.argv[separator + 1:])
    finish()
