"""Soak: the mini-app for thousands of steps with every pipeline firing often
holds its memory and file descriptors flat after warm-up (docs/testing.md,
"Soak"). Each rank logs its resident memory, heap in use and open descriptors
per step (the mini-app's --resource-log); after the first quarter of the steps
(warm-up), per rank:
- the open descriptors never change;
- the heap grows by less than HEAP_LIMIT KiB per step, resident memory by less
  than RESIDENT_LIMIT, once what follows the mesh is taken out (the least-squares
  fit memory = a + b * the rank's leaves + c * step over the steps after
  warm-up: c; with a mesh that does not change, the slope over steps);
With --planted-leak BYTES (the mini-app's --plant-leak, allocated and kept every
step), the check must catch it instead: the heap grows by more than HEAP_LIMIT.
With --viewer, a Catalyst Live viewer (live_sources_client.py) runs beside the
simulation for the whole run and must have received deliveries.

usage: python3 soak_check.py OUTPUT [--planted-leak BYTES] [--viewer PORT VIEWER...]
         -- COMMAND...
COMMAND runs the mini-app (under mpirun) with --resource-log OUTPUT/resources.
Prints a summary row for docs/testing.md."""
import glob
import json
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import expect, finish  # noqa: E402

# KiB per step. What legitimately grows: ParaView 5.11's extracts controller keeps a
# row per extract written for the whole run (its Cinema index, about 0.3 KiB each;
# Canopy cannot reach it), and the .pvd series lists every step. With two images
# every 2 steps that is about 0.5-0.6 KiB per step (measured: 0.60 on 1 rank); a leak
# of 1 KiB per step more shows above the limit.
HEAP_LIMIT = 1.0
# The allocator keeps what it once mapped: resident memory moves in steps, and is
# only bounded loosely.
RESIDENT_LIMIT = 2.0

output = sys.argv[1]
separator = sys.argv.index("--")
options = sys.argv[2:separator]
command = sys.argv[separator + 1:]
planted = 0
viewer = None
if "--planted-leak" in options:
    planted = int(options[options.index("--planted-leak") + 1])
if "--viewer" in options:
    at = options.index("--viewer")
    viewer = (int(options[at + 1]), options[at + 2:])
shutil.rmtree(output, ignore_errors=True)
os.makedirs(output)

env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           HWLOC_COMPONENTS="-gl")
client = None
if viewer:
    port, client_command = viewer
    client = subprocess.Popen(client_command + [str(port), "CanopyAdaptiveSurface1",
                                                os.path.join(output, "viewer.json"), "100000",
                                                "7200"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              env=env)
    for line in client.stdout:
        if line.startswith("listening"):
            break
run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                     env=env)
log = run.stdout
with open(os.path.join(output, "run.log"), "w") as out:
    out.write(log)
print(log[-1500:])
if client:
    client.terminate()
    client.wait(timeout=60)

expect(run.returncode == 0, "the mini-app exits normally (%d)" % run.returncode)
expect(re.search(r" 0 pipeline failure\(s\)", log) is not None, "no pipeline failed")


def growth_per_step(records, column):
    """The growth of `column` per step with the rank's leaves held fixed: the
    least-squares fit column = a + b * leaves + c * step returns c. Memory
    follows the mesh, which the moving objects grow and shrink; a leak is what
    still grows."""
    rows = [(1.0, float(r[1]), float(r[0]), float(r[column])) for r in records]
    # Normal equations (3 x 3), solved by Cramer's rule.
    m = [[sum(a[i] * a[j] for a in rows) for j in range(3)] for i in range(3)]
    v = [sum(a[i] * a[3] for a in rows) for i in range(3)]

    def det(x):
        return (x[0][0] * (x[1][1] * x[2][2] - x[1][2] * x[2][1]) -
                x[0][1] * (x[1][0] * x[2][2] - x[1][2] * x[2][0]) +
                x[0][2] * (x[1][0] * x[2][1] - x[1][1] * x[2][0]))

    d = det(m)
    if len({r[1] for r in records}) == 1:  # the leaves never changed: growth over steps alone
        xs = [r[0] for r in records]
        ys = [r[column] for r in records]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        var = sum((x - mx) ** 2 for x in xs)
        return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / var if var else 0.0
    with_step = [row[:2] + [v[i]] for i, row in enumerate(m)]
    return det(with_step) / d


files = sorted(glob.glob(os.path.join(output, "resources.*.csv")))
expect(len(files) >= 1, "%d rank(s) logged their resources" % len(files))
rows = []
for path in files:
    rank = int(re.search(r"resources\.(\d+)\.csv", path).group(1))
    lines = [line.split(",") for line in open(path).read().split("\n")[1:] if line]
    records = [tuple(int(x) for x in line) for line in lines]  # step, leaves, resident, heap, fds
    steps = [r[0] for r in records]
    expect(len(steps) >= 400, "rank %d logged %d steps" % (rank, len(steps)))
    after = [r for r in records if r[0] >= steps[-1] // 4]
    resident = growth_per_step(after, 2)
    heap = growth_per_step(after, 3)
    descriptors = sorted({r[4] for r in after})
    rows.append((rank, after[0][2], after[-1][2], resident, heap, descriptors))
    if planted:
        expect(heap > HEAP_LIMIT,
               "rank %d: the planted leak of %d bytes per step is caught: heap grows %.3f KiB "
               "per step (limit %.2f)" % (rank, planted, heap, HEAP_LIMIT))
    else:
        expect(len(descriptors) == 1, "rank %d: open descriptors flat after warm-up (%s)"
               % (rank, descriptors))
        expect(heap < HEAP_LIMIT and resident < RESIDENT_LIMIT,
               "rank %d: heap and resident memory flat after warm-up: %.3f KiB per step "
               "(limit %.2f) and %.3f (limit %.2f)"
               % (rank, heap, HEAP_LIMIT, resident, RESIDENT_LIMIT))
if viewer:
    path = os.path.join(output, "viewer.json")
    records = json.load(open(path))["records"] if os.path.exists(path) else []
    expect(len(records) >= 10, "the Live viewer received %d deliveries" % len(records))
for rank, first, last, resident, heap, descriptors in rows:
    print("summary: rank %d, resident %d -> %d KiB after warm-up, %.3f KiB/step, heap %.3f "
          "KiB/step, descriptors %s" % (rank, first, last, resident, heap, descriptors))
finish()
