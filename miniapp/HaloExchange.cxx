#include "HaloExchange.h"

#include <algorithm>
#include <tuple>

namespace miniamr
{

void HaloExchange::planRequests(MPI_Comm communicator, const std::vector<Remote>& needed,
                                std::vector<std::int32_t>& received,
                                std::vector<int>& receivedCounts)
{
  int size = 1;
  MPI_Comm_size(communicator, &size);
  // Unique remote leaves, grouped by owner, in (owner, tree, leaf) order.
  std::vector<Remote> unique = needed;
  std::sort(unique.begin(), unique.end(),
            [](const Remote& a, const Remote& b)
            { return std::tie(a.owner, a.tree, a.leaf) < std::tie(b.owner, b.tree, b.leaf); });
  unique.erase(std::unique(unique.begin(), unique.end(),
                           [](const Remote& a, const Remote& b)
                           { return a.owner == b.owner && a.tree == b.tree && a.leaf == b.leaf; }),
               unique.end());
  GhostIndex.clear();
  Ghosts.assign(unique.size(), 0.0);
  ReceiveCounts.assign(static_cast<std::size_t>(size), 0);
  ReceiveOffsets.assign(static_cast<std::size_t>(size), 0);
  std::vector<std::int32_t> requests;
  for (std::size_t g = 0; g < unique.size(); ++g)
  {
    GhostIndex.emplace(key(unique[g].tree, unique[g].leaf), g);
    ReceiveCounts[static_cast<std::size_t>(unique[g].owner)] += 1;
    requests.push_back(unique[g].tree);
    requests.push_back(unique[g].leaf);
  }
  std::vector<int> requestCounts(static_cast<std::size_t>(size)),
      requestOffsets(static_cast<std::size_t>(size), 0);
  for (int r = 0; r < size; ++r)
  {
    requestCounts[static_cast<std::size_t>(r)] = 2 * ReceiveCounts[static_cast<std::size_t>(r)];
    if (r > 0)
    {
      ReceiveOffsets[static_cast<std::size_t>(r)] =
          ReceiveOffsets[static_cast<std::size_t>(r - 1)] +
          ReceiveCounts[static_cast<std::size_t>(r - 1)];
      requestOffsets[static_cast<std::size_t>(r)] = 2 * ReceiveOffsets[static_cast<std::size_t>(r)];
    }
  }
  receivedCounts.assign(static_cast<std::size_t>(size), 0);
  MPI_Alltoall(requestCounts.data(), 1, MPI_INT, receivedCounts.data(), 1, MPI_INT, communicator);
  std::vector<int> receivedOffsets(static_cast<std::size_t>(size), 0);
  for (int r = 1; r < size; ++r)
    receivedOffsets[static_cast<std::size_t>(r)] =
        receivedOffsets[static_cast<std::size_t>(r - 1)] +
        receivedCounts[static_cast<std::size_t>(r - 1)];
  received.assign(static_cast<std::size_t>(receivedOffsets.back() + receivedCounts.back()), 0);
  MPI_Alltoallv(requests.data(), requestCounts.data(), requestOffsets.data(), MPI_INT32_T,
                received.data(), receivedCounts.data(), receivedOffsets.data(), MPI_INT32_T,
                communicator);
}

void HaloExchange::exchange(MPI_Comm communicator, const std::vector<double>& values)
{
  for (std::size_t i = 0; i < SendFrom.size(); ++i)
    SendBuffer[i] = values[SendFrom[i]];
  MPI_Alltoallv(SendBuffer.data(), SendCounts.data(), SendOffsets.data(), MPI_DOUBLE, Ghosts.data(),
                ReceiveCounts.data(), ReceiveOffsets.data(), MPI_DOUBLE, communicator);
}

} // namespace miniamr
