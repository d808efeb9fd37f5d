"""A Catalyst Live viewer, as a ParaView 5.11 user scripts one with pvpython
(paraview.live): listens on PORT, and once the simulation connects, pulls the
first adaptive surface, the packed grid (unpacked with the Canopy plugin), the
grid itself (a hypertree grid, which Canopy refuses to send) and a source that
does not exist. Records what arrives until RECORDS deliveries of both the
surface and the grid were seen, then exits (disconnecting).

  pvpython live_client.py PORT RESULT.json RECORDS SECONDS

RESULT.json: {"sources": [...], "records": [{"surface": quads, "grid_cells": n,
"grid_pieces": p}, ...]} (a record per delivery that changed something).
Prints "listening" once the port is open."""
import json
import os
import sys
import time

from paraview import live, simple

port, result_path, wanted, seconds = (int(sys.argv[1]), sys.argv[2], int(sys.argv[3]),
                                      float(sys.argv[4]))
simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
link = live.ConnectToCatalyst("localhost", port)
print("listening", flush=True)

result = {"sources": [], "records": []}
surface = packed = unpacked = None
deadline = time.time() + seconds
last = None
while time.time() < deadline and len(result["records"]) < wanted:
    live.ProcessServerNotifications()
    manager = link.GetInsituProxyManager()
    count = manager.GetNumberOfProxies("sources")
    if surface is None and count:
        names = sorted({manager.GetProxyName("sources", i) for i in range(count)})
        surfaces = [name for name in names if name.startswith("CanopyAdaptiveSurface")]
        if surfaces and "grid (packed)" in names:
            result["sources"] = names
            surface = live.ExtractCatalystData(link, surfaces[0])
            packed = live.ExtractCatalystData(link, "grid (packed)")
            unpacked = simple.CanopyUnpackGrid(Input=packed)
            live.ExtractCatalystData(link, "grid")  # refused: a hypertree grid
    if surface is not None:
        quads = surface.GetClientSideObject().GetOutputDataObject(0)
        unpacked.UpdatePipeline()
        grid = unpacked.GetClientSideObject().GetOutputDataObject(0)
        quads = quads.GetNumberOfCells() if hasattr(quads, "GetNumberOfCells") else 0
        pieces = grid.GetNumberOfBlocks()
        cells = sum(grid.GetBlock(i).GetNumberOfCells() for i in range(pieces))
        record = {"surface": quads, "grid_cells": cells, "grid_pieces": pieces}
        if quads and cells and record != last:
            result["records"].append(record)
            last = record
    time.sleep(0.05)

# Last, a source the simulation does not have (ParaView's viewer then stops
# receiving anything; the simulation must not notice beyond a warning).
if surface is not None:
    live.ExtractCatalystData(link, "no such source")
    until = time.time() + 3
    while time.time() < until:
        live.ProcessServerNotifications()
        time.sleep(0.05)

with open(result_path, "w") as f:
    json.dump(result, f)
print("records", len(result["records"]), flush=True)
