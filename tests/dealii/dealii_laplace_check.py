"""Runs the deal.II example (examples/dealii, step-40's adaptive Laplace problem)
and checks what Canopy's shipped pipelines wrote against what the program itself
computed with deal.II:

  dealii_laplace_check.py DIMENSION OUTPUT -- command...

- the run succeeds and prints no warning or error;
- every executed cycle has its image (2D the surface, 3D the slices), selection and
  grid extracts, and the VTKHDF file holds every cycle with one cell per grid cell;
- the selection (error indicator >= the threshold) holds exactly the cells the
  program counts in its Kelly vector;
- the hypertree-grid extract's pieces together have exactly one unmasked leaf per
  active cell (n_global_active_cells), their error indicators add up to the
  program's sum, and their cell averages of u times the cells' volumes add up to
  the integral of u deal.II computes (VectorTools::compute_mean_value, to 1e-10);
- 2D: the full-resolution surface has exactly one quad per active cell.
"""
import math
import os
import re
import shutil
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import (cell_array, expect, finish, read_htg_pieces,  # noqa: E402
                           read_png, read_polydata, read_unstructured, run_command,
                           vtkhdf_cells_per_step)
from paraview.vtk.util.numpy_support import vtk_to_numpy  # noqa: E402
from paraview.vtk.vtkCommonDataModel import (  # noqa: E402
    vtkHyperTreeGridNonOrientedGeometryCursor)


def htg_leaves(grids, names):
    """{name: values} and volumes of the unmasked leaves of all the pieces."""
    values = {name: [] for name in names}
    volumes = []
    cursor = vtkHyperTreeGridNonOrientedGeometryCursor()
    bounds = [0.0] * 6
    for grid in grids:
        arrays = {name: vtk_to_numpy(grid.GetCellData().GetArray(name)) for name in names}
        axes = [a for a, n in enumerate(grid.GetDimensions()) if n > 1]
        indices = []

        def walk():
            if cursor.IsMasked():
                return
            if cursor.IsLeaf():
                indices.append(cursor.GetGlobalNodeIndex())
                cursor.GetBounds(bounds)
                volumes.append(math.prod(bounds[2 * a + 1] - bounds[2 * a] for a in axes))
                return
            for child in range(cursor.GetNumberOfChildren()):
                cursor.ToChild(child)
                walk()
                cursor.ToParent()

        for tree in range(grid.GetMaxNumberOfTrees()):
            if grid.GetTree(tree) is not None:
                grid.InitializeNonOrientedGeometryCursor(cursor, tree)
                walk()
        for name in names:
            values[name].append(arrays[name][numpy.array(indices, dtype=numpy.int64)])
    return ({name: numpy.concatenate(v) if v else numpy.zeros(0) for name, v in values.items()},
            numpy.array(volumes))


separator = sys.argv.index("--")
dimension, output = int(sys.argv[1]), sys.argv[2]
shutil.rmtree(output, ignore_errors=True)
status, log = run_command(sys.argv[separator + 1:])
bad = re.search(r"WARN|ERR|Warning|Error|canopy: ", log)
expect(status == 0, "the program exits with 0 (got %d)" % status)
expect(not bad, "no warning or error in the output")

number = r"([-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|inf|nan))"
cycles = {int(c): (int(n), int(f)) for c, n, f in re.findall(
    r"dealii_laplace: cycle (\d+): (\d+) cells, (\d+) with error >= ", log)}
totals = {int(c): (float(i), float(e)) for c, i, e in re.findall(
    r"dealii_laplace: cycle (\d+): integral of u %s, error sum %s" % (number, number), log)}
expect(len(cycles) >= 2 and sorted(cycles) == sorted(totals),
       "the program reported counts and totals for its executed cycles (%s)" % sorted(cycles))
for cycle in sorted(cycles):
    cells, flagged = cycles[cycle]
    integral, error_sum = totals.get(cycle, (math.nan, math.nan))
    name = "%06d" % cycle
    image = os.path.join(output, ("surface_%s.png" if dimension == 2 else "slices_%s.png") % name)
    expect(os.path.exists(image), "cycle %d: %s written" % (cycle, os.path.basename(image)))
    if os.path.exists(image):
        pixels = read_png(image)
        colours = len({tuple(p) for p in pixels.reshape(-1, pixels.shape[2])[::7]})
        expect(colours > 50, "cycle %d: %s shows the colour map (%d colours sampled)"
               % (cycle, os.path.basename(image), colours))
    expect(0 < flagged < cells, "cycle %d: the program counts %d of %d cells over the "
           "threshold (the selection is neither empty nor everything)" % (cycle, flagged, cells))
    selection = read_unstructured(os.path.join(output, "selection_%s.pvtu" % name))
    expect(selection.GetNumberOfCells() == flagged,
           "cycle %d: the selection has %d cells, the program counts %d with error >= threshold"
           % (cycle, selection.GetNumberOfCells(), flagged))
    pieces = read_htg_pieces(output, "grid", cycle)
    expect(len(pieces) > 0, "cycle %d: grid extract written (%d .htg pieces)" % (cycle, len(pieces)))
    values, volumes = htg_leaves(pieces, ["u", "error"])
    expect(len(volumes) == cells, "cycle %d: the pieces have %d unmasked leaves, deal.II %d "
           "active cells" % (cycle, len(volumes), cells))
    leaf_integral = math.fsum(values["u"] * volumes)
    expect(abs(leaf_integral - integral) <= 1e-10 * abs(integral),
           "cycle %d: sum(u average * volume) over the leaves is %.17g, deal.II's integral of u "
           "%.17g" % (cycle, leaf_integral, integral))
    leaf_error = math.fsum(values["error"])
    expect(abs(leaf_error - error_sum) <= 1e-12 * abs(error_sum),
           "cycle %d: the leaves' error indicators add up to %.17g, the program's %.17g"
           % (cycle, leaf_error, error_sum))
    if dimension == 2:
        surface = read_polydata(os.path.join(output, "grid_surface_%s.pvtp" % name))
        expect(surface.GetNumberOfCells() == cells,
               "cycle %d: the full surface has %d quads for %d cells"
               % (cycle, surface.GetNumberOfCells(), cells))
vtkhdf = os.path.join(output, "grid.vtkhdf")
expect(os.path.exists(vtkhdf), "grid.vtkhdf written")
if os.path.exists(vtkhdf):
    per_step = vtkhdf_cells_per_step(vtkhdf)
    expect(len(per_step) == len(cycles),
           "grid.vtkhdf holds %d steps, the program executed %d" % (len(per_step), len(cycles)))
    for cycle, stored in zip(sorted(cycles), per_step):
        pieces = read_htg_pieces(output, "grid", cycle)
        expected = sum(piece.GetNumberOfCells() for piece in pieces)
        expect(stored == expected, "cycle %d: grid.vtkhdf has %d cells, the .htg pieces %d"
               % (cycle, stored, expected))
finish()
