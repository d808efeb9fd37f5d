// Halo exchange: the values of leaves in trees other ranks own that this
// rank's leaves touch. The plan is made once per regrid (requests go to the
// owners, who remember what to send); each exchange is one MPI_Alltoallv.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace miniamr
{

class HaloExchange
{
public:
  /// A leaf of another rank's tree: owner rank, tree, leaf index in the tree.
  struct Remote
  {
    int owner;
    std::int32_t tree;
    std::int32_t leaf;
  };

  /// Collective. `needed`: remote leaves this rank reads (any order, duplicates
  /// allowed). `localOffset(tree, leaf)`: where an own leaf's value is stored.
  template <typename LocalOffset>
  void plan(MPI_Comm communicator, const std::vector<Remote>& needed, LocalOffset localOffset);

  /// Collective: fills ghost values from the owners' `values`.
  void exchange(MPI_Comm communicator, const std::vector<double>& values);

  /// The ghost value of a remote leaf (must have been in `needed`).
  double ghost(std::int32_t tree, std::int32_t leaf) const
  {
    return Ghosts[GhostIndex.at(key(tree, leaf))];
  }
  std::size_t size() const { return Ghosts.size(); }

private:
  static std::uint64_t key(std::int32_t tree, std::int32_t leaf)
  {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(tree)) << 32) |
           static_cast<std::uint32_t>(leaf);
  }
  void planRequests(MPI_Comm communicator, const std::vector<Remote>& needed,
                    std::vector<std::int32_t>& received, std::vector<int>& receivedCounts);

  std::unordered_map<std::uint64_t, std::size_t> GhostIndex;
  std::vector<double> Ghosts;
  std::vector<int> ReceiveCounts, ReceiveOffsets; ///< ghosts per owner, in Ghosts order
  std::vector<int> SendCounts, SendOffsets;
  std::vector<std::size_t> SendFrom; ///< local value offsets, grouped by destination
  std::vector<double> SendBuffer;
};

template <typename LocalOffset>
void HaloExchange::plan(MPI_Comm communicator, const std::vector<Remote>& needed,
                        LocalOffset localOffset)
{
  std::vector<std::int32_t> requested;
  std::vector<int> requestedCounts;
  planRequests(communicator, needed, requested, requestedCounts);
  SendFrom.clear();
  for (std::size_t i = 0; i + 1 < requested.size(); i += 2)
    SendFrom.push_back(localOffset(requested[i], requested[i + 1]));
  const std::size_t ranks = requestedCounts.size();
  SendCounts.assign(ranks, 0);
  SendOffsets.assign(ranks, 0);
  for (std::size_t r = 0; r < ranks; ++r)
  {
    SendCounts[r] = requestedCounts[r] / 2;
    SendOffsets[r] = r == 0 ? 0 : SendOffsets[r - 1] + SendCounts[r - 1];
  }
  SendBuffer.resize(SendFrom.size());
}

} // namespace miniamr
