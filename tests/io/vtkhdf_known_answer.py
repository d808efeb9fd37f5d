#!/usr/bin/env python3
"""Known-answer test of Canopy's VTKHDF HyperTreeGrid files.

A second, independent reading of the format: every expected value below is
written out by hand from VTK's specification, for the tiny forests of
tests/io/KnownAnswerForests.cxx. Nothing is computed from the forests, and
nothing is shared with Canopy's writer or with tests/support/vtkhdf_check.py.

Usage: vtkhdf_known_answer.py serial|pieces DIR [-- COMMAND...]
  COMMAND (the writer, under mpiexec) is run first, after removing old files.

The reading of the format used here (quotes from VTK's
Documentation/docs/vtk_file_formats/vtkhdf_file_format/vtkhdf_specifications.md,
section "HyperTreeGrid", and where the text is silent, from how VTK's own
IO/HDF/vtkHDFReader.cxx and vtkHDFReaderImplementation.cxx read a file):

S1 "For each tree, the `Descriptor` dataset has one bit for each cell in the
   tree, except for its deepest level: 0 if the cell is not refined, and 1 if
   it is." Cells are listed level by level (breadth-first); within a level,
   children in the order of their parents, each parent's children in child
   order (x fastest, then y, then z). A tree that is only a root has 0 bits.
S2 "The `Descriptors` and `Mask` datasets are packed bit arrays, stored as
   unsigned chars." Packed as vtkBitArray packs (Common/Core/vtkBitArray.h,
   SetValue: `mask = 0x80 >> bitId`): bit i is in byte i // 8, the first bit
   the MOST significant one. Unused trailing bits are 0 (vtkBitArray clears
   them; VTK's vtkHDFWriter pads with 0).
S3 Within a piece, the trees' descriptor bits follow each other with no
   padding (ReadHyperTreeGridData: `treeDescriptorOffset += descriptorSize`,
   in bits), and so do their mask bits (one bit per cell, cells of the piece
   in file order: `inputCellOffset`).
S4 "Each new piece is required to start writing descriptors and mask on a new
   byte ... `DescriptorsSize` stores the size (in **bits**) of the descriptors
   array for each piece."
S5 "`DepthPerTree` contains the depth of each tree listed in `TreeIds` [in]
   the current piece. The size of both arrays is `NumberOfTrees`."
   "`NumberOfCellsPerTreeDepth`'s size is the sum of `DepthPerTree`. For each
   depth of each tree, it gives the information of the number of cells for
   this depth. For a given piece, we store the size of this dataset as
   `NumberOfDepths`." "The number of cells for the piece is stored as
   `NumberOfCells`." (NumberOfTrees, NumberOfCells, NumberOfDepths,
   DescriptorsSize: one entry per piece, pieces of all steps back to back.)
S6 "Each cell can be masked using an optional bit array `Mask`. A decomposed
   (refined) cell cannot be masked." "The size of the (optional) `Mask`
   dataset corresponds to the number of cells divided by 8 ..., rounded to the
   next bigger integer value." (per piece, S4)
S7 "Coordinates arrays `XCoordinates` (size `N * NumParts`) ... Coordinate
   arrays are defined separately for each partition of the current time
   step." `Dimensions` holds the points per axis N, M, P.
S8 "there can be a `CellData` group containing cell fields": one value per
   cell, in the cells' file order (tree by tree, each breadth-first).
S9 Steps: "read offsets into the `DepthPerTree`, `NumberOfCellsPerTreeDepth`,
   `TreeIds`, `Mask` `Descriptors` and coordinate datasets for each timestep
   ... for `Mask` and `Descriptors`, the offset is in **bytes**". Generic
   temporal data: `Values` (time of each step), `PartOffsets` (first piece
   of the step), `NumberOfParts` (pieces of the step; optional),
   `CellDataOffsets/{name}` (first value of the step). The reader needs
   Steps/TreeIdsOffsets, DepthPerTreeOffsets, NumberOfCellsPerTreeDepthOffsets,
   DescriptorsOffsets, MaskOffsets, X/Y/ZCoordinatesOffsets and PartOffsets
   (vtkHDFUtilities.txx, TemporalHyperTreeGridOffsets). Steps are appended one
   after the other (the spec's "Writing incrementally ... appending").
S10 Root attributes: Version [2, >= 4] (HyperTreeGrid is VTKHDF 2.4,
   vtkhdf_changelog.md), Type "HyperTreeGrid", BranchFactor, Dimensions;
   TreeIds are root indices i + (N-1) * (j + (M-1) * k) unless
   TransposedRootIndexing is set (vtkHyperTreeGrid::GetIndexFromLevelZeroCoordinates).
"""

