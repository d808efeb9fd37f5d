// How the builders' long loops over trees report progress and learn that their
// algorithm was aborted, without depending on VTK's pipeline: the filter hands
// them a TreeProgress made from itself (UpdateProgress, CheckAbort), and they
// run their loops through forEachTree.
//
// As VTK's own hypertree-grid filters do, the abort is checked once per tree,
// never per cell. The loop runs in a few batches (vtkSMPTools::For each): after
// each, on the pipeline's thread, the fraction done is reported and the abort
// checked; within a batch, every worker skips the trees left once an abort is
// known, and the pipeline's thread, when it walks trees itself (the Sequential
// backend), checks before each one. VTK's observers (a ProgressEvent observer
// setting AbortExecute, ParaView's progress handler) thus only ever run on the
// pipeline's thread. A stopped loop has walked whole trees or none of a tree:
// what it leaves is partial but consistent, and the caller discards it.
#pragma once

#include <vtkSMPTools.h>
#include <vtkType.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <thread>
#include <utility>

namespace canopy
{

class TreeProgress
{
public:
  /// `report(fraction)`: the execution's progress, 0 to 1; `aborted()`: whether
  /// it is to stop. Both are called only on the thread that makes this.
  TreeProgress(std::function<void(double)> report, std::function<bool()> aborted)
      : Report(std::move(report)), Aborted(std::move(aborted))
  {
  }
  /// The progress of a VTK algorithm (its UpdateProgress and CheckAbort).
  template <typename Algorithm>
  explicit TreeProgress(Algorithm* algorithm)
      : TreeProgress([algorithm](double fraction) { algorithm->UpdateProgress(fraction); },
                     [algorithm] { return algorithm->CheckAbort(); })
  {
  }
  TreeProgress(const TreeProgress&) = delete;
  TreeProgress& operator=(const TreeProgress&) = delete;

  /// Whether the execution was aborted: any thread, cheap.
  bool stopped() const { return Stopped.load(std::memory_order_relaxed); }

  /// Asks the algorithm whether to stop (on the owner's thread only; elsewhere
  /// nothing: observers must not run on the workers).
  void check()
  {
    if (!stopped() && std::this_thread::get_id() == Owner && Aborted && Aborted())
    {
      Stopped.store(true, std::memory_order_relaxed);
    }
  }

  /// Reports the fraction done (owner's thread only), then checks.
  void report(double fraction)
  {
    if (std::this_thread::get_id() == Owner && Report)
    {
      Report(fraction);
    }
    check();
  }

private:
  std::function<void(double)> Report;
  std::function<bool()> Aborted;
  std::atomic<bool> Stopped{false};
  const std::thread::id Owner = std::this_thread::get_id();
};

/// The part [from, to] of an execution's progress a loop (or a builder's loops)
/// covers. No progress: nothing reported, never stopped.
struct ProgressShare
{
  TreeProgress* progress = nullptr;
  double from = 0;
  double to = 1;

  /// Fractions a to b of this share.
  ProgressShare part(double a, double b) const
  {
    return {progress, from + a * (to - from), from + b * (to - from)};
  }
  bool stopped() const { return progress && progress->stopped(); }
};

/// Batches a loop over `count` trees is run in: up to 5 (progress is reported
/// after each), each with at least 4 trees per thread so that it stays balanced.
inline vtkIdType treeBatches(vtkIdType count)
{
  const vtkIdType threads = std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads());
  return std::clamp<vtkIdType>(count / (4 * threads), 1, 5);
}

/// body(t) for every tree t in [0, count), in parallel; trees not begun when
/// the execution is stopped are skipped. Returns false when stopped.
template <typename Body>
bool forEachTree(const ProgressShare& share, vtkIdType count, const Body& body)
{
  TreeProgress* progress = share.progress;
  const vtkIdType batches = progress ? treeBatches(count) : 1;
  for (vtkIdType k = 0; k < batches && !share.stopped(); ++k)
  {
    const vtkIdType end = count * (k + 1) / batches;
    vtkSMPTools::For(count * k / batches, end,
                     [&](vtkIdType first, vtkIdType last)
                     {
                       for (vtkIdType t = first; t < last; ++t)
                       {
                         if (progress)
                         {
                           progress->check();
                           if (progress->stopped())
                           {
                             return;
                           }
                         }
                         body(t);
                       }
                     });
    if (progress)
    {
      progress->report(share.from + (share.to - share.from) * static_cast<double>(end) /
                                        static_cast<double>(std::max<vtkIdType>(count, 1)));
    }
  }
  return !share.stopped();
}

/// The same in tree order on the calling thread, for loops that share their
/// state between trees; body(t) returns false to end the loop early.
template <typename Body>
bool forEachTreeInOrder(const ProgressShare& share, vtkIdType count, const Body& body)
{
  TreeProgress* progress = share.progress;
  const vtkIdType batches = progress ? treeBatches(count) : 1;
  vtkIdType next = 1; // the next batch whose end is reported
  for (vtkIdType t = 0; t < count; ++t)
  {
    if (progress)
    {
      progress->check();
      if (progress->stopped())
      {
        return false;
      }
    }
    if (!body(t))
    {
      break;
    }
    if (progress && t + 1 == count * next / batches)
    {
      progress->report(share.from + (share.to - share.from) * static_cast<double>(next) /
                                        static_cast<double>(batches));
      ++next;
    }
  }
  return !share.stopped();
}

} // namespace canopy
