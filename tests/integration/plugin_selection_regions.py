"""Box and frustum selection through the plugin's proxies in pvpython: the Box and
FrustumPlanes properties, FrustumCorners, and a frustum on the Selection port from
ParaView's own FrustumSelectionSource (what a rubber-band "select cells on" makes).
Paper case A (2D, binary) and case B (3D, ternary), built by ParaView's own
hypertree-grid source; checked against brute force over the leaves by VTK's cursors
(exact for the box, by sampling for frusta: the unit tests measure exactly).

Run: pvpython plugin_selection_regions.py <CanopyPlugin.so>
"""
import sys

from paraview import servermanager
from paraview.simple import HyperTreeGrid, LoadPlugin
from vtkmodules.vtkCommonDataModel import vtkHyperTreeGridNonOrientedGeometryCursor
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import vtkCamera

LoadPlugin(sys.argv[1], remote=False, ns=globals())
failures = []


def check(condition, message):
    print(("ok:     " if condition else "FAILED: ") + message)
    if not condition:
        failures.append(message)


def leaves(htg):
    """(global id, bounds) of every unmasked leaf, by VTK's cursors."""
    found = []
    for index in range(htg.GetMaxNumberOfTrees()):
        if htg.GetTree(index) is None:
            continue
        cursor = vtkHyperTreeGridNonOrientedGeometryCursor()
        htg.InitializeNonOrientedGeometryCursor(cursor, index)

        def walk():
            if cursor.IsMasked():
                return
            if cursor.IsLeaf():
                bounds = [0.0] * 6
                cursor.GetBounds(bounds)
                found.append((cursor.GetGlobalNodeIndex(), bounds))
                return
            for child in range(cursor.GetNumberOfChildren()):
                cursor.ToChild(child)
                walk()
                cursor.ToParent()
        walk()
    return found


def clipped_measure(bounds, planes):
    """Area (2D, z flat) or volume (3D) of the part of a cell inside every plane,
    estimated on a 12^d lattice of sample points at cell-relative positions
    (k + 0.5) / 12: positive when any sample is strictly inside."""
    n = 12
    flat = bounds[4] == bounds[5]
    inside = 0
    for i in range(n):
        for j in range(n):
            for k in range(1 if flat else n):
                p = (bounds[0] + (i + 0.5) / n * (bounds[1] - bounds[0]),
                     bounds[2] + (j + 0.5) / n * (bounds[3] - bounds[2]),
                     bounds[4] + (k + 0.5) / n * (bounds[5] - bounds[4]))
                inside += all(a * p[0] + b * p[1] + c * p[2] + d > 0 for a, b, c, d in planes)
    return inside


def selected_ids(proxy):
    proxy.UpdatePipeline()
    data = servermanager.Fetch(proxy)
    array = data.GetCellData().GetArray("OriginalCellId")
    return sorted(int(array.GetValue(i)) for i in range(array.GetNumberOfTuples()))


def camera_frustum(position, focal, angle, aspect, near, far):
    camera = vtkCamera()
    camera.SetPosition(position)
    camera.SetFocalPoint(focal)
    camera.SetViewAngle(angle)
    camera.SetClippingRange(near, far)
    planes = [0.0] * 24
    camera.GetFrustumPlanes(aspect, planes)
    inverse = vtkMatrix4x4()
    vtkMatrix4x4.Invert(camera.GetCompositeProjectionTransformMatrix(aspect, -1, 1), inverse)
    corners = []
    for c in range(8):  # bit 0 far, bit 1 upper, bit 2 right: vtkSelectionNode's order
        world = inverse.MultiplyPoint([1.0 if c & 4 else -1.0, 1.0 if c & 2 else -1.0,
                                       1.0 if c & 1 else -1.0, 1.0])
        corners.append([world[a] / world[3] for a in range(3)])
    return planes, corners


