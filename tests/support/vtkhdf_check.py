"""Checks a VTKHDF HyperTreeGrid file with h5py against the forests the
simulation wrote (grid_extract_expectations.py), step by step and piece by piece:
every group, dataset and attribute VTK's file-format documentation requires,
descriptors bit for bit, cells per tree depth, the mask, coordinates, values at
sampled cells, pieces adding up to the whole forest, and no row beyond the
last step (a failed step leaves none)."""
import h5py
import numpy

from grid_extract_expectations import (children_per_node, descriptor_bits, leaf_mask, levels,
                                       same_value, total_cells, trees_of_rank)

REQUIRED_DATASETS = ["XCoordinates", "YCoordinates", "ZCoordinates", "Descriptors",
                     "DescriptorsSize", "TreeIds", "DepthPerTree", "NumberOfTrees",
                     "NumberOfDepths", "NumberOfCells", "NumberOfCellsPerTreeDepth", "Mask"]
REQUIRED_STEPS = ["Values", "PartOffsets", "NumberOfParts", "TreeIdsOffsets",
                  "DepthPerTreeOffsets", "NumberOfCellsPerTreeDepthOffsets", "DescriptorsOffsets",
                  "MaskOffsets", "XCoordinatesOffsets", "YCoordinatesOffsets",
                  "ZCoordinatesOffsets"]
GHOSTS = "vtkGhostType"


def bits(data, count):
    """The first `count` bits of packed bytes (most significant bit first), and the rest."""
    unpacked = numpy.unpackbits(numpy.asarray(data, dtype=numpy.uint8), bitorder="big")
    return unpacked[:count].tolist(), unpacked[count:].tolist()


def verify(path, forests, expect):
    """Expects the file to hold exactly `forests`, one step each, in order."""
    with h5py.File(path, "r") as f:
        root = f["VTKHDF"]
        expect(root.attrs["Type"] in (b"HyperTreeGrid", "HyperTreeGrid"),
               "Type is HyperTreeGrid (%r)" % root.attrs["Type"])
        version = [int(v) for v in root.attrs["Version"]]
        expect(version[0] == 2 and version[1] >= 4, "Version %s: 2.4 or later" % version)
        first = forests[0]
        dims = [len(axis) for axis in first["coordinates"]]
        expect(list(root.attrs["Dimensions"]) == dims, "Dimensions %s" % list(root.attrs["Dimensions"]))
        expect(int(root.attrs["BranchFactor"]) == first["branch_factor"], "BranchFactor")
        # The forests number their roots i fastest, then j, then k: VTK's indexing unless
        # the file says it is transposed.
        transposed = root.attrs.get("TransposedRootIndexing", 0)
        expect(not int(transposed), "TransposedRootIndexing absent or false (%r)" % transposed)
        missing = [name for name in REQUIRED_DATASETS if name not in root]
        expect(not missing, "every required dataset is there (missing: %s)" % missing)
        expect("PointData" not in root, "no PointData (hypertree grids have cell data only)")
        steps = root["Steps"]
        missing = [name for name in REQUIRED_STEPS if name not in steps]
        expect(not missing, "every Steps dataset is there (missing: %s)" % missing)
        expect(int(steps.attrs["NSteps"]) == len(forests),
               "NSteps %d = %d steps" % (steps.attrs["NSteps"], len(forests)))
        expect(numpy.array_equal(steps["Values"][:], [forest["time"] for forest in forests]),
               "Steps/Values are the steps' times: %s" % steps["Values"][:].tolist())
        fields = first["fields"]
        arrays = sorted(root["CellData"].keys())
        expect(sorted(set(arrays) - {GHOSTS}) == sorted(fields),
               "CellData holds the fields %s (%s)" % (sorted(fields), arrays))
        for name, field in fields.items():
            shape = root["CellData"][name].shape
            components = shape[1] if len(shape) > 1 else 1
            expect(components == field["components"], "%s has %d components" % (name, components))
            expect(name in steps["CellDataOffsets"], "Steps/CellDataOffsets/%s" % name)
        ends = {}
        for k, forest in enumerate(forests):
            for name, end in verify_step(root, steps, k, forest, expect).items():
                ends[name] = max(ends.get(name, 0), end)
        # Nothing beyond the last step: a failed step leaves no row behind. Every
        # dataset is as long as the steps' offsets and sizes say (a step may reuse
        # an earlier step's rows, so the longest reach counts, not the last step's).
        last = len(forests) - 1
        parts = int(steps["PartOffsets"][last] + steps["NumberOfParts"][last])
        cells = int(steps["CellDataOffsets"][sorted(fields)[0]][last]) + total_cells(forests[-1])
        longer = sorted("%s has %d rows, not %d" % (name, root[name].shape[0], end)
                        for name, end in ends.items() if root[name].shape[0] != end)
        expect(root["NumberOfTrees"].shape[0] == parts and
               all(steps[name].shape[0] == len(forests) for name in REQUIRED_STEPS) and
               all(root["CellData"][name].shape[0] == cells for name in arrays) and not longer,
               "no rows beyond the last step (%d pieces, %d cells) %s" % (parts, cells, longer))


