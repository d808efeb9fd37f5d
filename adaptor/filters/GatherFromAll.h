// Every rank's values to every rank (an AllGather of the counts, then an
// AllGatherV), for exchanges whose receivers are not known in advance.
#pragma once

#include <vtkMultiProcessController.h>

#include <vector>

namespace canopy
{

/// Collective over `controller`: every rank's `local` values, back to back in
/// rank order; `counts` receives the number from each rank.
template <typename T>
std::vector<T> gatherFromAll(vtkMultiProcessController* controller, const std::vector<T>& local,
                             std::vector<vtkIdType>& counts)
{
  const int ranks = controller->GetNumberOfProcesses();
  const vtkIdType mine = static_cast<vtkIdType>(local.size());
  counts.assign(static_cast<std::size_t>(ranks), 0);
  controller->AllGather(&mine, counts.data(), 1);
  std::vector<vtkIdType> offsets(static_cast<std::size_t>(ranks), 0);
  vtkIdType total = 0;
  for (int r = 0; r < ranks; ++r)
  {
    offsets[static_cast<std::size_t>(r)] = total;
    total += counts[static_cast<std::size_t>(r)];
  }
  std::vector<T> all(static_cast<std::size_t>(total));
  // Empty buffers still take part: the call is collective.
  T unused{};
  controller->AllGatherV(local.empty() ? &unused : local.data(), all.empty() ? &unused : all.data(),
                         mine, counts.data(), offsets.data());
  return all;
}

} // namespace canopy
