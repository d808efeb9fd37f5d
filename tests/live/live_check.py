"""Catalyst Live against the mini-app, with real pvpython viewers on localhost:

  live_check.py PORT OUTPUT VIEWER_COMMAND... --simulation SIMULATION_COMMAND...

VIEWER_COMMAND runs live_client.py (under the project's Xvfb wrapper); this
adds its arguments. A first viewer listens, the simulation (with --live
localhost:PORT) connects, the viewer pulls the adaptive surface, the packed
grid, the grid itself and a source that does not exist, records three
deliveries and disconnects; a second viewer then connects and does the same.
Checks:
- the simulation exits with 0, reports no failed pipeline and writes an image
  for every step (a viewer never costs a step);
- every surface the viewers received has as many quads as the simulation drew
  at some step, and every unpacked grid as many cells as the simulation had at
  some step, in one piece per rank (the grid crossed the socket whole);
- both viewers received deliveries (disconnect, then reconnect);
- the refused hypertree-grid extract and the missing source cost one warning
  each in the simulation's log, and Live logs no error.
"""
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import expect, finish  # noqa: E402

separator = sys.argv.index("--simulation")
port, output = int(sys.argv[1]), sys.argv[2]
viewer = sys.argv[3:separator]
simulation = sys.argv[separator + 1:] + ["--live", "localhost:%d" % port, "--output", output]
shutil.rmtree(output, ignore_errors=True)
os.makedirs(output)


def start_viewer(name):
    log = open(os.path.join(output, name + ".log"), "w")
    process = subprocess.Popen(viewer + [str(port), os.path.join(output, name + ".json"), "3",
                                         "120"], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    deadline = time.time() + 60
    for line in process.stdout:
        log.write(line)
        if "listening" in line or time.time() > deadline:
            break
    return process, log


def end_viewer(process, log):
    out, _ = process.communicate(timeout=180)
    log.write(out)
    log.close()


first, first_log = start_viewer("viewer1")
sim_log = open(os.path.join(output, "simulation.log"), "w")
sim = subprocess.Popen(simulation, stdout=sim_log, stderr=subprocess.STDOUT)
end_viewer(first, first_log)
second, second_log = start_viewer("viewer2")
end_viewer(second, second_log)
status = sim.wait(timeout=600)
sim_log.close()
with open(os.path.join(output, "simulation.log")) as f:
    log = f.read()

expect(status == 0, "the simulation exits with 0 (got %d)" % status)
expect(re.search(r" 0 pipeline failure\(s\)", log) is not None,
       "the simulation reports no failed pipeline")
steps = [int(s) for s in re.findall(r"^step +(\d+) ", log, re.M)]
images = glob.glob(os.path.join(output, "surface_*.png"))
expect(len(steps) > 0 and len(images) == len(steps),
       "an image for every step (%d images, %d steps)" % (len(images), len(steps)))
quads = {int(n) for n in re.findall(r"quads: surface (\d+)", log)}
cells = {int(n) for n in re.findall(r" cells +(\d+)", log)}
ranks = int(re.search(r", (\d+) ranks,", log).group(1)) if re.search(r", (\d+) ranks,", log) else 0
for name in ("viewer1", "viewer2"):
    path = os.path.join(output, name + ".json")
    records = json.load(open(path))["records"] if os.path.exists(path) else []
    expect(len(records) >= 2, "%s received deliveries (%d)" % (name, len(records)))
    for record in records:
        expect(record["surface"] in quads, "%s: a surface of %d quads, as the simulation drew at "
               "some step (%s)" % (name, record["surface"], sorted(quads)[:5]))
        expect(record["grid_cells"] in cells and record["grid_pieces"] == ranks,
               "%s: an unpacked grid of %d cells in %d pieces; the simulation had %s cells on "
               "%d ranks" % (name, record["grid_cells"], record["grid_pieces"], sorted(cells)[:5],
                             ranks))
warnings = re.findall(r"WARN\|.*Catalyst Live: (.*)", log)
expect(len([w for w in warnings if "'sources:grid:0', a hypertree grid" in w]) >= 1,
       "the refused grid extract is one warning")
expect(any("no such source" in w for w in warnings), "the missing source is one warning")
expect(not re.search(r"ERR\|", log), "no error in the simulation's log")
finish()
