// The step protocol of canopy::io::VtkHdfWriter (VtkHdfWriter.h). One process
// writes the file: rank 0 of the writer's communicator, through a file driver
// that can undo a step byte for byte (StepRollback.h); every other rank sends
// its rows to it (VtkHdfRowTransfer.h). A step goes through phases, each ending
// where every rank agrees it went well: what the ranks have (their pieces,
// arrays and counts: VtkHdfStepShape.h), the file opened or created (its layout:
// VtkHdfLayout.h) and its arrays known to every rank, the rows written, then the
// step's offsets and NSteps, the file closed and made durable. A problem on any
// rank stops every rank at the same phase, and rank 0 undoes the step.
#include <canopy/io/VtkHdfWriter.h>

#include "GatherText.h"
#include "HdfHandle.h"
#include "StepRollback.h"
#include "VtkHdfArrays.h"
#include "VtkHdfLayout.h"
#include "VtkHdfPieceRows.h"
#include "VtkHdfRowTransfer.h"
#include "VtkHdfStepShape.h"
#include "WriterAgreement.h"
#include <canopy/io/HyperTreeGridPiece.h>

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
  MPI_Comm Communicator;         // the caller's: agreements
  MPI_Comm Rows = MPI_COMM_NULL; // a duplicate of it, for the rows sent to rank 0
  std::string FileName;
  VtkHdfWriterOptions Options;
  bool Started = false; // a step of this run is in the file (later steps append)
  std::int64_t Steps = 0;
  std::vector<ArraySpec> Arrays; // the file's arrays, on every rank
  // Rank 0's, while a step is written:
  StepRollback Rollback;
  VtkHdfLayout Layout;
  HdfFile File;
  bool StepOpen = false; // begun and neither kept nor undone

  Implementation(MPI_Comm communicator, std::string fileName, VtkHdfWriterOptions options)
      : Communicator(communicator), FileName(std::move(fileName)), Options(std::move(options)),
        Rollback(this->FileName)
  {
  }

  ~Implementation()
  {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (this->Rows != MPI_COMM_NULL && !finalized)
    {
      MPI_Comm_free(&this->Rows);
    }
  }

  bool writes() const { return rankOf(this->Communicator) == 0; }

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

  /// Rank 0: what went wrong on the disk so far in this step ("" if nothing).
  std::string diskProblem() const
  {
    return this->Rollback.failed()
               ? "cannot write " + this->FileName + ": " + this->Rollback.failure()
               : std::string();
  }

  /// Rank 0: closes the file and puts it back as it was before the step.
  std::string abandon()
  {
    if (!this->StepOpen)
    {
      return {};
    }
    this->Layout.close();
    this->File.reset();
    this->StepOpen = false;
    const std::string undone = this->Rollback.undo();
    return undone.empty() ? std::string()
                          : "; the file could not be put back yet (tried again at the next "
                            "step): " +
                                undone;
  }

  /// Throws the same WriteError on every rank when any rank has a problem,
  /// after rank 0 has undone the step.
  void agree(const std::string& localProblem, const std::string& context)
  {
    const std::string problems = gatherProblems(this->Communicator, localProblem);
    if (problems.empty())
    {
      return;
    }
    const std::string undo = this->abandon();
    // Rank 0's undo is news for every rank: the message is the same everywhere.
    throw WriteError(context + ": " + problems + canopy::broadcastText(this->Communicator, undo));
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
    this->agree(joined(problems), context);
    if (this->Rows == MPI_COMM_NULL && this->Communicator != MPI_COMM_NULL)
    {
      MPI_Comm_dup(this->Communicator, &this->Rows); // collective: every rank is here
    }
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
    // A step that cannot fit would fail and be undone: refuse it before any work.
    this->agree(this->writes() && this->Options.checkFreeSpace
                    ? freeSpaceProblem(this->FileName, shape.dataBytes)
                    : std::string(),
                context);
    return shape;
  }

  /// The file, created at the run's first step, then appended to; its arrays
  /// known to every rank and given by every rank.
  void openOrCreate(vtkHyperTreeGrid* htg, const LocalStep& local, const StepShape& shape,
                    const std::string& context)
  {
    int create = 0;
    if (this->writes())
    {
      create =
          !std::filesystem::exists(this->FileName) || (!this->Started && !this->Options.append);
    }
    if (this->Communicator != MPI_COMM_NULL)
    {
      MPI_Bcast(&create, 1, MPI_INT, 0, this->Communicator);
    }
    AgreedArrays agreed;
    if (create)
    {
      // The arrays: those of every rank, in rank order, each once.
      agreed = gatherArraySpecs(this->Communicator, local.arrays);
      if (!agreed.conflict.empty())
      {
        throw WriteError(context + ": " + agreed.conflict); // the same on every rank
      }
    }
    std::string problem;
    if (this->writes())
    {
      problem = this->Rollback.begin();
      if (problem.empty())
      {
        this->StepOpen = true;
        problem =
            create ? this->createFile(htg, shape, std::move(agreed.specs)) : this->openFile(shape);
      }
      if (problem.empty())
      {
        problem = this->diskProblem();
      }
    }
    this->agree(problem, context);
    this->Arrays = broadcastArraySpecs(this->Communicator, this->Layout.arrays());
    // Every array of the file must come from every rank (the ghost array excepted).
    this->agree(missingArrays(this->Arrays, local.arrays), context);
  }

  std::string createFile(vtkHyperTreeGrid* htg, const StepShape& shape,
                         std::vector<ArraySpec> arrays)
  {
    HdfProperties access{this->Rollback.fileAccess()};
    this->File =
        HdfFile{H5Fcreate(this->FileName.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get())};
    if (!this->File.valid())
    {
      return "cannot create " + this->FileName + ": " + hdfErrorText();
    }
    this->Steps = 0;
    this->Layout = VtkHdfLayout(std::move(arrays));
    return this->Layout.create(this->File.get(), shape, htg->GetTransposedRootIndexing());
  }

  std::string openFile(const StepShape& shape)
  {
    HdfProperties access{this->Rollback.fileAccess()};
    this->File = HdfFile{H5Fopen(this->FileName.c_str(), H5F_ACC_RDWR, access.get())};
    if (!this->File.valid())
    {
      return "cannot open " + this->FileName + ": " + hdfErrorText();
    }
    std::string problem = this->Layout.open(this->File.get(), shape, this->Steps);
    // Drop rows a step of a killed run left behind.
    return problem.empty() ? this->Layout.trim() : problem;
  }

  /// Every rank's rows: rank 0 writes its own, then each other rank's as they
  /// come; the other ranks send theirs.
  void writeRows(const LocalStep& local, vtkHyperTreeGrid* htg, const StepShape& shape,
                 const std::string& context)
  {
    std::string problem;
    if (this->writes())
    {
      problem = this->Layout.extendData(shape);
      WrittenRows own(this->Layout, shape, 0);
      if (problem.empty())
      {
        problem = putPieceRows(own, this->Layout, shape, local.piece, htg, local.arrays);
      }
      for (int from = 1; from < shape.numberOfPieces(); ++from)
      {
        WrittenRows theirs(this->Layout, shape, from);
        const std::string received = receiveRows(this->Rows, from, theirs);
        if (problem.empty())
        {
          problem = received;
        }
      }
      if (problem.empty())
      {
        problem = this->diskProblem();
      }
    }
    else
    {
      // Only the list of datasets is read: no file here.
      const VtkHdfLayout layout(this->Arrays);
      SentRows sent(this->Rows);
      problem = putPieceRows(sent, layout, shape, local.piece, htg, local.arrays);
      sent.finish();
    }
    this->agree(problem, context);
  }

  /// The step's offsets and NSteps (the step exists once it says so), the file
  /// closed and made durable, or undone.
  void commit(const StepShape& shape, double time, const std::string& context)
  {
    std::string problem;
    if (this->writes())
    {
      problem = this->Layout.extendSteps();
      if (problem.empty())
      {
        problem = this->Layout.writeStepRow(shape, time);
      }
      if (problem.empty())
      {
        problem = writeNumberOfSteps(this->File.get(), this->Steps + 1);
      }
      this->Layout.close();
      if (!this->File.reset() && problem.empty())
      {
        problem = "closing " + this->FileName + ": " + hdfErrorText();
      }
      // HDF5 keeps what a file's metadata took on its free lists; the metadata
      // grows with the steps, so a long run would keep the largest ever read.
      H5garbage_collect();
      if (problem.empty())
      {
        problem = this->diskProblem();
      }
      if (problem.empty())
      {
        this->StepOpen = false;
        const std::string kept = this->Rollback.keep(); // undoes the step if it fails
        if (!kept.empty())
        {
          problem = "cannot write " + this->FileName + ": " + kept;
        }
      }
    }
    this->agree(problem, context);
    this->Started = true;
    std::int64_t steps = this->Steps + 1;
    if (this->Communicator != MPI_COMM_NULL)
    {
      MPI_Bcast(&steps, 1, MPI_INT64_T, 0, this->Communicator); // the file's, from rank 0
    }
    this->Steps = steps;
  }
};

VtkHdfWriter::VtkHdfWriter(MPI_Comm communicator, std::string fileName, VtkHdfWriterOptions options)
    : Impl(std::make_unique<Implementation>(communicator, std::move(fileName), std::move(options)))
{
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
  impl.openOrCreate(htg, local, shape, context);
  impl.writeRows(local, htg, shape, context);
  impl.commit(shape, time, context);
}

} // namespace canopy::io
