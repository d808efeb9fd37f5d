"""Opens a data file in ParaView as a user would (paraview.simple.OpenDataFile, which
picks ParaView's own reader for the extension) and saves what it read for a checker
that runs under another Python: the reader's name, and of the polydata ParaView
delivers (every piece the file lists, appended), its points, its cells' types and
point ids, and every point array.

Run with pvpython: paraview_read.py FILE OUT.npz
OUT.npz: reader (the proxy's XML name), points (n x 3), cell_types (VTK cell types),
offsets and connectivity (the cells' point ids), point_arrays (their names, comma-
separated) and "point:<name>" (each array, tuples x components). Canopy's code is
not involved: the plugin is not loaded.
"""
import sys

import numpy
from paraview import servermanager
from paraview.simple import OpenDataFile
from paraview.vtk.util.numpy_support import vtk_to_numpy

path, out = sys.argv[1], sys.argv[2]
reader = OpenDataFile(path)
if reader is None:
    sys.exit("ParaView found no reader for %s" % path)
reader.UpdatePipeline()
data = servermanager.Fetch(reader)
if data.IsA("vtkMultiBlockDataSet") or data.IsA("vtkPartitionedDataSetCollection"):
    sys.exit("%s: ParaView delivered a %s, not polydata" % (path, data.GetClassName()))
saved = {"reader": numpy.array(reader.GetXMLName())}
points = data.GetPoints()
saved["points"] = (vtk_to_numpy(points.GetData()).astype(float) if points is not None
                   else numpy.zeros((0, 3)))
cells = data.GetPolys()
saved["cell_types"] = numpy.array([data.GetCellType(c) for c in range(data.GetNumberOfCells())],
                                  dtype=numpy.int64)
saved["offsets"] = vtk_to_numpy(cells.GetOffsetsArray()).astype(numpy.int64)
saved["connectivity"] = vtk_to_numpy(cells.GetConnectivityArray()).astype(numpy.int64)
arrays = data.GetPointData()
names = [arrays.GetArrayName(i) for i in range(arrays.GetNumberOfArrays())]
saved["point_arrays"] = numpy.array(",".join(names))
for name in names:
    values = vtk_to_numpy(arrays.GetArray(name)).astype(float)
    saved["point:" + name] = values.reshape(len(values), -1)
numpy.savez(out, **saved)
print("%s read %s: %d cells (%d polygons), %d points, point arrays %s"
      % (reader.GetXMLName(), path, data.GetNumberOfCells(), cells.GetNumberOfCells(),
         data.GetNumberOfPoints(), names))
