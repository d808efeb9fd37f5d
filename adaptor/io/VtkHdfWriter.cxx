// The step protocol of canopy::io::VtkHdfWriter (VtkHdfWriter.h). A step goes
// through phases, each ending where every rank agrees it went well: what the
// ranks have (their pieces, arrays and counts: VtkHdfStepShape.h), the file
// opened or created (its layout: VtkHdfLayout.h), the arrays checked against the
// file's, the rows written, then the step committed by NSteps. A problem on any
// rank stops every rank at the same phase and removes the step's rows again.
#include "VtkHdfWriter.h"

#include "HdfHandle.h"
#include "HyperTreeGridPiece.h"
#include "VtkHdfArrays.h"
#include "VtkHdfLayout.h"
#include "VtkHdfPieceRows.h"
#include "VtkHdfStepShape.h"
#include "WriterAgreement.h"

#include <vtkHyperTreeGrid.h>

#include <filesystem>
#include <sstream>

namespace canopy::io
{
namespace
{

/// What this rank brings to a step.
struct LocalStep
{
  HyperTreeGridPiece piece;
  std::vector<vtkDataArray*> arrays; // the grid's cell arrays to write
};

std::string joined(const std::vector<std::string>& problems)
{
  std::string text;
  for (const std::string& problem : problems)
  {
    text += (text.empty() ? "" : "; ") + problem;
  }
  return text;
}

} // namespace

struct VtkHdfWriter::Implementation
{
  MPI_Comm Communicator;
  std::string FileName;
  VtkHdfWriterOptions Options;
  bool Started = false; // a step of this run reached the file (later steps append)
  std::int64_t Steps = 0;
  VtkHdfLayout Layout; // the file's datasets, open while a step is written

  std::string where(std::int64_t step, double time) const
  {
    std::ostringstream text;
    text << "VTKHDF extract " << this->FileName << ": step ";
    if (step >= 0)
    {
      text << step << " ";
    }
    text << "(time " << time << ") not written";
    return text.str();
  }

  /// Throws the same WriteError on every rank when any rank has a problem,
  /// after restoring `file` (null: not open on every rank) to its earlier steps.
  void agree(const std::string& localProblem, const std::string& context, HdfFile* file)
  {
    const std::string problems = gatherProblems(this->Communicator, localProblem);
    if (problems.empty())
    {
      return;
    }
    std::string restore;
    if (file != nullptr)
    {
      restore = this->rollBack(*file);
    }
    throw WriteError(context + ": " + problems +
                     (restore.empty() ? "" : "; restoring the earlier steps: " + restore));
  }

  /// Shrinks every dataset back to the rows of the file's steps and closes the
  /// file. Collective. Returns what went wrong, if anything.
  std::string rollBack(HdfFile& file)
  {
    std::string local = this->Layout.shrinkToSteps();
    if (!file.reset() && local.empty())
    {
      local = "closing: " + hdfErrorText();
    }
    return gatherProblems(this->Communicator, local);
  }

  // ---- the phases of a step, in order ---------------------------------------------------

  /// This rank's piece of `htg` and the arrays it writes.
  LocalStep describe(vtkHyperTreeGrid* htg, const std::string& context)
  {
    std::vector<std::string> problems;
    if (htg == nullptr)
    {
      problems.push_back("no grid");
    }
    LocalStep local{HyperTreeGridPiece::describe(htg),
                    selectStepArrays(htg, this->Options.arrays, problems)};
    this->agree(joined(problems), context, nullptr);
    return local;
  }

  /// What every rank adds, checked to be one grid that fits on the disk.
  StepShape gatherShape(const LocalStep& local, vtkHyperTreeGrid* htg, const std::string& context)
  {
    StepShape shape =
        gatherStepShape(this->Communicator, countPiece(local.piece, htg, local.arrays));
    if (!shape.gridsMatch())
    {
      // The same on every rank: every rank compares every piece.
      throw WriteError(context + ": the ranks' grids differ in branch factor or dimensions");
    }
    // A write that fails for want of space may leave HDF5 unable to close the file
    // (HDF5 1.10 then crashes at exit, HDFFV-11052): refuse a step that will not
    // fit before touching the file.
    this->agree(shape.rank == 0 && this->Options.checkFreeSpace
                    ? freeSpaceProblem(this->FileName, shape.dataBytes)
                    : std::string(),
                context, nullptr);
    return shape;
  }

