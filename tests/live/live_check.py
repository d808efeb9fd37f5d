"""Catalyst Live against the mini-app, with real pvpython viewers on localhost:

  live_check.py PORT OUTPUT VIEWER_COMMAND... --simulation SIMULATION_COMMAND...

VIEWER_COMMAND runs live_client.py (under the project's Xvfb wrapper); this
adds its arguments. The simulation runs with --live localhost:PORT, a pause
limit of PAUSE_LIMIT s and a stall limit of STALL_LIMIT s. Three viewers, one
after the other:
1. pulls the surface, the slices (3D), the grid (sent packed), a selection and
   a missing source,
   records three deliveries, pauses the simulation for 3 s, resumes, leaves;
2. connects again, does the same and then keeps the simulation paused (its
   pause limit lets it go on), leaves;
3. connects, and after its first delivery is stopped (SIGSTOP: a stalled
   viewer), then killed.
Checks:
- the simulation exits with 0, reports no failed pipeline and writes an image
  for every step (a viewer never costs a step);
- every delivery equals the simulation's own counts at the delivered step: the
  surface's (3D: the selected region's) and the slices' quads, the grid's cells,
  in one piece per rank (the grid crossed the socket whole); the selection is
  not empty (3D: a masked grid, sent packed, of the grid's cells);
- viewers 1 and 2 received deliveries (disconnect, then reconnect), with the
  missing source asked for from the start (it does not stop deliveries);
- the pause held the step it was taken on for the time it lasted, the held
  pause ended at the limit, the stalled viewer was dropped after the limit;
- the simulation's log has one warning each for the packed grid, the missing
  source, the pause limit and the stall, nothing else from Live beyond one
  socket message per disconnection, and no error.
"""
import glob
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import expect, finish  # noqa: E402

PAUSE_LIMIT = 4
STALL_LIMIT = 3
separator = sys.argv.index("--simulation")
port, output = int(sys.argv[1]), sys.argv[2]
viewer = sys.argv[3:separator]
simulation = sys.argv[separator + 1:] + [
    "--live", "localhost:%d" % port, "--live-pause-limit", str(PAUSE_LIMIT),
    "--live-stall-limit", str(STALL_LIMIT), "--output", output]
shutil.rmtree(output, ignore_errors=True)
os.makedirs(output)


def start_viewer(name, pause):
    log = open(os.path.join(output, name + ".log"), "w")
    process = subprocess.Popen(viewer + [str(port), os.path.join(output, name + ".json"), "3",
                                         "120", pause], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, start_new_session=True)
    wait_for(process, log, "listening")
    return process, log


def wait_for(process, log, text, seconds=90):
    deadline = time.time() + seconds
    for line in process.stdout:
        log.write(line)
        log.flush()
        if text in line or time.time() > deadline:
            return text in line
    return False


def end_viewer(process, log):
    out, _ = process.communicate(timeout=180)
    log.write(out)
    log.close()


def load(name):
    path = os.path.join(output, name + ".json")
    return json.load(open(path)) if os.path.exists(path) else {"records": []}


first, first_log = start_viewer("viewer1", "3")
sim_log = open(os.path.join(output, "simulation.log"), "w")
sim = subprocess.Popen(simulation, stdout=sim_log, stderr=subprocess.STDOUT)
end_viewer(first, first_log)
second, second_log = start_viewer("viewer2", "hold")
end_viewer(second, second_log)
third, third_log = start_viewer("viewer3", "3")
stalled = wait_for(third, third_log, "record 1")
# The whole group: pvpython runs under the Xvfb wrapper.
os.killpg(third.pid, signal.SIGSTOP)
time.sleep(STALL_LIMIT + 5)
os.killpg(third.pid, signal.SIGKILL)
third.wait()
third_log.close()
status = sim.wait(timeout=600)
sim_log.close()
with open(os.path.join(output, "simulation.log")) as f:
    log = f.read()

expect(status == 0, "the simulation exits with 0 (got %d)" % status)
expect(re.search(r" 0 pipeline failure\(s\)", log) is not None,
       "the simulation reports no failed pipeline")
steps = {int(m.group(1)): m.group(0) for m in re.finditer(r"^step +(\d+) .*$", log, re.M)}
for kind in ("surface",) if "quads: surface" in log else ("slices", "region"):
    images = glob.glob(os.path.join(output, kind + "_*.png"))
    expect(len(steps) > 0 and len(images) == len(steps),
           "a %s image for every step (%d images, %d steps)" % (kind, len(images), len(steps)))
