"""The viewer of live_transfer.py (pvpython): listens on PORT, pulls every
adaptive surface of the simulation and its grid (sent packed), and once one
delivery of each arrived writes what came: {"step": s, "surfaces": {name:
[cells, KiB]}, "grid": [cells, KiB packed]} to RESULT.json.

  pvpython live_transfer_viewer.py PORT RESULT.json SECONDS"""
import json
import os
import sys
import time

from paraview import live, simple

port, result_path, seconds = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
link = live.ConnectToCatalyst("localhost", port)
print("listening", flush=True)
deadline = time.time() + seconds
extracts = None
result = None
while time.time() < deadline and result is None:
    live.ProcessServerNotifications()
    manager = link.GetInsituProxyManager()
    names = sorted({manager.GetProxyName("sources", i)
                    for i in range(manager.GetNumberOfProxies("sources"))})
    if extracts is None and "grid" in names:
        extracts = {name: live.ExtractCatalystData(link, name) for name in names
                    if name.startswith("CanopyAdaptiveSurface")}
        packed = live.ExtractCatalystData(link, "grid")
        unpacked = simple.CanopyUnpackGrid(Input=packed)
    if extracts:
        sizes = {}
        for name, proxy in extracts.items():
            proxy.UpdatePipeline()
            info = proxy.GetDataInformation()
            sizes[name] = [info.GetNumberOfCells(), info.GetMemorySize()]
        unpacked.UpdatePipeline()
        grids = unpacked.GetClientSideObject().GetOutputDataObject(0)
        cells = sum(grids.GetBlock(i).GetNumberOfCells() for i in range(grids.GetNumberOfBlocks()))
        if cells and all(cells_kib[0] for cells_kib in sizes.values()):
            packed.UpdatePipeline()
            result = {"step": int(link.GetTimeStep()), "surfaces": sizes,
                      "grid": [cells, packed.GetDataInformation().GetMemorySize()]}
    time.sleep(0.02)
json.dump(result, open(result_path, "w"))
print("done", flush=True)
