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
- 3D, the front's isosurface (density 1.5: the sphere of radius 0.8 the example moves,
  centred at (1 + 1.6 t, 1.5, 1)): the slices image shows it where the sphere faces the
  camera (grey, the colour map's middle, where the slices behind it are red), and
  slices_contour_<step>.pvtp, opened by ParaView's own reader (pvpython, PVPYTHON in the
  environment), has as many triangles as the step's "slices contour triangles" measure,
  density 1.5 at every point, Normals out of the sphere, no open edge, every point at
  0.8 from the centre to h/8 (h the finest quadrant's side);
- with REFERENCE (the same run on one rank): every image is identical to it, and 3D
  isosurfaces have its triangles and area (1e-9).
"""
import json
import math
import os
import re
import shutil
import sys
import time

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import (cell_array, check_isosurface_extract, compare_images,  # noqa: E402
                           expect, finish, read_htg_pieces, read_png, read_polydata,
                           read_unstructured, read_with_paraview, run_command)
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


FRONT_RADIUS = 0.8
FRONT_LEVEL = 1.5  # the density on the front: 1.5 - 0.5 tanh(0)
MAX_LEVEL_3D = 4  # the example's default maximum level in 3D (unit trees)


def front_centre(step_time):
    """The front's centre at a time (examples/p4est/p4est_front.cxx, advance)."""
    return numpy.array([1.0 + 1.6 * step_time, 1.5, 1.0])


def facing_pixel(centre, width, height):
    """(column, row from the bottom) where the sphere's point nearest the camera is seen by
    the image scripts' default camera (canopy_catalyst.frame_bounds on the 4 x 3 x 2
    brick: perspective, 30 degrees, from its centre + (1.2, 0.9, 1.5) x its diagonal, y
    up), projected with VTK's own camera."""
    from paraview.vtk.vtkRenderingCore import vtkCamera
    middle = numpy.array([2.0, 1.5, 1.0])
    diagonal = math.sqrt(4.0 ** 2 + 3.0 ** 2 + 2.0 ** 2)
    eye = middle + diagonal * numpy.array([1.2, 0.9, 1.5])
    camera = vtkCamera()
    camera.SetFocalPoint(*middle)
    camera.SetPosition(*eye)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(30.0)
    camera.SetClippingRange(0.01, 100.0)  # x and y do not depend on it
    matrix = camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1)
    toward = (eye - centre) / numpy.linalg.norm(eye - centre)
    point = list(centre + FRONT_RADIUS * toward) + [1.0]
    clip = [sum(matrix.GetElement(r, c) * point[c] for c in range(4)) for r in range(4)]
    return (int(round((clip[0] / clip[3] + 1) / 2 * width)),
            int(round((clip[1] / clip[3] + 1) / 2 * height)))


def check_isosurface(output, step, step_time, log, found):
    """The front's isosurface at a 3D step: in the slices image and as an extract."""
    name = "%06d" % step
    centre = front_centre(step_time)
    image = os.path.join(output, "slices_%s.png" % name)
    if os.path.exists(image):
        pixels = read_png(image).astype(int)
        height, width, _ = pixels.shape
        column, row = facing_pixel(centre, width, height)
        patch = pixels[row - 2:row + 3, column - 2:column + 3].reshape(-1, 3)
        spread = int((patch.max(axis=1) - patch.min(axis=1)).max()) if len(patch) else -1
        expect(len(patch) == 25 and spread <= 12 and patch.min() >= 150,
               "step %d: slices_%s.png shows the front's isosurface where the sphere faces the "
               "camera (pixel %d, %d from the bottom left: grey, the colour map's middle; "
               "channels %s to %s, spread %d)" % (step, name, column, row,
                                                  patch.min(axis=0).tolist() if len(patch) else [],
                                                  patch.max(axis=0).tolist() if len(patch) else [],
                                                  spread))
    measured = re.search(r"p4est_front: step %d: slices contour triangles (\d+)" % step, log)
    expect(measured is not None, "step %d: the example printed the contour's triangles" % step)
    triangles = int(measured.group(1)) if measured else -1
    path = os.path.join(output, "slices_contour_%s.pvtp" % name)
    read = read_with_paraview(path, os.environ["PVPYTHON"])
    label = "step %d: slices_contour_%s.pvtp" % (step, name)
    area, _ = check_isosurface_extract(read, label, "density", FRONT_LEVEL, triangles, centre)
    if read is not None and len(read["points"]):
        distance = numpy.abs(numpy.linalg.norm(read["points"] - centre, axis=1) - FRONT_RADIUS)
        h = 1.0 / 2 ** MAX_LEVEL_3D
        expect(distance.max() <= h / 8, "%s: every point on the front's sphere to %.4f (h/8; "
               "largest distance %.5f)" % (label, h / 8, distance.max()))
    found[step] = (triangles, area)


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
found = {}  # 3D: step -> (isosurface triangles, area)
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
    if dimension == 3:
        check_isosurface(output, step, 0.1 * step, log, found)
    for prefix in images if reference else []:
        image = "%s_%s.png" % (prefix, name)
        both = [os.path.join(folder, image) for folder in (output, reference)]
        expect(all(os.path.exists(path) for path in both),
               "step %d: %s in this run and in the 1-rank run" % (step, image))
        if all(os.path.exists(path) for path in both):
            # Slices: a few depth ties where planes meet (compare_images).
            differing, unexplained = compare_images(*(read_png(path) for path in both),
                                                    ties=8 if prefix == "slices" else 0,
                                                    shading=2 if prefix == "slices" else 0)
            expect(unexplained == 0, "step %d: %s identical to the 1-rank run (%d pixels "
                   "differ, %d of them not a depth tie where planes meet nor a level of "
                   "lighting)"
                   % (step, image, differing, unexplained))
if dimension == 3:
    with open(os.path.join(output, "isosurfaces.json"), "w") as saved:
        json.dump(found, saved)
    if reference:
        with open(os.path.join(reference, "isosurfaces.json")) as saved:
            theirs = {int(step): value for step, value in json.load(saved).items()}
        for step, (triangles, area) in sorted(found.items()):
            other = theirs.get(step, (-1, math.nan))
            expect(triangles == other[0] and abs(area - other[1]) <= 1e-9 * other[1],
                   "step %d: the isosurface has %d triangles of area %.9g, the 1-rank run's %d "
                   "of area %.9g" % (step, triangles, area, other[0], other[1]))
finish()
