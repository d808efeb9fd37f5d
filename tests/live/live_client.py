"""A Catalyst Live viewer, as a ParaView 5.11 user scripts one with pvpython
(paraview.live): listens on PORT and, once the simulation connects, pulls the
first adaptive surface, the first adaptive slice (3D), the grid itself (a
hypertree grid, which Canopy sends packed; unpacked here with the Canopy
plugin, as docs/insitu.md says), the first selection (unpacked too when it is a
masked grid), and a source the simulation does not have. Records what
arrives until RECORDS deliveries were seen, then pauses the simulation as
ParaView's "Pause Simulation" does, for PAUSE seconds (resumes after them, or
stays paused if PAUSE is "hold", leaving it to the simulation's pause limit),
and exits (disconnecting).

  pvpython live_client.py PORT RESULT.json RECORDS SECONDS PAUSE

RESULT.json: {"sources": [...], "records": [{"step": s, "surface": quads,
"slices": quads or None, "grid_cells": n, "grid_pieces": p, "selection_cells": c,
"selection_packed": bool, "surface_bytes": b, "grid_bytes": b}, ...] (a record per
delivery that changed something), "paused": [start, end] (wall-clock seconds,
time.time()), "steps_while_paused": [...] (steps delivered meanwhile)}.
Prints "listening" once the port is open."""
import json
import os
import sys
import time

from paraview import live, simple

port, result_path, wanted, seconds = (int(sys.argv[1]), sys.argv[2], int(sys.argv[3]),
                                      float(sys.argv[4]))
hold = sys.argv[5] == "hold"
pause_seconds = 0.0 if hold else float(sys.argv[5])
simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
link = live.ConnectToCatalyst("localhost", port)
print("listening", flush=True)

result = {"sources": [], "records": [], "paused": None, "steps_while_paused": []}
extracts = None
deadline = time.time() + seconds


def cells(proxy):
    # An extract's proxy holds what the last delivery brought once it is
    # updated (ParaView's GUI does this when it renders).
    proxy.UpdatePipeline()
    return proxy.GetDataInformation().GetNumberOfCells()


def unpacked_cells(proxy):
    """Cells of every block of a CanopyUnpackGrid proxy, and its block count."""
    proxy.UpdatePipeline()
    grids = proxy.GetClientSideObject().GetOutputDataObject(0)
    pieces = grids.GetNumberOfBlocks()
    return sum(grids.GetBlock(i).GetNumberOfCells() for i in range(pieces)
               if grids.GetBlock(i)), pieces


def is_packed(proxy):
    data = proxy.GetClientSideObject().GetOutputDataObject(0)
    return data is not None and data.GetFieldData().GetArray("CanopyPackedGrid") is not None


def delivered_step():
    return int(link.GetTimeStep())  # the step of the last delivery


def poll(duration):
    until = time.time() + duration
    while time.time() < until:
        live.ProcessServerNotifications()
        time.sleep(0.02)


last = None
while time.time() < deadline and len(result["records"]) < wanted:
    live.ProcessServerNotifications()
    manager = link.GetInsituProxyManager()
    count = manager.GetNumberOfProxies("sources")
    if extracts is None and count:
        names = sorted({manager.GetProxyName("sources", i) for i in range(count)})
        surfaces = [name for name in names if name.startswith("CanopyAdaptiveSurface")]
        slices = [name for name in names if name.startswith("CanopyAdaptiveSlice")]
        selections = [name for name in names if name.startswith("CanopyExtractSelection")]
        if surfaces and selections and "grid" in names:
            result["sources"] = names
            grid = live.ExtractCatalystData(link, "grid")
            extracts = {
                "surface": live.ExtractCatalystData(link, surfaces[0]),
                "unpacked": simple.CanopyUnpackGrid(Input=grid),
                "selection": live.ExtractCatalystData(link, selections[0]),
                "slices": live.ExtractCatalystData(link, slices[0]) if slices else None,
                "selection_unpacked": None,
                # Not in the simulation: ParaView's viewer would wait for it
                # and show nothing new; Canopy sends an empty dataset instead.
                "missing": live.ExtractCatalystData(link, "no such source"),
            }
    if extracts is not None:
        grid_cells, pieces = unpacked_cells(extracts["unpacked"])
        selection = extracts["selection"]
        selection_cells = cells(selection)
        if is_packed(selection):
            # A masked grid (a selection that keeps the topology) comes packed.
            if extracts["selection_unpacked"] is None:
                extracts["selection_unpacked"] = simple.CanopyUnpackGrid(Input=selection)
            selection_cells = unpacked_cells(extracts["selection_unpacked"])[0]
        record = {"surface": cells(extracts["surface"]),
                  "slices": cells(extracts["slices"]) if extracts["slices"] else None,
                  "grid_cells": grid_cells, "grid_pieces": pieces,
                  "selection_cells": selection_cells,
                  "selection_packed": is_packed(selection),
                  # What crossed the socket for each (ParaView's data information).
                  "surface_bytes": extracts["surface"].GetDataInformation().GetMemorySize()
                  * 1024,
                  "grid_bytes": extracts["unpacked"].Input.GetDataInformation().GetMemorySize()
                  * 1024}
        if record["surface"] and record["grid_cells"] and record != last:
            last = dict(record)
            record["step"] = delivered_step()
            result["records"].append(record)
            print("record", len(result["records"]), flush=True)
    time.sleep(0.02)

if extracts is not None and result["records"]:
    start = time.time()
    live.PauseCatalyst(link, True)
    poll(1.0)
    first = delivered_step()
    poll(max(pause_seconds - 1.0, 0.0) if not hold else 0.0)
    if hold:
        # Stays paused until the simulation's pause limit lets it go on.
        while time.time() < deadline and delivered_step() == first:
            poll(0.2)
    result["steps_while_paused"] = sorted({first, delivered_step()})
    result["paused"] = [start, time.time()]
    if not hold:
        live.PauseCatalyst(link, False)
        poll(1.0)

with open(result_path, "w") as f:
    json.dump(result, f)
print("records", len(result["records"]), flush=True)
