// What the in-situ driver checks before it starts anything (MPI, the options)
// and before each step that runs scripts (the output directory).
#pragma once

#include <canopy/InSitu.h>

#include <mpi.h>

#include <string>
#include <vector>

namespace canopy
{

/// Throws InSituError unless MPI is initialized and not finalized, and the
/// communicator is not MPI_COMM_NULL.
void requireUsableMpi(MPI_Comm communicator);

/// Finds each script (a relative path is also looked for among the pipelines,
/// ScriptSearch.h) and makes the paths and the output directory absolute
/// (ParaView imports scripts lazily, and the simulation may change its working
/// directory), then lists what is wrong with the options on this rank: no
/// script, a script missing (with every place looked at) or given twice, an empty channel or output
/// directory, a time limit that is not a number of seconds >= 0, Catalyst not startable in this
/// process.
std::vector<std::string> normalizeAndCheckOptions(InSituOptions& options);

/// Creates `directory` if it is missing; returns what is wrong with it, empty
/// when it exists and is writable.
std::string prepareOutputDirectory(const std::string& directory);

} // namespace canopy
