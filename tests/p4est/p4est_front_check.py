"""Runs the p4est example simulation (examples/p4est) and checks what Canopy's
shipped pipelines wrote against what the simulation itself counted:

  p4est_front_check.py DIMENSION OUTPUT [REFERENCE] -- command...

- the run succeeds and prints no warning or error;
- every executed step has its image, selection and hypertree-grid extracts;
- the selection holds exactly the quadrants the simulation counts with a density
  in [1.9, 2.1] (p4est_iterate on every rank, reduced);
- 2D: the full-resolution surface has exactly one quad per quadrant of the forest;
- images: 2D the adaptive surface (surface_<step>.png), 3D the slices and the dense
  region's surface (slices_<step>.png, region_<step>.png), each showing the density's
  colours (not a blank or single-colour picture);
- with REFERENCE (the same run on one rank): every image is identical to it.
"""
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import (cell_array, compare_images, expect, finish,  # noqa: E402
                           read_htg_pieces, read_png,
                           read_polydata, read_unstructured, run_command)

separator = sys.argv.index("--")
arguments = sys.argv[1:separator]
dimension = int(arguments[0])
output = arguments[1]
reference = arguments[2] if len(arguments) > 2 else None
shutil.rmtree(output, ignore_errors=True)
status, log = run_command(sys.argv[separator + 1:])
expect(status == 0, "the simulation exits with 0 (got %d)" % status)
expect(not re.search(r"WARN|ERR|Warning|Error", log), "no warning or error in the output")

steps = [(int(s), int(q), int(d)) for s, q, d in re.findall(
    r"p4est_front: step (\d+): (\d+) quadrants, (\d+) with density", log)]
expect(len(steps) >= 2, "the simulation reported %d executed steps" % len(steps))
for step, quadrants, dense in steps:
    name = "%06d" % step
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
    if dimension == 2:
        surface = read_polydata(os.path.join(output, "grid_surface_%s.pvtp" % name))
        expect(surface.GetNumberOfCells() == quadrants,
               "step %d: full surface has %d quads for %d quadrants"
               % (step, surface.GetNumberOfCells(), quadrants))
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
