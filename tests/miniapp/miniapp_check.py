"""Runs the mini-app (or README's main job), then checks what it left, by content.

usage: python3 miniapp_check.py CHECK OUTPUT_DIR -- COMMAND...
CHECK: insitu (images, selection, HTG and surface extracts against the
simulation's own final state, arrays untouched), insitu_blocks (the same with
--blocks N: every block cell of the extracts against values recomputed from the
dump), insitu_3d_defaults (the default 3D images: the blob's isosurface drawn where
the blob is), isosurface_extract_3d (the isosurface's .pvtp as ParaView reads it),
contour_settings_refused (slice_image.py's wrong contour settings, each refused),
contour_level_of_detail (the isosurface following the view: fewer triangles, closed),
same_answer (COMMAND is run at 1, 2 and 4 ranks; final states must agree)
or exact_solution_order (COMMAND in --exact-solution mode at several levels:
errors against the exact solution shrink at the expected order).
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
from output_checks import (cell_array, check_isosurface_extract, compare_images,  # noqa: E402
                           expect, finish, read_htg_pieces, read_multiblock, read_png,
                           read_polydata, read_unstructured, read_with_paraview, run_command,
                           vtkhdf_cells_per_step)


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
    # What a new user's console shows: no X authorization noise from OpenMPI's
    # hwloc (scripts/run_miniapp.sh leaves its gl probe out), no colour codes.
    expect("Authorization required" not in log and "\x1b[" not in log,
           "no X authorization noise and no colour codes in the output")
    worst = float(re.search(r"worst relative mass change ([0-9.e+-]+)", log).group(1))
    expect(worst < 1e-12, "mass conserved to %.1e" % worst)
    steps = [int(s) for s in re.findall(r"^step\s+(\d+)", log, re.M)]
    last = steps[-1]
    cells = int(re.findall(r"^step\s+%d\s.*nodes\s+(\d+)" % last, log, re.M)[0])
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
                # and the isosurface's lighting rounded a level differently.
                differing, unexplained = compare_images(pixels, read_png(theirs), ties,
                                                        shading=2 if ties else 0)
                expect(unexplained == 0,
                       "%s identical to the 1-rank run (%d pixels differ, %d of them not a "
                       "depth tie where planes meet nor a level of lighting)"
                       % (os.path.basename(name), differing, unexplained))


BLOB_LEVEL = 0.5
"""The level of the default 3D isosurface (miniapp/main.cxx), its region and selection."""


def projected_box(lo, hi, width, height):
    """The pixel box (x0, x1, y0, y1; y up from the bottom row, as read_png's rows) of
    the box lo-hi seen by the image scripts' default camera on the unit domain
    (canopy_catalyst.frame_bounds: perspective, 30 degrees, from centre + (1.2, 0.9, 1.5)
    x diagonal, y up), projected with VTK's own camera."""
    from paraview.vtk.vtkRenderingCore import vtkCamera
    camera = vtkCamera()
    diagonal = math.sqrt(3.0)
    camera.SetFocalPoint(0.5, 0.5, 0.5)
    camera.SetPosition(0.5 + 1.2 * diagonal, 0.5 + 0.9 * diagonal, 0.5 + 1.5 * diagonal)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(30.0)
    camera.SetClippingRange(0.01, 100.0)  # x and y do not depend on it
    matrix = camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1)
    xs, ys = [], []
    for corner in range(8):
        point = [hi[a] if (corner >> a) & 1 else lo[a] for a in range(3)] + [1.0]
        clip = [sum(matrix.GetElement(r, c) * point[c] for c in range(4)) for r in range(4)]
        xs.append((clip[0] / clip[3] + 1) / 2 * width)
        ys.append((1 + clip[1] / clip[3]) / 2 * height)
    return min(xs), max(xs), min(ys), max(ys)


def image_step_lines(log):
    """{step: line} of the steps that drew images (their line says the quads)."""
    return {int(step): line for step, line in
            re.findall(r"^step\s+(\d+)\s(.*quads:.*)$", log, re.M)}


def contour_triangles(line):
    found = re.search(r"triangles: slices contour (\d+)", line)
    return int(found.group(1)) if found else -1


