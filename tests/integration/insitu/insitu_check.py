"""Runs an in-situ test command, then checks what the pipelines wrote, by content.

usage: python3 insitu_check.py CHECK OUTPUT_DIR [REFERENCE_DIR] -- COMMAND...

COMMAND (usually canopy_insitu_run under mpirun / xvfb-run) writes into
OUTPUT_DIR, including expected.json: the simulation's brute-force totals per
step. CHECK names one of the check_* functions below. Runs with Debian's
/usr/bin/python3, which imports ParaView's VTK (python3-paraview); the helpers
shared with the mini-app's checker are in tests/support/output_checks.py.
"""
import glob
import json
import os
import re
import shutil
import sys

import numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from output_checks import (cell_array, expect, finish, read_htg_pieces,  # noqa: E402
                           read_multiblock, read_png, read_polydata, read_unstructured,
                           run_command, vtkhdf_cells_per_step, write_faults)



def run(command, faults=False):
    """Runs the command in a fresh OUTPUT; with `faults`, the write-fault shim
    preloaded for OUTPUT (InSituRun's --fill-disk-step writes its control file,
    OUTPUT + ".fault")."""
    shutil.rmtree(OUTPUT, ignore_errors=True)
    os.makedirs(OUTPUT, exist_ok=True)
    control = OUTPUT + ".fault"
    if os.path.exists(control):
        os.remove(control)
    code, log = run_command(command, extra_env=write_faults(OUTPUT, control) if faults else None)
    with open(os.path.join(OUTPUT, "run.log"), "w") as out:
        out.write(log)
    return code, log


def expected():
    with open(os.path.join(OUTPUT, "expected.json")) as source:
        return json.load(source)


def path(name, directory=None):
    return os.path.join(directory or OUTPUT, name)


def polydata(name, directory=None):
    return read_polydata(path(name, directory))


def unstructured(name, directory=None):
    return read_unstructured(path(name, directory))


def htg_pieces(prefix, step):
    return read_htg_pieces(OUTPUT, prefix, step)


def image(name, directory=None):
    return read_png(path(name, directory))


def covered_pixels(pixels):
    """Pixels not of the white background."""
    return int((pixels.min(axis=2) < 250).sum())


def steps_ran(log):
    return [int(m.group(1)) for m in re.finditer(r"^step (\d+) executed ran (\d+) failures 0$",
                                                log, re.M) if int(m.group(2)) > 0]


def compare_image_sets(pattern):
    """Every image of this run against np 1's of the same name. Both sides must
    have images, and the same ones: with none on either side nothing would be
    compared."""
    mine = sorted(os.path.basename(p) for p in glob.glob(path(pattern)))
    reference = sorted(os.path.basename(p) for p in glob.glob(path(pattern, REFERENCE)))
    expect(len(reference) > 0, "the np 1 reference run wrote %s images" % pattern)
    expect(mine == reference, "the same %s images as np 1: %s (np 1: %s)"
           % (pattern, mine, reference))
    for name in sorted(set(mine) & set(reference)):
        compare_images(image(name), image(name, REFERENCE), name)


def compare_images(a, b, label):
    """np N against np 1: IceT composites the ranks' pieces; pixels may differ
    only on a few edges where faces of different ranks meet."""
    difference = numpy.abs(a.astype(int) - b.astype(int)).max(axis=2)
    differing = int((difference > 0).sum())
    expect(a.shape == b.shape, "%s: same image size %s" % (label, a.shape))
    expect(differing <= 0.0005 * difference.size and difference.max() <= 40,
           "%s: %d of %d pixels differ (limit 0.05%%), largest difference %d (limit 40)"
           % (label, differing, difference.size, difference.max()))


# ---- checks ------------------------------------------------------------------

def check_surface_image_case_a(code, log):
    """Case A, 600x400, every 2nd step of 3: images at steps 0 and 2 only; the
    surface extract holds one quad per visible leaf (nothing is sub-pixel here)."""
    expect(code == 0, "the simulation exits normally")
    totals = expected()
    expect(sorted(os.path.basename(p) for p in glob.glob(path("surface_*.png"))) ==
           ["surface_000000.png", "surface_000002.png"], "images at steps 0 and 2 only")
    pixels = image("surface_000002.png")
    # The grid is 3 x 3 units; the view fits the height: 400/3 pixels per unit.
    expect(abs(covered_pixels(pixels) - 400 * 400) <= 0.01 * 400 * 400,
           "the grid covers 400x400 pixels (%d)" % covered_pixels(pixels))
    colors = len(numpy.unique(pixels.reshape(-1, 3), axis=0))
    expect(colors >= 6, "colored by Depth: %d distinct colors" % colors)
    surface = polydata("surface_000002.pvtp")
    expect(surface.GetNumberOfCells() == totals[2]["leaves"],
           "surface quads %d = visible leaves %d" % (surface.GetNumberOfCells(),
                                                     totals[2]["leaves"]))
    expect(numpy.array_equal(cell_array(surface, "Depth"), cell_array(surface, "Level")),
           "each quad carries its own cell's Depth")


def check_overlays_off(code, log):
    """The reference for check_overlays: no legend, no time label."""
    expect(code == 0, "the simulation exits normally")
    expect(len(glob.glob(path("surface_*.png"))) == 3, "three images")


