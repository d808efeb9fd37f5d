// Agreement between the ranks of a collective writer: one rank's problem must
// stop every rank at the same point, or the others would wait forever in the
// next collective call.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace canopy::io
{

/// Every rank's problem ("rank R: text", rank order, "; "-separated), or empty
/// when no rank has one. Collective; `communicator` MPI_COMM_NULL means a
/// single process without MPI.
std::string gatherProblems(MPI_Comm communicator, const std::string& localProblem);

/// Every rank's `values` (the same count on each), rank after rank. Collective.
std::vector<std::int64_t> gatherCounts(MPI_Comm communicator,
                                       const std::vector<std::int64_t>& values);

/// Every rank's text, in rank order. Collective.
std::vector<std::string> gatherTexts(MPI_Comm communicator, const std::string& text);

int rankOf(MPI_Comm communicator);
int sizeOf(MPI_Comm communicator);

} // namespace canopy::io