import os
import subprocess
import sys

import h5py

# Kinds of dataset values: how the type is checked.
U8 = "uint8"  # packed bits (S2)
INT = "int"  # any integer type
F64 = "float64"  # the simulation's field type, and coordinates
FLOAT = "float"  # any floating-point type (step times)


class Expectation:
    """Everything one file must hold. `required`: path -> (kind, values);
    `optional`: the same for datasets the specification lets a writer leave
    out (checked when present)."""

    def __init__(self, branch_factor, dimensions, required, optional=None,
                 steps=1, single_step_group_optional=False, cell_arrays=("value",)):
        self.branch_factor = branch_factor
        self.dimensions = dimensions
        self.required = required
        self.optional = optional or {}
        self.steps = steps
        self.single_step_group_optional = single_step_group_optional
        self.cell_arrays = set(cell_arrays)


def single_step_offsets():
    """Steps datasets of a one-step file: every read offset 0 (S9)."""
    return {
        "Steps/Values": (FLOAT, [0.0]),
        "Steps/PartOffsets": (INT, [0]),
        "Steps/TreeIdsOffsets": (INT, [0]),
        "Steps/DepthPerTreeOffsets": (INT, [0]),
        "Steps/NumberOfCellsPerTreeDepthOffsets": (INT, [0]),
        "Steps/DescriptorsOffsets": (INT, [0]),
        "Steps/XCoordinatesOffsets": (INT, [0]),
        "Steps/YCoordinatesOffsets": (INT, [0]),
        "Steps/ZCoordinatesOffsets": (INT, [0]),
        "Steps/CellDataOffsets/value": (INT, [0]),
    }


# ---- (a) 2D binary, 2x1 roots, root 0 refined once, root 1 a leaf -------------
#   tree 0: level 0: root R        level 1: c0 c1 c2 c3 (leaves)
#   tree 1: level 0: root (leaf)
def case_a():
    return Expectation(
        branch_factor=2,
        dimensions=[3, 2, 1],  # points per axis: x {0,1,2}, y {0,1}, z {0} (S10)
        required={
            "NumberOfTrees": (INT, [2]),
            "NumberOfCells": (INT, [6]),  # 1 + 4, then 1
            "NumberOfDepths": (INT, [3]),  # 2 levels + 1 level (S5)
            # Tree 0: level 0 only (level 1 is the deepest): 1 bit. Tree 1: its
            # only level is its deepest: 0 bits (S1).
            "DescriptorsSize": (INT, [1]),
            "TreeIds": (INT, [0, 1]),
            "DepthPerTree": (INT, [2, 1]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 4, 1]),
            # Bits: 1 -> first bit in the most significant place (S2).
            "Descriptors": (U8, [0b10000000]),
            "XCoordinates": (F64, [0.0, 1.0, 2.0]),
            "YCoordinates": (F64, [0.0, 1.0]),
            "ZCoordinates": (F64, [0.0]),
            # Tree 0 breadth-first (root, c0..c3), then tree 1 (S8).
            "CellData/value": (F64, [10.0, 11.0, 12.0, 13.0, 14.0, 20.0]),
        },
        optional={
            # No cell masked: if a Mask is written, 6 bits of 0 in 1 byte (S6).
            "Mask": (U8, [0b00000000]),
            "Steps/MaskOffsets": (INT, [0]),
            "Steps/NumberOfParts": (INT, [1]),
            **single_step_offsets(),
        },
        single_step_group_optional=True,
    )