def check_overlays(code, log):
    """Legend and time label (the defaults) against the same run without them
    (REFERENCE), both with the first step's colour range kept: the images differ in
    the upper left corner (time) and the lower right (legend) only; the time label
    changes with the step, the legend (a fixed range) does not."""
    expect(code == 0, "the simulation exits normally")
    # vtkPNGReader's rows go bottom to top: flip them so row 0 is the image's top.
    images = [image("surface_%06d.png" % step)[::-1] for step in range(3)]
    height, width, _ = images[0].shape
    time_box = (slice(0, height // 8), slice(0, width // 4))
    legend_box = (slice(height // 2, height), slice(3 * width // 4, width))
    for step, pixels in enumerate(images):
        bare = image("surface_%06d.png" % step, REFERENCE)[::-1]
        differs = (pixels.astype(int) != bare.astype(int)).any(axis=2)
        in_time = int(differs[time_box].sum())
        in_legend = int(differs[legend_box].sum())
        elsewhere = int(differs.sum()) - in_time - in_legend
        expect(in_time > 30, "step %d: a time label in the upper left (%d pixels)" % (step, in_time))
        expect(in_legend > 300, "step %d: a legend in the lower right (%d pixels)"
               % (step, in_legend))
        expect(elsewhere == 0, "step %d: nothing else differs (%d pixels)" % (step, elsewhere))
    expect(not numpy.array_equal(images[0][time_box], images[2][time_box]),
           "the time label changes from step 0 to step 2")
    expect(all(numpy.array_equal(images[0][legend_box], other[legend_box]) for other in images),
           "color_range=first: the legend (and its range) stays the same over the run")


def check_fixed_color_range(code, log):
    """color_range=100,200 on a density within [1, 4]: every cell below the range,
    so the grid is drawn in the lookup table's lowest colour only."""
    expect(code == 0, "the simulation exits normally")
    for step in range(2):
        pixels = image("surface_%06d.png" % step)
        grid = pixels[(pixels != 255).any(axis=2)]
        colors = numpy.unique(grid.reshape(-1, 3), axis=0)
        expect(len(grid) > 10000 and len(colors) == 1,
               "step %d: %d grid pixels, %d colour(s)" % (step, len(grid), len(colors)))


def check_surface_zoomed_case_a(code, log):
    """A camera given to the script culls: only quads meeting the view remain,
    and every leaf inside the view is there."""
    expect(code == 0, "the simulation exits normally")
    surface = polydata("surface_000000.pvtp")
    # Camera at (0.75, 0.75), parallel scale 0.5, 600x400: x in [0, 1.5], y in [0.25, 1.25].
    view = (0.0, 1.5, 0.25, 1.25)
    total = expected()[0]["leaves"]
    expect(0 < surface.GetNumberOfCells() < total,
           "zoomed: %d of %d quads" % (surface.GetNumberOfCells(), total))
    outside = 0
    for c in range(surface.GetNumberOfCells()):
        b = surface.GetCell(c).GetBounds()
        if b[1] < view[0] - 1e-9 or b[0] > view[1] + 1e-9 or b[3] < view[2] - 1e-9 or \
                b[2] > view[3] + 1e-9:
            outside += 1
    expect(outside == 0, "no quad outside the view (%d)" % outside)
    full = polydata("surface_000000.pvtp", REFERENCE) if REFERENCE else None
    if full is not None:
        kept = set(cell_array(surface, "OriginalCellId").tolist())
        missing = 0
        for c in range(full.GetNumberOfCells()):
            b = full.GetCell(c).GetBounds()
            inside = b[0] > view[0] and b[1] < view[1] and b[2] > view[2] and b[3] < view[3]
            if inside and int(cell_array(full, "OriginalCellId")[c]) not in kept:
                missing += 1
        expect(missing == 0, "every leaf inside the view is kept (%d missing)" % missing)


def check_selection_points_case_a(code, log):
    expect(code == 0, "the simulation exits normally")
    selection = unstructured("selection_000000.pvtu")
    # (0.1,0.1), (2.2,1.6) and the domain corner (3,3) select a cell each; (5,5) is outside.
    expect(selection.GetNumberOfCells() == 3, "3 cells selected (%d)" % selection.GetNumberOfCells())
    expect(all(selection.GetCellType(c) == 9 for c in range(selection.GetNumberOfCells())),
           "as VTK_QUAD cells")
    ids = sorted(cell_array(selection, "OriginalCellId").tolist())
    expect(len(set(ids)) == 3, "three distinct original cells %s" % ids)
    # Which cells: each point inside the domain lies in exactly one of them (closed
    # bounds; none of the points is on a leaf's edge), and each of them holds a point.
    points = [(0.1, 0.1), (2.2, 1.6), (3.0, 3.0)]
    bounds = [selection.GetCell(c).GetBounds() for c in range(selection.GetNumberOfCells())]
    holds = [[b[0] <= x <= b[1] and b[2] <= y <= b[3] for x, y in points] for b in bounds]
    for p, (x, y) in enumerate(points):
        containing = [c for c in range(len(bounds)) if holds[c][p]]
        expect(len(containing) == 1, "(%g, %g) lies in exactly one selected cell (%d)"
               % (x, y, len(containing)))
    expect(all(any(row) for row in holds), "every selected cell holds one of the points")


def check_selection_ids_case_a(code, log):
    expect(code == 0, "the simulation exits normally")
    selection = unstructured("selection_000000.pvtu")
    ids = sorted(cell_array(selection, "OriginalCellId").tolist())
    expect(ids == [0, 7, 20], "ids 0 (a coarse root), 7, 20 selected: %s" % ids)


def check_selection_range_moving(code, log):
    """Value range on refinementLevel over 3 steps of the moving front: the count
    of leaves at levels 3..4 follows the simulation's own count each step, and
    only the field the script asked for (--fields) reaches the pipeline."""
    expect(code == 0, "the simulation exits normally")
    for entry in expected():
        step = entry["step"]
        want = sum(entry["leaves_by_level"].get(str(level), 0) for level in (3, 4))
        selection = unstructured("selection_%06d.pvtu" % step)
        got = selection.GetNumberOfCells()
        expect(got == want, "step %d: %d leaves at levels 3-4 (expected %d)" % (step, got, want))
        if step > 0:  # step 0 imports the script: every field is wrapped then
            data = selection.GetCellData()
            names = sorted(data.GetArrayName(i) for i in range(data.GetNumberOfArrays()))
            expect(names == ["Level", "OriginalCellId", "refinementLevel"],
                   "step %d: only the requested field was wrapped: %s" % (step, names))


def clipped_area(polygon, planes):
    """Area of the part of a polygon in the z = 0 plane inside every plane
    (a, b, c, d: a x + b y + c z + d >= 0)."""
    for a, b, c, d in planes:
        out = []
        for i, p in enumerate(polygon):
            q = polygon[(i + 1) % len(polygon)]
            fp, fq = a * p[0] + b * p[1] + d, a * q[0] + b * q[1] + d
            if fp >= 0:
                out.append(p)
            if fp * fq < 0:
                t = fp / (fp - fq)
                out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
        polygon = out
        if len(polygon) < 3:
            return 0.0
    return 0.5 * abs(sum(p[0] * q[1] - q[0] * p[1]
                         for p, q in zip(polygon, polygon[1:] + polygon[:1])))


def expect_region_tiled(selection, planes, label):
    """Case A (no mask, leaves tiling [0, 3]^2): every selected cell overlaps the
    region with positive area and together they cover its part of the domain once."""
    total, empty = 0.0, 0
    for c in range(selection.GetNumberOfCells()):
        b = selection.GetCell(c).GetBounds()
        area = clipped_area([(b[0], b[2]), (b[1], b[2]), (b[1], b[3]), (b[0], b[3])], planes)
        empty += area <= 1e-12
        total += area
    domain = clipped_area([(0.0, 0.0), (3.0, 0.0), (3.0, 3.0), (0.0, 3.0)], planes)
    expect(0 < selection.GetNumberOfCells() < 75,
           "%s: %d of 75 leaves selected" % (label, selection.GetNumberOfCells()))
    expect(empty == 0, "%s: no selected cell merely touches the region (%d)" % (label, empty))
    expect(abs(total - domain) <= 1e-9, "%s: the cells cover the region's part of the domain "
           "exactly once (%.12g against %.12g)" % (label, total, domain))


def camera_planes(position, focal, aspect, angle=30.0):
    from vtkmodules.vtkRenderingCore import vtkCamera
    camera = vtkCamera()
    camera.SetPosition(position)
    camera.SetFocalPoint(focal)
    camera.SetViewAngle(angle)
    camera.SetClippingRange(0.01, 100.0)  # the plane z = 0 lies well inside
    planes = [0.0] * 24
    camera.GetFrustumPlanes(aspect, planes)
    return [planes[4 * i:4 * i + 4] for i in range(6)]


def check_selection_box_case_a(code, log):
    """A box whose z range misses the plane z = 0: flat axes are ignored."""
    expect(code == 0, "the simulation exits normally")
    box = (0.3, 2.2, 0.4, 2.7)
    expect_region_tiled(unstructured("selection_000000.pvtu"),
                        [(1, 0, 0, -box[0]), (-1, 0, 0, box[1]), (0, 1, 0, -box[2]),
                         (0, -1, 0, box[3])], "box")


def check_selection_frustum_camera_case_a(code, log):
    """A tilted perspective camera (the script's settings), on 2 ranks."""
    expect(code == 0, "the simulation exits normally")
    expect_region_tiled(unstructured("selection_000000.pvtu"),
                        camera_planes((2.5, -1.0, 4.0), (1.2, 1.4, 0.0), 600 / 400, 12.0),
                        "camera")


def check_selection_frustum_corners_case_a(code, log):
    """Eight corners: the frustum of a camera at (1.2, 1.6, 4) looking down at
    (1.2, 1.6, 0), 30 degrees, aspect 1.5, near 1, far 10."""
    expect(code == 0, "the simulation exits normally")
    expect_region_tiled(unstructured("corners_000000.pvtu"),
                        camera_planes((1.2, 1.6, 4.0), (1.2, 1.6, 0.0), 1.5), "corners")


def check_selection_long_field_name(code, log):
    """A value range on a field named with 40 characters, over 4 steps: the script
    asks for that field alone, and it arrives at every step (ParaView 5.11's
    GetFieldName hands out freed memory, so a long name used to come back as
    garbage after the first step, with no failure reported)."""
    name = "refinementLevel_named_with_forty_chars_x"
    expect(code == 0, "the simulation exits normally")
    expect(steps_ran(log) == [0, 1, 2, 3], "every step ran without failure (%s)" % steps_ran(log))
    for entry in expected():
        step = entry["step"]
        want = sum(entry["leaves_by_level"].get(str(level), 0) for level in (3, 4))
        selection = unstructured("selection_%06d.pvtu" % step)
        data = selection.GetCellData()
        names = sorted(data.GetArrayName(i) for i in range(data.GetNumberOfArrays()))
        expect(name in names, "step %d: the field reached the pipeline (%s)" % (step, names))
        expect(selection.GetNumberOfCells() == want > 0,
               "step %d: %d leaves at levels 3-4 selected (expected %d)"
               % (step, selection.GetNumberOfCells(), want))


def check_data_extracts(code, log):
    """Every step: the .htg pieces hold every node, and so do the step's .vtm, the
    .pvd and the VTKHDF file's pieces; the full-resolution surface one quad per leaf
    (2D) or one face per boundary leaf face (3D, unmasked)."""
    expect(code == 0, "the simulation exits normally")
    entries = expected()
    with open(path("grid.pvd")) as series:
        listed = re.findall(r'file="(grid_\d{6}\.vtm)"', series.read())
    expect(listed == ["grid_%06d.vtm" % entry["step"] for entry in entries],
           "grid.pvd lists every step's .vtm: %s" % listed)
    cells_per_step = vtkhdf_cells_per_step(path("grid.vtkhdf"))
    expect(cells_per_step == [entry["nodes"] for entry in entries],
           "grid.vtkhdf holds every step, all nodes: %s" % cells_per_step)
    for entry in entries:
        step = entry["step"]
        grids = htg_pieces("grid", step)
        nodes = sum(g.GetNumberOfCells() for g in grids)
        expect(nodes == entry["nodes"], "step %d: .htg pieces hold %d nodes (expected %d)"
               % (step, nodes, entry["nodes"]))
        multiblock = read_multiblock(path("grid_%06d.vtm" % step))
        nodes = sum(multiblock.GetBlock(b).GetNumberOfCells()
                    for b in range(multiblock.GetNumberOfBlocks()))
        expect(multiblock.GetNumberOfBlocks() == RANKS and nodes == entry["nodes"],
               "step %d: the .vtm has a block per rank, %d nodes" % (step, nodes))
        surface = polydata("grid_surface_%06d.pvtp" % step)
        faces = surface.GetNumberOfCells()
        if not entry["boundary_faces"]:
            want, what = entry["leaves"], "one quad per leaf"
        elif RANKS == 1:
            want, what = entry["boundary_faces"], "the domain's boundary faces"
        else:
            # Whole trees per rank: each rank draws the boundary of its own part,
            # faces against another rank's trees included (brute force in InSituRun).
            want = entry.get("rank_boundary_faces")
            what = "every rank's part's boundary faces"
        expect(want is not None and faces == want,
               "step %d: surface has %d cells (expected %s: %s)" % (step, faces, what, want))


def check_moving_2d(code, log):
    """Four steps of a moving front: data extracts right every step, images
    every step, and the images change as the front moves."""
    check_data_extracts(code, log)
    summaries = re.findall(r"canopy: step (\d) time [0-9.e-]+: ran \[.*surface_image.py, .*"
                           r"data_extracts.py\], 0 failure\(s\), (\d+) cells", log)
    expect([int(step) for step, _ in summaries] == [0, 1, 2, 3],
           "one summary line per step: %s" % summaries)
    expect([int(cells) for _, cells in summaries] == [entry["nodes"] for entry in expected()],
           "summaries give the grid's cells each step")
    rebuilt = trees_rebuilt(log)
    expect(len(rebuilt) == 4 and any(0 < r < t for r, t in rebuilt[1:]),
           "a moving front rebuilds some trees, not all: %s" % rebuilt)
    images = [image("surface_%06d.png" % step) for step in range(4)]
    for step in range(1, 4):
        changed = int((numpy.abs(images[step].astype(int) - images[step - 1].astype(int))
                       .max(axis=2) > 0).sum())
        expect(changed > 100, "the image changes from step %d to %d (%d pixels)"
               % (step - 1, step, changed))


def trees_rebuilt(log):
    """Per executed step in the summaries: (trees rebuilt, trees)."""
    return [(int(r), int(t)) for r, t in
            re.findall(r"canopy: step \d+ time .*\(grid [0-9.]+ s, (\d+) of (\d+) trees rebuilt\)",
                       log)]


def check_unchanged_steps(code, log):
    """A forest that does not change: the first step builds every tree, the
    next ones none (the grid is kept), and the extracts are right every step."""
    check_data_extracts(code, log)
    rebuilt = trees_rebuilt(log)
    expect(len(rebuilt) == 3 and rebuilt[0][0] == rebuilt[0][1] > 0,
           "step 0 builds every tree: %s" % rebuilt)
    expect(all(r == 0 for r, _ in rebuilt[1:]), "steps 1 and 2 rebuild no tree: %s" % rebuilt)


def check_cinema(code, log):
    """--cinema=1: the images and a data.csv index form a Cinema database."""
    expect(code == 0, "the simulation exits normally")
    with open(path("surface.cdb/data.csv")) as table:
        rows = [line.strip().split(",") for line in table if line.strip()]
    expect(rows[0] == ["producer", "time", "FILE_png"], "data.csv header %s" % rows[0])
    expect([row[2] for row in rows[1:]] == ["surface_%06d.png" % step for step in range(3)],
           "one row per step: %s" % [row[2] for row in rows[1:]])
    expect([float(row[1]) for row in rows[1:]] == [0.0, 0.1, 0.2], "with each step's time")
    expect(all(covered_pixels(image("surface.cdb/" + row[2])) > 1000 for row in rows[1:]),
           "every listed image exists and shows the grid")


def check_mpi_against_np1(code, log):
    """np 2/4 against the np 1 reference run: the same images (IceT compositing),
    and extract totals that add up to the same numbers."""
    check_data_extracts(code, log)
    compare_image_sets("surface_*.png")
    for name in sorted(os.path.basename(p) for p in glob.glob(path("selection_*.pvtu"))):
        got = unstructured(name).GetNumberOfCells()
        want = unstructured(name, REFERENCE).GetNumberOfCells()
        expect(got == want, "%s: %d selected cells over all ranks (np 1: %d)" % (name, got, want))


def check_mpi_split(code, log):
    """Trees split between ranks (each masks what it does not own): every leaf
    appears exactly once in the 2D surface, and the image equals np 1's."""
    expect(code == 0, "the simulation exits normally")
    for entry in expected():
        step = entry["step"]
        surface = polydata("grid_surface_%06d.pvtp" % step)
        ids = cell_array(surface, "OriginalCellId")
        expect(surface.GetNumberOfCells() == entry["leaves"],
               "step %d: %d quads over all ranks = %d leaves" % (step, surface.GetNumberOfCells(),
                                                                 entry["leaves"]))
        expect(len(numpy.unique(ids)) == len(ids), "step %d: no leaf twice" % step)
    compare_image_sets("surface_*.png")


def check_clean_log(code, log):
    """Several steps of three scripts (an image, data extracts, a selection) on 2
    ranks: everything written every step, and not one warning or error in the
    job's output (ParaView's time handling used to warn on every image step)."""
    expect(code == 0, "the simulation exits normally")
    steps = [entry["step"] for entry in expected()]
    expect(steps_ran(log) == steps and all(
        re.search(r"^step %d executed ran 3 failures 0$" % step, log, re.M) for step in steps),
        "all three scripts ran at every step %s (%s)" % (steps, steps_ran(log)))
    for step in steps:
        expect(os.path.exists(path("surface_%06d.png" % step)) and
               os.path.exists(path("selection_%06d.pvtu" % step)) and
               len(htg_pieces("grid", step)) == RANKS,
               "step %d: image, selection and grid extracts written" % step)
    noisy = [line for line in log.splitlines()
             if re.search(r"WARN|Warning|ERROR", line)]
    expect(not noisy, "no warning or error in the output (%d line(s)%s)"
           % (len(noisy), (": " + noisy[0].strip()) if noisy else ""))


def check_python_error(code, log):
    """The script raises at step 1 on every rank: step 1 is reported with rank,
    step and the Python message, nothing is extracted then, steps 0 and 2 run."""
    expect(code == 0, "the simulation exits normally")
    expect(re.search(r"rank 0, step 1: the script .*marker_script.py' raised", log)
           is not None, "the failure names rank, step and script")
    expect("RuntimeError: failing on purpose at step 1" in log, "the Python message is shown")
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))
    pieces = [len(htg_pieces("grid", step)) for step in range(3)]
    expect(pieces == [RANKS, 0, RANKS], "extracts at steps 0 and 2 only: %s" % pieces)


def check_python_error_one_rank(code, log):
    """The script raises at step 1 on rank 1 only: no rank waits for it (the
    test would time out), every rank skips the step, both ranks are reported."""
    expect(code == 0, "the simulation exits normally")
    expect(re.search(r"rank 1, step 1: the script .*marker_script.py' raised", log)
           is not None, "rank 1's failure is reported (by rank 0)")
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))
    pieces = [len(htg_pieces("grid", step)) for step in range(3)]
    expect(pieces == [RANKS, 0, RANKS], "extracts at steps 0 and 2 only: %s" % pieces)


