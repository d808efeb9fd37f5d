"""Run by ParaView 5.11's GUI (paraview --script=...; live_gui_picture.sh does it
all): connects to the 3D mini-app through paraview.live from the GUI's Python,
extracts its slices, selected region and grid (unpacked), shows them in the
GUI's render view with the simulation's camera, and writes DONE_FILE. What the
GUI then shows is docs/insitu.md's picture of a live session.

Environment: CANOPY_PLUGIN, CANOPY_LIVE_PORT, CANOPY_GUI_FLAGS (a folder: the
script writes "listening" and "done" there)."""
import os
import time

from paraview import live, simple
simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
flags = os.environ["CANOPY_GUI_FLAGS"]
link = live.ConnectToCatalyst("localhost", int(os.environ["CANOPY_LIVE_PORT"]))
open(os.path.join(flags, "listening"), "w").write("1")
deadline = time.time() + 120
shown = None
first = None
while time.time() < deadline:
    live.ProcessServerNotifications()
    m = link.GetInsituProxyManager()
    names = {m.GetProxyName("sources", i) for i in range(m.GetNumberOfProxies("sources"))}
    if shown is None and {"CanopyAdaptiveSlice1", "CanopyAdaptiveSurface1", "grid"} <= names:
        shown = [live.ExtractCatalystData(link, n) for n in ("CanopyAdaptiveSlice1", "CanopyAdaptiveSurface1")]
        grid = simple.CanopyUnpackGrid(Input=live.ExtractCatalystData(link, "grid"))
    if shown:
        for p in shown + [grid]:
            p.UpdatePipeline()
        if first is None and shown[0].GetDataInformation().GetNumberOfCells():
            first = link.GetTimeStep()
        if first is not None and link.GetTimeStep() >= first + 4:
            break
    time.sleep(0.05)
view = simple.GetActiveView() or simple.GetActiveViewOrCreate("RenderView")
lut = simple.GetColorTransferFunction("scalar")
for p in shown:
    d = simple.Show(p, view)
    simple.ColorBy(d, ("CELLS", "scalar"))
slices = simple.GetDisplayProperties(shown[0], view)
slices.Ambient, slices.Diffuse = 1.0, 0.0  # the colour map as it is
region = simple.GetDisplayProperties(shown[1], view)
region.Ambient, region.Diffuse = 0.45, 0.55
simple.Show(simple.Outline(Input=shown[0]), view)
lut.RescaleTransferFunction(0.0, 0.85)
simple.GetDisplayProperties(shown[0], view).SetScalarBarVisibility(view, True)
d3 = 3 ** 0.5
view.CameraFocalPoint = [0.5, 0.5, 0.5]
view.CameraPosition = [0.5 + 1.2 * d3, 0.5 + 0.9 * d3, 0.5 + 1.5 * d3]
view.CameraViewUp = [0, 1, 0]
simple.SetActiveSource(grid)
simple.Render(view)
open(os.path.join(flags, "done"), "w").write(str(link.GetTimeStep()))