  /// The file, created at the run's first step, then appended to.
  HdfFile openOrCreate(vtkHyperTreeGrid* htg, const LocalStep& local, const StepShape& shape,
                       const std::string& context)
  {
    int exists = std::filesystem::exists(this->FileName) ? 1 : 0;
    if (this->Communicator != MPI_COMM_NULL)
    {
      MPI_Bcast(&exists, 1, MPI_INT, 0, this->Communicator); // rank 0's view decides
    }
    const bool create = !exists || (!this->Started && !this->Options.append);
    HdfFile file = openFile(this->Communicator, this->FileName, create);
    this->agree(file.valid() ? std::string()
                             : std::string(create ? "cannot create " : "cannot open ") +
                                   this->FileName + ": " + hdfErrorText(),
                context, nullptr);
    if (create)
    {
      this->create(file, htg, local, shape, context);
    }
    else
    {
      this->agree(this->Layout.open(file.get(), shape, this->Steps), context, &file);
      // Drop rows a failed or interrupted step left behind.
      this->agree(this->Layout.trim(), context, &file);
    }
    return file;
  }

  void create(HdfFile& file, vtkHyperTreeGrid* htg, const LocalStep& local, const StepShape& shape,
              const std::string& context)
  {
    // The arrays: those of every rank, in rank order, each once.
    AgreedArrays agreed = gatherArraySpecs(this->Communicator, local.arrays);
    if (!agreed.conflict.empty())
    {
      file.reset();
      throw WriteError(context + ": " + agreed.conflict);
    }
    this->Steps = 0;
    this->Layout = VtkHdfLayout(std::move(agreed.specs));
    std::string created = this->Layout.create(file.get(), shape, htg->GetTransposedRootIndexing());
    if (created.empty() && H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0)
    {
      // On disk before any data: a later failure finds a file it can restore.
      created = "cannot flush the new file: " + hdfErrorText();
    }
    this->agree(created, context, &file);
  }

  /// Data, then the step's offsets: nothing a reader sees until commit().
  void writeRows(HdfFile& file, const LocalStep& local, vtkHyperTreeGrid* htg,
                 const StepShape& shape, double time, const std::string& context)
  {
    this->agree(this->Layout.extendData(shape), context, &file);
    this->agree(writePieceRows(this->Layout, shape, local.piece, htg, local.arrays), context,
                &file);
    std::string row = this->Layout.extendSteps();
    if (row.empty() && shape.rank == 0)
    {
      row = this->Layout.writeStepRow(shape, time);
    }
    this->agree(row, context, &file);
    this->agree(H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0
                    ? "cannot flush the step's data: " + hdfErrorText()
                    : std::string(),
                context, &file);
  }

  /// NSteps: the step exists once it says so. Then the file is closed.
  void commit(HdfFile& file, const std::string& context)
  {
    const std::int64_t stepsAfter = this->Steps + 1;
    this->agree(commitNumberOfSteps(file.get(), this->Steps, stepsAfter), context, &file);
    this->Layout.close();
    const std::string closed = file.reset() ? std::string() : "closing: " + hdfErrorText();
    this->Started = true;
    this->Steps = stepsAfter;
    const std::string closeProblems = gatherProblems(this->Communicator, closed);
    if (!closeProblems.empty())
    {
      throw WriteError(context + " completely (the step's data and offsets were flushed before): " +
                       closeProblems);
    }
  }
};

VtkHdfWriter::VtkHdfWriter(MPI_Comm communicator, std::string fileName, VtkHdfWriterOptions options)
    : Impl(std::make_unique<Implementation>())
{
  this->Impl->Communicator = communicator;
  this->Impl->FileName = std::move(fileName);
  this->Impl->Options = std::move(options);
}

VtkHdfWriter::~VtkHdfWriter() = default;

std::int64_t VtkHdfWriter::numberOfSteps() const
{
  return this->Impl->Steps;
}

const std::string& VtkHdfWriter::fileName() const
{
  return this->Impl->FileName;
}

void VtkHdfWriter::writeStep(vtkHyperTreeGrid* htg, std::int64_t step, double time)
{
  Implementation& impl = *this->Impl;
  const QuietHdfErrors quiet;
  const std::string context = impl.where(step, time);
  const LocalStep local = impl.describe(htg, context);
  const StepShape shape = impl.gatherShape(local, htg, context);
  HdfFile file = impl.openOrCreate(htg, local, shape, context);
  // Every array of the file must come from every rank (the ghost array excepted).
  impl.agree(missingArrays(impl.Layout.arrays(), local.arrays), context, &file);
  impl.writeRows(file, local, htg, shape, time, context);
  impl.commit(file, context);
}

} // namespace canopy::io
