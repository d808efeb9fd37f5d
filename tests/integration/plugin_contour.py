"""The plugin's CanopyContour proxy in pvpython: ContourBy, ContourValues and
InterpolatedFields reach vtkCanopyContour. Paper case A (2D, binary, level jumps)
and case B (3D, ternary), built by ParaView's own hypertree-grid source, with a
field computed here at every cell's centre by VTK's cursors: a linear field's
isolines lie on their lines, and every contour is watertight inside the domain
(2D: each segment end shared by two segments; 3D: each triangle edge by two
triangles).

Run: pvpython plugin_contour.py <CanopyPlugin.so>
"""
import sys
from collections import Counter

from paraview import servermanager
from paraview.simple import HyperTreeGrid, LoadPlugin, TrivialProducer
from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import (vtkHyperTreeGrid,
                                           vtkHyperTreeGridNonOrientedGeometryCursor)

LoadPlugin(sys.argv[1], remote=False, ns=globals())
failures = []


def check(condition, message):
    print(("ok:     " if condition else "FAILED: ") + message)
    if not condition:
        failures.append(message)


def with_field(source, formula):
    """A copy of the source's grid with cell fields f = formula(centre) and
    g = 2 f + 1, for every node, fed to the pipeline by a TrivialProducer."""
    htg = vtkHyperTreeGrid()
    htg.ShallowCopy(servermanager.Fetch(source))
    for name, scale, shift in (("f", 1.0, 0.0), ("g", 2.0, 1.0)):
        array = vtkDoubleArray()
        array.SetName(name)
        array.SetNumberOfTuples(htg.GetNumberOfCells())
        for index in range(htg.GetMaxNumberOfTrees()):
            if htg.GetTree(index) is None:
                continue
            cursor = vtkHyperTreeGridNonOrientedGeometryCursor()
            htg.InitializeNonOrientedGeometryCursor(cursor, index)

            def walk():
                bounds = [0.0] * 6
                cursor.GetBounds(bounds)
                centre = [(bounds[2 * a] + bounds[2 * a + 1]) / 2 for a in range(3)]
                array.SetValue(cursor.GetGlobalNodeIndex(), scale * formula(centre) + shift)
                if cursor.IsLeaf() or cursor.IsMasked():
                    return
                for child in range(cursor.GetNumberOfChildren()):
                    cursor.ToChild(child)
                    walk()
                    cursor.ToParent()
            walk()
        htg.GetCellData().AddArray(array)
    producer = TrivialProducer()
    producer.GetClientSideObject().SetOutput(htg)
    return producer, htg.GetBounds()


def cells_of(cell_array):
    cells = []
    ids = cell_array.GetConnectivityArray()
    offsets = cell_array.GetOffsetsArray()
    for c in range(cell_array.GetNumberOfCells()):
        cells.append([ids.GetValue(i) for i in range(offsets.GetValue(c), offsets.GetValue(c + 1))])
    return cells


def strictly_inside(point, bounds):
    return all(bounds[2 * a] < point[a] < bounds[2 * a + 1]
               for a in range(3) if bounds[2 * a] < bounds[2 * a + 1])


case_a = HyperTreeGrid(
    Dimensions=[3, 4, 1], GridScale=[1.5, 1, 10], BranchFactor=2, MaxDepth=6,
    Descriptor="RRRRR.|.... .R.. RRRR R... R...|.R.. ...R ..RR .R.. R... .... ....|.... "
               "...R ..R. .... .R.. R...|.... .... .R.. ....|....")
case_b = HyperTreeGrid(
    Dimensions=[4, 4, 3], GridScale=[1.5, 1, 0.7], BranchFactor=3, MaxDepth=3,
    Descriptor="RRR .R. .RR ..R ..R .R.|R.......................... ........................... "
               "........................... .............R............. ....RR.RR........R......... "
               ".....RRRR.....R.RR......... ........................... ........................... "
               "...........................|........................... ........................... "
               "........................... ...RR.RR.......RR.......... ........................... "
               "RR......................... ........................... ........................... "
               "........................... ........................... ........................... "
               "........................... ........................... ............RRR............")

