#include "RenderDecision.h"

#include "FailureLog.h"
#include "ScriptInspection.h"

#include <vtkLogger.h>

namespace canopy
{

RenderPlan planRendering(MPI_Comm communicator, const std::vector<PipelineScript>& scripts,
                         const XDisplayConnection& display)
{
  int rank = 0;
  MPI_Comm_rank(communicator, &rank);
  int localDisplay = display.connected() ? 1 : 0;
  int everyDisplay = 0;
  MPI_Allreduce(&localDisplay, &everyDisplay, 1, MPI_INT, MPI_MIN, communicator);
  RenderPlan plan;
  plan.canRender = everyDisplay == 1;
  std::vector<int> renders(scripts.size(), 0);
  if (rank == 0)
  {
    for (std::size_t i = 0; i < renders.size(); ++i)
    {
      renders[i] = scriptRenders(scripts[i].path) ? 1 : 0;
    }
  }
  MPI_Bcast(renders.data(), static_cast<int>(renders.size()), MPI_INT, 0, communicator);
  std::vector<std::string> skipped;
  for (std::size_t i = 0; i < renders.size(); ++i)
  {
    if (!plan.canRender && renders[i])
    {
      skipped.push_back(scripts[i].path);
    }
    else
    {
      plan.scripts.push_back(scripts[i]);
    }
  }
  if (!skipped.empty() && rank == 0)
  {
    vtkLogF(WARNING,
            "canopy: no X display (%s on at least one rank): rendering pipeline(s) %s will not "
            "run at any step; data extracts still run. Run under 'xvfb-run -a' to get images.",
            display.why().empty() ? "another rank has none" : display.why().c_str(),
            joined(skipped, ", ").c_str());
  }
  return plan;
}

} // namespace canopy
