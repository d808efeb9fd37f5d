// The error Canopy's writers throw when a step could not be written.
#pragma once

#include "CanopyIOModule.h"

#include <stdexcept>
#include <string>

namespace canopy::io
{

/// A step was not written. Collective writers throw it on every rank with the
/// same text, naming each rank's problem ("rank 1: ..."), so that all ranks
/// skip the step together.
class CANOPYIO_EXPORT WriteError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

} // namespace canopy::io
