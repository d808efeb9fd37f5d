"""What a grid extract must hold, from the forest the stand-in simulation wrote
(forest_<step>.json, tests/support/ForestJson.h): each tree's breadth-first
refinement and mask, who owns it, the root grid, sampled field values. Plain
Python (no VTK), shared by the VTKHDF checker (h5py) and the ParaView 5.11
checker (pvpython)."""
import glob
import json
import math
import os
import re


def load_forests(directory):
    """forest_<step>.json of a run, by step."""
    forests = {}
    for path in glob.glob(os.path.join(directory, "forest_*.json")):
        with open(path) as source:
            forest = json.load(source)
        forests[forest["step"]] = forest
    return [forests[step] for step in sorted(forests)]


def children_per_node(forest):
    return forest["branch_factor"] ** forest["dimension"]


def levels(tree, children):
    """Cells per level of a tree, from its breadth-first refinement."""
    refinement = tree["refinement"]
    counts, start, width = [], 0, 1
    while width:
        counts.append(width)
        refined = refinement[start:start + width].count("1")
        start += width
        width = refined * children
    return counts


def descriptor_bits(tree, children):
    """The VTK descriptor of a tree: one bit per cell but the deepest level's."""
    return [int(c) for c in tree["refinement"][:len(tree["refinement"]) - levels(tree, children)[-1]]]


def leaf_mask(tree, children):
    """VTKHDF's mask: a leaf is masked when it or an ancestor is; refined cells never."""
    refinement, mask = tree["refinement"], tree["mask"] or "0" * len(tree["refinement"])
    hidden = [False] * len(refinement)
    first_child = 1
    for node, refined in enumerate(refinement):
        hidden[node] = hidden[node] or mask[node] == "1"
        if refined == "1":
            for child in range(first_child, first_child + children):
                hidden[child] = hidden[node]
            first_child += children
    return [int(hidden[n] and refinement[n] == "0") for n in range(len(refinement))]


def trees_of_rank(forest, rank):
    """The trees a rank writes, in its (the simulation's) order."""
    return [tree for tree in forest["trees"] if tree["rank"] == rank]


def total_cells(forest):
    return sum(len(tree["refinement"]) for tree in forest["trees"])


def total_leaves(forest):
    return sum(tree["refinement"].count("0") for tree in forest["trees"])


def total_masked(forest):
    return sum(tree["mask"].count("1") for tree in forest["trees"])


def selected_by_level(forest, low, high):
    """The forest as vtkCanopyExtractSelection's preserve-topology output shows a
    value-range selection on a field equal to each cell's depth (the stand-in's
    refinementLevel): the visible leaves with low <= depth <= high stay visible with
    their ancestors, every other cell is masked (brute force over every node)."""
    children = children_per_node(forest)
    selected = dict(forest)
    selected["trees"] = []
    for tree in forest["trees"]:
        refinement = tree["refinement"]
        mask = tree["mask"] or "0" * len(refinement)
        parent, depth, hidden = [-1] * len(refinement), [0] * len(refinement), [False] * len(refinement)
        first_child = 1
        for node, refined in enumerate(refinement):
            hidden[node] = hidden[node] or mask[node] == "1"
            if refined == "1":
                for child in range(first_child, first_child + children):
                    parent[child], depth[child], hidden[child] = node, depth[node] + 1, hidden[node]
                first_child += children
        visible = [False] * len(refinement)
        for node, refined in enumerate(refinement):
            if refined == "0" and not hidden[node] and low <= depth[node] <= high:
                while node >= 0 and not visible[node]:
                    visible[node] = True
                    node = parent[node]
        copy = dict(tree)
        copy["mask"] = "".join("0" if v else "1" for v in visible)
        selected["trees"].append(copy)
    return selected


def same_value(got, want):
    """Values are written exactly: equal, or both NaN."""
    if isinstance(want, float) and math.isnan(want):
        return math.isnan(got)
    return got == want


def failed_steps(log):
    """The steps the driver reported as failed, from the stand-in's output."""
    return sorted({int(s) for s in re.findall(r"^  failure: rank \d+, step (\d+):", log, re.M)})
