! Canopy's C API (canopy.h) for Fortran, through iso_c_binding. Compile this
! file with your code (it is installed next to canopy.h) and `use canopy`.
! Every function of canopy.h is bound here (canopy_open through canopy_open_f,
! which takes the integer communicator handle).
!
! Strings passed in end with c_null_char; Canopy copies them during the call.
! Handles are type(c_ptr). Return values: CANOPY_OK (0) or an error code;
! canopy_last_error_message() then says what went wrong.
!
! Arrays that Canopy keeps after the call (root grid coordinates, refinement,
! masks, storage slots, absent bytes, field data) are `type(c_ptr), value`
! dummies: pass c_loc(a) of a contiguous array declared `target` (or a pointer
! to one), or c_null_ptr where canopy.h allows NULL. A dimension(*) dummy would
! let the compiler pass a temporary copy (for a section or an expression) that
! is freed when the call returns, while Canopy reads it at canopy_execute.
! Such an array is borrowed until canopy_forest_clear (root grid coordinates:
! canopy_forest_destroy): keep it allocated and in place (no reallocation) until
! then; its values may change between steps, each canopy_execute reads them.
! Lists of addresses (canopy_forest_add_field_soa's component_data, the block
! fields' block_addresses) are copied during the call: an array of type(c_ptr).
! Block forests (canopy_forest_set_blocks): see the canopy_block_strides type below
! and docs/api.md.
! See docs/insitu.md.
module canopy
  use iso_c_binding
  implicit none

  integer(c_int), parameter :: CANOPY_OK = 0, CANOPY_INVALID_ARGUMENT = 1, &
                               CANOPY_OPEN_FAILED = 2, CANOPY_STEP_FAILED = 3, &
                               CANOPY_OUT_OF_MEMORY = 4
  integer(c_int), parameter :: CANOPY_FLOAT32 = 0, CANOPY_FLOAT64 = 1, &
                               CANOPY_INT32 = 2, CANOPY_INT64 = 3
  integer(c_int), parameter :: CANOPY_EVERY_NODE = 0, CANOPY_LEAVES_ONLY = 1
  integer(c_int), parameter :: CANOPY_VARIABLE_OUTERMOST = 0, CANOPY_VARIABLE_INNERMOST = 1

  ! canopy.h's canopy_block_strides: where the cells of one block lie in its array.
  ! Interior cell (i, j, k), counted from 0 along the forest's axes that are not flat,
  ! component c (from 0), is at the block's first byte (its first ghost cell) plus
  !   c * component_bytes + (i + ghost_cells(1)) * cell_bytes(1)
  !     + (j + ghost_cells(2)) * cell_bytes(2) + (k + ghost_cells(3)) * cell_bytes(3)
  ! Fill one with canopy_block_strides_packed for the two usual orders; in Fortran's
  ! column-major terms:
  !   CANOPY_VARIABLE_INNERMOST  unk(var, i, j, k[, block]): the components of a cell
  !                              together (FLASH/PARAMESH's unk);
  !   CANOPY_VARIABLE_OUTERMOST  u(i, j, k, var[, block]): each variable a whole block
  !                              array (and u(i, j, k) of one variable, for
  !                              canopy_forest_add_block_field_components).
  ! A 2D code's k extent (1) and a 1D code's j and k extents do not matter. Arrays
  ! declared larger than cells + 2 ghosts per side (room for the largest block) need
  ! their strides set by hand: cell_bytes(1) = the bytes of what varies fastest
  ! before i (components and all), cell_bytes(2) = cell_bytes(1) * the declared i
  ! extent, and so on.
  type, bind(c) :: canopy_block_strides
    integer(c_size_t) :: cell_bytes(3) = 0
    integer(c_size_t) :: component_bytes = 0
    integer(c_int) :: ghost_cells(3) = 0
  end type

  interface
    type(c_ptr) function canopy_last_error() bind(c)
      import :: c_ptr
    end function

    ! ---- options ----
    ! options: set to a new handle (c_null_ptr on failure).
    integer(c_int) function canopy_options_create(options) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), intent(out) :: options
    end function
    subroutine canopy_options_destroy(options) bind(c)
      import :: c_ptr
      type(c_ptr), value :: options
    end subroutine
    integer(c_int) function canopy_options_add_script(options, path) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*), intent(in) :: path
    end function
    integer(c_int) function canopy_options_add_script_argument(options, argument) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*), intent(in) :: argument
    end function
    integer(c_int) function canopy_options_set_output_directory(options, directory) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*), intent(in) :: directory
    end function
    integer(c_int) function canopy_options_set_channel(options, channel) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*), intent(in) :: channel
    end function
    integer(c_int) function canopy_options_set_verbosity(options, verbosity) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), value :: options
      integer(c_int), value :: verbosity
    end function
    integer(c_int) function canopy_options_set_step_summary(options, enabled) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), value :: options
      integer(c_int), value :: enabled
    end function
    integer(c_int) function canopy_options_set_step_time_limit(options, seconds) bind(c)
      import :: c_int, c_ptr, c_double
      type(c_ptr), value :: options
      real(c_double), value :: seconds
    end function

    ! ---- forest ----
    ! x, y, z: c_loc of real(c_double) target arrays, borrowed until canopy_forest_destroy.
    ! forest: set to a new handle (c_null_ptr on failure).
    integer(c_int) function canopy_forest_create(dimension, branch_factor, max_levels, x, &
                                                 points_x, y, points_y, z, points_z, forest) &
                                                 bind(c)
      import :: c_int, c_ptr, c_size_t
      integer(c_int), value :: dimension, branch_factor, max_levels
      type(c_ptr), value :: x, y, z
      integer(c_size_t), value :: points_x, points_y, points_z
      type(c_ptr), intent(out) :: forest
    end function
    subroutine canopy_forest_destroy(forest) bind(c)
      import :: c_ptr
      type(c_ptr), value :: forest
    end subroutine
    integer(c_int) function canopy_forest_clear(forest) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), value :: forest
    end function
    ! refinement, masked: c_loc of integer(c_int8_t) target arrays; storage_slots: of an
    ! integer(c_int64_t) target array; masked and storage_slots may be c_null_ptr.
    ! All borrowed until canopy_forest_clear.
    integer(c_int) function canopy_forest_add_tree(forest, root_index, refinement, &
                                                   number_of_nodes, masked, storage_slots) bind(c)
      import :: c_int, c_ptr, c_int64_t, c_size_t
      type(c_ptr), value :: forest
      integer(c_int64_t), value :: root_index
      type(c_ptr), value :: refinement
      integer(c_size_t), value :: number_of_nodes
      type(c_ptr), value :: masked, storage_slots
    end function
    ! A tree split between ranks; absent: c_loc of an integer(c_int8_t) target array
    ! (nonzero = another rank owns that node's part), borrowed until canopy_forest_clear,
    ! or c_null_ptr (the same as canopy_forest_add_tree).
    integer(c_int) function canopy_forest_add_partial_tree(forest, root_index, refinement, &
                                                           number_of_nodes, masked, &
                                                           storage_slots, absent) bind(c)
      import :: c_int, c_ptr, c_int64_t, c_size_t
      type(c_ptr), value :: forest
      integer(c_int64_t), value :: root_index
      type(c_ptr), value :: refinement
      integer(c_size_t), value :: number_of_nodes
      type(c_ptr), value :: masked, storage_slots, absent
    end function
    ! data: c_loc of a target array of the value type, borrowed until canopy_forest_clear
    ! (c_null_ptr only with number_of_tuples = 0).
    integer(c_int) function canopy_forest_add_field(forest, name, value_type, components, &
                                                    data, tuple_stride_bytes, number_of_tuples, &
                                                    centering) bind(c)
      import :: c_int, c_ptr, c_char, c_size_t
      type(c_ptr), value :: forest
      character(kind=c_char), dimension(*), intent(in) :: name
      integer(c_int), value :: value_type, components, centering
      type(c_ptr), value :: data
      integer(c_size_t), value :: tuple_stride_bytes, number_of_tuples
    end function
    ! component_data: `components` addresses (c_loc of target arrays). The list of
    ! addresses is copied during the call; the arrays they point to are borrowed until
    ! canopy_forest_clear.
    integer(c_int) function canopy_forest_add_field_soa(forest, name, value_type, components, &
                                                        component_data, number_of_tuples, &
                                                        centering) bind(c)
      import :: c_int, c_ptr, c_char, c_size_t
      type(c_ptr), value :: forest
      character(kind=c_char), dimension(*), intent(in) :: name
      integer(c_int), value :: value_type, components, centering
      type(c_ptr), dimension(*), intent(in) :: component_data
      integer(c_size_t), value :: number_of_tuples
    end function

    ! ---- block forests (canopy.h: canopy_forest_set_blocks and after) ----
    ! cells_per_side: 0 (no blocks) or a power of the branch factor; call it on a forest
    ! without trees or fields. canopy_forest_create's max_levels counts the levels
    ! inside the blocks.
    integer(c_int) function canopy_forest_set_blocks(forest, cells_per_side) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), value :: forest
      integer(c_int), value :: cells_per_side
    end function
    ! refinement, masked, absent: c_loc of integer(c_int8_t) target arrays; block_index: of
    ! an integer(c_int64_t) target array, per node, the 0-based index of the leaf's block in
    ! the fields' block tables (block b is Fortran's block b + 1). masked, absent and
    ! block_index may be c_null_ptr. All borrowed until canopy_forest_clear.
    integer(c_int) function canopy_forest_add_block_tree(forest, root_index, refinement, &
                                                         number_of_nodes, masked, absent, &
                                                         block_index) bind(c)
      import :: c_int, c_ptr, c_int64_t, c_size_t
      type(c_ptr), value :: forest
      integer(c_int64_t), value :: root_index
      type(c_ptr), value :: refinement
      integer(c_size_t), value :: number_of_nodes
      type(c_ptr), value :: masked, absent, block_index
    end function
    ! strides: filled for blocks of (cells_per_side + 2 * ghost_cells)^dimension cells,
    ! in the given order (unchanged when the call fails: intent(inout), as intent(out)
    ! would reset it to the type's defaults); block_bytes: the bytes of one block
    ! (block_stride_bytes of canopy_forest_add_block_field_array for unk(:, :, :, :, block)).
    integer(c_int) function canopy_block_strides_packed(dimension, cells_per_side, ghost_cells, &
                                                        components, value_type, order, strides, &
                                                        block_bytes) bind(c)
      import :: c_int, c_size_t, canopy_block_strides
      integer(c_int), value :: dimension, cells_per_side, ghost_cells, components, value_type, &
                               order
      type(canopy_block_strides), intent(inout) :: strides
      integer(c_size_t), intent(out) :: block_bytes
    end function
    ! Blocks allocated one by one: block_addresses(b) = c_loc of block b's array (a
    ! contiguous target: a whole array, e.g. an allocatable component blocks(b)%u of a
    ! target array of derived type, from its first ghost cell). The list of addresses is
    ! copied during the call (canopy_forest_clear and add the field again when blocks
    ! move); the arrays are borrowed until canopy_forest_clear. strides is copied.
    integer(c_int) function canopy_forest_add_block_field(forest, name, value_type, components, &
                                                          block_addresses, number_of_blocks, &
                                                          strides) bind(c)
      import :: c_int, c_ptr, c_char, c_size_t, canopy_block_strides
      type(c_ptr), value :: forest
      character(kind=c_char), dimension(*), intent(in) :: name
      integer(c_int), value :: value_type, components
      type(c_ptr), dimension(*), intent(in) :: block_addresses
      integer(c_size_t), value :: number_of_blocks
      type(canopy_block_strides), intent(in) :: strides
    end function
    ! Every block in one array: first_block = c_loc(unk(1, lo, lo, lo, 1)) (c_loc(unk) of
    ! the whole target array), block_stride_bytes the bytes from unk(:, :, :, :, b) to
    ! unk(:, :, :, :, b + 1); number_of_blocks may be the array's size (MAXBLOCKS): at
    ! least the blocks this rank has. The array is borrowed until canopy_forest_clear.
    integer(c_int) function canopy_forest_add_block_field_array(forest, name, value_type, &
                                                                components, first_block, &
                                                                block_stride_bytes, &
                                                                number_of_blocks, strides) &
                                                                bind(c)
      import :: c_int, c_ptr, c_char, c_size_t, canopy_block_strides
      type(c_ptr), value :: forest
      character(kind=c_char), dimension(*), intent(in) :: name
      integer(c_int), value :: value_type, components
      type(c_ptr), value :: first_block
      integer(c_size_t), value :: block_stride_bytes, number_of_blocks
      type(canopy_block_strides), intent(in) :: strides
    end function
    ! Each component in per-block arrays of its own: block_addresses is a
    ! type(c_ptr) :: addresses(number_of_blocks, components) array (addresses(b, c) =
    ! c_loc of component c's array of block b), copied during the call; the arrays are
    ! borrowed until canopy_forest_clear. strides: those of one component's array.
    integer(c_int) function canopy_forest_add_block_field_components(forest, name, value_type, &
                                                                     components, &
                                                                     block_addresses, &
                                                                     number_of_blocks, &
                                                                     strides) bind(c)
      import :: c_int, c_ptr, c_char, c_size_t, canopy_block_strides
      type(c_ptr), value :: forest
      character(kind=c_char), dimension(*), intent(in) :: name
      integer(c_int), value :: value_type, components
      type(c_ptr), dimension(*), intent(in) :: block_addresses
      integer(c_size_t), value :: number_of_blocks
      type(canopy_block_strides), intent(in) :: strides
    end function

    ! ---- in situ (collective) ----
    ! communicator: the integer handle (MPI_COMM_WORLD from `use mpi`, or comm%MPI_VAL).
    ! insitu: set to a new handle (c_null_ptr on failure).
    integer(c_int) function canopy_open_f(communicator, options, insitu) bind(c)
      import :: c_int, c_ptr
      integer(c_int), value :: communicator
      type(c_ptr), value :: options
      type(c_ptr), intent(out) :: insitu
    end function
    integer(c_int) function canopy_options_add_query(options, expression) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*), intent(in) :: expression
    end function
    integer(c_int) function canopy_options_add_field_name(options, name) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*), intent(in) :: name
    end function
    integer(c_int) function canopy_will_execute_forest(insitu, step, time, forest, will_execute) &
        bind(c)
      import :: c_int, c_ptr, c_int64_t, c_double
      type(c_ptr), value :: insitu, forest
      integer(c_int64_t), value :: step
      real(c_double), value :: time
      integer(c_int) :: will_execute
    end function
    integer(c_int) function canopy_query_value(insitu, expression, value) bind(c)
      import :: c_int, c_ptr, c_char, c_double
      type(c_ptr), value :: insitu
      character(kind=c_char), dimension(*), intent(in) :: expression
      real(c_double) :: value
    end function
    integer(c_int) function canopy_will_execute(insitu, step, time, will_execute) bind(c)
      import :: c_int, c_ptr, c_int64_t, c_double
      type(c_ptr), value :: insitu
      integer(c_int64_t), value :: step
      real(c_double), value :: time
      integer(c_int) :: will_execute
    end function
    integer(c_int) function canopy_execute(insitu, step, time, forest) bind(c)
      import :: c_int, c_ptr, c_int64_t, c_double
      type(c_ptr), value :: insitu, forest
      integer(c_int64_t), value :: step
      real(c_double), value :: time
    end function
    ! insitu: becomes c_null_ptr.
    integer(c_int) function canopy_close(insitu) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), intent(inout) :: insitu
    end function
  end interface

contains

  !> The message of the last failing call, as a Fortran string.
  function canopy_last_error_message() result(message)
    character(len=:), allocatable :: message
    character(kind=c_char), pointer :: text(:)
    type(c_ptr) :: address
    integer :: length
    interface
      integer(c_size_t) function strlen(s) bind(c)
        import :: c_size_t, c_ptr
        type(c_ptr), value :: s
      end function
    end interface
    address = canopy_last_error()
    length = int(strlen(address))
    call c_f_pointer(address, text, [length])
    allocate(character(len=length) :: message)
    message = transfer(text(1:length), message)
  end function

end module canopy
