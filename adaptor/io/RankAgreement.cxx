#include "RankAgreement.h"

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

std::vector<std::string> gatherTexts(MPI_Comm communicator, const std::string& text)
{
  if (communicator == MPI_COMM_NULL)
  {
    return {text};
  }
  const int size = sizeOf(communicator);
  int length = static_cast<int>(text.size());
  std::vector<int> lengths(static_cast<std::size_t>(size));
  MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, communicator);
  std::vector<int> displacements(static_cast<std::size_t>(size), 0);
  for (int r = 1; r < size; ++r)
  {
    displacements[static_cast<std::size_t>(r)] =
        displacements[static_cast<std::size_t>(r - 1)] + lengths[static_cast<std::size_t>(r - 1)];
  }
  std::string all(static_cast<std::size_t>(displacements.back() + lengths.back()), '\0');
  MPI_Allgatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), displacements.data(),
                 MPI_CHAR, communicator);
  std::vector<std::string> texts;
  for (int r = 0; r < size; ++r)
  {
    texts.push_back(all.substr(static_cast<std::size_t>(displacements[static_cast<std::size_t>(r)]),
                               static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)])));
  }
  return texts;
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
  const std::vector<std::string> texts = gatherTexts(communicator, localProblem);
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

std::vector<std::int64_t> gatherCounts(MPI_Comm communicator,
                                       const std::vector<std::int64_t>& values)
{
  if (communicator == MPI_COMM_NULL)
  {
    return values;
  }
  std::vector<std::int64_t> all(values.size() * static_cast<std::size_t>(sizeOf(communicator)));
  MPI_Allgather(values.data(), static_cast<int>(values.size()), MPI_INT64_T, all.data(),
                static_cast<int>(values.size()), MPI_INT64_T, communicator);
  return all;
}

} // namespace canopy::io