def check_insitu_3d_defaults(output, command):
    """README's 3D job with the default pipelines (no --pipeline): the slices image
    draws the blob's isosurface. COMMAND is the default run, then after --then the same
    run with slice_image.py given the default image arguments but no contour (its
    --output a folder of its own). At the last step, against the dump: the images differ
    only inside the projection of the blob's region (the leaves with scalar >= 0.5,
    grown by a finest cell: the isosurface lies between their centres and their
    neighbours'), and there on at least 5% of it (the surface is drawn where the
    blob is); every image step's line says the contour's triangles (> 0). With
    REFERENCE=<dir> (the 1-rank run): the images equal its own (slices up to depth ties
    where planes meet; the region up to compositing rounding on mesh lines) and each
    step drew as many triangles."""
    split = command.index("--then")
    default, without = command[:split], command[split + 1:]
    shutil.rmtree(output, ignore_errors=True)
    code, log = run(default + ["--dump", os.path.join(output, "final.txt")])
    os.makedirs(output, exist_ok=True)
    with open(os.path.join(output, "log.txt"), "w") as saved:
        saved.write(log)
    expect(code == 0, "the default run exits normally")
    expect(re.search(r"0 pipeline failure\(s\)", log) is not None, "no pipeline failed")
    expect("simulation arrays untouched by Canopy: yes" in log, "Canopy left the arrays untouched")
    noisy = [line for line in log.splitlines() if re.search(r"WARN|Warning|ERROR", line)]
    expect(not noisy, "no warning or error in the output (%d line(s)%s)"
           % (len(noisy), (": " + noisy[0].strip()) if noisy else ""))
    if code != 0:
        return
    lines = image_step_lines(log)
    expect(len(lines) >= 2 and all(contour_triangles(line) > 0 for line in lines.values()),
           "every image step's line says the isosurface's triangles: %s"
           % {step: contour_triangles(line) for step, line in sorted(lines.items())})
    last = max(lines)
    name = "slices_%06d.png" % last
    mine = read_png(os.path.join(output, name))
    other_folder = option(without, "--output", None)
    code, _ = run(without)
    expect(code == 0, "the run without the contour exits normally")
    if code != 0 or other_folder is None:
        return
    plain = read_png(os.path.join(other_folder, name))
    height, width, _ = mine.shape
    differing = (mine != plain).any(axis=2)
    roots = int(option(default, "--roots", 16))
    final = read_dump(os.path.join(output, "final.txt"))
    finest = 1.0 / (roots * 2 ** max(level for level, _, _, _ in final))
    blob = [(lo, hi) for lo, hi, value in leaf_boxes(final, roots) if value >= BLOB_LEVEL]
    expect(len(blob) > 0, "%d leaves with scalar >= %g at step %d" % (len(blob), BLOB_LEVEL, last))
    if not blob:
        return
    lo = [min(box[0][a] for box in blob) - finest for a in range(3)]
    hi = [max(box[1][a] for box in blob) + finest for a in range(3)]
    x0, x1, y0, y1 = projected_box(lo, hi, width, height)
    x0, y0 = max(0, int(math.floor(x0)) - 2), max(0, int(math.floor(y0)) - 2)
    x1, y1 = min(width, int(math.ceil(x1)) + 3), min(height, int(math.ceil(y1)) + 3)
    inside = int(differing[y0:y1, x0:x1].sum())
    area = (x1 - x0) * (y1 - y0)
    expect(inside >= 0.05 * area and inside == int(differing.sum()),
           "%s: the isosurface changes %d pixels, %d of them inside the blob's projected box "
           "[%d, %d) x [%d, %d) (%d pixels; at least 5%% of them expected, none outside)"
           % (name, int(differing.sum()), inside, x0, x1, y0, y1, area))
    for image in sorted(glob.glob(os.path.join(output, "*.png"))):
        expect(len(numpy.unique(read_png(image).reshape(-1, 3), axis=0)) > 50,
               "%s shows the colour map" % os.path.basename(image))

    reference = os.environ.get("REFERENCE")
    if not reference:
        return
    with open(os.path.join(reference, "log.txt")) as saved:
        theirs = image_step_lines(saved.read())
    expect({s: contour_triangles(l) for s, l in lines.items()} ==
           {s: contour_triangles(l) for s, l in theirs.items()},
           "each image step drew as many isosurface triangles as the 1-rank run (%s, 1 rank %s)"
           % ({s: contour_triangles(l) for s, l in sorted(lines.items())},
              {s: contour_triangles(l) for s, l in sorted(theirs.items())}))
    for image in sorted(glob.glob(os.path.join(output, "*.png"))):
        base = os.path.basename(image)
        pixels, other = read_png(image), read_png(os.path.join(reference, base))
        if base.startswith("region"):
            # As miniapp.blocks_3d_np2: anti-aliased mesh lines composited from several
            # ranks round a few pixels differently; everything else must be equal.
            change = numpy.abs(pixels.astype(int) - other.astype(int)).max(axis=2)
            count = int((change > 0).sum())
            expect(change.max() <= 8 and count <= 0.002 * change.size,
                   "%s equal to the 1-rank run's but for compositing rounding on mesh lines: "
                   "%d pixels differ, by at most %d" % (base, count, change.max()))
            continue
        differing_count, unexplained = compare_images(pixels, other, 8, shading=2)
        expect(unexplained == 0, "%s identical to the 1-rank run's (%d pixels differ, %d of "
               "them not a depth tie where planes meet nor a level of lighting)" % (base, differing_count, unexplained))