# ---- (b) 3D binary, 1 root refined once, child c5 refined again ---------------
#   level 0: root R
#   level 1: c0 c1 c2 c3 c4 c5 c6 c7      (c5 R)
#   level 2: c5's children g0..g7          (leaves)
# The simulation stores nodes depth-first: root, c0..c5, g0..g7, c6, c7 with
# value 100 + storage slot, so breadth-first the values are
# root 100, c0..c5 101..106, c6 115, c7 116, g0..g7 107..114.
def case_b():
    return Expectation(
        branch_factor=2,
        dimensions=[2, 2, 2],
        required={
            "NumberOfTrees": (INT, [1]),
            "NumberOfCells": (INT, [17]),  # 1 + 8 + 8
            "NumberOfDepths": (INT, [3]),
            "DescriptorsSize": (INT, [9]),  # levels 0 and 1: 1 + 8 bits (S1)
            "TreeIds": (INT, [0]),
            "DepthPerTree": (INT, [3]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 8, 8]),
            # Bits: root 1 | c0..c7 0 0 0 0 0 1 0 0
            #   byte 0: 1 0 0 0 0 0 1 0   (root, c0..c6)
            #   byte 1: 0 + 7 padding 0s  (c7)
            "Descriptors": (U8, [0b10000010, 0b00000000]),
            "XCoordinates": (F64, [0.0, 1.0]),
            "YCoordinates": (F64, [0.0, 1.0]),
            "ZCoordinates": (F64, [0.0, 1.0]),
            "CellData/value": (F64, [100.0, 101.0, 102.0, 103.0, 104.0, 105.0, 106.0, 115.0,
                                     116.0, 107.0, 108.0, 109.0, 110.0, 111.0, 112.0, 113.0,
                                     114.0]),
        },
        optional={
            "Mask": (U8, [0, 0, 0]),  # 17 cells: 3 bytes (S6)
            "Steps/MaskOffsets": (INT, [0]),
            "Steps/NumberOfParts": (INT, [1]),
            **single_step_offsets(),
        },
        single_step_group_optional=True,
    )


# ---- (c) 2D ternary, 1 root refined once, centre child c4 refined again -------
#   level 0: root R
#   level 1: c0..c8 (x fastest: c4 is the centre)   (c4 R)
#   level 2: c4's children g0..g8                    (leaves)
# Values 300 + breadth-first node number (the default, breadth-first storage).
def case_c():
    return Expectation(
        branch_factor=3,
        dimensions=[2, 2, 1],
        required={
            "NumberOfTrees": (INT, [1]),
            "NumberOfCells": (INT, [19]),  # 1 + 9 + 9
            "NumberOfDepths": (INT, [3]),
            "DescriptorsSize": (INT, [10]),  # 1 + 9 bits
            "TreeIds": (INT, [0]),
            "DepthPerTree": (INT, [3]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 9, 9]),
            # Bits: root 1 | c0..c8 0 0 0 0 1 0 0 0 0
            #   byte 0: 1 0 0 0 0 1 0 0   (root, c0..c6)
            #   byte 1: 0 0 + 6 padding   (c7, c8)
            "Descriptors": (U8, [0b10000100, 0b00000000]),
            "XCoordinates": (F64, [0.0, 3.0]),
            "YCoordinates": (F64, [0.0, 3.0]),
            "ZCoordinates": (F64, [0.0]),
            "CellData/value": (F64, [300.0, 301.0, 302.0, 303.0, 304.0, 305.0, 306.0, 307.0,
                                     308.0, 309.0, 310.0, 311.0, 312.0, 313.0, 314.0, 315.0,
                                     316.0, 317.0, 318.0]),
        },
        optional={
            "Mask": (U8, [0, 0, 0]),  # 19 cells: 3 bytes
            "Steps/MaskOffsets": (INT, [0]),
            "Steps/NumberOfParts": (INT, [1]),
            **single_step_offsets(),
        },
        single_step_group_optional=True,
    )


