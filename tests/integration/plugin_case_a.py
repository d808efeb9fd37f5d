"""The Canopy ParaView plugin in pvbatch: load it, build paper case A with
ParaView's own hypertree-grid source, run both filters, show every output type,
write an image and a .vtu, and check them by content.

Run: tests/support/with_xvfb.sh pvbatch plugin_case_a.py <CanopyPlugin.so> <output dir>
"""
import os
import sys

from paraview.simple import (CreateRenderView, Delete, HyperTreeGrid, LoadPlugin, Render,
                             SaveData, SaveScreenshot, Show, ColorBy,
                             XMLUnstructuredGridReader)
from paraview import servermanager

plugin, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
LoadPlugin(plugin, remote=False, ns=globals())

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED: " + message)


grid = HyperTreeGrid(
    Dimensions=[3, 4, 1], GridScale=[1.5, 1, 10], BranchFactor=2, MaxDepth=6,
    Descriptor="RRRRR.|.... .R.. RRRR R... R...|.R.. ...R ..RR .R.. R... .... ....|.... "
               "...R ..R. .... .R.. R...|.... .... .R.. ....|....")

# The paper's view: parallel, scale 1 around (0.75, 1.5), 400 x 400.
surface = CanopyAdaptiveSurface(  # noqa: F821 (defined by LoadPlugin)
    Input=grid, CameraPosition=[0.75, 1.5, 10], CameraFocalPoint=[0.75, 1.5, 0],
    ParallelScale=1.0, ViewportSize=[400, 400], LevelOfDetail=0)
surface.UpdatePipeline()
quads = surface.GetDataInformation().GetNumberOfCells()
check(quads == 58, "adaptive surface of case A in the paper's view: %d quads, expected 58" % quads)

# Two points inside, one on the domain's upper corner, one outside.
selection = CanopyExtractSelection(  # noqa: F821
    Input=grid, SelectionMode="Locations",
    Locations=[0.1, 0.1, 0.0, 2.2, 1.6, 0.0, 3.0, 3.0, 0.0, 5.0, 5.0, 0.0])
selection.UpdatePipeline()
cells = selection.GetDataInformation().GetNumberOfCells()
check(cells == 3, "selection by location: %d cells, expected 3" % cells)
SaveData(os.path.join(out, "selection.vtu"), proxy=selection)
reread = XMLUnstructuredGridReader(FileName=[os.path.join(out, "selection.vtu")])
reread.UpdatePipeline()
check(reread.GetDataInformation().GetNumberOfCells() == 3, "the .vtu holds the 3 cells")

masked = CanopyExtractSelection(  # noqa: F821
    Input=grid, SelectionMode="Ids", Ids=[0, 7], PreserveTopology=1)
masked.UpdatePipeline()
check(servermanager.Fetch(masked).GetClassName() == "vtkHyperTreeGrid",
      "PreserveTopology gives a hypertree grid")

view = CreateRenderView()
view.ViewSize = [400, 400]
view.CameraPosition = [0.75, 1.5, 10]
view.CameraFocalPoint = [0.75, 1.5, 0]
view.CameraParallelProjection = 1
view.CameraParallelScale = 1.0
display = Show(surface, view)
ColorBy(display, ("CELLS", "Depth"))
Show(selection, view)
Show(masked, view)  # every output type can be shown
Render(view)
image = os.path.join(out, "case_a_surface.png")
SaveScreenshot(image, view, ImageResolution=[400, 400])

from vtkmodules.vtkIOImage import vtkPNGReader  # noqa: E402

reader = vtkPNGReader()
reader.SetFileName(image)
reader.Update()
pixels = reader.GetOutput().GetPointData().GetScalars()
background = pixels.GetTuple(0)
different = sum(1 for i in range(0, pixels.GetNumberOfTuples(), 7)
                if pixels.GetTuple(i) != background)
check(different > 1000, "the image shows the surface (%d sampled pixels differ from the "
                        "background)" % different)

print("plugin: %d quads, %d selected cells, image %s" % (quads, cells, image))
# Release the render view before the interpreter exits: tearing it down during
# interpreter finalization triggers GLXBadContext under Xvfb.
Delete(view)  # noqa: F821
del view
sys.exit(1 if failures else 0)
