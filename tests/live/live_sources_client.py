"""A Catalyst Live viewer that pulls one source by name: listens on PORT, waits
for the simulation to offer SOURCE, and records the cells of each delivery and
its step until RECORDS deliveries with different steps were seen or SECONDS
passed.

  pvpython live_sources_client.py PORT SOURCE RESULT.json RECORDS SECONDS

RESULT.json: {"sources": [names offered], "records": [{"step": s, "cells": n}, ...]},
rewritten at each record (a viewer stopped early leaves what it got).
Prints "listening" once the port is open."""
import json
import os
import sys
import time

from paraview import live, simple

port, source, result_path = int(sys.argv[1]), sys.argv[2], sys.argv[3]
wanted, seconds = int(sys.argv[4]), float(sys.argv[5])
simple.LoadPlugin(os.environ["CANOPY_PLUGIN"], remote=False)
link = live.ConnectToCatalyst("localhost", port)
print("listening", flush=True)

result = {"sources": [], "records": []}
extract = None
deadline = time.time() + seconds
while time.time() < deadline and len(result["records"]) < wanted:
    live.ProcessServerNotifications()
    manager = link.GetInsituProxyManager()
    names = sorted({manager.GetProxyName("sources", i)
                    for i in range(manager.GetNumberOfProxies("sources"))})
    if names:
        result["sources"] = names
    if extract is None and source in names:
        extract = live.ExtractCatalystData(link, source)
    if extract is not None:
        extract.UpdatePipeline()
        step = int(link.GetTimeStep())
        cells = extract.GetDataInformation().GetNumberOfCells()
        if cells and (not result["records"] or result["records"][-1]["step"] != step):
            result["records"].append({"step": step, "cells": cells})
            print("record", len(result["records"]), step, cells, flush=True)
            with open(result_path, "w") as out:  # as it goes: the viewer may be stopped
                json.dump(result, out)
    time.sleep(0.02)

with open(result_path, "w") as out:
    json.dump(result, out)
print("records", len(result["records"]), flush=True)
