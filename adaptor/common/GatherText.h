// Texts between ranks: gathering one text from every rank, the one home of this
// exchange in Canopy (lengths first, then the characters at their offsets), and
// one rank's text broadcast to all. Used by Canopy::IO's
// writer agreement and insitu's CollectiveAgreement. Header only, MPI's C API
// only, so any Canopy library can include it. (The filters' gatherFromAll is
// the same exchange over a VTK controller, which need not be MPI.)
#pragma once

#include <mpi.h>

#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

namespace canopy
{
namespace gather_text_detail
{

/// `lengths` (one per rank) turned into the offsets of each rank's text in the whole.
inline std::vector<int> offsetsOf(const std::vector<int>& lengths)
{
  std::vector<int> offsets(lengths.size(), 0);
  std::exclusive_scan(lengths.begin(), lengths.end(), offsets.begin(), 0);
  return offsets;
}

inline std::string concatenated(const std::vector<int>& lengths, const std::vector<int>& offsets)
{
  return std::string(
      lengths.empty() ? 0 : static_cast<std::size_t>(offsets.back() + lengths.back()), '\0');
}

/// `all` cut back into the texts it was gathered from.
inline std::vector<std::string> split(const std::string& all, const std::vector<int>& lengths,
                                      const std::vector<int>& offsets)
{
  std::vector<std::string> texts;
  texts.reserve(lengths.size());
  for (std::size_t rank = 0; rank < lengths.size(); ++rank)
  {
    texts.push_back(all.substr(static_cast<std::size_t>(offsets[rank]),
                               static_cast<std::size_t>(lengths[rank])));
  }
  return texts;
}

} // namespace gather_text_detail

/// Every rank's `text` (any bytes), in rank order, on every rank. Collective over
/// `communicator`; MPI_COMM_NULL means a single process without MPI ({text}).
inline std::vector<std::string> gatherTextsToAll(MPI_Comm communicator, const std::string& text)
{
  if (communicator == MPI_COMM_NULL)
  {
    return {text};
  }
  int size = 1;
  MPI_Comm_size(communicator, &size);
  int length = static_cast<int>(text.size());
  std::vector<int> lengths(static_cast<std::size_t>(size), 0);
  MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, communicator);
  const std::vector<int> offsets = gather_text_detail::offsetsOf(lengths);
  std::string all = gather_text_detail::concatenated(lengths, offsets);
  MPI_Allgatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(),
                 MPI_CHAR, communicator);
  return gather_text_detail::split(all, lengths, offsets);
}

/// Every rank's `text`, in rank order, on `root`; empty on the other ranks.
/// Collective over `communicator`; MPI_COMM_NULL means a single process ({text}).
inline std::vector<std::string> gatherTextsToRoot(MPI_Comm communicator, const std::string& text,
                                                  int root = 0)
{
  if (communicator == MPI_COMM_NULL)
  {
    return {text};
  }
  int size = 1;
  int rank = 0;
  MPI_Comm_size(communicator, &size);
  MPI_Comm_rank(communicator, &rank);
  int length = static_cast<int>(text.size());
  // Only the root receives: the other ranks' vectors stay empty.
  std::vector<int> lengths(rank == root ? static_cast<std::size_t>(size) : 0, 0);
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, root, communicator);
  const std::vector<int> offsets = gather_text_detail::offsetsOf(lengths);
  std::string all = gather_text_detail::concatenated(lengths, offsets);
  MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
              root, communicator);
  return gather_text_detail::split(all, lengths, offsets);
}

/// `root`'s `text` (any bytes) on every rank. Collective over `communicator`;
/// MPI_COMM_NULL means a single process (`text`).
inline std::string broadcastText(MPI_Comm communicator, const std::string& text, int root = 0)
{
  if (communicator == MPI_COMM_NULL)
  {
    return text;
  }
  int length = static_cast<int>(text.size());
  MPI_Bcast(&length, 1, MPI_INT, root, communicator);
  std::string all(static_cast<std::size_t>(length), '\0');
  int rank = 0;
  MPI_Comm_rank(communicator, &rank);
  if (rank == root)
  {
    all = text;
  }
  MPI_Bcast(all.data(), length, MPI_CHAR, root, communicator);
  return all;
}

} // namespace canopy
