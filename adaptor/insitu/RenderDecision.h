// Which scripts run, given the X display: Debian's ParaView renders through X
// only, creating a render window without a display aborts the process, and
// IceT composites images over every rank, so a rendering script runs only if
// every rank has a display.
#pragma once

#include "XDisplayConnection.h"

#include <canopy/InSitu.h>

#include <mpi.h>

#include <vector>

namespace canopy
{

struct RenderPlan
{
  bool canRender = false;              ///< every rank has a display
  std::vector<PipelineScript> scripts; ///< the scripts that will run
};

/// Collective. Rank 0 decides which scripts render (the same list everywhere)
/// and, when some cannot run, logs one warning naming them and the remedy.
RenderPlan planRendering(MPI_Comm communicator, const std::vector<PipelineScript>& scripts,
                         const XDisplayConnection& display);

} // namespace canopy