# 2D: a linear field; its isolines on their lines, watertight inside the domain.
producer, bounds = with_field(case_a, lambda x: 0.4 * x[0] - 0.7 * x[1])
values = [-1.1, -0.5, 0.1]
contour = CanopyContour(Input=producer, ContourBy=["CELLS", "f"],  # noqa: F821
                        ContourValues=values, InterpolatedFields=["g"])
out = servermanager.Fetch(contour)
segments = cells_of(out.GetLines())
check(len(segments) > 20, "2D: %d segments" % len(segments))
f = out.GetPointData().GetArray("f")
g = out.GetPointData().GetArray("g")
check(f is not None and g is not None, "2D: the contour value and g are point arrays")
worst = max(abs(0.4 * out.GetPoint(p)[0] - 0.7 * out.GetPoint(p)[1] - f.GetValue(p))
            for p in range(out.GetNumberOfPoints()))
check(worst < 1e-12, "2D: every point on its line (worst %.2g)" % worst)
check(sorted(set(f.GetValue(p) for p in range(out.GetNumberOfPoints()))) == values,
      "2D: the three contour values")
uses = Counter(i for s in segments for i in s)
open_ends = [p for p, n in uses.items() if n != 2 and strictly_inside(out.GetPoint(p), bounds)]
check(not open_ends, "2D: every segment end inside the domain shared by two segments")

# 3D, ternary: a sphere, watertight inside the domain, with normals.
producer, bounds = with_field(
    case_b, lambda x: ((x[0] - 2.2) ** 2 + (x[1] - 1.6) ** 2 + (x[2] - 0.9) ** 2) ** 0.5)
contour = CanopyContour(Input=producer, ContourBy=["CELLS", "f"],  # noqa: F821
                        ContourValues=[0.6, 1.1])
out = servermanager.Fetch(contour)
triangles = cells_of(out.GetPolys())
check(len(triangles) > 100, "3D: %d triangles" % len(triangles))
check(out.GetPointData().GetNormals() is not None, "3D: normals")
edges = Counter(tuple(sorted((t[k], t[(k + 1) % 3]))) for t in triangles for k in range(3))
open_edges = [e for e, n in edges.items() if n != 2 and not all(
    any(out.GetPoint(p)[a] in (bounds[2 * a], bounds[2 * a + 1]) for a in range(3)) for p in e)]
check(not open_edges, "3D: every edge inside the domain shared by two triangles (%d open)"
      % len(open_edges))

# The view, through the proxy: off by default (the full contour whatever the camera);
# on, a far camera on a small viewport stops at nodes of PixelThreshold pixels: fewer
# triangles, still watertight inside the domain.
full = len(triangles)
check(contour.ViewDependent == 0 and contour.LevelOfDetail == 1 and contour.ViewCulling == 1,
      "3D: ViewDependent off by default, LevelOfDetail and ViewCulling on")
centre = [0.5 * (bounds[2 * a] + bounds[2 * a + 1]) for a in range(3)]
contour.CameraFocalPoint = centre
contour.CameraPosition = [centre[0], centre[1], centre[2] + 40.0]
contour.CameraViewUp = [0.0, 1.0, 0.0]
contour.ParallelProjection = 0
contour.ViewAngle = 30.0
contour.ViewportSize = [64, 64]
contour.PixelThreshold = 4.0
out = servermanager.Fetch(contour)
check(len(cells_of(out.GetPolys())) == full, "3D: moving the camera alone changes nothing "
      "while ViewDependent is off (%d triangles)" % len(cells_of(out.GetPolys())))
contour.ViewDependent = 1
out = servermanager.Fetch(contour)
coarse = cells_of(out.GetPolys())
edges = Counter(tuple(sorted((t[k], t[(k + 1) % 3]))) for t in coarse for k in range(3))
open_edges = [e for e, n in edges.items() if n != 2 and not all(
    any(out.GetPoint(p)[a] in (bounds[2 * a], bounds[2 * a + 1]) for a in range(3)) for p in e)]
check(0 < len(coarse) < full and not open_edges,
      "3D: ViewDependent on, seen far away on 64 x 64 pixels: %d triangles instead of %d, "
      "%d edges inside the domain open" % (len(coarse), full, len(open_edges)))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
