"""The picture of docs/insitu.md's "Catalyst Live": a pvpython viewer, as a
user would write it, that pulls the 3D mini-app's slices, its selected region
and its grid (unpacked; drawn as its outline), colours them by the scalar and
saves what it shows after a few deliveries (with the simulation's camera).

  pvpython live_picture.py PORT IMAGE.png
(with CANOPY_PLUGIN set; then start the mini-app with --dimension 3 --live
localhost:PORT)"""
import os
import sys
import time

from paraview import live, simple

port, image = int(sys.argv[1]), sys.argv[2]
simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
link = live.ConnectToCatalyst("localhost", port)
print("listening", flush=True)

view = simple.CreateView("RenderView")
view.ViewSize = [1000, 760]
view.UseColorPaletteForBackground = 0
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
deadline = time.time() + 300
shown = None
first_step = None
while time.time() < deadline:
    live.ProcessServerNotifications()
    manager = link.GetInsituProxyManager()
    names = {manager.GetProxyName("sources", i)
             for i in range(manager.GetNumberOfProxies("sources"))}
    if shown is None and {"CanopyAdaptiveSlice1", "CanopyAdaptiveSurface1", "grid"} <= names:
        slices = live.ExtractCatalystData(link, "CanopyAdaptiveSlice1")
        region = live.ExtractCatalystData(link, "CanopyAdaptiveSurface1")
        grid = simple.CanopyUnpackGrid(Input=live.ExtractCatalystData(link, "grid"))
        shown = [slices, region, grid]
    if shown is not None:
        for proxy in shown:
            proxy.UpdatePipeline()
        if shown[0].GetDataInformation().GetNumberOfCells() and first_step is None:
            first_step = link.GetTimeStep()
        if first_step is not None and link.GetTimeStep() >= first_step + 5:
            break
    time.sleep(0.05)

slices, region, grid = shown
lut = simple.GetColorTransferFunction("scalar")
lut.AutomaticRescaleRangeMode = "Never"
for proxy in (slices, region):
    display = simple.Show(proxy, view)
    simple.ColorBy(display, ("CELLS", "scalar"))
    display.LookupTable = lut
    print(proxy.GetDataInformation().GetNumberOfCells(), "cells", flush=True)
lut.RescaleTransferFunction(0.0, 0.85)
region_display = simple.GetDisplayProperties(region, view)
region_display.Ambient, region_display.Diffuse = 0.45, 0.55  # as Canopy's images light it
slices_display = simple.GetDisplayProperties(slices, view)
slices_display.Ambient = 1.0
slices_display.Diffuse = 0.0
outline = simple.Show(simple.Outline(Input=slices), view)  # the slices span the domain
outline.AmbientColor = outline.DiffuseColor = [0.2, 0.2, 0.2]
bar = simple.GetScalarBar(lut, view)
bar.Title = "scalar (step %d, received live)" % link.GetTimeStep()
bar.ComponentTitle = ""
bar.RangeLabelFormat = "%.2f"
bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
bar.Visibility = 1
# The camera the simulation's slice_image.py used (its slices and region are
# culled and coarsened for that view).
diagonal = 3 ** 0.5
view.CameraFocalPoint = [0.5, 0.5, 0.5]
view.CameraPosition = [0.5 + 1.2 * diagonal, 0.5 + 0.9 * diagonal, 0.5 + 1.5 * diagonal]
view.CameraViewUp = [0, 1, 0]
view.CameraViewAngle = 30
simple.Render(view)
simple.SaveScreenshot(image, view, ImageResolution=[1000, 760])
print("saved", image, "step", link.GetTimeStep(), flush=True)
