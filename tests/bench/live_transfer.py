"""What a Catalyst Live viewer receives, against the grid's size: the mini-app
(2D, README's shape) at growing refinement with a pvpython viewer that pulls
every adaptive surface and the grid (docs/benchmarks.md, "Catalyst Live").
Prints a Markdown table: per refinement, the grid's cells and packed KiB, and
for the surface image's full view and its zoomed view the quads and KiB that
crossed the socket.

  python3 live_transfer.py BUILD_DIR [MAX_LEVEL ...]   (under an X server)
"""
import json
import os
import re
import subprocess
import sys
import tempfile

build = os.path.abspath(sys.argv[1])
levels = [int(level) for level in sys.argv[2:]] or [5, 7, 9]
here = os.path.dirname(os.path.abspath(__file__))
environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   CANOPY_PLUGIN=os.path.join(build, "lib", "canopy-plugins", "CanopyPlugin",
                                              "CanopyPlugin.so"))
print("| max level | grid cells | grid KiB (packed) | full view: quads | KiB | bytes/quad "
      "| zoomed view: quads | KiB | bytes/quad |")
print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for level in levels:
    work = tempfile.mkdtemp(prefix="canopy-live-transfer-")
    result = os.path.join(work, "viewer.json")
    port = 22500 + level * 10
    viewer = subprocess.Popen(["pvpython", os.path.join(here, "live_transfer_viewer.py"),
                               str(port), result, "600"], env=environment,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for line in viewer.stdout:
        if "listening" in line:
            break
    simulation = subprocess.run(
        ["mpirun", "-np", "1", os.path.join(build, "miniapp", "canopy_miniamr"),
         "--max-level", str(level), "--steps", "3", "--image-every", "1",
         "--selection-every", "1000", "--extract-every", "1000",
         "--live", "localhost:%d" % port, "--output", os.path.join(work, "out")],
        env=environment, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    viewer.communicate(timeout=600)
    received = json.load(open(result))
    step = re.search(r"^step +%d .*nodes +(\d+).*quads: surface (\d+), zoom (\d+)"
                     % received["step"], simulation.stdout, re.M)
    cells, full, zoom = (int(step.group(i)) for i in (1, 2, 3))
    # The surfaces the image drew, found by their quads (the others are overlays).
    by_quads = {value[0]: value[1] for value in received["surfaces"].values()}
    row = [level, received["grid"][0], received["grid"][1]]
    for quads in (full, zoom):
        kib = by_quads.get(quads)
        row += [quads, kib if kib is not None else "?",
                "%.0f" % (kib * 1024.0 / quads) if kib else "?"]
    assert received["grid"][0] == cells, "the grid received is the simulation's"
    print("| " + " | ".join(str(value) for value in row) + " |", flush=True)