# ---- (d) masked, 2D binary, 2x1 roots ------------------------------------------
#   tree 0: root R | c0 c1(R) c2(masked leaf) c3 | c1's d0 d1 d2 d3(masked)
#   tree 1: root R | c0(R, masked) c1 c2 c3      | c0's e0 e1 e2 e3
#   values: tree 0 nodes 40..48, tree 1 nodes 50..58, breadth-first.
# S6 forbids a mask on tree 1's refined c0, and the specification allows two
# files that show the same cells; both are written out in full:
#   "leaves": c0 stays refined and unmasked, its four leaves are masked.
#   "pruned": c0 becomes a masked leaf, its subtree is dropped (what VTK's own
#             vtkHDFWriter does: vtkHyperTree::ComputeBreadthFirstOrderDescriptor
#             does not descend into masked cells).
def case_d_leaves():
    return Expectation(
        branch_factor=2,
        dimensions=[3, 2, 1],
        required={
            "NumberOfTrees": (INT, [2]),
            "NumberOfCells": (INT, [18]),  # 9 + 9
            "NumberOfDepths": (INT, [6]),  # 3 + 3
            "DescriptorsSize": (INT, [10]),  # 5 + 5 bits
            "TreeIds": (INT, [0, 1]),
            "DepthPerTree": (INT, [3, 3]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 4, 4, 1, 4, 4]),
            # Tree 0: root 1 | c0..c3 0 1 0 0; tree 1: root 1 | c0..c3 1 0 0 0;
            # no padding between trees (S3): 1 0 1 0 0 1 1 0 | 0 0
            "Descriptors": (U8, [0b10100110, 0b00000000]),
            # Mask, one bit per cell, trees back to back (S3):
            #   tree 0: root 0 | c0..c3 0 0 1 0 | d0..d3 0 0 0 1
            #   tree 1: root 0 | c0..c3 0 0 0 0 | e0..e3 1 1 1 1
            #   byte 0: 0 0 0 1 0 0 0 0   (tree 0: root, c0..c3, d0..d2)
            #   byte 1: 1 0 0 0 0 0 1 1   (tree 0: d3; tree 1: root, c0..c3, e0, e1)
            #   byte 2: 1 1 + 6 padding   (tree 1: e2, e3)
            "Mask": (U8, [0b00010000, 0b10000011, 0b11000000]),
            "XCoordinates": (F64, [0.0, 1.0, 2.0]),
            "YCoordinates": (F64, [0.0, 1.0]),
            "ZCoordinates": (F64, [0.0]),
            "CellData/value": (F64, [40.0, 41.0, 42.0, 43.0, 44.0, 45.0, 46.0, 47.0, 48.0,
                                     50.0, 51.0, 52.0, 53.0, 54.0, 55.0, 56.0, 57.0, 58.0]),
        },
        optional={
            "Steps/MaskOffsets": (INT, [0]),
            "Steps/NumberOfParts": (INT, [1]),
            **single_step_offsets(),
        },
        single_step_group_optional=True,
    )


def case_d_pruned():
    return Expectation(
        branch_factor=2,
        dimensions=[3, 2, 1],
        required={
            "NumberOfTrees": (INT, [2]),
            "NumberOfCells": (INT, [14]),  # 9 + 5
            "NumberOfDepths": (INT, [5]),  # 3 + 2
            "DescriptorsSize": (INT, [6]),  # 5 + 1 bits
            "TreeIds": (INT, [0, 1]),
            "DepthPerTree": (INT, [3, 2]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 4, 4, 1, 4]),
            # Tree 0: 1 0 1 0 0; tree 1: root 1 (level 1 is now its deepest).
            "Descriptors": (U8, [0b10100100]),
            #   tree 0: 0 | 0 0 1 0 | 0 0 0 1;  tree 1: 0 | 1 0 0 0
            #   byte 0: 0 0 0 1 0 0 0 0;  byte 1: 1 0 1 0 0 0 + 2 padding
            "Mask": (U8, [0b00010000, 0b10100000]),
            "XCoordinates": (F64, [0.0, 1.0, 2.0]),
            "YCoordinates": (F64, [0.0, 1.0]),
            "ZCoordinates": (F64, [0.0]),
            "CellData/value": (F64, [40.0, 41.0, 42.0, 43.0, 44.0, 45.0, 46.0, 47.0, 48.0,
                                     50.0, 51.0, 52.0, 53.0, 54.0]),
        },
        optional=case_d_leaves().optional,
        single_step_group_optional=True,
    )