case_a = HyperTreeGrid(
    Dimensions=[3, 4, 1], GridScale=[1.5, 1, 10], BranchFactor=2, MaxDepth=6,
    Descriptor="RRRRR.|.... .R.. RRRR R... R...|.R.. ...R ..RR .R.. R... .... ....|.... "
               "...R ..R. .... .R.. R...|.... .... .R.. ....|....")
case_b = HyperTreeGrid(
    Dimensions=[4, 4, 3], GridScale=[1.5, 1, 0.7], BranchFactor=3, MaxDepth=5,
    Descriptor="RRR .R. .RR ..R ..R .R.|R.......................... ........................... "
               "........................... .............R............. ....RR.RR........R......... "
               ".....RRRR.....R.RR......... ........................... ........................... "
               "...........................|........................... ........................... "
               "........................... ...RR.RR.......RR.......... ........................... "
               "RR......................... ........................... ........................... "
               "........................... ........................... ........................... "
               "........................... ........................... ............RRR............|"
               "........................... ........................... .......RR.................. "
               "........................... ........................... ........................... "
               "........................... ........................... ........................... "
               "........................... ...........................|........................... "
               "...........................")

# Box, case A: z range away from the plane (ignored in 2D); touching is not overlapping.
box = [0.75, 2.25, 0.5, 2.0, 4.0, 5.0]
leaves_a = leaves(servermanager.Fetch(case_a))
expected = sorted(g for g, b in leaves_a
                  if b[0] < box[1] and box[0] < b[1] and b[2] < box[3] and box[2] < b[3])
got = selected_ids(CanopyExtractSelection(Input=case_a, SelectionMode="Box",  # noqa: F821
                                          Box=box))
check(got == expected and 0 < len(got) < len(leaves_a),
      "box on case A: %d cells, brute force %d" % (len(got), len(expected)))

# Frusta: planes, corners and FrustumSelectionSource give the brute force's cells.
views = [(case_a, (2.5, -1.0, 4.0), (1.2, 1.4, 0.0), 14.0, 1.5, 2.0, 9.0),
         (case_b, (7.0, 5.5, 4.0), (2.2, 1.4, 0.7), 18.0, 1.2, 5.5, 8.0)]
for grid, position, focal, angle, aspect, near, far in views:
    planes, corners = camera_frustum(position, focal, angle, aspect, near, far)
    grouped = [planes[4 * i:4 * i + 4] for i in range(6)]
    all_leaves = leaves(servermanager.Fetch(grid))
    expected = sorted(g for g, b in all_leaves if clipped_measure(b, grouped) > 0)
    label = "case A" if grid is case_a else "case B"
    by_planes = selected_ids(CanopyExtractSelection(  # noqa: F821
        Input=grid, SelectionMode="Frustum", FrustumPlanes=planes))
    check(0 < len(expected) < len(all_leaves),
          "%s: the frustum cuts the grid (%d of %d leaves)"
          % (label, len(expected), len(all_leaves)))
    # Sampling can miss a sliver a cell shares with the frustum, never invent one.
    missing = sorted(set(expected) - set(by_planes))
    check(not missing, "%s, FrustumPlanes: every sampled overlap selected (%d missing)"
          % (label, len(missing)))
    check(len(by_planes) - len(expected) <= 0.05 * len(expected),
          "%s, FrustumPlanes: %d cells, sampling finds %d" % (label, len(by_planes), len(expected)))
    by_corners = selected_ids(CanopyExtractSelection(  # noqa: F821
        Input=grid, SelectionMode="Frustum", FrustumCorners=[x for c in corners for x in c]))
    check(by_corners == by_planes, "%s: FrustumCorners select what FrustumPlanes do" % label)
    source = servermanager.sources.FrustumSelectionSource(
        Frustum=[x for c in corners for x in c + [1.0]], FieldType="CELL")
    by_source = selected_ids(CanopyExtractSelection(  # noqa: F821
        Input=grid, Selection=source, SelectionMode="Ids"))
    check(by_source == by_planes,
          "%s: a FrustumSelectionSource on the Selection port selects the same" % label)

sys.exit(1 if failures else 0)
