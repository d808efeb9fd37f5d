"""Runs the p4est example simulation (examples/p4est) and checks what Canopy's
shipped pipelines wrote against what the simulation itself counted:

  p4est_front_check.py DIMENSION OUTPUT [REFERENCE] -- command...

- the run succeeds and prints no warning or error;
- every executed step has its image, selection and hypertree-grid extracts;
- the selection holds exactly the quadrants the simulation counts with a density
  in [1.9, 2.1] (p4est_iterate on every rank, reduced);
- the hypertree-grid extract's pieces (one per rank; other ranks' parts of split
  trees are masked there, and skipped) together have exactly one unmasked leaf per
  quadrant, and their densities have the mass sum(density * volume) the simulation
  computes itself with p4est (to 1e-12, relative), and its minimum and maximum;
- 2D: the full-resolution surface has exactly one quad per quadrant of the forest,
  and its densities times the quads' areas add up to the same mass;
- images: 2D the adaptive surface (surface_<step>.png), 3D the slices and the dense
  region's surface (slices_<step>.png, region_<step>.png), each showing the density's
  colours (not a blank or single-colour picture);
- with REFERENCE (the same run on one rank): every image is identical to it.
"""
import math
import os
import re
import shutil
import sys
import time

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import (cell_array, compare_images, expect, finish,  # noqa: E402
                           read_htg_pieces, read_png,
                           read_polydata, read_unstructured, run_command)
from paraview.vtk.util.numpy_support import vtk_to_numpy  # noqa: E402
from paraview.vtk.vtkCommonDataModel import (  # noqa: E402
    vtkHyperTreeGridNonOrientedGeometryCursor)


def htg_leaves(grids):
    """(densities, volumes, masked cells skipped) of the unmasked leaves of all the
    pieces, walked with VTK's cursors. A rank's piece holds the trees it has
    quadrants in; another rank's part of a split tree is a masked (absent) cell."""
    densities, volumes = [numpy.zeros(0)], [numpy.zeros(0)]
    masked = 0
    cursor = vtkHyperTreeGridNonOrientedGeometryCursor()
    bounds = [0.0] * 6
    for grid in grids:
        values = vtk_to_numpy(grid.GetCellData().GetArray("density"))
        indices, sizes = [], []
        axes = [a for a, n in enumerate(grid.GetDimensions()) if n > 1]  # 2D: z is flat

        def walk():
            nonlocal masked
            if cursor.IsMasked():  # a masked cell's subtree is masked too
                masked += 1
            elif cursor.IsLeaf():
                indices.append(cursor.GetGlobalNodeIndex())
                cursor.GetBounds(bounds)
                sizes.append(math.prod(bounds[2 * a + 1] - bounds[2 * a] for a in axes))
            else:
                for child in range(cursor.GetNumberOfChildren()):
                    cursor.ToChild(child)
                    walk()
                    cursor.ToParent()

        for tree in range(grid.GetMaxNumberOfTrees()):
            if grid.GetTree(tree) is not None:  # trees this rank has nothing of are absent
                grid.InitializeNonOrientedGeometryCursor(cursor, tree)
                walk()
        densities.append(values[numpy.array(indices, dtype=numpy.int64)])
        volumes.append(numpy.array(sizes))
    return numpy.concatenate(densities), numpy.concatenate(volumes), masked


def polygon_areas(polydata):
    """The area of each polygon of a polydata (planar polygons, any number of sides)."""
    polys = polydata.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    corners = vtk_to_numpy(polys.GetConnectivityArray())
    points = vtk_to_numpy(polydata.GetPoints().GetData())[corners]
    following = numpy.arange(1, len(corners) + 1)
    following[offsets[1:] - 1] = offsets[:-1]  # each polygon's last corner wraps to its first
    crossed = numpy.cross(points, points[following])
    return 0.5 * numpy.linalg.norm(numpy.add.reduceat(crossed, offsets[:-1]), axis=1)


def close(value, expected, relative=1e-12):
    return abs(value - expected) <= relative * abs(expected)

separator = sys.argv.index("--")
arguments = sys.argv[1:separator]
dimension = int(arguments[0])
output = arguments[1]
reference = arguments[2] if len(arguments) > 2 else None
shutil.rmtree(output, ignore_errors=True)
status, log = run_command(sys.argv[separator + 1:])
if status != 0 or re.search(r"WARN|ERR|Warning|Error", log):
    print(log)  # what went wrong, for whoever reads the test's output
expect(status == 0, "the simulation exits with 0 (got %d)" % status)
expect(not re.search(r"WARN|ERR|Warning|Error", log), "no warning or error in the output")

steps = [(int(s), int(q), int(d)) for s, q, d in re.findall(
    r"p4est_front: step (\d+): (\d+) quadrants, (\d+) with density", log)]
