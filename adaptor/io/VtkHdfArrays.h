// The cell arrays of a VTKHDF step: which of the grid's arrays a rank writes,
// the HDF5 types their values are stored as, and the one list of arrays all
// ranks agree on when the file is created (afterwards, the file's arrays).
#pragma once

#include <hdf5.h>
#include <mpi.h>
#include <vtkType.h>

#include <string>
#include <vector>

class vtkDataArray;
class vtkHyperTreeGrid;

namespace canopy::io
{

/// A cell array of the file: name, VTK value type, components.
struct ArraySpec
{
  std::string name;
  int type = VTK_DOUBLE;
  int components = 1;
};

/// The HDF5 type values of `vtkType` are stored as (H5I_INVALID_HID: VTKHDF
/// cannot store them).
hid_t fileTypeOf(int vtkType);
/// The HDF5 type of values of `vtkType` in memory (H5I_INVALID_HID: none).
hid_t memoryTypeOf(int vtkType);
/// The VTK type of values stored as the HDF5 `type` (a file written earlier).
int vtkTypeOf(hid_t type);

/// The cell arrays of `htg` (may be null) this rank writes: those named in
/// `names` (empty: every numeric one), and the ghost array whenever `names`
/// leaves it out and the grid has it. Arrays VTKHDF cannot name or store, and
/// names the grid lacks, are added to `problems`. The arrays are the grid's,
/// valid while it lives.
std::vector<vtkDataArray*> selectStepArrays(vtkHyperTreeGrid* htg,
                                            const std::vector<std::string>& names,
                                            std::vector<std::string>& problems);

/// The arrays of every rank, in rank order, each once.
struct AgreedArrays
{
  std::vector<ArraySpec> specs;
  /// Why the ranks do not agree ("" if they do); the same on every rank.
  std::string conflict;
};
/// Gathers every rank's `arrays` (borrowed, as selectStepArrays gives them).
/// Collective over `communicator` (MPI_COMM_NULL: one process).
AgreedArrays gatherArraySpecs(MPI_Comm communicator, const std::vector<vtkDataArray*>& arrays);

/// Rank 0's `specs` (the file's arrays, which only the writing rank reads) on
/// every rank. Collective over `communicator` (MPI_COMM_NULL: one process).
std::vector<ArraySpec> broadcastArraySpecs(MPI_Comm communicator,
                                           const std::vector<ArraySpec>& specs);

/// Why `arrays` cannot give the file's arrays `specs` their values ("" if they
/// can): each must be there, with the file's components; only the ghost array
/// may be missing (it is then written as zeros).
std::string missingArrays(const std::vector<ArraySpec>& specs,
                          const std::vector<vtkDataArray*>& arrays);

/// The one of `arrays` named `name`; null if none is.
vtkDataArray* findArray(const std::vector<vtkDataArray*>& arrays, const std::string& name);

} // namespace canopy::io
