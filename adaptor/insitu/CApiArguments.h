// The C API's arguments turned into Canopy's types, with the refusals: each
// check returns CANOPY_OK or the status of a message recorded with fail()
// ("<function>: ..."), so an entry point returns it as it is.
#pragma once

#include "canopy/ForestDescription.h"

#include <cstddef>

namespace canopy::capi
{

/// size_t counts above PTRDIFF_MAX are negative numbers converted (Fortran's
/// c_size_t is signed) rather than real sizes.
bool negativeCount(std::size_t count);

/// A NUL-terminated string argument (`what`: how a message names it).
int checkString(const char* function, const char* what, const char* text, bool mayBeEmpty);

/// What both field calls share, filled into `field` (name, type, centering,
/// components, number of tuples); `name` is copied. May throw bad_alloc.
int checkField(const char* function, const char* name, int valueType, int components,
               std::size_t numberOfTuples, int centering, FieldDescription& field);

/// One axis of the root grid: `points` coordinates at `coordinates`.
int checkAxis(const char* function, char axis, const double* coordinates, std::size_t points);

} // namespace canopy::capi
