"""Runs the mini-app (or README's main job), then checks what it left, by content.

usage: python3 miniapp_check.py CHECK OUTPUT_DIR -- COMMAND...
CHECK: insitu (images, selection, HTG and surface extracts against the
simulation's own final state, arrays untouched), same_answer (COMMAND is run
at 1, 2 and 4 ranks; final states must agree) or exact_solution_order (COMMAND
in --exact-solution mode at several levels: errors against the exact solution
shrink at the expected order).
"""
import glob
import json
import math
import os
import re
import shutil
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import (cell_array, compare_images, expect, finish,  # noqa: E402
                           read_htg_pieces, read_multiblock, read_png, read_polydata, read_unstructured,
                           run_command, vtkhdf_cells_per_step)


def run(command):
    return run_command(command, tail=3000)


def read_dump(path):
    rows = {}
    with open(path) as source:
        for line in source:
            level, x, y, z, value = line.split()
            rows[(int(level), int(x), int(y), int(z))] = float(value)
    return rows


def edge_pixels(pixels):
    """Pixels clearly darker (by 15%) than the brightest of their neighbours two
    pixels away on either axis: a line drawn over the cells, whatever the lighting."""
    light = pixels.astype(float).sum(axis=2)
    around = numpy.zeros_like(light)
    around[2:, :] = numpy.maximum(around[2:, :], light[:-2, :])
    around[:-2, :] = numpy.maximum(around[:-2, :], light[2:, :])
    around[:, 2:] = numpy.maximum(around[:, 2:], light[:, :-2])
    around[:, :-2] = numpy.maximum(around[:, :-2], light[:, 2:])
    return int((light < 0.85 * around).sum())


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
        edges = edge_pixels(pixels)
        expect(colors > 50 and edges > 0.01 * width * height,
               "%s: the field in %d colors and the mesh's edges (%d edge pixels)"
               % (os.path.basename(name), colors, edges))

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

    # The grid, in both forms: the .htg pieces (listed by the step's .vtm, in the
    # .pvd ParaView 5.11 opens) and the VTKHDF file hold every node, with the
    # leaves' values; the full 2D surface one quad per leaf.
    pieces = read_htg_pieces(output, "grid", last)
    nodes = sum(grid.GetNumberOfCells() for grid in pieces)
    expect(nodes == cells, "HTG extract at step %d: %d nodes (the simulation has %d)"
           % (last, nodes, cells))
    multiblock = read_multiblock(os.path.join(output, "grid_%06d.vtm" % last))
    expect(multiblock.GetNumberOfBlocks() == len(pieces) and
           sum(multiblock.GetBlock(b).GetNumberOfLeaves()
               for b in range(multiblock.GetNumberOfBlocks())) == leaves,
           "grid_%06d.vtm: one block per rank, %d leaves" % (last, leaves))
    with open(os.path.join(output, "grid.pvd")) as series:
        expect("grid_%06d.vtm" % last in series.read(), "grid.pvd lists step %d" % last)
    hdf_cells = vtkhdf_cells_per_step(os.path.join(output, "grid.vtkhdf"))
    expect(hdf_cells and hdf_cells[-1] == cells,
           "grid.vtkhdf: %d steps, the last with %d nodes" % (len(hdf_cells), cells))
    surface = read_polydata(os.path.join(output, "grid_surface_%06d.pvtp" % last))
    expect(surface.GetNumberOfCells() == leaves, "surface extract: %d quads for %d leaves"
           % (surface.GetNumberOfCells(), leaves))
    scalar = cell_array(surface, "scalar")
    expect(abs(float(scalar.sum()) - sum(final.values())) < 1e-9 * max(1.0, sum(final.values())),
           "the surface carries the leaves' values")


def quads_of(surface):
    """Per quad: its bounds (xmin, xmax, ...) and its scalar."""
    values = cell_array(surface, "scalar")
    return [(tuple(surface.GetCell(c).GetBounds()), float(values[c]))
            for c in range(surface.GetNumberOfCells())]


def leaf_boxes(final, roots):
    """(lo, hi, value) of each leaf of a dump of a uniform root grid."""
    boxes = []
    for (level, i, j, k), value in final.items():
        n = roots * 2 ** level
        lo = (i / n, j / n, k / n)
        boxes.append((lo, tuple(x + 1.0 / n for x in lo), value))
    return boxes


