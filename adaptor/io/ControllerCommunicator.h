// The MPI communicator behind a VTK controller, for the VTK writer classes.
#pragma once

#include <mpi.h>

class vtkMultiProcessController;

namespace canopy::io
{

/// The controller's MPI communicator (null controller: the global one). Not an
/// MPI controller: MPI_COMM_SELF if MPI is running, MPI_COMM_NULL (no MPI) if not.
MPI_Comm communicatorOf(vtkMultiProcessController* controller);

} // namespace canopy::io