def _check_sys_exit_execute(code, log, rank):
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    expect(re.search(r"failure: rank %d, step 1: the script .*marker_script.py' .*sys\.exit\(3\)"
                     % rank, log) is not None,
           "rank %d's sys.exit is reported with step and script" % rank)
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))
    expect("closed" in log.splitlines(), "the simulation closed Canopy at the end")
    pieces = [len(htg_pieces("grid", step)) for step in range(3)]
    expect(pieces == [RANKS, 0, RANKS], "extracts at steps 0 and 2 only: %s" % pieces)


def check_sys_exit_execute(code, log):
    """sys.exit() in catalyst_execute at step 1 is reported like an exception (rank,
    step, script) instead of ending the simulation: steps 0 and 2 run."""
    _check_sys_exit_execute(code, log, rank=0)


def check_sys_exit_execute_one_rank(code, log):
    """sys.exit() on rank 1 only: reported for rank 1, every rank skips the step
    (nobody waits for rank 1), later steps run."""
    _check_sys_exit_execute(code, log, rank=1)


def check_sys_exit_import(code, log):
    """sys.exit() at import (module level or catalyst_initialize, on every rank or
    one): the import failure is reported once, the script disabled everywhere,
    the simulation runs all its steps."""
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    failing = "1" if RANKS > 1 else "0"
    expect(len(re.findall(r"failure: rank %s, step 0: the script .*marker_script.py' failed to "
                          r"import.*sys\.exit\(4\).*; the script is disabled" % failing,
                          log)) == 1,
           "rank %s's sys.exit at import is reported once, at step 0" % failing)
    # Not anchored at line starts: ParaView's stderr (the traceback) shares the pipe
    # and may land in the middle of a step line.
    reported = sorted(set(int(n) for n in re.findall(r"step (\d+) (?:executed|idle) ran", log)))
    expect(reported == [0, 1, 2], "all 3 steps reported (%s)" % reported)
    expect("closed" in log.splitlines(), "the simulation closed Canopy at the end")
    expect(not glob.glob(path("ran_*.txt")) and not glob.glob(path("grid_*")),
           "no rank ran the script: no outputs")


