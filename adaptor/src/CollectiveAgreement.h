// Rank agreement for the in-situ driver: every decision that leads into a
// collective (building, running a pipeline) is taken by all ranks together,
// so a problem on one rank makes every rank skip instead of leaving the
// others waiting.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

namespace canopy
{

/// Every rank's failure message (empty on ranks that succeeded), as
/// "rank R, message", in rank order; empty when all succeeded. Collective.
/// Cost when nothing failed: one MPI_Allreduce of an int.
std::vector<std::string> gatherFailures(MPI_Comm communicator, const std::string& localFailure);

/// Per-item states agreed across ranks: MPI_MIN and MPI_MAX of each entry. Collective.
struct AgreedStates
{
  std::vector<int> minimum;
  std::vector<int> maximum;
};
AgreedStates agreeOnStates(MPI_Comm communicator, const std::vector<int>& localStates);

} // namespace canopy
