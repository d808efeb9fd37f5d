"""What the in-situ and mini-app checkers share: recording expectations, running
a command under MPI, and reading the files pipelines write (with Debian's
/usr/bin/python3, which imports ParaView's VTK)."""
import glob
import os
import subprocess
import sys

from paraview.vtk.util.numpy_support import vtk_to_numpy
from paraview.vtk.vtkIOImage import vtkPNGReader
from paraview.vtk.vtkIOXML import (vtkXMLHyperTreeGridReader, vtkXMLMultiBlockDataReader,
                                   vtkXMLPPolyDataReader, vtkXMLPUnstructuredGridReader)

FAILURES = []


def expect(condition, message):
    print(("ok:     " if condition else "FAILED: ") + message)
    if not condition:
        FAILURES.append(message)


def finish(exit_on_success=True):
    """Prints the verdict and exits 1 if any expectation failed, else 0, or, with
    exit_on_success=False, returns (pvbatch crashes in its teardown after
    sys.exit(0): a pvbatch script ends by returning)."""
    print("%d check(s) failed" % len(FAILURES) if FAILURES else "all checks passed")
    if FAILURES or exit_on_success:
        sys.exit(1 if FAILURES else 0)


def write_faults(folder, control):
    """The environment that preloads the write-fault shim (tests/support/
    write_fault_shim.c) into a command: files under `folder` fail as the
    `control` file says, while it exists. The shim's path comes from CTest
    (CANOPY_WRITE_FAULT_SHIM); without it the test fails, it does not skip."""
    shim = os.environ.get("CANOPY_WRITE_FAULT_SHIM", "")
    if not os.path.isfile(shim):
        raise SystemExit("FAILED: CANOPY_WRITE_FAULT_SHIM does not name the write-fault shim "
                         "(%r); CTest sets it" % shim)
    asan = os.environ.get("ASAN_OPTIONS", "")
    return {"LD_PRELOAD": shim, "CANOPY_WRITE_FAULT_DIR": os.path.abspath(folder),
            "CANOPY_WRITE_FAULT_CONTROL": os.path.abspath(control),
            # In the sanitizer build the executable brings ASan's runtime; the
            # shim (never sanitized) may come first.
            "ASAN_OPTIONS": (asan + ":" if asan else "") + "verify_asan_link_order=0"}


def run_command(command, tail=4000, extra_env=None):
    """Runs the command (OpenMPI allowed as root); returns (exit code, stdout+stderr)."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    env.update(extra_env or {})
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=env)
    print(result.stdout[-tail:])
    return result.returncode, result.stdout


def _read(reader, path):
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def read_polydata(path):
    return _read(vtkXMLPPolyDataReader(), path)


def read_unstructured(path):
    return _read(vtkXMLPUnstructuredGridReader(), path)


def read_multiblock(path):
    """A .vtm; Canopy's grid extract lists one .htg piece per rank in one."""
    return _read(vtkXMLMultiBlockDataReader(), path)


def vtkhdf_cells_per_step(path):
    """The cells of every step of a VTKHDF hypertree-grid file, all pieces (h5py)."""
    import h5py
    with h5py.File(path, "r") as f:
        steps = f["VTKHDF/Steps"]
        cells = f["VTKHDF/NumberOfCells"][:]
        return [int(cells[o:o + n].sum()) for o, n in zip(steps["PartOffsets"][:],
                                                          steps["NumberOfParts"][:])]


def read_htg_pieces(directory, prefix, step):
    """The .htg pieces of a step (one per rank), read one by one: Canopy's grid
    extract, or the pieces of ParaView 5.11's .phtg (whose own reader crashes)."""
    pattern = os.path.join(directory, "%s_%06d" % (prefix, step), "%s_%06d_*.htg" % (prefix, step))
    return [_read(vtkXMLHyperTreeGridReader(), piece) for piece in sorted(glob.glob(pattern))]


def read_png(path):
    """The image's RGB pixels, height x width x 3."""
    data = _read(vtkPNGReader(), path)
    width, height, _ = data.GetDimensions()
    return vtk_to_numpy(data.GetPointData().GetScalars()).reshape(height, width, -1)[:, :, :3]


def compare_images(mine, reference, ties=0, shading=0):
    """(differing pixels, unexplained pixels) between two images of the same scene.
    With ties > 0, a differing pixel is explained when its colour is one of the
    reference's 3x3 neighbourhood: where slices intersect, two fragments have the
    same depth and which one wins depends on drawing order (one rank) or on the
    compositor's tie-break (several ranks); both are cells meeting at that pixel.
    More than `ties` such pixels are unexplained all the same. With shading > 0, a
    pixel within `shading` levels of the reference's in every channel is explained
    too: a lit curved surface (an isosurface) drawn from several ranks' pieces is
    shaded from float positions VTK shifts by each rank's own bounds, which rounds
    its lighting a level differently here and there (a wrong triangle or normal
    changes a pixel by far more)."""
    import numpy
    if mine.shape != reference.shape:
        return -1, -1
    change = numpy.abs(mine.astype(int) - reference.astype(int)).max(axis=2)
    differing = change > 0
    count = int(differing.sum())
    if not ties and not shading:
        return count, count
    unexplained = 0
    tied = 0
    height, width, _ = reference.shape
    for y, x in zip(*numpy.nonzero(differing)):
        if change[y, x] <= shading:
            continue
        window = reference[max(0, y - 1):min(height, y + 2), max(0, x - 1):min(width, x + 2)]
        if ties and (window.reshape(-1, 3) == mine[y, x]).all(axis=1).any():
            tied += 1
        else:
            unexplained += 1
    return count, unexplained + max(0, tied - ties)