def check_sys_exit_finalize(code, log):
    """sys.exit() in catalyst_finalize on rank 1: close() reports it (rank 0 logs
    rank 1's failure) and the simulation ends normally."""
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    expect(steps_ran(log) == [0, 1], "steps 0 and 1 ran (%s)" % steps_ran(log))
    expect(re.search(r"rank 1, close: the script .*marker_script.py' failed in "
                     r"catalyst_finalize.*sys\.exit\(4\)", log) is not None,
           "rank 1's failure in catalyst_finalize is logged")
    expect("closed" in log.splitlines(), "close() returned")


LIMIT = r"the step time limit \(5 s\)"


def check_loop_one_rank(code, log):
    """catalyst_execute loops forever on rank 1 at step 1 (under @canopy.collective,
    rank 0 waits in its reduction over ranks): rank 1 is interrupted at the limit, the
    step is skipped on both ranks, the run goes on."""
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    expect(re.search(r"failure: rank 1, step 1: the script .*marker_script.py' exceeded "
                     + LIMIT + " and was interrupted", log) is not None,
           "rank 1's loop is reported with step, script and the limit")
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))
    expect("closed" in log.splitlines(), "the simulation closed Canopy at the end")


def check_loop_all_ranks(code, log):
    """catalyst_execute loops on both ranks at step 1: both are interrupted and
    reported, the step is skipped, the run goes on."""
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    for rank in (0, 1):
        expect(re.search(r"failure: rank %d, step 1: the script .*marker_script.py' exceeded "
                         % rank + LIMIT + " and was interrupted", log) is not None,
               "rank %d's loop is reported with step, script and the limit" % rank)
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))
    expect("closed" in log.splitlines(), "the simulation closed Canopy at the end")