def check_isosurface_extract_3d(output, command):
    """slice_image.py with the blob's isosurface and slice_extract: every image step's
    slices_contour_<step>.pvtp, opened by ParaView's own reader (pvpython, PVPYTHON in
    the environment), is what the step line says was drawn (triangles), with its fields
    (output_checks.check_isosurface_extract: the contour value, Normals pointing out of
    the blob, closed) and velocity interpolated onto it (the colour field: its z
    component the swirl's constant 0.5, its x and y the swirl's at the point within
    0.05). With REFERENCE=<dir> (the 1-rank run): the same triangles and area (1e-9)."""
    shutil.rmtree(output, ignore_errors=True)
    code, log = run(command + ["--dump", os.path.join(output, "final.txt")])
    os.makedirs(output, exist_ok=True)
    with open(os.path.join(output, "log.txt"), "w") as saved:
        saved.write(log)
    expect(code == 0 and re.search(r"0 pipeline failure\(s\)", log) is not None,
           "the mini-app exits normally, no pipeline failed")
    noisy = [line for line in log.splitlines() if re.search(r"WARN|Warning|ERROR", line)]
    expect(not noisy, "no warning or error in the output (%d line(s)%s)"
           % (len(noisy), (": " + noisy[0].strip()) if noisy else ""))
    if code != 0:
        return
    pvpython = os.environ["PVPYTHON"]
    lines = image_step_lines(log)
    expect(len(lines) >= 2, "%d image steps" % len(lines))
    roots = int(option(command, "--roots", 16))
    final = read_dump(os.path.join(output, "final.txt"))
    last = max(lines) if lines else -1
    found = {}
    for step, line in sorted(lines.items()):
        triangles = contour_triangles(line)
        name = "slices_contour_%06d.pvtp" % step
        read = read_with_paraview(os.path.join(output, name), pvpython)
        # Inside: the centre of the blob's leaves (the last step's from the dump; the
        # initial blob's centre at step 0).
        if step == last:
            blob = [(lo, hi) for lo, hi, value in leaf_boxes(final, roots) if value >= BLOB_LEVEL]
            centre = [sum(lo[a] + hi[a] for lo, hi in blob) / (2.0 * len(blob)) for a in range(3)]
        elif step == 0:
            centre = [0.5, 0.72, 0.5]  # Simulation::initialValue's blob
        else:
            centre = read["points"].mean(axis=0) if read is not None else [0.0] * 3
        area, _ = check_isosurface_extract(read, "step %d: %s" % (step, name), "scalar",
                                           BLOB_LEVEL, triangles, centre, ["velocity"])
        found[step] = (triangles, area)
        if read is None or "point:velocity" not in read:
            continue
        velocity, points = read["point:velocity"], read["points"]
        sx, sy = numpy.sin(numpy.pi * points[:, 0]), numpy.sin(numpy.pi * points[:, 1])
        swirl = numpy.stack([sx * sx * numpy.sin(2 * numpy.pi * points[:, 1]),
                             -sy * sy * numpy.sin(2 * numpy.pi * points[:, 0])], axis=1)
        expect(velocity.shape[1] == 3 and numpy.abs(velocity[:, 2] - 0.5).max() < 1e-12 and
               numpy.abs(velocity[:, :2] - swirl).max() < 0.05,
               "step %d: velocity interpolated onto the isosurface: z the swirl's 0.5 (largest "
               "difference %.1e), x and y the swirl's at the points (largest difference %.3f)"
               % (step, numpy.abs(velocity[:, 2] - 0.5).max(),
                  numpy.abs(velocity[:, :2] - swirl).max()))
    with open(os.path.join(output, "found.json"), "w") as saved:
        json.dump(found, saved)
    reference = os.environ.get("REFERENCE")
    if reference:
        with open(os.path.join(reference, "found.json")) as saved:
            theirs = {int(step): value for step, value in json.load(saved).items()}
        for step, (triangles, area) in sorted(found.items()):
            other = theirs.get(step, (-1, math.nan))
            expect(triangles == other[0] and abs(area - other[1]) <= 1e-9 * other[1],
                   "step %d: %d triangles of area %.9g, the 1-rank run %d of area %.9g"
                   % (step, triangles, area, other[0], other[1]))