ranks = re.search(r", (\d+) ranks,", log)
ranks = int(ranks.group(1)) if ranks else 0
dimension = re.search(r"canopy_miniamr: (\d)D,", log)
dimension = int(dimension.group(1)) if dimension else 0


def step_value(step, pattern):
    match = re.search(pattern, steps.get(step, ""))
    return int(match.group(1)) if match else None


for name in ("viewer1", "viewer2"):
    records = load(name)["records"]
    expect(len(records) >= 2, "%s received deliveries (%d)" % (name, len(records)))
    for record in records:
        step = record["step"]
        # 2D: the surface image's surface; 3D: the selected region's surface.
        surface = step_value(step, r"quads: (?:surface|region) (\d+)")
        expect(record["surface"] == surface,
               "%s, step %d: a surface of %d quads, as the simulation drew (%s)"
               % (name, step, record["surface"], surface))
        if record["slices"] is not None:
            slices = step_value(step, r"slices (\d+)")
            expect(record["slices"] == slices, "%s, step %d: slices of %d quads, as the "
                   "simulation drew (%s)" % (name, step, record["slices"], slices))
        expect(record["grid_cells"] == step_value(step, r" nodes +(\d+)") and
               record["grid_pieces"] == ranks,
               "%s, step %d: an unpacked grid of %d cells in %d pieces; the simulation had %s "
               "cells on %d ranks" % (name, step, record["grid_cells"], record["grid_pieces"],
                                      step_value(step, r" nodes +(\d+)"), ranks))
        if record["selection_packed"]:
            # A selection that keeps the topology: the grid with a mask.
            expect(record["selection_cells"] == record["grid_cells"],
                   "%s, step %d: a masked selection grid of %d cells (the grid's %d)"
                   % (name, step, record["selection_cells"], record["grid_cells"]))
        else:
            expect(0 < record["selection_cells"] < record["grid_cells"],
                   "%s, step %d: a selection of %d cells" % (name, step,
                                                             record["selection_cells"]))
    expect(any(r["slices"] for r in records) == (dimension == 3),
           "%s: slices pulled exactly when the simulation is 3D" % name)

# The pause: the step it was taken on lasted as long as the pause.
paused = load("viewer1")
held = paused.get("steps_while_paused", [])
expect(len(held) == 1, "viewer1's pause held one step (%s)" % held)
if len(held) == 1:
    match = re.search(r"canopy ([0-9.]+) ms", steps.get(held[0], ""))
    took = float(match.group(1)) / 1000 if match else 0
    expect(took >= 2.5, "step %d, paused for 3 s, took %.2f s" % (held[0], took))
held = load("viewer2").get("steps_while_paused", [])
expect(len(held) == 2, "viewer2's endless pause ended at the limit (steps %s)" % held)
expect(stalled, "viewer3 received a delivery before it stalled")

warnings = re.findall(r"WARN\|.*Catalyst Live: (.*?)(?:\x1b\[0m)?$", log, re.M)
kinds = {"grid": r"'sources:grid:0', a hypertree grid, .* sent packed",
         "missing": r"'sources:no such source:0', which this simulation does not have",
         "packed selection": r"'sources:CanopyExtractSelection\d+:0', a hypertree grid, .* sent "
                             r"packed",
         "pause limit": r"paused by the viewer for %d" % PAUSE_LIMIT,
         "stall": r"did not answer for %d" % STALL_LIMIT,
         "socket": r"vtk\w*Socket\w* \(0x[0-9a-f]+\): |Could not receive|Broken pipe"}
counts = {kind: sum(1 for w in warnings if re.search(pattern, w))
          for kind, pattern in kinds.items()}
for kind in ("grid", "missing", "pause limit", "stall"):
    expect(counts[kind] == 1, "one warning for the %s (%d)" % (kind, counts[kind]))
packed_selections = 1 if any(r["selection_packed"] for r in load("viewer1")["records"]) else 0
expect(counts["packed selection"] == packed_selections,
       "%d warning(s) for the selection sent packed (%d)" % (packed_selections,
                                                            counts["packed selection"]))
others = [w for w in warnings if not any(re.search(p, w) for p in kinds.values())]
expect(not others, "no other Live warning (%s)" % others[:3])
expect(counts["socket"] <= 3, "at most one socket message per disconnection (%d)"
       % counts["socket"])
expect(not re.search(r"ERR\|", log), "no error in the simulation's log")
finish()
