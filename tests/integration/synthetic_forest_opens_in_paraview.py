"""The synthetic-forest tool writes a .htg file that ParaView opens with the right content.

Run with pvpython: synthetic_forest_opens_in_paraview.py <canopy_write_synthetic_forest> <work dir>
"""
import os
import re
import subprocess
import sys

from paraview import servermanager
from paraview.simple import OpenDataFile


def run_tool(tool, output, *extra):
    result = subprocess.run([tool, "--output", output, *extra], capture_output=True, text=True,
                            check=True)
    match = re.search(r"(\d+) cells \((\d+) leaves\)", result.stdout)
    assert match, "unexpected output: " + result.stdout
    return int(match.group(1)), int(match.group(2))


def open_in_paraview(path):
    reader = OpenDataFile(path)
    assert reader is not None, "ParaView found no reader for " + path
    reader.UpdatePipeline()
    data = servermanager.Fetch(reader)
    assert data.GetClassName() == "vtkHyperTreeGrid", data.GetClassName()
    return data


def check(condition, message):
    if not condition:
        print("FAILED: " + message)
        sys.exit(1)


def main():
    tool, work = sys.argv[1], sys.argv[2]
    levels = 5

    # Without the cut-away every cell is in the file.
    full_dir = os.path.join(work, "full")
    cells, leaves = run_tool(tool, full_dir, "--levels", str(levels), "--no-cutaway")
    data = open_in_paraview(os.path.join(full_dir, "synthetic_forest.htg"))
    check(data.GetNumberOfCells() == cells,
          "ParaView sees %d cells, the tool built %d" % (data.GetNumberOfCells(), cells))
    check(not data.HasMask(), "no mask expected without the cut-away")
    cd = data.GetCellData()
    names = sorted(cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays()))
    check(names == ["density", "pressure", "refinementLevel", "velocity"], "arrays: %s" % names)
    check(cd.GetArray("velocity").GetNumberOfComponents() == 3, "velocity is a 3-vector")
    density = cd.GetArray("density").GetRange(0)
    check(1.0 <= density[0] and density[1] <= 4.0 and density[1] > 3.5,
          "density range %s: the front (peak 4) must be resolved" % (density,))
    level = cd.GetArray("refinementLevel").GetRange(0)
    check(level == (0.0, levels - 1.0), "refinement levels %s" % (level,))
    check(leaves < cells, "a refined forest has fewer leaves than cells")

    # With the cut-away, the file keeps every cell and the mask.
    cut_dir = os.path.join(work, "cutaway")
    cut_cells, _ = run_tool(tool, cut_dir, "--levels", str(levels))
    check(cut_cells == cells, "the cut-away must not change the forest")
    data = open_in_paraview(os.path.join(cut_dir, "synthetic_forest.htg"))
    check(data.HasMask(), "the cut-away is a mask")
    mask = data.GetMask()
    masked = sum(mask.GetValue(i) for i in range(mask.GetNumberOfTuples()))
    check(data.GetNumberOfCells() == cells and 0 < masked < cells,
          "every cell kept, %d of %d masked" % (masked, data.GetNumberOfCells()))
    print("the synthetic forest opens in ParaView: %d cells, %d masked with the cut-away"
          % (cells, masked))


if __name__ == "__main__":
    main()
