"""Opens a run's hypertree-grid extract in ParaView 5.11, as a user would, and
checks it against the forests the simulation wrote (forest_<step>.json): the
.pvd series and each step's .vtm, one block per rank, cell and leaf counts,
masks, field names and components, values at sampled cells; then renders it.

Run with pvpython: paraview511_open.py OUTPUT_DIR data|render [PREFIX [LOW,HIGH]]
(render: with an X display; it draws the series and checks the image shows the
grid). PREFIX: the files' prefix (grid); LOW,HIGH: the series is selection_extract.py's
preserve-topology output for a value range on refinementLevel (the cell's depth).
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from grid_extract_expectations import (load_forests, same_value,  # noqa: E402
                                       selected_by_level, total_cells, total_leaves,
                                       total_masked)

from paraview import servermanager  # noqa: E402
from paraview.simple import (ColorBy, CreateRenderView, Delete, Hide,  # noqa: E402
                             OpenDataFile, Render, ResetCamera, SaveScreenshot, Show)

FAILURES = []


def expect(condition, message):
    print(("ok:     " if condition else "FAILED: ") + message)
    if not condition:
        FAILURES.append(message)


def blocks(data):
    """The hypertree grids of a multiblock, in block order."""
    return [data.GetBlock(b) for b in range(data.GetNumberOfBlocks())]


def check_step(data, forest, label):
    expect(data is not None and data.IsA("vtkMultiBlockDataSet"),
           "%s: one multiblock dataset (%s)" % (label, data.GetClassName() if data else None))
    grids = blocks(data)
    expect(len(grids) == forest["ranks"] and all(g is not None and g.IsA("vtkHyperTreeGrid")
                                                 for g in grids),
           "%s: %d hypertree-grid blocks, one per rank" % (label, len(grids)))
    cells = sum(g.GetNumberOfCells() for g in grids)
    leaves = sum(g.GetNumberOfLeaves() for g in grids)
    expect(cells == total_cells(forest) and leaves == total_leaves(forest),
           "%s: %d cells, %d leaves (the simulation: %d, %d)"
           % (label, cells, leaves, total_cells(forest), total_leaves(forest)))
    masked = sum(sum(g.GetMask().GetValue(i) for i in range(g.GetMask().GetNumberOfTuples()))
                 for g in grids if g.HasMask())
    expect(masked == total_masked(forest), "%s: %d masked cells (the simulation: %d)"
           % (label, masked, total_masked(forest)))
    for g in grids:
        if g.GetNumberOfCells() == 0:
            continue
        cd = g.GetCellData()
        arrays = {cd.GetArrayName(i): cd.GetArray(i).GetNumberOfComponents()
                  for i in range(cd.GetNumberOfArrays())}
        want = {name: field["components"] for name, field in forest["fields"].items()}
        expect(arrays == want, "%s: fields and components %s (expected %s)" % (label, arrays, want))
        break
    wrong = []
    for sample in forest["samples"]:
        owner = next((g for g in grids if g.GetTree(sample["root"]) is not None), None)
        if owner is None:
            wrong.append("root %d is in no block" % sample["root"])
            continue
        cell = owner.GetTree(sample["root"]).GetGlobalIndexFromLocal(sample["node"])
        for name, want in sample["values"].items():
            array = owner.GetCellData().GetArray(name)
            got = [array.GetComponent(cell, c) for c in range(array.GetNumberOfComponents())]
            if len(got) != len(want) or not all(same_value(g, w) for g, w in zip(got, want)):
                wrong.append("%s at root %d node %d: %s, expected %s"
                             % (name, sample["root"], sample["node"], got, want))
    expect(not wrong, "%s: %d sampled cells hold the simulation's values %s"
           % (label, len(forest["samples"]), wrong[:3]))


def main():
    output, mode = sys.argv[1], sys.argv[2]
    prefix = sys.argv[3] if len(sys.argv) > 3 else "grid"
    forests = load_forests(output)
    if len(sys.argv) > 4:
        low, high = (int(v) for v in sys.argv[4].split(","))
        forests = [selected_by_level(forest, low, high) for forest in forests]
    series = OpenDataFile(os.path.join(output, prefix + ".pvd"))
    expect(series is not None, "ParaView 5.11 has a reader for %s.pvd" % prefix)
    if mode == "render":
        render(series, output)
    else:
        check_data(series, forests, output, prefix)
    print("%d check(s) failed" % len(FAILURES) if FAILURES else "all checks passed")
    sys.exit(1 if FAILURES else 0)


def check_data(series, forests, output, prefix):
    times = list(series.TimestepValues) if len(forests) > 1 else [forests[0]["time"]]
    expect(all(math.isclose(t, f["time"], abs_tol=1e-12) for t, f in zip(times, forests)) and
           len(times) == len(forests), "the series has the steps' times %s" % times)
    for forest in forests:
        series.UpdatePipeline(forest["time"])
        check_step(servermanager.Fetch(series), forest,
                   "%s.pvd at time %g" % (prefix, forest["time"]))
        name = "%s_%06d.vtm" % (prefix, forest["step"])
        step = OpenDataFile(os.path.join(output, name))
        step.UpdatePipeline()
        check_step(servermanager.Fetch(step), forest, name)


def render(series, output):
    """The series shows in a render view (ParaView 5.11 renders hypertree-grid blocks)."""
    view = CreateRenderView()
    view.ViewSize = [400, 400]
    view.OrientationAxesVisibility = 0
    display = Show(series, view)
    ColorBy(display, ("CELLS", "velocity", "Magnitude"))
    ResetCamera(view)
    Render(view)
    image = os.path.join(output, "paraview511.png")
    SaveScreenshot(image, view, ImageResolution=[400, 400])
    from paraview.vtk.vtkIOImage import vtkPNGReader
    reader = vtkPNGReader()
    reader.SetFileName(image)
    reader.Update()
    pixels = reader.GetOutput().GetPointData().GetScalars()
    background = pixels.GetTuple(0)
    differing = sum(1 for i in range(pixels.GetNumberOfTuples()) if pixels.GetTuple(i) != background)
    expect(differing > 0.2 * pixels.GetNumberOfTuples(),
           "the render shows the grid (%d of %d pixels)" % (differing, pixels.GetNumberOfTuples()))
    # Release the window while the X server is surely there (not at interpreter exit).
    Hide(series, view)
    Delete(view)
    del view


if __name__ == "__main__":
    main()