def check_unguarded_error_one_rank(code, log):
    """Rank 1 raises at step 2 of 4 in a catalyst_execute without @canopy.collective;
    rank 0 then waits for it in the script's reduction over ranks (canopy._reduce:
    an MPI_Allreduce), where Python cannot be interrupted. Instead of hanging, the job ends (MPI_Abort, exit code 124) with
    rank 0 named as stuck (script, step) and rank 1's own error shown."""
    expect(code == 124, "the job is ended with exit code 124 (got %d)" % code)
    expect(re.search(r"rank 0, step 2: the script '.*marker_script.py' is still in "
                     r"catalyst_execute .* after " + LIMIT + " and cannot be interrupted", log)
           is not None, "rank 0 is named as stuck, with script and step")
    expect(re.search(r"rank 1, .*step 2.*RuntimeError: failing on purpose at step 2 on rank 1",
                     log) is not None, "rank 1's error reaches the output")
    expect(steps_ran(log) == [0, 1], "steps 0 and 1 ran before (%s)" % steps_ran(log))


def check_loop_finalize(code, log):
    """catalyst_finalize loops on rank 1: interrupted at the limit, reported by
    close(), and the simulation ends normally."""
    expect(code == 0, "the simulation exits normally (exit code %d)" % code)
    expect(re.search(r"rank 1, close: the script .*marker_script.py' failed in catalyst_finalize: "
                     r"exceeded " + LIMIT, log) is not None,
           "rank 1's looping catalyst_finalize is reported")
    expect("closed" in log.splitlines(), "close() returned")
    expect(os.path.exists(path("finalized.txt")), "rank 0's catalyst_finalize ran")