def check_contour_level_of_detail(output, command):
    """COMMAND runs slice_image.py with the blob's isosurface, slice_extract and a large
    pixel_threshold, contour_level_of_detail on; after --then, the same with it off (each
    --output its own). At the last image step both extracts (ParaView's reader) are
    closed, with as many triangles as the step line says; the one that follows the
    view has fewer, but some: nodes below the threshold are contoured as leaves."""
    split = command.index("--then")
    runs = {"on": command[:split], "off": command[split + 1:]}
    shutil.rmtree(output, ignore_errors=True)
    counts = {}
    for name, run_command_ in runs.items():
        code, log = run(run_command_)
        expect(code == 0 and "0 pipeline failure(s)" in log,
               "level of detail %s: the mini-app exits normally, no pipeline failed" % name)
        lines = image_step_lines(log)
        if code != 0 or not lines:
            return
        last = max(lines)
        folder = option(run_command_, "--output", output)
        read = read_with_paraview(os.path.join(folder, "slices_contour_%06d.pvtp" % last),
                                  os.environ["PVPYTHON"])
        counts[name] = contour_triangles(lines[last])
        centre = read["points"].mean(axis=0) if read is not None else [0.0] * 3
        check_isosurface_extract(read, "level of detail %s, step %d" % (name, last), "scalar",
                                 BLOB_LEVEL, counts[name], centre)
    expect(0 < counts["on"] < counts["off"],
           "following the view, the isosurface has %d triangles, at full resolution %d"
           % (counts["on"], counts["off"]))


REFUSED_CONTOUR_SETTINGS = [
    (["--contour-field=scalar", "--contour-opacity=0,5"],
     "setting --contour-opacity: a number expected (got '0,5')"),
    (["--contour-field=scalar", "--contour-opacity=0"],
     "contour_opacity: greater than 0, at most 1 (got 0.0)"),
    (["--contour-field=scalar", "--contour-opacity=1.5"],
     "contour_opacity: greater than 0, at most 1 (got 1.5)"),
    (["--contour-field=scalar", "--contour-values=0.2;0.5"],
     "contour_values: numbers separated by commas, e.g. '0.5' or '0.2,0.5' (got '0.2;0.5')"),
    (["--contour-field=scalar", "--contour-values=0.5,nan"],
     "contour_values: finite numbers (got '0.5,nan')"),
    (["--contour-values=0.5"], "contour_values='0.5' needs contour_field"),
    (["--contour-field=scalar", "--contour-count=0"], "contour_count: at least 1 (got 0)"),
    (["--contour-field=scalar", "--contour-count=two"],
     "setting --contour-count: an integer expected (got 'two')"),
    (["--contour-field=scalar", "--contour-level-of-detail=maybe"],
     "setting --contour-level-of-detail: true or false (1/0, yes/no, on/off) expected "
     "(got 'maybe')"),
    (["--contour-field=nosuch"],
     "contour_field 'nosuch': no rank's grid has a cell field of that name"),
]
"""slice_image.py's contour settings that are refused, each with the error it must give."""


def check_contour_settings_refused(output, command):
    """COMMAND runs the mini-app with slice_image.py as its only pipeline; each of
    REFUSED_CONTOUR_SETTINGS is added to it in turn: the script fails (at import, or at
    its first step for a field the grid lacks), the run goes on and reports one pipeline
    failure, and the failure's message is the one expected, naming the setting."""
    shutil.rmtree(output, ignore_errors=True)
    for given, message in REFUSED_CONTOUR_SETTINGS:
        arguments = [word for argument in given for word in ("--pipeline-arg", argument)]
        code, log = run(command + arguments)
        expect(code == 0 and "1 pipeline failure(s)" in log and
               re.search(r"rank 0, step 0: the script '.*slice_image.py' .*ValueError: " +
                         re.escape(message), log) is not None,
               "%s: the script is refused with \"%s\", the run goes on" % (" ".join(given), message))


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


