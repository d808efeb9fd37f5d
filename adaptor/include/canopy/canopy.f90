! Canopy's C API (canopy.h) for Fortran, through iso_c_binding. Compile this
! file with your code (it is installed next to canopy.h) and `use canopy`.
! Strings passed in must end with c_null_char; handles are type(c_ptr).
! Return values: CANOPY_OK (0) or an error code; canopy_last_error_message()
! then says what went wrong. See docs/insitu.md.
module canopy
  use iso_c_binding
  implicit none

  integer(c_int), parameter :: CANOPY_OK = 0, CANOPY_INVALID_ARGUMENT = 1, &
                               CANOPY_OPEN_FAILED = 2, CANOPY_STEP_FAILED = 3
  integer(c_int), parameter :: CANOPY_FLOAT32 = 0, CANOPY_FLOAT64 = 1, &
                               CANOPY_INT32 = 2, CANOPY_INT64 = 3
  integer(c_int), parameter :: CANOPY_EVERY_NODE = 0, CANOPY_LEAVES_ONLY = 1

  interface
    type(c_ptr) function canopy_last_error() bind(c)
      import :: c_ptr
    end function

    type(c_ptr) function canopy_options_create() bind(c)
      import :: c_ptr
    end function
    subroutine canopy_options_destroy(options) bind(c)
      import :: c_ptr
      type(c_ptr), value :: options
    end subroutine
    integer(c_int) function canopy_options_add_script(options, path) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*) :: path
    end function
    integer(c_int) function canopy_options_add_script_argument(options, argument) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*) :: argument
    end function
    integer(c_int) function canopy_options_set_output_directory(options, directory) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*) :: directory
    end function
    integer(c_int) function canopy_options_set_channel(options, channel) bind(c)
      import :: c_int, c_ptr, c_char
      type(c_ptr), value :: options
      character(kind=c_char), dimension(*) :: channel
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

    type(c_ptr) function canopy_forest_create(dimension, branch_factor, max_levels, x, &
                                              points_x, y, points_y, z, points_z) bind(c)
      import :: c_ptr, c_int, c_double, c_size_t
      integer(c_int), value :: dimension, branch_factor, max_levels
      real(c_double), dimension(*) :: x, y, z
      integer(c_size_t), value :: points_x, points_y, points_z
    end function
    subroutine canopy_forest_destroy(forest) bind(c)
      import :: c_ptr
      type(c_ptr), value :: forest
    end subroutine
    integer(c_int) function canopy_forest_clear(forest) bind(c)
      import :: c_int, c_ptr
      type(c_ptr), value :: forest
    end function
    ! masked and storage_slots: pass c_null_ptr when absent.
    integer(c_int) function canopy_forest_add_tree(forest, root_index, refinement, &
                                                   number_of_nodes, masked, storage_slots) bind(c)
      import :: c_int, c_ptr, c_int64_t, c_int8_t, c_size_t
      type(c_ptr), value :: forest
      integer(c_int64_t), value :: root_index
      integer(c_int8_t), dimension(*) :: refinement
      integer(c_size_t), value :: number_of_nodes
      type(c_ptr), value :: masked, storage_slots
    end function
    integer(c_int) function canopy_forest_add_field(forest, name, value_type, components, &
                                                    data, tuple_stride_bytes, number_of_tuples, &
                                                    centering) bind(c)
      import :: c_int, c_ptr, c_char, c_size_t
      type(c_ptr), value :: forest
      character(kind=c_char), dimension(*) :: name
      integer(c_int), value :: value_type, components, centering
      type(c_ptr), value :: data
      integer(c_size_t), value :: tuple_stride_bytes, number_of_tuples
    end function

    ! communicator: the integer handle (MPI_COMM_WORLD from `use mpi`, or comm%MPI_VAL).
    integer(c_int) function canopy_open_f(communicator, options, insitu) bind(c)
      import :: c_int, c_ptr
      integer(c_int), value :: communicator
      type(c_ptr), value :: options
      type(c_ptr) :: insitu
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
    integer(c_int) function canopy_close(insitu) bind(c)
      import :: c_int, c_ptr
      type(c_ptr) :: insitu
    end function
  end interface

contains

  !> The message of the last failing call, as a Fortran string.
  function canopy_last_error_message() result(message)
    character(len=:), allocatable :: message
    character(kind=c_char), pointer :: text(:)
    integer :: length
    interface
      integer(c_size_t) function strlen(s) bind(c)
        import :: c_size_t, c_ptr
        type(c_ptr), value :: s
      end function
    end interface
    length = int(strlen(canopy_last_error()))
    call c_f_pointer(canopy_last_error(), text, [length])
    allocate(character(len=length) :: message)
    message = transfer(text(1:length), message)
  end function

end module canopy
