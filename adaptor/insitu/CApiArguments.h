// The C API's arguments turned into Canopy's types, with the refusals: each
// check returns CANOPY_OK or the status of a message recorded with fail()
// ("<function>: ..."), so an entry point returns it as it is.
#pragma once

#include <canopy/ForestDescription.h>
#include <canopy/canopy.h>

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

/// A valueType code turned into `type` (false: unknown code).
bool valueTypeFromC(int code, ValueType& type);

/// The block size of canopy_forest_set_blocks for a forest of `branchFactor` and
/// `maxLevels`: 0, or a power of the branch factor whose levels fit.
int checkBlockSize(const char* function, int cellsPerSide, int branchFactor, int maxLevels);

/// What the block field calls share, filled into `field` (name, type, components,
/// Layout::Blocks, number of blocks, strides): a floating-point type, strides that
/// step over whole values along the forest's `dimension` axes, and (unless the
/// components are separate arrays) over whole values from component to component.
/// `name` is copied. May throw bad_alloc.
int checkBlockField(const char* function, const char* name, int valueType, int components,
                    std::size_t numberOfBlocks, const canopy_block_strides* strides, int dimension,
                    bool separateComponents, FieldDescription& field);

/// A table of `count` block addresses (`what`: how a message names it), NULL only
/// when `count` is 0: each entry present and aligned to `valueSize`. Entries past
/// `blocksPerComponent` are named by component and block.
int checkBlockAddresses(const char* function, const char* name, const char* what,
                        const void* const* table, std::size_t count, std::size_t blocksPerComponent,
                        std::size_t valueSize);

/// Whether `pointer` is not a multiple of `valueSize`.
bool misaligned(const void* pointer, std::size_t valueSize);

} // namespace canopy::capi