def check_insitu_3d(output, command):
    """The 3D mini-app with slices (slice_image.py) and the scalar's region with an
    octant cut away (surface_image.py), both written as extracts at full resolution:
    at the last step, against the simulation's own dump. COMMAND's --roots is R
    (uniform, a power of two: every face exact). With REFERENCE=<dir> in the
    environment (the 1-rank run's output), every image must equal its own."""
    shutil.rmtree(output, ignore_errors=True)
    code, log = run(command + ["--dump", os.path.join(output, "final.txt")])
    expect(code == 0, "the mini-app exits normally")
    expect("simulation arrays untouched by Canopy: yes" in log,
           "Canopy left the arrays untouched (slices and selections read them in place)")
    expect(re.search(r"0 pipeline failure\(s\)", log) is not None, "no pipeline failed")
    noisy = [line for line in log.splitlines() if re.search(r"WARN|Warning|ERROR", line)]
    expect(not noisy, "no warning or error in the output (%d line(s)%s)"
           % (len(noisy), (": " + noisy[0].strip()) if noisy else ""))
    roots = int(command[command.index("--roots") + 1])
    steps = [int(s) for s in re.findall(r"^step\s+(\d+)", log, re.M)]
    last = steps[-1]
    final = read_dump(os.path.join(output, "final.txt"))
    leaves = leaf_boxes(final, roots)

    # Slices at x = 0.5 (a face of every level: cells above it), y = 0.3, and z =
    # 0.5625 (a face of the finest cells only).
    slices = quads_of(read_polydata(os.path.join(output, "slices_%06d.pvtp" % last)))
    want = []
    for axis, p in ((0, 0.5), (1, 0.3), (2, 0.5625)):
        for lo, hi, value in leaves:
            if lo[axis] <= p < hi[axis]:
                bounds = []
                for a in range(3):
                    bounds += [p, p] if a == axis else [lo[a], hi[a]]
                want.append((tuple(bounds), value))
    expect(sorted(slices) == sorted(want),
           "slices at step %d: %d quads, the dump's leaves cut by the planes give %d "
           "(boxes and values equal)" % (last, len(slices), len(want)))

    # The region: scalar >= 0.5 without the octant towards the default camera
    # (+x, +y, +z) from the region's centre; its surface, voxel by voxel.
    inside = [(lo, hi) for lo, hi, value in leaves if value >= 0.5]
    expect(len(inside) > 8, "%d leaves with scalar >= 0.5" % len(inside))
    centre = [0.5 * (min(lo[a] for lo, _ in inside) + max(hi[a] for _, hi in inside))
              for a in range(3)]
    fine = roots * 2 ** max(level for level, _, _, _ in final)
    occupied = numpy.zeros((fine + 2,) * 3, dtype=bool)  # a margin of empty voxels
    for lo, hi in inside:
        if all(hi[a] > centre[a] for a in range(3)):
            continue  # in the octant cut away
        i0, i1 = ([int(round(x * fine)) + 1 for x in corner] for corner in (lo, hi))
        occupied[i0[0]:i1[0], i0[1]:i1[1], i0[2]:i1[2]] = True
    expected_area = [float(numpy.logical_xor(occupied, numpy.roll(occupied, 1, axis)).sum())
                     / fine ** 2 for axis in range(3)]
    region = read_polydata(os.path.join(output, "region_%06d.pvtp" % last))
    area = [0.0, 0.0, 0.0]
    misplaced = 0
    for bounds, _ in quads_of(region):
        axis = [a for a in range(3) if bounds[2 * a] == bounds[2 * a + 1]][0]
        sides = [(bounds[2 * a + 1] - bounds[2 * a]) for a in range(3) if a != axis]
        area[axis] += sides[0] * sides[1]
        centre_voxel = [int((bounds[2 * a] + bounds[2 * a + 1]) / 2 * fine) + 1 for a in range(3)]
        plane = int(round(bounds[2 * axis] * fine)) + 1
        below, above = list(centre_voxel), list(centre_voxel)
        below[axis], above[axis] = plane - 1, plane
        misplaced += occupied[tuple(below)] == occupied[tuple(above)]
    expect(all(abs(area[a] - expected_area[a]) < 1e-9 for a in range(3)) and misplaced == 0,
           "region at step %d: exposed area %s, the dump's voxels give %s; %d quads not "
           "between a selected and an unselected voxel" % (
               last, ["%.6f" % x for x in area], ["%.6f" % x for x in expected_area], misplaced))

    reference = os.environ.get("REFERENCE")
    images = sorted(glob.glob(os.path.join(output, "*.png")))
    expect(len(images) >= 4, "%d images (slices and region, two steps)" % len(images))
    for name in images:
        pixels = read_png(name)
        expect(len(numpy.unique(pixels.reshape(-1, 3), axis=0)) > 50,
               "%s shows the colour map" % os.path.basename(name))
        if reference:
            theirs = os.path.join(reference, os.path.basename(name))
            expect(os.path.exists(theirs), "%s in the 1-rank run too" % os.path.basename(name))
            if os.path.exists(theirs):
                # Slices: a few depth ties where planes meet (compare_images).
                ties = 8 if os.path.basename(name).startswith("slices") else 0
                differing, unexplained = compare_images(pixels, read_png(theirs), ties)
                expect(unexplained == 0,
                       "%s identical to the 1-rank run (%d pixels differ, %d of them not a "
                       "depth tie where planes meet)"
                       % (os.path.basename(name), differing, unexplained))


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