# ---- (e) two steps of one 2D root ----------------------------------------------
#   step 0 (time 0.0), x {0,1} y {0,1} z {0}:
#     root R | c0 c1(R) c2 c3 | c1's d0..d3            values 60..68
#   step 1 (time 0.5), x {0,2} y {0,2} z {1} (the coordinates change, so
#   they cannot be stored once for both steps, S9):
#     root R | c0 c1 c2 c3(R) | c3's d0(R) d1 d2 d3 | d0's e0..e3   values 70..82
def case_e():
    return Expectation(
        branch_factor=2,
        dimensions=[2, 2, 1],
        steps=2,
        required={
            # Per piece, step 0's piece then step 1's (S5).
            "NumberOfTrees": (INT, [1, 1]),
            "NumberOfCells": (INT, [9, 13]),  # 1+4+4; 1+4+4+4
            "NumberOfDepths": (INT, [3, 4]),
            "DescriptorsSize": (INT, [5, 9]),  # 1+4; 1+4+4 bits
            "TreeIds": (INT, [0, 0]),
            "DepthPerTree": (INT, [3, 4]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 4, 4, 1, 4, 4, 4]),
            # Step 0: 1 | 0 1 0 0                -> byte 0: 1 0 1 0 0 + 3 padding
            # Step 1 (a new piece: a new byte, S4): 1 | 0 0 0 1 | 1 0 0 0
            #                                    -> byte 1: 1 0 0 0 1 1 0 0
            #                                       byte 2: 0 + 7 padding
            "Descriptors": (U8, [0b10100000, 0b10001100, 0b00000000]),
            # One copy per piece and step (S7).
            "XCoordinates": (F64, [0.0, 1.0, 0.0, 2.0]),
            "YCoordinates": (F64, [0.0, 1.0, 0.0, 2.0]),
            "ZCoordinates": (F64, [0.0, 1.0]),
            "CellData/value": (F64, [60.0, 61.0, 62.0, 63.0, 64.0, 65.0, 66.0, 67.0, 68.0,
                                     70.0, 71.0, 72.0, 73.0, 74.0, 75.0, 76.0, 77.0, 78.0,
                                     79.0, 80.0, 81.0, 82.0]),
            # S9: where step 1 starts in each dataset.
            "Steps/Values": (FLOAT, [0.0, 0.5]),
            "Steps/PartOffsets": (INT, [0, 1]),  # one piece per step
            "Steps/TreeIdsOffsets": (INT, [0, 1]),
            "Steps/DepthPerTreeOffsets": (INT, [0, 1]),
            "Steps/NumberOfCellsPerTreeDepthOffsets": (INT, [0, 3]),
            "Steps/DescriptorsOffsets": (INT, [0, 1]),  # bytes, not the 5 bits
            "Steps/XCoordinatesOffsets": (INT, [0, 2]),
            "Steps/YCoordinatesOffsets": (INT, [0, 2]),
            "Steps/ZCoordinatesOffsets": (INT, [0, 1]),
            "Steps/CellDataOffsets/value": (INT, [0, 9]),
        },
        optional={
            # Unmasked: 9 bits -> 2 bytes, 13 bits -> 2 bytes, all 0.
            "Mask": (U8, [0, 0, 0, 0]),
            "Steps/MaskOffsets": (INT, [0, 2]),  # bytes: ceil(9 / 8)
            "Steps/NumberOfParts": (INT, [1, 1]),
        },
    )


