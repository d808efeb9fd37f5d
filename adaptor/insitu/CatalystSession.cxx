#include "CatalystSession.h"

#include <vtkCPProcessor.h>
#include <vtkMPI.h>

namespace canopy
{
namespace
{

bool sessionAlive = false;
bool catalystEverStarted = false;

} // namespace

std::string CatalystSession::whyNotStartable()
{
  if (sessionAlive)
  {
    return "another canopy::InSitu is open in this process";
  }
  if (catalystEverStarted)
  {
    return "Catalyst was already started and finalized in this process; ParaView 5.11 cannot "
           "start it again (open one canopy::InSitu per run)";
  }
  return {};
}

CatalystSession::CatalystSession(MPI_Comm communicator) : Communicator(communicator)
{
  sessionAlive = true;
  catalystEverStarted = true;
  this->Processor = vtkSmartPointer<vtkCPProcessor>::New();
  MPI_Comm handle = this->Communicator.get();
  vtkMPICommunicatorOpaqueComm opaque(&handle);
  this->Started = this->Processor->Initialize(opaque) != 0;
}

CatalystSession::~CatalystSession()
{
  this->Processor->Finalize();
  this->Processor = nullptr;
  sessionAlive = false;
}

} // namespace canopy
