"""Runs the block-AMR example (examples/blocks) and checks what Canopy's shipped
pipelines wrote against what the simulation itself knows:

  block_advection_check.py DIMENSION RANKS OUTPUT [REFERENCE] -- command...

- the run succeeds and prints no warning or error (Canopy's step failures included);
- the mesh changed during the run (blocks refined or coarsened and moved between ranks);
- every executed step has its images, selection and hypertree-grid extracts;
- the hypertree-grid extract (one .htg piece per rank; other ranks' parts of split
  trees masked there) has exactly one unmasked leaf per interior cell of the
  simulation's blocks (blocks x 16^d), their densities the mass the simulation
  computes (to 1e-12, relative) and its minimum and maximum exactly; every leaf's
  velocity is the rotation's at the leaf's centre and, at step 0, its density the
  initial density there (so every interior cell is read from the right place, and
  no ghost cell is: ghosts the scheme never fills are NaN);
- grid.vtkhdf holds every executed step, with as many cells as the .htg pieces;
- the selection holds exactly the cells the simulation counts with density >= 1.5;
- 2D: the full-resolution surface has one quad per cell, with the same mass;
- images show the density's colours;
- with REFERENCE (the same run on one rank): the same mesh and values at every
  executed step (blocks, cells, counts, minimum and maximum exactly, mass to 1e-12),
  and every image identical to it (slices: up to 8 depth ties where planes meet).

When every check passes, the bulky extracts (hundreds of MB in 3D) are removed;
the images and the run's log (run.log) stay for the other rank counts' comparison.
"""
import glob
import math
import os
import re
import shutil
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import (FAILURES, cell_array, compare_images, expect,  # noqa: E402
                           finish, read_htg_pieces, read_png, read_polydata,
                           read_unstructured, run_command, vtkhdf_cells_per_step)
from paraview.vtk.util.numpy_support import vtk_to_numpy  # noqa: E402
from paraview.vtk.vtkFiltersHyperTree import vtkHyperTreeGridToUnstructuredGrid  # noqa: E402

OMEGA = 2 * math.pi


def initial_density(x, y, z, dimension):
    """examples/blocks/block_advection.cxx's initialDensity, vectorized."""
    disc = (x - 0.3) ** 2 + (y - 0.7) ** 2 + ((z - 0.5) ** 2 if dimension == 3 else 0)
    hump = (x - 0.7) ** 2 + (y - 0.3) ** 2 + ((z - 0.5) ** 2 if dimension == 3 else 0)
    return (1.0 + 0.5 * (1.0 - numpy.tanh((numpy.sqrt(disc) - 0.13) / 0.01))
            + numpy.exp(-hump / (2 * 0.06 * 0.06)))


def leaves(pieces, dimension):
    """(density, velocity, centres, volumes) of the unmasked leaves of all pieces:
    vtkHyperTreeGridToUnstructuredGrid makes one cell per unmasked leaf."""
    found = {"density": [], "velocity": [], "centres": [], "volumes": []}
    for piece in pieces:
        to_cells = vtkHyperTreeGridToUnstructuredGrid()
        to_cells.SetInputData(piece)
        to_cells.Update()
        cells = to_cells.GetOutput()
        count = cells.GetNumberOfCells()
        if count == 0:
            continue
        corners = vtk_to_numpy(cells.GetCells().GetConnectivityArray()).reshape(count, -1)
        points = vtk_to_numpy(cells.GetPoints().GetData())[corners]
        extent = points.max(axis=1) - points.min(axis=1)
        found["density"].append(cell_array(cells, "density"))
        found["velocity"].append(cell_array(cells, "velocity").reshape(count, dimension))
        found["centres"].append(points.mean(axis=1))
        found["volumes"].append(numpy.prod(extent[:, :dimension], axis=1))
    if not found["density"]:
        return numpy.zeros(0), numpy.zeros((0, dimension)), numpy.zeros((0, 3)), numpy.zeros(0)
    return tuple(numpy.concatenate(found[k]) for k in ("density", "velocity", "centres", "volumes"))


def close(value, expected, relative=1e-12):
    return abs(value - expected) <= relative * abs(expected)


