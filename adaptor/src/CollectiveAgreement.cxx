#include "CollectiveAgreement.h"

#include <numeric>

namespace canopy
{

std::vector<std::string> gatherFailures(MPI_Comm communicator, const std::string& localFailure)
{
  int localFailed = localFailure.empty() ? 0 : 1;
  int anyFailed = 0;
  MPI_Allreduce(&localFailed, &anyFailed, 1, MPI_INT, MPI_MAX, communicator);
  if (!anyFailed)
  {
    return {};
  }
  int size = 1;
  MPI_Comm_size(communicator, &size);
  int localLength = static_cast<int>(localFailure.size());
  std::vector<int> lengths(size, 0);
  MPI_Allgather(&localLength, 1, MPI_INT, lengths.data(), 1, MPI_INT, communicator);
  std::vector<int> offsets(size, 0);
  std::exclusive_scan(lengths.begin(), lengths.end(), offsets.begin(), 0);
  std::string all(static_cast<std::size_t>(offsets.back() + lengths.back()), '\0');
  MPI_Allgatherv(localFailure.data(), localLength, MPI_CHAR, all.data(), lengths.data(),
                 offsets.data(), MPI_CHAR, communicator);
  std::vector<std::string> failures;
  for (int rank = 0; rank < size; ++rank)
  {
    if (lengths[rank] > 0)
    {
      failures.push_back("rank " + std::to_string(rank) + ", " +
                         all.substr(static_cast<std::size_t>(offsets[rank]),
                                    static_cast<std::size_t>(lengths[rank])));
    }
  }
  return failures;
}

AgreedStates agreeOnStates(MPI_Comm communicator, const std::vector<int>& localStates)
{
  const int count = static_cast<int>(localStates.size());
  AgreedStates agreed{std::vector<int>(localStates.size()), std::vector<int>(localStates.size())};
  // One reduction for both: the minimum is the negated maximum of the negations.
  std::vector<int> both(2 * localStates.size());
  for (std::size_t i = 0; i < localStates.size(); ++i)
  {
    both[i] = localStates[i];
    both[localStates.size() + i] = -localStates[i];
  }
  std::vector<int> reduced(both.size());
  MPI_Allreduce(both.data(), reduced.data(), 2 * count, MPI_INT, MPI_MAX, communicator);
  for (std::size_t i = 0; i < localStates.size(); ++i)
  {
    agreed.maximum[i] = reduced[i];
    agreed.minimum[i] = -reduced[localStates.size() + i];
  }
  return agreed;
}

} // namespace canopy
