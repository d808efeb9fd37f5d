// The ranks' exchange of remote faces (AdaptiveSurfaceBuilder.h): every rank
// sends the faces it asks about to all ranks, answers every other rank's faces
// for the parts it owns, and receives the pieces meant for it.
//
// Owners are not known (an absent cell or a tree elsewhere does not say whose
// it is), so faces and pieces are gathered by all ranks: two AllGatherV calls,
// each preceded by one AllGather of the counts. What travels is proportional
// to the faces between ranks' parts that a drawn node has, not to the grid.
#pragma once

class vtkMultiProcessController;

namespace canopy
{

class AdaptiveSurfaceBuilder;

/// Collective over `controller`: every rank calls it after builder.count(),
/// with builders made with the same options. Adds the pieces this rank was
/// sent (builder.cells() counts them). Throws std::invalid_argument on a
/// malformed answer (after the collective calls: no rank is left waiting).
void exchangeRemoteFaces(AdaptiveSurfaceBuilder& builder, vtkMultiProcessController* controller);

} // namespace canopy