def verify_step(root, steps, k, forest, expect):
    """Checks step k; returns where its rows end in each dataset of /VTKHDF."""
    children = children_per_node(forest)
    ranks = forest["ranks"]
    label = "step %d" % forest["step"]
    part = int(steps["PartOffsets"][k])
    expect(int(steps["NumberOfParts"][k]) == ranks, "%s: one piece per rank (%d)"
           % (label, steps["NumberOfParts"][k]))
    tree_at = int(steps["TreeIdsOffsets"][k])
    expect(int(steps["DepthPerTreeOffsets"][k]) == tree_at, "%s: DepthPerTreeOffsets" % label)
    depth_at = int(steps["NumberOfCellsPerTreeDepthOffsets"][k])
    descriptor_at = int(steps["DescriptorsOffsets"][k])
    mask_at = int(steps["MaskOffsets"][k])
    coordinate_at = [int(steps[axis + "CoordinatesOffsets"][k]) for axis in "XYZ"]
    cell_offsets = {name: int(steps["CellDataOffsets"][name][k]) for name in forest["fields"]}
    expect(len(set(cell_offsets.values())) == 1, "%s: every array's cells start together" % label)
    cell_at = next(iter(cell_offsets.values()))
    seen_roots, cells_total, where = [], 0, {}
    problems = []
    for piece in range(ranks):
        trees = trees_of_rank(forest, piece)
        n_trees = int(root["NumberOfTrees"][part + piece])
        n_cells = int(root["NumberOfCells"][part + piece])
        n_depths = int(root["NumberOfDepths"][part + piece])
        n_bits = int(root["DescriptorsSize"][part + piece])
        ids = root["TreeIds"][tree_at:tree_at + n_trees].tolist()
        if ids != [tree["root"] for tree in trees]:
            problems.append("piece %d TreeIds %s" % (piece, ids[:8]))
        want_levels = [levels(tree, children) for tree in trees]
        if root["DepthPerTree"][tree_at:tree_at + n_trees].tolist() != [len(l) for l in want_levels]:
            problems.append("piece %d DepthPerTree" % piece)
        if root["NumberOfCellsPerTreeDepth"][depth_at:depth_at + n_depths].tolist() != \
                [count for l in want_levels for count in l]:
            problems.append("piece %d NumberOfCellsPerTreeDepth" % piece)
        want_bits = [b for tree in trees for b in descriptor_bits(tree, children)]
        got_bits, padding = bits(root["Descriptors"][descriptor_at:descriptor_at + (n_bits + 7) // 8],
                                 n_bits)
        if n_bits != len(want_bits) or got_bits != want_bits or any(padding):
            problems.append("piece %d Descriptors differ from the breadth-first refinement" % piece)
        want_cells = sum(len(tree["refinement"]) for tree in trees)
        if n_cells != want_cells:
            problems.append("piece %d NumberOfCells %d, expected %d" % (piece, n_cells, want_cells))
        want_mask = [m for tree in trees for m in leaf_mask(tree, children)]
        got_mask, padding = bits(root["Mask"][mask_at:mask_at + (n_cells + 7) // 8], n_cells)
        if got_mask != want_mask or any(padding):
            problems.append("piece %d Mask differs from the leaves' mask" % piece)
        for axis, name in enumerate("XYZ"):
            length = len(forest["coordinates"][axis])
            start = coordinate_at[axis] + piece * length
            got = root[name + "Coordinates"][start:start + length].tolist()
            if got != forest["coordinates"][axis]:
                problems.append("piece %d %sCoordinates %s" % (piece, name, got[:4]))
        position = cell_at + cells_total
        for tree in trees:
            # A tree split between ranks is in several pieces: samples then name the rank.
            where[(piece, tree["root"])] = position
            where[tree["root"]] = position
            position += len(tree["refinement"])
        seen_roots += ids
        cells_total += n_cells
        tree_at += n_trees
        depth_at += n_depths
        descriptor_at += (n_bits + 7) // 8
        mask_at += (n_cells + 7) // 8
    ends = {"TreeIds": tree_at, "DepthPerTree": tree_at, "NumberOfCellsPerTreeDepth": depth_at,
            "Descriptors": descriptor_at, "Mask": mask_at}
    for axis, name in enumerate("XYZ"):
        ends[name + "Coordinates"] = coordinate_at[axis] + ranks * len(forest["coordinates"][axis])
    for name in ["NumberOfTrees", "NumberOfCells", "NumberOfDepths", "DescriptorsSize"]:
        ends[name] = part + ranks
    expect(not problems, "%s: every piece's trees, depths, descriptors, mask and coordinates "
           "match the forest %s" % (label, problems[:4]))
    expect(sorted(seen_roots) == sorted(tree["root"] for tree in forest["trees"]) and
           cells_total == total_cells(forest),
           "%s: pieces add up to the forest: %d trees, %d cells" % (label, len(seen_roots), cells_total))
    wrong = []
    for sample in forest["samples"]:
        key = (sample["rank"], sample["root"]) if "rank" in sample else sample["root"]
        cell = where[key] + sample["node"]
        for name, want in sample["values"].items():
            got = root["CellData"][name][cell]
            got = [float(got)] if numpy.ndim(got) == 0 else [float(v) for v in got]
            if len(got) != len(want) or not all(same_value(g, w) for g, w in zip(got, want)):
                wrong.append("%s at root %d node %d: %s, expected %s"
                             % (name, sample["root"], sample["node"], got, want))
    expect(not wrong, "%s: %d sampled cells hold the simulation's values %s"
           % (label, len(forest["samples"]), wrong[:3]))
    return ends
