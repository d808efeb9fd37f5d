"""Reads a run's VTKHDF file with VTK's own vtkHDFReader (read_vtkhdf_with_vtk,
built against VTK 9.5 or later) and compares what VTK read with the forests the
simulation wrote (forest_<step>.json): every step and its time, one piece per
rank, cells, leaves and masked leaves adding up to the forest's, the fields and
their components, values at sampled cells.

usage: python3 check_vtk_read.py OUTPUT_DIR FILE_NAME READER [LOW,HIGH]
  LOW,HIGH: the file is selection_extract.py's preserve-topology output for a
  value range on refinementLevel (grid_extract_expectations.selected_by_level).
"""
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from grid_extract_expectations import (children_per_node, leaf_mask, load_forests,  # noqa: E402
                                       same_value, selected_by_level, total_cells,
                                       total_leaves)
from output_checks import expect, finish  # noqa: E402


def value(text):
    return float("nan") if text == "nan" else text


def main():
    output, name, reader = sys.argv[1], sys.argv[2], sys.argv[3]
    forests = load_forests(output)
    if len(sys.argv) > 4:
        low, high = (int(v) for v in sys.argv[4].split(","))
        forests = [selected_by_level(forest, low, high) for forest in forests]
    expect(len(forests) >= 2, "%d steps written by the simulation" % len(forests))
    result = subprocess.run([reader, os.path.join(output, name)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    print(result.stderr[-3000:])
    expect(result.returncode == 0, "vtkHDFReader reads %s without an error or warning (exit %d)"
           % (name, result.returncode))
    steps = [json.loads(line) for line in result.stdout.splitlines() if line.startswith("{")]
    expect(len(steps) == len(forests), "vtkHDFReader sees %d steps (the simulation wrote %d)"
           % (len(steps), len(forests)))
    for read, forest in zip(steps, forests):
        label = "step %d (time %g)" % (forest["step"], forest["time"])
        expect(math.isclose(read["time"], forest["time"], abs_tol=1e-12),
               "%s: the reader's time value %s" % (label, read["time"]))
        pieces = [p for p in read["pieces"] if p is not None]
        expect(len(pieces) == forest["ranks"] and len(read["pieces"]) == forest["ranks"],
               "%s: %d hypertree-grid pieces in a %s, one per rank" % (label, len(pieces),
                                                                      read["output"]))
        cells = sum(p["cells"] for p in pieces)
        leaves = sum(p["leaves"] for p in pieces)
        expect(cells == total_cells(forest) and leaves == total_leaves(forest),
               "%s: %d cells, %d leaves (the simulation: %d, %d)"
               % (label, cells, leaves, total_cells(forest), total_leaves(forest)))
        children = children_per_node(forest)
        masked_leaves = sum(sum(leaf_mask(tree, children)) for tree in forest["trees"])
        masked = sum(p["masked"] for p in pieces)
        expect(masked == masked_leaves, "%s: %d masked leaves (VTKHDF masks leaves; the "
               "simulation's mask hides %d)" % (label, masked, masked_leaves))
        want = {n: f["components"] for n, f in forest["fields"].items()}
        for p in pieces:
            got = {n: c for n, c in p["arrays"].items() if n != "vtkGhostType"}
            expect(got == want, "%s: arrays %s (expected %s)" % (label, got, want))
        wrong = []
        for sample in forest["samples"]:
            owner = next((p for p in pieces if str(sample["root"]) in p["values"]), None)
            if owner is None:
                wrong.append("root %d is in no piece" % sample["root"])
                continue
            tree = owner["values"][str(sample["root"])]
            for field, expected in sample["values"].items():
                got = [value(v) for v in tree[field][sample["node"]]]
                if len(got) != len(expected) or not all(same_value(g, w)
                                                        for g, w in zip(got, expected)):
                    wrong.append("%s at root %d node %d: %s, expected %s"
                                 % (field, sample["root"], sample["node"], got, expected))
        expect(not wrong, "%s: %d sampled cells hold the simulation's values %s"
               % (label, len(forest["samples"]), wrong[:3]))
    finish()


if __name__ == "__main__":
    main()