def check_error_text_rank1(code, log):
    """A Python error on rank 1 only (ParaView silences rank 1's stderr): its
    message and its traceback reach the job's output, with rank and step."""
    expect(code == 0, "the simulation exits normally")
    expect(re.search(r"rank 1, step 1: the script .*marker_script.py' raised an error: "
                     r"RuntimeError: zebra-7731-only-on-rank-1", log) is not None,
           "rank 1's exception message is in the output, with rank and step")
    match = re.search(r"rank 1, step 1: Python traceback of [^\n]*marker_script.py':\n(.*?)"
                      r"RuntimeError: zebra-7731-only-on-rank-1", log, re.S)
    expect(match is not None and re.search(r'File ".*marker_script.py", line \d+, in execute',
                                           match.group(1)) is not None,
           "rank 1's traceback (down to the script's line) is in the output")
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))


def read_expected(name):
    """The simulation's totals written outside OUTPUT (None if it did not finish them)."""
    try:
        with open(os.path.join(os.path.dirname(OUTPUT), name)) as source:
            return json.load(source)
    except (OSError, ValueError):
        return None


def step_files(step):
    return sorted(os.path.relpath(p, OUTPUT) for p in glob.glob(path("*_%06d*" % step)) +
                  glob.glob(path("*_%06d*/*" % step)))