# ---- (f) two pieces (2 MPI ranks), 2D binary, 2x1 roots ------------------------
#   piece 0 (rank 0): tree 0: root R | c0..c3                      values 80..84
#   piece 1 (rank 1): tree 1: root R | c0(R) c1 c2 c3(masked) | c0's e0(masked) e1 e2 e3
#                                                                  values 90..98
def case_f():
    return Expectation(
        branch_factor=2,
        dimensions=[3, 2, 1],
        required={
            "NumberOfTrees": (INT, [1, 1]),
            "NumberOfCells": (INT, [5, 9]),
            "NumberOfDepths": (INT, [2, 3]),
            "DescriptorsSize": (INT, [1, 5]),
            "TreeIds": (INT, [0, 1]),
            "DepthPerTree": (INT, [2, 3]),
            "NumberOfCellsPerTreeDepth": (INT, [1, 4, 1, 4, 4]),
            # Piece 0: 1 -> byte 0. Piece 1 starts a new byte (S4):
            # 1 | 1 0 0 0 -> byte 1: 1 1 0 0 0 + 3 padding.
            "Descriptors": (U8, [0b10000000, 0b11000000]),
            # Piece 0: 5 cells, none masked -> 1 byte.
            # Piece 1 from a new byte: root 0 | c0..c3 0 0 0 1 | e0..e3 1 0 0 0
            #   byte 1: 0 0 0 0 1 1 0 0;  byte 2: 0 + 7 padding
            "Mask": (U8, [0b00000000, 0b00001100, 0b00000000]),
            # Each piece its own copy (S7).
            "XCoordinates": (F64, [0.0, 1.0, 2.0, 0.0, 1.0, 2.0]),
            "YCoordinates": (F64, [0.0, 1.0, 0.0, 1.0]),
            "ZCoordinates": (F64, [0.0, 0.0]),
            "CellData/value": (F64, [80.0, 81.0, 82.0, 83.0, 84.0,
                                     90.0, 91.0, 92.0, 93.0, 94.0, 95.0, 96.0, 97.0, 98.0]),
        },
        optional={
            "Steps/MaskOffsets": (INT, [0]),
            "Steps/NumberOfParts": (INT, [2]),  # the one step has both pieces
            **single_step_offsets(),
        },
        single_step_group_optional=True,
    )


CASES = {
    "serial": {
        "a_2d_binary.vtkhdf": {"": case_a},
        "b_3d_binary.vtkhdf": {"": case_b},
        "c_2d_ternary.vtkhdf": {"": case_c},
        "d_masked.vtkhdf": {"leaves": case_d_leaves, "pruned": case_d_pruned},
        "e_two_steps.vtkhdf": {"": case_e},
    },
    "pieces": {
        "f_two_pieces.vtkhdf": {"": case_f},
    },
}


# ---- reading --------------------------------------------------------------------
def text(value):
    if isinstance(value, bytes):
        value = value.decode()
    return str(value).rstrip("\0")


def as_list(value):
    return value.tolist() if hasattr(value, "tolist") else value


def bits(values):
    return "[" + ", ".join("0b{:08b}".format(v) for v in values) + "]"


def dtype_problem(kind, dtype):
    if kind == U8 and dtype != "uint8":
        return "type %s, expected uint8 (unsigned chars, S2)" % dtype
    if kind == INT and dtype.kind not in "iu":
        return "type %s, expected an integer type" % dtype
    if kind == F64 and dtype != "float64":
        return "type %s, expected float64" % dtype
    if kind == FLOAT and dtype.kind != "f":
        return "type %s, expected a floating-point type" % dtype
    return None


def check_dataset(root, path, kind, expected, problems):
    show = bits if kind == U8 else str
    if path not in root:
        problems.append("/VTKHDF/%s: missing, expected %s" % (path, show(expected)))
        return
    dataset = root[path]
    if not isinstance(dataset, h5py.Dataset):
        problems.append("/VTKHDF/%s: not a dataset" % path)
        return
    if dataset.ndim != 1:
        problems.append("/VTKHDF/%s: shape %s, expected one dimension" % (path, dataset.shape))
        return
    wrong_type = dtype_problem(kind, dataset.dtype)
    if wrong_type:
        problems.append("/VTKHDF/%s: %s" % (path, wrong_type))
    actual = as_list(dataset[()])
    if actual != expected:
        problems.append("/VTKHDF/%s: %s, expected %s" % (path, show(actual), show(expected)))


def check_attribute(group, name, check, problems, where):
    if name not in group.attrs:
        problems.append("%s attribute %s: missing" % (where, name))
        return
    problem = check(group.attrs[name])
    if problem:
        problems.append("%s attribute %s: %s" % (where, name, problem))