def option(command, name, default):
    """The value after `name` in COMMAND, or the default."""
    return command[command.index(name) + 1] if name in command else default


class Forest:
    """The mini-app's leaves from its dump (level, i, j, k -> value) on `roots`^d root
    cells of a binary periodic forest: face neighbours and the scalar's limited slopes
    as docs/miniapp.md states them (Simulation::sampleBlocks), rewritten here."""

    def __init__(self, leaves, roots, dimension):
        self.leaves, self.roots, self.dimension = leaves, roots, dimension

    def size(self, level):
        return 1.0 / (self.roots * 2 ** level)

    def _leaves_touching(self, key, axis, side):
        """Leaves of the subtree at `key` touching its face on the side facing `side`."""
        if key in self.leaves:
            return [key]
        level, position = key[0], key[1:]
        found = []
        for child in range(2 ** self.dimension):
            digits = [(child >> a) & 1 if a < self.dimension else 0 for a in range(3)]
            if digits[axis] != (0 if side > 0 else 1):
                continue
            found += self._leaves_touching(
                (level + 1,) + tuple(position[a] * (2 if a < self.dimension else 1) + digits[a]
                                     for a in range(3)), axis, side)
        return found

    def parent(self, key):
        return (key[0] - 1,) + tuple(p // 2 if a < self.dimension else p
                                     for a, p in enumerate(key[1:]))

    def across(self, key, axis, side):
        """The leaves across a face: one same-level or coarser leaf, or the finer ones."""
        level, position = key[0], list(key[1:])
        position[axis] = (position[axis] + side) % (self.roots * 2 ** level)
        probe = (level,) + tuple(position)
        ancestor = probe
        while ancestor not in self.leaves and ancestor[0] > 0:
            ancestor = self.parent(ancestor)
        if ancestor in self.leaves:
            return [ancestor]
        return self._leaves_touching(probe, axis, side)

    def slopes(self, key, n):
        """The scalar's slopes in a leaf shown as an n^d block."""
        u, h = self.leaves[key], self.size(key[0])
        slopes = [0.0, 0.0, 0.0]
        low = high = u
        for axis in range(self.dimension):
            sided = []
            for side in (-1, 1):
                area = value = distance = 0.0
                for other in self.across(key, axis, side):
                    face = self.size(max(key[0], other[0])) ** (self.dimension - 1)
                    low, high = min(low, self.leaves[other]), max(high, self.leaves[other])
                    area += face
                    value += face * self.leaves[other]
                    distance += face * 0.5 * (h + self.size(other[0]))
                sided.append(side * (value / area - u) / (distance / area))
            if sided[0] * sided[1] > 0:
                slopes[axis] = sided[0] if abs(sided[0]) < abs(sided[1]) else sided[1]
        reach = sum(abs(s) for s in slopes) * (n - 1) / (2.0 * n) * h
        room = min(high - u, u - low)
        if reach > room:
            slopes = [s * room / reach for s in slopes]
        return slopes, (low, high)


def largest(worst, differences):
    """The larger of worst and the largest |difference|; infinite if one is NaN."""
    differences = numpy.abs(numpy.asarray(differences, dtype=float))
    return max(worst, float(differences.max()) if numpy.isfinite(differences).all() else math.inf)


