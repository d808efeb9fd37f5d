// Agreement between the ranks of a collective writer (HtgSeriesWriter,
// VtkHdfWriter): one rank's problem must stop every rank at the same point, or
// the others would wait forever in the next collective call. Not insitu's
// CollectiveAgreement (adaptor/insitu), which also bounds how long ranks wait.
#pragma once

#include <mpi.h>

#include <string>
#include <type_traits>
#include <vector>

namespace canopy::io
{

/// Every rank's problem ("rank R: text", rank order, "; "-separated), or empty
/// when no rank has one. Collective; `communicator` MPI_COMM_NULL means a
/// single process without MPI.
std::string gatherProblems(MPI_Comm communicator, const std::string& localProblem);

/// Every rank's `local` record, in rank order, on every rank. Collective (same
/// MPI_COMM_NULL meaning). `Record` is plain data (sent as its bytes: the ranks
/// of a job share one machine representation).
template <typename Record>
std::vector<Record> gatherRecords(MPI_Comm communicator, const Record& local)
{
  static_assert(std::is_trivially_copyable_v<Record>, "records travel as their bytes");
  if (communicator == MPI_COMM_NULL)
  {
    return {local};
  }
  int size = 1;
  MPI_Comm_size(communicator, &size);
  std::vector<Record> all(static_cast<std::size_t>(size));
  MPI_Allgather(&local, static_cast<int>(sizeof(Record)), MPI_BYTE, all.data(),
                static_cast<int>(sizeof(Record)), MPI_BYTE, communicator);
  return all;
}

/// This process's rank and the number of ranks (0 and 1 for MPI_COMM_NULL).
int rankOf(MPI_Comm communicator);
int sizeOf(MPI_Comm communicator);

} // namespace canopy::io