def file_problems(path, expectation):
    problems = []
    with h5py.File(path, "r") as f:
        if "VTKHDF" not in f:
            return ["no /VTKHDF group"]
        root = f["VTKHDF"]

        def version(value):
            v = as_list(value)
            if not (isinstance(v, list) and len(v) == 2 and v[0] == 2 and v[1] >= 4):
                return "%s, expected [2, >= 4] (S10)" % v
            return None

        def equal(expected):
            def check(value):
                v = as_list(value)
                if isinstance(v, list) and len(v) == 1 and not isinstance(expected, list):
                    v = v[0]
                return None if v == expected else "%s, expected %s" % (v, expected)
            return check

        check_attribute(root, "Version", version, problems, "/VTKHDF")
        check_attribute(root, "Type", lambda v: None if text(v) == "HyperTreeGrid"
                        else "%r, expected 'HyperTreeGrid'" % text(v), problems, "/VTKHDF")
        check_attribute(root, "BranchFactor", equal(expectation.branch_factor), problems,
                        "/VTKHDF")
        check_attribute(root, "Dimensions", equal(expectation.dimensions), problems, "/VTKHDF")
        if "TransposedRootIndexing" in root.attrs:
            # TreeIds above are i-fastest root indices (S10).
            check_attribute(root, "TransposedRootIndexing", equal(0), problems, "/VTKHDF")

        for name, (kind, expected) in expectation.required.items():
            check_dataset(root, name, kind, expected, problems)

        has_steps = "Steps" in root
        if expectation.steps > 1 or not expectation.single_step_group_optional:
            if not has_steps:
                problems.append("/VTKHDF/Steps: missing")
        if has_steps:
            check_attribute(root["Steps"], "NSteps", equal(expectation.steps), problems,
                            "/VTKHDF/Steps")
        for name, (kind, expected) in expectation.optional.items():
            if name.startswith("Steps/"):
                # A one-step file may leave Steps out; once there, the reader
                # needs every offset dataset (S9) but NumberOfParts and, without
                # a Mask, MaskOffsets.
                needed = has_steps and name not in ("Steps/NumberOfParts",
                                                    "Steps/MaskOffsets")
                if name == "Steps/MaskOffsets":
                    needed = has_steps and "Mask" in root
                if needed or name in root:
                    check_dataset(root, name, kind, expected, problems)
            elif name in root:
                check_dataset(root, name, kind, expected, problems)

        if "CellData" not in root:
            problems.append("/VTKHDF/CellData: missing")
        else:
            names = set(root["CellData"].keys())
            if names != expectation.cell_arrays:
                problems.append("/VTKHDF/CellData: arrays %s, expected %s"
                                % (sorted(names), sorted(expectation.cell_arrays)))
        if "PointData" in root and len(root["PointData"]) > 0:
            problems.append("/VTKHDF/PointData: HyperTreeGrids have no point data (S8)")
    return problems


def main(argv):
    if len(argv) < 3 or argv[1] not in CASES:
        print(__doc__)
        return 2
    cases, directory = CASES[argv[1]], argv[2]
    if len(argv) > 3:
        if argv[3] != "--" or len(argv) == 4:
            print("expected: -- COMMAND...")
            return 2
        # Old files must not pass for new ones.
        for name in cases:
            if os.path.exists(os.path.join(directory, name)):
                os.remove(os.path.join(directory, name))
        result = subprocess.run(argv[4:])
        if result.returncode != 0:
            print("FAIL: the writer exited with %d" % result.returncode)
            return 1
    failed = 0
    for name, alternatives in cases.items():
        path = os.path.join(directory, name)
        if not os.path.exists(path):
            print("FAIL %s: not written" % name)
            failed += 1
            continue
        found = {label: file_problems(path, make()) for label, make in alternatives.items()}
        if any(not problems for problems in found.values()):
            matched = [label for label, problems in found.items() if not problems][0]
            print("ok   %s%s" % (name, " (%s)" % matched if matched else ""))
            continue
        failed += 1
        for label, problems in found.items():
            print("FAIL %s%s:" % (name, " (as '%s')" % label if label else ""))
            for problem in problems:
                print("       " + problem)
    print("%d of %d files as the specification gives them" % (len(cases) - failed, len(cases)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