def reported(log):
    """Per executed step: (blocks, levels, cells, dense) and (mass, minimum, maximum)."""
    counts = {int(s): (int(b), levels, int(c), int(d)) for s, b, levels, c, d in re.findall(
        r"block_advection: step (\d+): (\d+) blocks \(by level ([\d, ]+)\), (\d+) cells, "
        r"(\d+) with density", log)}
    number = r"([-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|inf|nan))"
    totals = {int(s): (float(m), float(low), float(high)) for s, m, low, high in re.findall(
        r"block_advection: step (\d+): mass %s, density from %s to %s" % ((number,) * 3), log)}
    return counts, totals


separator = sys.argv.index("--")
arguments = sys.argv[1:separator]
dimension, ranks, output = int(arguments[0]), int(arguments[1]), arguments[2]
reference = arguments[3] if len(arguments) > 3 else None
shutil.rmtree(output, ignore_errors=True)
status, log = run_command(sys.argv[separator + 1:])
os.makedirs(output, exist_ok=True)
with open(os.path.join(output, "run.log"), "w") as f:
    f.write(log)
if status != 0 or re.search(r"WARN|ERR|Warning|Error", log):
    print(log)  # what went wrong, for whoever reads the test's output
expect(status == 0, "the simulation exits with 0 (got %d; 1: Canopy reported a failed step)"
       % status)
expect(not re.search(r"WARN|ERR|Warning|Error", log), "no warning or error in the output")

counts, totals = reported(log)
steps = sorted(counts)
expect(len(steps) >= 2, "the simulation reported %d executed steps" % len(steps))
expect(sorted(totals) == steps, "the simulation reported mass and density range for its "
       "executed steps %s (got %s)" % (steps, sorted(totals)))
regrids = re.findall(r"block_advection: step (\d+): regrid: (\d+) -> (\d+) blocks", log)
expect(len(regrids) >= 1, "the mesh changed during the run (%d regrids changed it: %s)"
       % (len(regrids), ", ".join("step %s: %s -> %s" % r for r in regrids)))

vtkhdf_path = os.path.join(output, "grid.vtkhdf")
vtkhdf_cells = vtkhdf_cells_per_step(vtkhdf_path) if os.path.exists(vtkhdf_path) else []
expect(len(vtkhdf_cells) == len(steps), "grid.vtkhdf holds the %d executed steps (%d)"
       % (len(steps), len(vtkhdf_cells)))