expect(len(steps) >= 2, "the simulation reported %d executed steps" % len(steps))
number = r"([-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|inf|nan))"
totals = {int(s): (float(m), float(low), float(high)) for s, m, low, high in re.findall(
    r"p4est_front: step (\d+): mass %s, density from %s to %s" % ((number,) * 3), log)}
expect(sorted(totals) == [step for step, _, _ in steps],
       "the simulation reported mass and density range for its executed steps %s (got %s)"
       % ([step for step, _, _ in steps], sorted(totals)))
for step, quadrants, dense in steps:
    name = "%06d" % step
    mass, low, high = totals.get(step, (math.nan,) * 3)
    images = ["surface"] if dimension == 2 else ["slices", "region"]
    for prefix in images:
        image = os.path.join(output, "%s_%s.png" % (prefix, name))
        expect(os.path.exists(image), "step %d: %s written" % (step, os.path.basename(image)))
        if os.path.exists(image):
            pixels = read_png(image)
            colours = len({tuple(p) for p in pixels.reshape(-1, pixels.shape[2])[::7]})
            expect(colours > 50, "step %d: %s shows the colour map (%d colours sampled)"
                   % (step, os.path.basename(image), colours))
    selection = read_unstructured(os.path.join(output, "selection_%s.pvtu" % name))
    expect(selection.GetNumberOfCells() == dense,
           "step %d: the selection has %d cells, the simulation counts %d quadrants in range"
           % (step, selection.GetNumberOfCells(), dense))
    if selection.GetNumberOfCells():
        density = cell_array(selection, "density")
        expect(density.min() >= 1.9 and density.max() <= 2.1,
               "step %d: selected densities within [1.9, 2.1]" % step)
    pieces = read_htg_pieces(output, "grid", step)
    expect(os.path.exists(os.path.join(output, "grid_%s.vtm" % name)) and pieces
           and all(piece.GetNumberOfCells() > 0 for piece in pieces),
           "step %d: hypertree-grid extract written (grid_%s.vtm, %d .htg piece(s))"
           % (step, name, len(pieces)))
    started = time.perf_counter()
    densities, volumes, masked = htg_leaves(pieces)
    walked = time.perf_counter() - started
    expect(len(densities) == quadrants,
           "step %d: the .htg pieces have %d unmasked leaves together (%d masked cells of "
           "other ranks skipped; walked in %.2f s), the simulation %d quadrants"
           % (step, len(densities), masked, walked, quadrants))
    leaf_mass = math.fsum(densities * volumes)
    expect(close(leaf_mass, mass),
           "step %d: the .htg leaves' mass sum(density * volume) is %.17g, the simulation's "
           "%.17g (relative difference %.3g, at most 1e-12)"
           % (step, leaf_mass, mass, abs(leaf_mass - mass) / abs(mass) if mass else math.inf))
    if len(densities):
        expect(densities.min() == low and densities.max() == high,
               "step %d: the .htg leaves' densities are in [%.17g, %.17g], the simulation's "
               "in [%.17g, %.17g]" % (step, densities.min(), densities.max(), low, high))
    if dimension == 2:
        surface = read_polydata(os.path.join(output, "grid_surface_%s.pvtp" % name))
        expect(surface.GetNumberOfCells() == quadrants,
               "step %d: full surface has %d quads for %d quadrants"
               % (step, surface.GetNumberOfCells(), quadrants))
        expect(surface.GetNumberOfPolys() == surface.GetNumberOfCells(),
               "step %d: the full surface is polygons only" % step)
        surface_mass = (math.fsum(cell_array(surface, "density") * polygon_areas(surface))
                        if surface.GetNumberOfPolys() == surface.GetNumberOfCells() else math.nan)
        expect(close(surface_mass, mass),
               "step %d: the full surface's mass sum(density * area) is %.17g, the "
               "simulation's %.17g (relative difference %.3g, at most 1e-12)"
               % (step, surface_mass, mass,
                  abs(surface_mass - mass) / abs(mass) if mass else math.inf))
    for prefix in images if reference else []:
        image = "%s_%s.png" % (prefix, name)
        both = [os.path.join(folder, image) for folder in (output, reference)]
        expect(all(os.path.exists(path) for path in both),
               "step %d: %s in this run and in the 1-rank run" % (step, image))
        if all(os.path.exists(path) for path in both):
            # Slices: a few depth ties where planes meet (compare_images).
            differing, unexplained = compare_images(*(read_png(path) for path in both),
                                                    ties=8 if prefix == "slices" else 0)
            expect(unexplained == 0, "step %d: %s identical to the 1-rank run (%d pixels "
                   "differ, %d of them not a depth tie where planes meet)"
                   % (step, image, differing, unexplained))
finish()
