"""Catalyst Live from a script of the user's own with no extractor (docs/insitu.md,
"Catalyst Live"): a real pvpython viewer listens on PORT, the mini-app runs
tests/live/live_only_script.py alone (Live turned on in the script's own
options; the mini-app is not given --live).

  live_only_check.py PORT OUTPUT VIEWER_COMMAND... --simulation SIMULATION_COMMAND...

VIEWER_COMMAND runs live_sources_client.py (this adds its arguments). Checks:
the simulation exits with 0 and no failed pipeline; the viewer is offered the
script's surface and the grid, and receives the surface at 4 different steps,
each with exactly the leaves the simulation had at that step (the 2D surface
at full resolution: one quad per leaf, all ranks together)."""
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "support"))
from output_checks import expect, finish  # noqa: E402

separator = sys.argv.index("--simulation")
port, output = int(sys.argv[1]), sys.argv[2]
viewer = sys.argv[3:separator]
simulation = sys.argv[separator + 1:] + ["--output", output]
shutil.rmtree(output, ignore_errors=True)
os.makedirs(output)
result_path = os.path.join(output, "viewer.json")
environment = dict(os.environ, LIVE_URL="localhost:%d" % port)

with open(os.path.join(output, "viewer.log"), "w") as viewer_log:
    client = subprocess.Popen(viewer + [str(port), "CanopyAdaptiveSurface1", result_path, "4",
                                        "180"], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, env=environment)
    for line in client.stdout:
        viewer_log.write(line)
        if line.startswith("listening"):
            break
    run = subprocess.run(simulation, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                         env=environment, timeout=600)
    rest, _ = client.communicate(timeout=240)
    viewer_log.write(rest)
log = run.stdout
with open(os.path.join(output, "simulation.log"), "w") as out:
    out.write(log)
print(log[-3000:])

expect(run.returncode == 0, "the simulation exits with 0 (%d)" % run.returncode)
expect(re.search(r" 0 pipeline failure\(s\)", log) is not None, "no pipeline failed")
leaves = {int(step): int(count) for step, count in
          re.findall(r"^step +(\d+) .*leaves +(\d+)", log, re.M)}
result = json.load(open(result_path)) if os.path.exists(result_path) else {"sources": [],
                                                                          "records": []}
expect({"CanopyAdaptiveSurface1", "grid"} <= set(result["sources"]),
       "the viewer is offered the script's surface and the grid (%s)" % result["sources"])
records = result["records"]
steps = [record["step"] for record in records]
expect(len(set(steps)) == 4, "the surface arrived at 4 different steps (%s)" % steps)
for record in records:
    expect(record["cells"] == leaves.get(record["step"]),
           "step %d: the surface delivered has %d quads, the simulation %s leaves"
           % (record["step"], record["cells"], leaves.get(record["step"])))
finish()