images = ["surface"] if dimension == 2 else ["slices", "region"]
for number, step in enumerate(steps):
    name = "%06d" % step
    blocks, levels, cells, dense = counts[step]
    mass, low, high = totals.get(step, (math.nan,) * 3)
    expect(cells == blocks * 16 ** dimension, "step %d: %d blocks of 16^%d cells, %d cells"
           % (step, blocks, dimension, cells))
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
           "step %d: the selection has %d cells, the simulation counts %d with density >= 1.5"
           % (step, selection.GetNumberOfCells(), dense))
    if selection.GetNumberOfCells():
        expect(cell_array(selection, "density").min() >= 1.5,
               "step %d: selected densities >= 1.5" % step)

    pieces = read_htg_pieces(output, "grid", step)
    expect(len(pieces) == ranks, "step %d: grid_%s.vtm lists %d .htg pieces, one per rank"
           % (step, name, len(pieces)))
    if number < len(vtkhdf_cells):
        htg_cells = sum(piece.GetNumberOfCells() for piece in pieces)
        expect(vtkhdf_cells[number] == htg_cells, "step %d: grid.vtkhdf has %d cells, the .htg "
               "pieces %d" % (step, vtkhdf_cells[number], htg_cells))
    density, velocity, centres, volumes = leaves(pieces, dimension)
    expect(len(density) == cells, "step %d: the .htg pieces have %d unmasked leaves together, "
           "the simulation's blocks %d interior cells" % (step, len(density), cells))
    leaf_mass = math.fsum(density * volumes)
    expect(close(leaf_mass, mass),
           "step %d: the leaves' mass sum(density * volume) is %.17g, the simulation's %.17g"
           % (step, leaf_mass, mass))
    if len(density):
        expect(density.min() == low and density.max() == high,
               "step %d: the leaves' densities are in [%.17g, %.17g], the simulation's in "
               "[%.17g, %.17g]" % (step, density.min(), density.max(), low, high))
        # The centres come from the conversion's single-precision points (about 3e-8
        # off); a cell read from its neighbour's place would be off by a cell, 1/256 or
        # more: 0.025 in velocity, up to 0.2 in density at the disc's edge.
        x, y, z = centres[:, 0], centres[:, 1], centres[:, 2]
        expected = numpy.stack([-OMEGA * (y - 0.5), OMEGA * (x - 0.5), 0 * x][:dimension], 1)
        error = numpy.abs(velocity - expected).max()
        expect(error < 1e-5, "step %d: every leaf's velocity is the rotation's at its centre "
               "(largest difference %.3g, at most 1e-5)" % (step, error))
        if step == 0:
            error = numpy.abs(density - initial_density(x, y, z, dimension)).max()
            expect(error < 1e-4, "step 0: every leaf's density is the initial density at its "
                   "centre (largest difference %.3g, at most 1e-4)" % error)
    if dimension == 2:
        surface = read_polydata(os.path.join(output, "grid_surface_%s.pvtp" % name))
        expect(surface.GetNumberOfPolys() == cells,
               "step %d: the full surface has %d quads for %d cells"
               % (step, surface.GetNumberOfPolys(), cells))
        if surface.GetNumberOfPolys():
            # Each quad's box: a polygon also carries, on its edges, the corners of
            # finer neighbours, so cells have 4 points or more.
            polys = surface.GetPolys()
            offsets = vtk_to_numpy(polys.GetOffsetsArray())[:-1]
            corners = vtk_to_numpy(polys.GetConnectivityArray())
            points = vtk_to_numpy(surface.GetPoints().GetData())[corners]
            extent = (numpy.maximum.reduceat(points, offsets, axis=0) -
                      numpy.minimum.reduceat(points, offsets, axis=0))
            area = numpy.prod(extent[:, :2], axis=1)
            surface_mass = math.fsum(cell_array(surface, "density") * area)
            expect(close(surface_mass, mass), "step %d: the full surface's mass is %.17g, the "
                   "simulation's %.17g" % (step, surface_mass, mass))

if reference:
    with open(os.path.join(reference, "run.log")) as f:
        reference_counts, reference_totals = reported(f.read())
    expect(sorted(reference_counts) == steps, "executed steps %s, as on one rank (%s)"
           % (steps, sorted(reference_counts)))
    for step in steps:
        if step not in reference_counts or step not in reference_totals:
            continue
        expect(counts[step] == reference_counts[step], "step %d: the mesh as on one rank "
               "(blocks, by level, cells, dense: %s and %s)"
               % (step, counts[step], reference_counts[step]))
        (mass, low, high), (mass1, low1, high1) = totals[step], reference_totals[step]
        expect(low == low1 and high == high1 and close(mass, mass1),
               "step %d: density from %.17g to %.17g, mass %.17g; on one rank %.17g to %.17g, "
               "%.17g" % (step, low, high, mass, low1, high1, mass1))
        for prefix in images:
            image = "%s_%06d.png" % (prefix, step)
            both = [os.path.join(folder, image) for folder in (output, reference)]
            expect(all(os.path.exists(path) for path in both),
                   "step %d: %s in this run and in the 1-rank run" % (step, image))
            if all(os.path.exists(path) for path in both):
                # Slices: a few depth ties where planes meet (output_checks.compare_images).
                differing, unexplained = compare_images(*(read_png(path) for path in both),
                                                        ties=8 if prefix == "slices" else 0,
                                                        shading=2 if prefix == "slices" else 0)
                expect(unexplained == 0, "step %d: %s identical to the 1-rank run (%d pixels "
                       "differ, %d of them not a depth tie where planes meet nor a level of "
                       "lighting)"
                       % (step, image, differing, unexplained))

if not FAILURES:
    for bulky in glob.glob(os.path.join(output, "grid*")) + \
            glob.glob(os.path.join(output, "selection*")):
        (shutil.rmtree if os.path.isdir(bulky) else os.remove)(bulky)
finish()
