// ParaView 5.11's Catalyst (the legacy vtkCPProcessor), started once per
// process: its state is global, and Initialize after Finalize aborts the
// process. Catalyst gets its own communicator, so that ParaView's collectives
// are never matched with Canopy's agreements.
#pragma once

#include "OwnCommunicator.h"

#include <vtkSmartPointer.h>

#include <mpi.h>

#include <string>

class vtkCPProcessor;

namespace canopy
{

class CatalystSession
{
public:
  /// Why no session can start in this process now; empty if one can.
  static std::string whyNotStartable();

  /// Starts Catalyst on a duplicate of `communicator`; started() says whether
  /// it worked on this rank.
  explicit CatalystSession(MPI_Comm communicator);
  /// Finalizes Catalyst (scripts must be gone first).
  ~CatalystSession();
  CatalystSession(const CatalystSession&) = delete;
  CatalystSession& operator=(const CatalystSession&) = delete;

  bool started() const { return Started; }

private:
  OwnCommunicator Communicator;
  vtkSmartPointer<vtkCPProcessor> Processor;
  bool Started = false;
};

} // namespace canopy
