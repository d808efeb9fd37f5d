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


def compare_images(mine, reference, ties=0):
    """(differing pixels, unexplained pixels) between two images of the same scene.
    With ties > 0, a differing pixel is explained when its colour is one of the
    reference's 3x3 neighbourhood: where slices intersect, two fragments have the
    same depth and which one wins depends on drawing order (one rank) or on the
    compositor's tie-break (several ranks); both are cells meeting at that pixel.
    More than `ties` explained pixels are unexplained all the same."""
    import numpy
    if mine.shape != reference.shape:
        return -1, -1
    differing = (mine != reference).any(axis=2)
    count = int(differing.sum())
    if not ties:
        return count, count
    unexplained = 0
    height, width, _ = reference.shape
    for y, x in zip(*numpy.nonzero(differing)):
        window = reference[max(0, y - 1):min(height, y + 2), max(0, x - 1):min(width, x + 2)]
        unexplained += not (window.reshape(-1, 3) == mine[y, x]).all(axis=1).any()
    return count, unexplained + max(0, count - unexplained - ties)


def cell_array(data, name):
    return vtk_to_numpy(data.GetCellData().GetArray(name))