def check_full_disk(code, log):
    """The output's disk full for step 2 of 4 (the write-fault shim) so that the step's
    extracts (grid, surface, selection) do not fit: step 2 is reported failed,
    saying so, for both scripts; it leaves no file at all (not even a partial
    one); steps 0 and 1 are intact; nothing crashes (VTK 9.2's polydata and
    unstructured writers segfault on a full disk); step 3, with the space back,
    is written again."""
    totals = read_expected("full_disk.expected.json")
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    if totals is None:
        expect(False, "the simulation wrote its totals")
        return
    expect("Segmentation fault" not in log and "SIGSEGV" not in log, "no crash")
    for script in ("data_extracts.py", "selection_extract.py"):
        expect(re.search(r"failure: rank \d, step 2: the script '.*%s' .*not enough free disk "
                         r"space" % script, log) is not None,
               "step 2 of %s is reported failed for want of disk space" % script)
    expect(steps_ran(log) == [0, 1, 3], "steps 0, 1 and 3 ran, step 2 failed (%s)"
           % steps_ran(log))
    expect(step_files(2) == [], "nothing of step 2 is left (%s)" % step_files(2))
    for step in (0, 1, 3):
        nodes = sum(g.GetNumberOfCells() for g in htg_pieces("grid", step))
        surface = polydata("grid_surface_%06d.pvtp" % step).GetNumberOfCells()
        selected = unstructured("selection_%06d.pvtu" % step).GetNumberOfCells()
        expect(nodes == totals[step]["nodes"] and surface == totals[step]["leaves"] and
               selected > 0, "step %d's extracts are intact: %d nodes, %d quads, %d selected"
               % (step, nodes, surface, selected))


check_full_disk.faults = True


def expect_step_2_failed_alone(code, log, totals_name, scripts):
    """What every write-fault run at step 2 of 4 must show: the simulation
    survives without a crash, step 2 of each script is reported failed, steps 0,
    1 and 3 ran and nothing of step 2 is left. Returns the simulation's totals
    (None, failed, if it did not write them)."""
    totals = read_expected(totals_name)
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    expect(not re.search(r"munmap_chunk|SIGABRT|SIGSEGV|Segmentation fault", log), "no crash")
    if totals is None:
        expect(False, "the simulation wrote its totals")
        return None
    for script in scripts:
        expect(re.search(r"failure: rank \d, step 2: the script '.*%s'" % script, log)
               is not None, "step 2 of %s is reported failed" % script)
    expect(steps_ran(log) == [0, 1, 3], "steps 0, 1 and 3 ran, step 2 failed (%s)"
           % steps_ran(log))
    expect(step_files(2) == [], "nothing of step 2 is left (%s)" % step_files(2))
    return totals


def check_write_errors(code, log):
    """Every write under the output fails with EIO at step 2 of 4 (the
    write-fault shim; free space looks ample, so the step goes ahead):
    both scripts' step 2 is reported failed, nothing of step 2 is left (no
    partial image or piece), the .pvd lists the other steps, the run goes on
    and steps 0, 1 and 3 are whole."""
    totals = expect_step_2_failed_alone(code, log, "write_errors.expected.json",
                                        ("surface_image.py", "data_extracts.py"))
    if totals is None:
        return
    kept = [step for step in range(4) if step != 2]
    with open(path("grid.pvd")) as series:
        listed = re.findall(r'file="(grid_\d{6}\.vtm)"', series.read())
    expect(listed == ["grid_%06d.vtm" % step for step in kept],
           "grid.pvd lists steps 0, 1 and 3: %s" % listed)
    for step in kept:
        nodes = sum(g.GetNumberOfCells() for g in htg_pieces("grid", step))
        expect(nodes == totals[step]["nodes"] and
               covered_pixels(image("surface_%06d.png" % step)) > 1000,
               "step %d's image and grid are whole: %d nodes" % (step, nodes))


check_write_errors.faults = True


def check_write_errors_mid_piece(code, log):
    """Writes under the output fail with EIO after 30 KB at step 2 of 4: the
    surface (.pvtp) and selection (.pvtu) pieces fail in the middle (VTK 9.2's
    own piece writers then free arrays they never allocated and the simulation
    dies): both scripts' step 2 is reported failed, nothing of it is left, and
    steps 0, 1 and 3 are whole."""
    totals = expect_step_2_failed_alone(code, log, "write_errors_mid_piece.expected.json",
                                        ("surface_image.py", "selection_extract.py"))
    if totals is None:
        return
    for step in (0, 1, 3):
        want = sum(totals[step]["leaves_by_level"].get(str(level), 0) for level in (1, 2))
        selected = unstructured("selection_%06d.pvtu" % step).GetNumberOfCells()
        quads = polydata("surface_%06d.pvtp" % step).GetNumberOfCells()
        expect(selected == want and quads > 0 and
               covered_pixels(image("surface_%06d.png" % step)) > 1000,
               "step %d's extracts are whole: %d selected (%d leaves at depth 1-2), %d quads"
               % (step, selected, want, quads))


check_write_errors_mid_piece.faults = True


def check_writer_error(code, log):
    """A folder stands where step 1's selection summary (.pvtu) goes: the writer's
    error marks the selection's step failed with VTK's message; the pieces it
    had written are removed; the other script's step and the other steps are
    untouched."""
    expect(code == 0, "the simulation survives and exits normally (exit code %d)" % code)
    expect(re.search(r"failure: rank 0, step 1: the script '.*selection_extract.py' .*"
                     r"(cannot|Cannot|unable|Unable|Error|error).*selection_000001", log)
           is not None, "step 1 of the selection is reported failed with the writer's message")
    expect(re.search(r"^step 1 executed ran 1 failures [1-9]", log, re.M) is not None,
           "step 1: the other script ran")
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran without failure (%s)" % steps_ran(log))
    expect(not os.path.exists(path("selection_000001")),
           "the pieces written for the failed step are removed")
    expect(os.path.isdir(path("selection_000001.pvtu")), "the folder in the way is left alone")
    expect(len(htg_pieces("grid", 1)) == RANKS, "the other script's step 1 is intact")
    for step in (0, 2):
        expect(unstructured("selection_%06d.pvtu" % step).GetNumberOfCells() > 0,
               "step %d's selection is intact" % step)


