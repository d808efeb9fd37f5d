#include "RemoteFaceExchange.h"

#include "AdaptiveSurfaceBuilder.h"
#include "GatherFromAll.h"

#include <vtkMultiProcessController.h>

#include <vector>

namespace canopy
{

void exchangeRemoteFaces(AdaptiveSurfaceBuilder& builder, vtkMultiProcessController* controller)
{
  const int me = controller->GetLocalProcessId();
  const int ranks = controller->GetNumberOfProcesses();

  std::vector<vtkIdType> asked;
  for (const RemoteFace& f : builder.remoteFaces())
  {
    asked.insert(asked.end(), {f.root[0], f.root[1], f.root[2], f.level, f.ijk[0], f.ijk[1],
                               f.ijk[2], f.axis, f.side});
  }
  std::vector<vtkIdType> counts;
  const std::vector<vtkIdType> everyFace = gatherFromAll(controller, asked, counts);

  // Answers to every other rank, each tagged with the rank it is for.
  std::vector<double> answers;
  const std::size_t width = RemoteFace::Values;
  std::size_t at = 0;
  for (int r = 0; r < ranks; ++r)
  {
    const std::size_t values = static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
    if (r != me)
    {
      std::vector<RemoteFace> faces;
      for (std::size_t i = at; i + width <= at + values; i += width)
      {
        const vtkIdType* v = everyFace.data() + i;
        faces.push_back({{{v[0], v[1], v[2]}}, v[3], {{v[4], v[5], v[6]}}, v[7], v[8]});
      }
      for (const RemotePiece& p : builder.answerRemoteFaces(faces))
      {
        answers.insert(answers.end(),
                       {static_cast<double>(r), static_cast<double>(p.face), p.whole ? 1.0 : 0.0,
                        p.lo[0], p.lo[1], p.lo[2], p.hi[0], p.hi[1], p.hi[2],
                        static_cast<double>(p.level), static_cast<double>(p.ijk[0]),
                        static_cast<double>(p.ijk[1]), static_cast<double>(p.ijk[2])});
      }
    }
    at += values;
  }
  const std::vector<double> everyAnswer = gatherFromAll(controller, answers, counts);

  std::vector<RemotePiece> mine;
  const std::size_t pieceWidth = RemotePiece::Values + 1; // + the rank it is for
  for (std::size_t i = 0; i + pieceWidth <= everyAnswer.size(); i += pieceWidth)
  {
    const double* v = everyAnswer.data() + i;
    if (static_cast<int>(v[0]) == me)
    {
      mine.push_back({static_cast<std::size_t>(v[1]),
                      v[2] != 0,
                      {{v[3], v[4], v[5]}},
                      {{v[6], v[7], v[8]}},
                      static_cast<std::int64_t>(v[9]),
                      {{static_cast<std::int64_t>(v[10]), static_cast<std::int64_t>(v[11]),
                        static_cast<std::int64_t>(v[12])}}});
    }
  }
  builder.addRemotePieces(mine);
}

} // namespace canopy
