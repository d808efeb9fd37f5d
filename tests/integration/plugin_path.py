"""With PV_PLUGIN_PATH pointing at the plugin's folder, pvpython loads it at
start-up: the filters are there without LoadPlugin, and they run."""
import sys

from paraview import simple

if not hasattr(simple, "CanopyExtractSelection") or not hasattr(simple, "CanopyAdaptiveSurface"):
    print("FAILED: the Canopy proxies are not available; PV_PLUGIN_PATH was not honoured")
    sys.exit(1)
grid = simple.HyperTreeGrid(Dimensions=[3, 3, 1], GridScale=[1, 1, 1], BranchFactor=2,
                            MaxDepth=2, Descriptor="R... |....")
selection = simple.CanopyExtractSelection(Input=grid, SelectionMode="Locations",
                                          Locations=[0.25, 0.25, 0.0, 1.5, 1.5, 0.0])
selection.UpdatePipeline()
cells = selection.GetDataInformation().GetNumberOfCells()
if cells != 2:
    print("FAILED: %d cells selected, expected 2" % cells)
    sys.exit(1)
print("plugin loaded through PV_PLUGIN_PATH: %d cells selected" % cells)
