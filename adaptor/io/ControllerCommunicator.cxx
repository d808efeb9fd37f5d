#include "ControllerCommunicator.h"

#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMultiProcessController.h>

namespace canopy::io
{

MPI_Comm communicatorOf(vtkMultiProcessController* controller)
{
  if (controller == nullptr)
  {
    controller = vtkMultiProcessController::GetGlobalController();
  }
  auto* mpi =
      vtkMPICommunicator::SafeDownCast(controller ? controller->GetCommunicator() : nullptr);
  if (mpi != nullptr && mpi->GetMPIComm() != nullptr && mpi->GetMPIComm()->GetHandle() != nullptr)
  {
    return *mpi->GetMPIComm()->GetHandle();
  }
  int initialized = 0;
  int finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized ? MPI_COMM_SELF : MPI_COMM_NULL;
}

} // namespace canopy::io