EXACT_LINE = re.compile(r"^exact: (\S+) level (\d+) cells (\d+) h (\S+) time (\S+) "
                        r"L1 (\S+) max (\S+)$", re.M)


def check_exact_solution_order(output, command):
    """COMMAND (the mini-app in --exact-solution mode with --end-time, without
    --max-level) is run at each of LEVELS (environment, e.g. "1,2,3": the same
    final time, the step shrinking with the cells at a fixed CFL). The errors
    against the exact solution must be positive and finite and shrink between
    consecutive levels at an observed order log(e_coarse / e_fine) /
    log(h_coarse / h_fine) inside ORDER (environment, "low,high"), for L1 and
    max. The errors go to OUTPUT/errors.json; with REFERENCE=<dir> (another
    run's OUTPUT, e.g. on 1 rank) they must equal its own to 1e-12 (relative)."""
    shutil.rmtree(output, ignore_errors=True)
    os.makedirs(output)
    levels = [int(level) for level in os.environ["LEVELS"].split(",")]
    low, high = (float(x) for x in os.environ["ORDER"].split(","))
    runs = []
    for level in levels:
        code, log = run(command + ["--max-level", str(level)])
        expect(code == 0, "level %d runs" % level)
        lines = EXACT_LINE.findall(log)
        expect(len(lines) == 1, "level %d prints one 'exact:' line" % level)
        if code != 0 or len(lines) != 1:
            return
        _, printed_level, cells, h, time, l1, largest = lines[0]
        runs.append({"level": int(printed_level), "cells": int(cells), "h": float(h),
                     "time": float(time), "L1": float(l1), "max": float(largest)})
    with open(os.path.join(output, "errors.json"), "w") as target:
        json.dump(runs, target, indent=1)
    for run_ in runs:
        expect(all(math.isfinite(run_[norm]) and run_[norm] > 0 for norm in ("L1", "max")),
               "level %d (%d cells): L1 %.3e, max %.3e, positive and finite"
               % (run_["level"], run_["cells"], run_["L1"], run_["max"]))
    expect(max(abs(r["time"] - runs[0]["time"]) for r in runs) < 1e-12,
           "every level ends at time %.6g" % runs[0]["time"])
    for coarse, fine in zip(runs, runs[1:]):
        expect(fine["h"] < coarse["h"], "level %d is finer than level %d"
               % (fine["level"], coarse["level"]))
        for norm in ("L1", "max"):
            if not (coarse[norm] > 0 and fine[norm] > 0 and fine["h"] < coarse["h"]):
                continue
            order = math.log(coarse[norm] / fine[norm]) / math.log(coarse["h"] / fine["h"])
            expect(low <= order <= high, "%s order from level %d to %d: %.3f (%.3e -> %.3e), "
                   "expected in [%g, %g]" % (norm, coarse["level"], fine["level"], order,
                                             coarse[norm], fine[norm], low, high))
    reference = os.environ.get("REFERENCE")
    if reference:
        theirs_path = os.path.join(reference, "errors.json")
        expect(os.path.exists(theirs_path), "the reference run left %s" % theirs_path)
        if not os.path.exists(theirs_path):
            return
        with open(theirs_path) as source:
            theirs = json.load(source)
        expect([r["level"] for r in theirs] == [r["level"] for r in runs],
               "the reference ran the same levels")
        for mine, other in zip(runs, theirs):
            for norm in ("L1", "max"):
                expect(abs(mine[norm] - other[norm]) <= 1e-12 * abs(other[norm]),
                       "level %d: %s %.15e, the reference's %.15e (relative 1e-12)"
                       % (mine["level"], norm, mine[norm], other[norm]))


if __name__ == "__main__":
    separator = sys.argv.index("--")
    check, output = sys.argv[1], sys.argv[2]
    globals()["check_" + check](output, sys.argv[separator + 1:])
    finish()