def check_import_error_one_rank(code, log):
    """The script fails to import on rank 1 only: no rank runs it alone (the test
    would time out), the failure is reported once, the script is disabled."""
    expect(code == 0, "the simulation exits normally")
    expect(len(re.findall(r"failure: rank 1, step 0: the script .*marker_script.py' failed to "
                          r"import .*; the script is disabled", log)) == 1,
           "rank 1's import failure is reported once, at step 0")
    expect(steps_ran(log) == [], "the script never runs (%s)" % steps_ran(log))
    expect(not glob.glob(path("ran_*.txt")) and not glob.glob(path("grid_*")),
           "no rank ran it: no outputs")
    expect(not os.path.exists(path("finalized.txt")), "a disabled script is not finalized")


def check_duplicate_script(code, log):
    expect(code == 2, "open fails (exit code %d)" % code)
    expect(re.search(r"marker_script.py' is given twice", log) is not None,
           "the error names the script given twice")


def check_no_display(code, log):
    """No X display: the image pipeline is skipped with one message, the
    selection extract is still written."""
    expect(code == 0, "the simulation exits normally (no abort)")
    expect(log.count("no X display") == 1, "one message about the display (%d)"
           % log.count("no X display"))
    expect("surface_image.py" in log and "xvfb-run" in log, "it names the script and the remedy")
    expect(not glob.glob(path("*.png")), "no image written")
    expect(unstructured("selection_000001.pvtu").GetNumberOfCells() == 3,
           "the selection extract is written")


def check_unwritable_output(code, log):
    expect(code == 0, "the simulation exits normally")
    failures = re.findall(r"rank 0, step (\d+): the output directory .* cannot be created",
                          log)
    expect(sorted(set(failures)) == ["0", "1", "2"],
           "each step reported with rank and step: %s" % failures)


def check_invalid_forest_one_rank(code, log):
    """Rank 1 passes a malformed tree at step 1: every rank skips step 1 (nobody
    waits in a collective), the failure names rank 1 and its tree."""
    expect(code == 0, "the simulation exits normally")
    expect(re.search(r"rank 1, step 1: invalid forest: tree 0 \(root 1\): refinement", log)
           is not None,
           "the failure names rank 1, step 1 and the tree")
    expect(steps_ran(log) == [0, 2], "steps 0 and 2 ran (%s)" % steps_ran(log))
    expect(len(htg_pieces("grid", 1)) == 0 and len(htg_pieces("grid", 2)) == RANKS,
           "no extract at step 1, all pieces at step 2")


def check_forgotten_close(code, log):
    expect(code == 0, "the simulation exits normally")
    expect("MPI_Finalize closed the driver" in log, "MPI_Finalize closed the driver")
    expect(os.path.exists(path("finalized.txt")), "the script's catalyst_finalize ran")


def check_bad_script(code, log):
    expect(code == 2, "open fails (exit code %d)" % code)
    expect(re.search(r"pipeline script '.*no_such_script.py': no such file", log) is not None,
           "the error names the script and the problem")


SHIPPED_PIPELINES = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "..", "..", "..", "pipelines"))


def check_script_search_by_name(code, log):
    """Scripts given by bare name from a working directory without them:
    surface_image.py is the marker in CANOPY_PIPELINES_DIR (it comes before the
    shipped pipelines), selection_extract.py the shipped one."""
    expect(code == 0, "the simulation exits normally")
    alternate = os.environ["CANOPY_PIPELINES_DIR"]
    ran = re.search(r"canopy: step 0 time [0-9.e-]+: ran \[(.*)\], 0 failure", log)
    expect(ran is not None and ran.group(1).split(", ") ==
           [os.path.join(alternate, "surface_image.py"),
            os.path.join(SHIPPED_PIPELINES, "selection_extract.py")],
           "step 0 ran the alternate surface_image.py and the shipped selection_extract.py: %s"
           % (ran.group(1) if ran else None))
    expect(os.path.exists(path("ran_000000.txt")), "the marker script ran")
    expect(not glob.glob(path("surface_*.png")), "the shipped surface_image.py did not run")
    ids = sorted(cell_array(unstructured("selection_000000.pvtu"), "OriginalCellId").tolist())
    expect(ids == [0, 7, 20], "the shipped selection_extract.py selected ids 0, 7, 20: %s" % ids)


def check_script_search_missing(code, log):
    """A bare name found nowhere: open fails, and the error lists every place
    looked at, in search order."""
    expect(code == 2, "open fails (exit code %d)" % code)
    places = [os.path.join(os.getcwd(), "no_such_pipeline.py"),
              os.path.join(os.environ["CANOPY_PIPELINES_DIR"], "no_such_pipeline.py"),
              os.path.join(SHIPPED_PIPELINES, "no_such_pipeline.py")]
    expect(("pipeline script 'no_such_pipeline.py': no such file or directory; looked for "
            + ", ".join(places)) in log, "the error lists %s" % ", ".join(places))


if __name__ == "__main__":
    separator = sys.argv.index("--")
    CHECK, OUTPUT = sys.argv[1], sys.argv[2]
    REFERENCE = sys.argv[3] if separator > 3 else None
    COMMAND = sys.argv[separator + 1:]
    RANKS = int(COMMAND[COMMAND.index("-np") + 1]) if "-np" in COMMAND else 1
    check = globals()["check_" + CHECK]
    exit_code, output = run(COMMAND, getattr(check, "faults", False))
    check(exit_code, output)
    finish()
