// How many MPI communication calls this process made (PMPI interposition in
// CountedCollectives.cxx): collectives and point-to-point calls, any communicator.
#pragma once

namespace canopy::testing
{

/// Calls counted since the process started.
long long mpiCallsMade();

} // namespace canopy::testing
