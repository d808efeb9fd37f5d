"""The filters' outputs are the same on every run and rank count (docs/testing.md,
"Determinism"): runs canopy_filter_outputs (tests/mpi/FilterOutputs.cxx) on 1 rank
twice (the second with one thread: VTK_SMP_MAX_THREADS=1), on 2 ranks twice and on
4 ranks once, then compares
- each rank's output bytes between the two runs of a rank count (every case);
- the sorted cells of every case without level of detail between 1, 2 and 4 ranks,
  flat pieces (surfaces, slices) as their shape: a vertex where the polygon runs
  straight on is left out. Such vertices close T-junctions (EdgeVertices.h); a rank
  puts there the corners of every finer neighbour it holds, also one outside the view
  or one the plane does not cut, where another rank sends only the corners of the
  pieces it draws, so their number depends on the split. Whether the pieces meet
  without holes across ranks is mpi.images.np* (tests/mpi/SplitImagesTest.cxx).
A case missing on either side, or empty, fails.

usage: python3 filter_outputs_check.py WORK MPIEXEC PROGRAM"""
import filecmp
import glob
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from output_checks import expect, finish  # noqa: E402

work, mpiexec, program = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)


def run(name, ranks, threads=None):
    folder = os.path.join(work, name)
    os.makedirs(folder)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    if threads:
        env["VTK_SMP_MAX_THREADS"] = str(threads)
    result = subprocess.run([mpiexec, "--oversubscribe", "-np", str(ranks), program, folder],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(result.stdout[-2000:])
    expect(result.returncode == 0, "%s: %d rank(s) ran (exit code %d)"
           % (name, ranks, result.returncode))
    return folder


def names(folder, pattern):
    return sorted(os.path.basename(p) for p in glob.glob(os.path.join(folder, pattern)))


def same_bytes(a, b, label):
    files = names(a, "*.bytes")
    expect(len(files) >= 20 and files == names(b, "*.bytes"),
           "%s: both runs wrote the same %d outputs" % (label, len(files)))
    for name in files:
        x, y = os.path.join(a, name), os.path.join(b, name)
        expect(os.path.getsize(x) > 0 and filecmp.cmp(x, y, shallow=False),
               "%s: %s is the same, byte for byte (%d bytes)" % (label, name, os.path.getsize(x)))


def straight(a, b, c):
    """Whether b lies on the segment from a to c, all three on one axis-parallel line."""
    differing = [k for k in range(3) if not (a[k] == b[k] == c[k])]
    return len(differing) == 1 and min(a[differing[0]], c[differing[0]]) < b[differing[0]] \
        < max(a[differing[0]], c[differing[0]])


def shape(line):
    """A cell's line (id, level, points as hex floats) with the points where its polygon
    runs straight on left out."""
    words = line.split()
    points = [tuple(words[i:i + 3]) for i in range(2, len(words), 3)]
    values = [tuple(float.fromhex(x) for x in p) for p in points]
    kept = [points[i] for i in range(len(points))
            if len(points) < 4 or not straight(values[i - 1], values[i],
                                               values[(i + 1) % len(points)])]
    return " ".join(words[:2] + [x for p in kept for x in p])


def shapes(text):
    return sorted(shape(line) for line in text.splitlines())


one, one_again = run("np1", 1), run("np1_one_thread", 1, threads=1)
two, two_again = run("np2", 2), run("np2_again", 2)
four = run("np4", 4)
same_bytes(one, one_again, "1 rank, then 1 rank with one thread")
same_bytes(two, two_again, "2 ranks, twice")
cases = names(one, "*.cells")
expect(len(cases) >= 10, "%d cases to compare between rank counts" % len(cases))
for name in cases:
    reference = open(os.path.join(one, name)).read()
    expect(reference.count("\n") > 0, "%s: 1 rank draws cells" % name)
    flat = name.startswith(("surface", "slice"))
    for folder, ranks in ((two, 2), (four, 4)):
        path = os.path.join(folder, name)
        other = open(path).read() if os.path.exists(path) else None
        if flat and other is not None:
            same = shapes(other) == shapes(reference)
        else:
            same = other == reference
        expect(same, "%s: the same %d cells on %d ranks as on 1%s"
               % (name, reference.count("\n"), ranks, " (as shapes)" if flat else ""))
finish()