def read_vtkhdf_cells(path):
    """Every cell of the last step of a VTKHDF hypertree grid (h5py, its descriptors
    decoded here, level by level): numpy arrays of each cell's depth, integer position
    at that depth (cells x 3), whether it is refined, and {array: values}, rows in the
    file's order."""
    import h5py
    with h5py.File(path, "r") as f:
        root = f["VTKHDF"]
        steps = root["Steps"]
        k = int(steps.attrs["NSteps"]) - 1
        dims = [int(n) for n in root.attrs["Dimensions"]]
        roots = [max(1, n - 1) for n in dims]
        bf = int(root.attrs["BranchFactor"])
        dimension = sum(n > 1 for n in dims)
        children = bf ** dimension
        digits = numpy.array([[(c // bf ** a) % bf if a < dimension else 0 for a in range(3)]
                              for c in range(children)], dtype=numpy.int64)
        scale = numpy.array([bf if a < dimension else 1 for a in range(3)], dtype=numpy.int64)
        part = int(steps["PartOffsets"][k])
        tree_at = int(steps["TreeIdsOffsets"][k])
        descriptor_at = int(steps["DescriptorsOffsets"][k])
        depth, position, refined = [], [], []
        for piece in range(int(steps["NumberOfParts"][k])):
            n_trees = int(root["NumberOfTrees"][part + piece])
            n_bits = int(root["DescriptorsSize"][part + piece])
            bits = numpy.unpackbits(
                root["Descriptors"][descriptor_at:descriptor_at + (n_bits + 7) // 8],
                bitorder="big")[:n_bits].astype(bool)
            descriptor_at += (n_bits + 7) // 8
            bit = 0
            for tree_id, depths in zip(root["TreeIds"][tree_at:tree_at + n_trees].tolist(),
                                       root["DepthPerTree"][tree_at:tree_at + n_trees].tolist()):
                level = numpy.array([[tree_id % roots[0], (tree_id // roots[0]) % roots[1],
                                      tree_id // (roots[0] * roots[1])]], dtype=numpy.int64)
                for d in range(depths):
                    count = len(level)
                    split = (bits[bit:bit + count] if d < depths - 1
                             else numpy.zeros(count, dtype=bool))
                    bit += count if d < depths - 1 else 0
                    depth.append(numpy.full(count, d))
                    position.append(level)
                    refined.append(split)
                    # Children of the refined cells, in order, each in child order.
                    level = (level[split][:, None, :] * scale + digits[None, :, :]).reshape(-1, 3)
            tree_at += n_trees
        rows = sum(len(d) for d in depth)
        values = {name: root["CellData"][name][int(steps["CellDataOffsets"][name][k]):][:rows]
                  for name in root["CellData"]}
        return (numpy.concatenate(depth), numpy.concatenate(position),
                numpy.concatenate(refined), values)


def check_insitu_blocks(output, command):
    """The mini-app with --blocks N (a block forest) and its default pipelines, at the
    last step (an image, selection and extract step), against its own dump: the grid
    extracts hold every leaf as N^d cells below it (VTKHDF cell count from the dump:
    nodes + leaves x (c + c^2 + ... + c^levels), c = 2^d), each cell's velocity the
    swirl at its centre, level and rank the leaf's, scalar the leaf's value with the
    documented limited slopes (recomputed here), the block's coarse cell the leaf's
    value; the selection and the surface from those cells; images in colour, and with
    REFERENCE=<dir> equal to that run's (1 rank)."""
    shutil.rmtree(output, ignore_errors=True)
    code, log = run(command + ["--dump", os.path.join(output, "final.txt")])
    expect(code == 0, "the mini-app exits normally")
    expect("simulation arrays untouched by Canopy: yes" in log,
           "Canopy left the arrays (blocks and their address tables) untouched")
    expect(re.search(r"0 pipeline failure\(s\)", log) is not None, "no pipeline failed")
    noisy = [line for line in log.splitlines() if re.search(r"WARN|Warning|ERROR|rror", line)]
    expect(not noisy, "no warning or error in the output (%d line(s)%s)"
           % (len(noisy), (": " + noisy[0].strip()) if noisy else ""))
    if code != 0:
        return
    n = int(option(command, "--blocks", 0))
    dimension = int(option(command, "--dimension", 2))
    roots = int(option(command, "--roots", 16))
    ranks = int(option(command, "-np", 1))
    sub = int(round(math.log2(n)))
    children = 2 ** dimension
    last = [int(s) for s in re.findall(r"^step\s+(\d+)", log, re.M)][-1]
    final = read_dump(os.path.join(output, "final.txt"))
    forest = Forest(final, roots, dimension)
    leaves = len(final)
    nodes = leaves + (leaves - roots ** dimension) // (children - 1)
    want_cells = nodes + leaves * sum(children ** s for s in range(1, sub + 1))
    expect(("blocks of %d^%d cells" % (n, dimension)) in log, "the run says its blocks")

    # The grid as written (VTKHDF, decoded here), and the .htg pieces (ParaView 5.11).
    hdf_cells = vtkhdf_cells_per_step(os.path.join(output, "grid.vtkhdf"))
    expect(hdf_cells and hdf_cells[-1] == want_cells,
           "grid.vtkhdf: the last step has %d cells; the dump's %d leaves give %d nodes + "
           "%d leaves x %d cells at %d levels inside each block = %d"
           % (hdf_cells[-1] if hdf_cells else -1, leaves, nodes, leaves,
              sum(children ** s for s in range(1, sub + 1)), sub, want_cells))
    pieces = read_htg_pieces(output, "grid", last)
    expect(len(pieces) == ranks and sum(g.GetNumberOfCells() for g in pieces) == want_cells,
           "grid_%06d/*.htg: %d pieces, %d cells" % (last, len(pieces),
                                                    sum(g.GetNumberOfCells() for g in pieces)))
    multiblock = read_multiblock(os.path.join(output, "grid_%06d.vtm" % last))
    htg_leaves = sum(multiblock.GetBlock(b).GetNumberOfLeaves()
                     for b in range(multiblock.GetNumberOfBlocks()))
    expect(htg_leaves == leaves * n ** dimension, "grid_%06d.vtm: %d leaves = %d blocks x %d^%d"
           % (last, htg_leaves, leaves, n, dimension))

    depth, position, refined, values = read_vtkhdf_cells(os.path.join(output, "grid.vtkhdf"))
    row_of = {key: row for row, key in enumerate(
        zip(depth.tolist(), *(position[:, a].tolist() for a in range(3))))}
    expect(len(row_of) == len(depth) == want_cells, "every cell of the grid is a distinct box")
    expect(all(numpy.isfinite(values[name]).all() for name in values),
           "no NaN anywhere in the grid: ghost cells (NaN in the blocks) are never read")
    per = n ** dimension
    # A block's cells, in the order [k][j][i] (i fastest), as offsets at its finest depth.
    offsets = numpy.array([[(c // n ** a) % n if a < dimension else 0 for a in range(3)]
                           for c in range(per)], dtype=numpy.int64)
    factor = numpy.array([n if a < dimension else 1 for a in range(3)], dtype=numpy.int64)
    expected_rows = []
    wrong = {"block root": [], "missing": 0, "level": [], "rank": [], "bounds": 0}
    worst = {"scalar": 0.0, "velocity": 0.0, "root": 0.0}
    for (level, i, j, k), u in sorted(final.items()):
        root_row = row_of.get((level, i, j, k))
        if root_row is None or not refined[root_row]:
            wrong["block root"].append((level, i, j, k))
            continue
        # Canopy's coarse value of the block's own cell: the mean of its cells, u.
        worst["root"] = largest(worst["root"], values["scalar"][root_row] - u)
        cells = numpy.array((i, j, k), dtype=numpy.int64) * factor + offsets
        rows = [row_of.get((level + sub, a, b, c)) for a, b, c in cells.tolist()]
        if None in rows or refined[rows].any():
            wrong["missing"] += 1
            continue
        expected_rows += rows
        slopes, (low, high) = forest.slopes((level, i, j, k), n)
        h = forest.size(level)
        want = u + sum(slopes[a] * (2 * offsets[:, a] + 1 - n) / (2.0 * n) * h
                       for a in range(dimension))
        scalar = values["scalar"][rows]
        worst["scalar"] = largest(worst["scalar"], scalar - want)
        wrong["bounds"] += int(((scalar < low - 1e-14) | (scalar > high + 1e-14)).sum())
        centre = [(cells[:, a] + 0.5) * forest.size(level + sub) if a < dimension
                  else numpy.zeros(per) for a in range(3)]
        sx, sy = numpy.sin(numpy.pi * centre[0]), numpy.sin(numpy.pi * centre[1])
        # The swirl (the default velocity; 3D: w = 0.5) at the cells' centres.
        swirl = numpy.stack([sx * sx * numpy.sin(2 * numpy.pi * centre[1]),
                             -sy * sy * numpy.sin(2 * numpy.pi * centre[0]),
                             numpy.full(per, 0.5 if dimension == 3 else 0.0)], axis=1)
        worst["velocity"] = largest(worst["velocity"], values["velocity"][rows] - swirl)
        if (values["level"][rows] != level).any():
            wrong["level"].append((level, i, j, k))
        owners = numpy.unique(values["rank"][rows])
        if len(owners) != 1 or not 0 <= owners[0] < ranks:
            wrong["rank"].append((level, i, j, k))
    grid_leaves = numpy.flatnonzero(~refined)
    expect(not wrong["block root"] and not wrong["missing"] and
           sorted(expected_rows) == grid_leaves.tolist(),
           "the grid's %d leaves are the dump's %d leaves, each a refined cell split into "
           "%d^%d cells (%d leaves not refined, %d blocks incomplete)"
           % (len(grid_leaves), leaves, n, dimension, len(wrong["block root"]), wrong["missing"]))
    expect(worst["velocity"] <= 1e-12, "velocity at each of the %d block cells is the swirl at "
           "its centre (largest difference %.1e)" % (leaves * per, worst["velocity"]))
    expect(worst["scalar"] <= 1e-12, "scalar at each block cell is the leaf's value with its "
           "limited slopes, recomputed from the dump (largest difference %.1e)" % worst["scalar"])
    expect(not wrong["bounds"], "no block cell outside the range of its leaf's and the face "
           "neighbours' values (%d outside)" % wrong["bounds"])
    expect(worst["root"] <= 1e-12, "each block's own (coarse) cell holds the leaf's value: the "
           "mean of its cells (largest difference %.1e)" % worst["root"])
    expect(not wrong["level"] and not wrong["rank"], "level the leaf's and rank one owner per "
           "block (%d, %d blocks wrong)" % (len(wrong["level"]), len(wrong["rank"])))
    selected = sorted(float(v) for v in values["scalar"][grid_leaves] if v >= 0.5)

    # The selection (scalar >= 0.5) at the last step: the block cells that have it.
    selection = read_unstructured(os.path.join(output, "selection_%06d.pvtu" % last))
    got = (sorted(cell_array(selection, "scalar").tolist())
           if selection.GetNumberOfCells() > 0 else [])
    expect(len(got) == len(selected) and len(got) > 0 and got == selected,
           "selection at step %d: %d cells, %d block cells have scalar >= 0.5, same values"
           % (last, len(got), len(selected)))

    surface = read_polydata(os.path.join(output, "grid_surface_%06d.pvtp" % last))
    if dimension == 2:
        want_quads, where = leaves * per, "one quad per block cell"
    else:
        # The domain's boundary: each leaf's face on it in n^2 quads.
        want_quads, where = 0, "the domain's boundary, n^2 quads per leaf face on it"
        for (level, i, j, k) in final:
            last_index = roots * 2 ** level - 1
            want_quads += per // n * sum((p == 0) + (p == last_index) for p in (i, j, k))
    expect(surface.GetNumberOfCells() == want_quads, "grid_surface_%06d.pvtp: %d quads, %s: %d"
           % (last, surface.GetNumberOfCells(), where, want_quads))

    reference = os.environ.get("REFERENCE")
    prefixes = ("surface", "zoom") if dimension == 2 else ("slices", "region")
    images = sorted(glob.glob(os.path.join(output, "*.png")))
    for prefix in prefixes:
        count = len([name for name in images if os.path.basename(name).startswith(prefix + "_")])
        expect(count >= 2, "%d %s images" % (count, prefix))
    for name in images:
        pixels = read_png(name)
        expect(len(numpy.unique(pixels.reshape(-1, 3), axis=0)) > 50,
               "%s shows the colour map" % os.path.basename(name))
        if not reference:
            continue
        base = os.path.basename(name)
        theirs = os.path.join(reference, base)
        expect(os.path.exists(theirs), "%s in the reference run too" % base)
        if not os.path.exists(theirs):
            continue
        if base.startswith("region"):
            # A 3D surface with its cells' edges: where an anti-aliased mesh line meets
            # the faces, compositing several ranks' images rounds a few line pixels
            # differently (by 1, rarely a few levels; the default 3D run without
            # --blocks does the same). Everything else must be equal.
            other = read_png(theirs)
            change = numpy.abs(pixels.astype(int) - other.astype(int)).max(axis=2)
            differing = int((change > 0).sum())
            expect(change.max() <= 8 and differing <= 0.002 * change.size,
                   "%s equal to the reference run's but for compositing rounding on mesh "
                   "lines: %d pixels (at most 0.2%%) differ, by at most %d (at most 8)"
                   % (base, differing, change.max()))
            continue
        ties = 8 if base.startswith("slices") else 0
        differing, unexplained = compare_images(pixels, read_png(theirs), ties,
                                                shading=2 if ties else 0)
        expect(unexplained == 0, "%s identical to the reference run's (%d pixels differ, %d "
               "of them not a depth tie where planes meet nor a level of lighting)" % (base, differing, unexplained))


EXACT_LINE = re.compile(r"^exact: (\S+) level (\d+) leaves (\d+) h (\S+) time (\S+) "
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
