// Agreement between the ranks of a collective writer (see WriterAgreement.h).
#include "WriterAgreement.h"

#include "GatherText.h"

namespace canopy::io
{

int rankOf(MPI_Comm communicator)
{
  int rank = 0;
  if (communicator != MPI_COMM_NULL)
  {
    MPI_Comm_rank(communicator, &rank);
  }
  return rank;
}

int sizeOf(MPI_Comm communicator)
{
  int size = 1;
  if (communicator != MPI_COMM_NULL)
  {
    MPI_Comm_size(communicator, &size);
  }
  return size;
}

std::string gatherProblems(MPI_Comm communicator, const std::string& localProblem)
{
  int local = localProblem.empty() ? 0 : 1;
  int any = local;
  if (communicator != MPI_COMM_NULL)
  {
    // The common case costs one reduction of an int.
    MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, communicator);
  }
  if (!any)
  {
    return {};
  }
  const std::vector<std::string> texts = gatherTextsToAll(communicator, localProblem);
  std::string combined;
  for (std::size_t r = 0; r < texts.size(); ++r)
  {
    if (!texts[r].empty())
    {
      combined += (combined.empty() ? "" : "; ") + std::string("rank ") + std::to_string(r) + ": " +
                  texts[r];
    }
  }
  return combined;
}

} // namespace canopy::io