def cell_array(data, name):
    return vtk_to_numpy(data.GetCellData().GetArray(name))


def read_with_paraview(path, pvpython):
    """What ParaView itself reads from a polydata file (paraview_read.py under
    pvpython: OpenDataFile picks the reader, no Canopy code loaded): a dict of numpy
    arrays (reader, points, cell_types, offsets, connectivity, point_arrays,
    "point:<name>"), or None when ParaView could not read it."""
    import tempfile

    import numpy
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_read.py")
    with tempfile.TemporaryDirectory() as folder:
        out = os.path.join(folder, "read.npz")
        # hwloc's X probe would print authorization noise under a virtual display.
        code, _ = run_command([pvpython, script, path, out], tail=600,
                              extra_env={"HWLOC_COMPONENTS": "-gl"})
        if code != 0 or not os.path.exists(out):
            return None
        with numpy.load(out) as saved:
            return {name: saved[name] for name in saved.files}


VTK_TRIANGLE = 5


def triangle_edges(read):
    """Each triangle's three edges as pairs of point keys (the points' coordinates,
    exact: pieces of different ranks have points of their own), for watertightness."""
    import numpy
    points = read["points"]
    corners = read["connectivity"].reshape(-1, 3)
    _, key = numpy.unique(points, axis=0, return_inverse=True)
    key = key.reshape(-1)[corners]
    edges = numpy.concatenate([key[:, [0, 1]], key[:, [1, 2]], key[:, [2, 0]]])
    return numpy.sort(edges, axis=1)


def check_isosurface_extract(read, label, field, value, triangles, centre, interpolated=()):
    """The checks an isosurface extract (slice_image.py's <prefix>_contour_<step>.pvtp,
    as ParaView read it) must pass: ParaView's polydata reader opened it; triangles
    only, as many as the pipeline reported (`triangles`, the StepReport measure); the
    point arrays `field` (every value the contour value), "Normals" (unit vectors
    pointing away from `centre`, a point inside the closed surface: towards lower
    values) and each of `interpolated`; closed: every edge shared by exactly two
    triangles (the surface lies inside the domain). Returns (area, open edges)."""
    import numpy
    expect(read is not None, "%s: ParaView opened it" % label)
    if read is None:
        return 0.0, -1
    reader = str(read["reader"])
    expect(reader in ("XMLPPolyDataReader", "XMLPartitionedPolydataReader"),
           "%s: ParaView chose its parallel polydata reader (%s)" % (label, reader))
    types = read["cell_types"]
    expect(len(types) == triangles and len(types) > 0 and (types == VTK_TRIANGLE).all()
           and len(read["offsets"]) == len(types) + 1,
           "%s: %d cells, all triangles; the pipeline reported %d triangles"
           % (label, len(types), triangles))
    names = str(read["point_arrays"]).split(",")
    wanted = [field, "Normals"] + list(interpolated)
    expect(all(name in names for name in wanted),
           "%s: point arrays %s hold %s" % (label, names, wanted))
    if not all(name in names for name in wanted) or len(types) == 0 or \
            not (types == VTK_TRIANGLE).all():
        return 0.0, -1
    values = read["point:" + field]
    expect(values.shape[1] == 1 and (values == value).all(),
           "%s: '%s' is the contour value %g at each of the %d points (from %g to %g)"
           % (label, field, value, len(values), values.min(), values.max()))
    points = read["points"]
    normals = read["point:Normals"]
    length = numpy.linalg.norm(normals, axis=1)
    outward = numpy.einsum("ij,ij->i", normals, points - numpy.asarray(centre))
    expect(normals.shape[1] == 3 and numpy.abs(length - 1).max() < 1e-6 and (outward > 0).all(),
           "%s: Normals unit vectors (largest |length - 1| %.1e) pointing away from the "
           "inside at (%s) at %d of %d points" % (label, numpy.abs(length - 1).max(),
                                                  ", ".join("%.3f" % c for c in centre),
                                                  int((outward > 0).sum()), len(points)))
    corners = points[read["connectivity"].reshape(-1, 3)]
    area = 0.5 * float(numpy.linalg.norm(numpy.cross(corners[:, 1] - corners[:, 0],
                                                     corners[:, 2] - corners[:, 0]), axis=1).sum())
    _, uses = numpy.unique(triangle_edges(read), axis=0, return_counts=True)
    open_edges = int((uses != 2).sum())
    expect(open_edges == 0, "%s: closed, every edge shared by exactly two triangles (%d of %d "
           "edges are not; area %.6g)" % (label, open_edges, len(uses), area))
    return area, open_edges
