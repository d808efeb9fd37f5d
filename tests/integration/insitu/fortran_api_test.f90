! Canopy's C API from Fortran through the canopy module (iso_c_binding): a 2x1
! forest whose first root is refined once, the selection pipeline on a value
! range, run on every rank (rank r owns root r; other ranks none). Checks the
! return codes, will_execute, an error message, and the extract's cell count.
! Usage: canopy_fortran_api_test SELECTION_SCRIPT OUTPUT_DIR
program fortran_api_test
  use iso_c_binding
  use mpi
  use canopy
  implicit none
  character(len=4096) :: script, output
  integer :: ierr, rank, size, failures, step, unit, ios
  type(c_ptr) :: options, insitu, forest
  real(c_double), target :: x(3) = [0d0, 1d0, 2d0], y(2) = [0d0, 1d0], z(1) = [0d0]
  integer(c_int8_t), target :: refined(5) = [1_c_int8_t, 0_c_int8_t, 0_c_int8_t, 0_c_int8_t, &
                                             0_c_int8_t], leaf(1) = [0_c_int8_t]
  ! Root 0: coarse value, then 4 leaves; root 1: one leaf.
  real(c_double), target :: density(6) = [0.5d0, 1d0, 2d0, 3d0, 4d0, 2.5d0]
  integer(c_int) :: will
  integer(c_size_t) :: nodes
  character(len=65536) :: text
  character(len=256) :: piece

  failures = 0
  call mpi_init(ierr)
  call mpi_comm_rank(MPI_COMM_WORLD, rank, ierr)
  call mpi_comm_size(MPI_COMM_WORLD, size, ierr)
  call get_command_argument(1, script)
  call get_command_argument(2, output)

  options = canopy_options_create()
  call check(canopy_options_add_script_argument(options, "--x=1"//c_null_char) &
             == CANOPY_INVALID_ARGUMENT, "an argument before any script is refused")
  call check(index(canopy_last_error_message(), "add a script first") > 0, "and the message says so")
  call check(canopy_options_add_script(options, trim(script)//c_null_char) == CANOPY_OK, "script")
  ierr = canopy_options_add_script_argument(options, "--selection=range"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--value-field=density"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--value-range=1.5,3.5"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--frequency=2"//c_null_char)
  call check(canopy_options_set_output_directory(options, trim(output)//c_null_char) == CANOPY_OK, &
             "output directory")
  call check(canopy_options_set_step_time_limit(options, 120.0_c_double) == CANOPY_OK, "time limit")
  insitu = c_null_ptr
  call check(canopy_open_f(int(MPI_COMM_WORLD, c_int), options, insitu) == CANOPY_OK, "open")
  call canopy_options_destroy(options)

  forest = canopy_forest_create(2_c_int, 2_c_int, 8_c_int, x, 3_c_size_t, y, 2_c_size_t, z, &
                                1_c_size_t)
  do step = 0, 2
    ierr = canopy_forest_clear(forest)
    nodes = 0
    if (rank == 0) then
      ierr = canopy_forest_add_tree(forest, 0_c_int64_t, refined, 5_c_size_t, c_null_ptr, &
                                    c_null_ptr)
      nodes = 5
    end if
    if (rank == mod(1, size)) then
      ierr = canopy_forest_add_tree(forest, 1_c_int64_t, leaf, 1_c_size_t, c_null_ptr, c_null_ptr)
      nodes = nodes + 1
    end if
    if (rank == 0) then
      ierr = canopy_forest_add_field(forest, "density"//c_null_char, CANOPY_FLOAT64, 1_c_int, &
                                     c_loc(density(1)), 0_c_size_t, nodes, CANOPY_EVERY_NODE)
    else if (nodes > 0) then
      ierr = canopy_forest_add_field(forest, "density"//c_null_char, CANOPY_FLOAT64, 1_c_int, &
                                     c_loc(density(6)), 0_c_size_t, nodes, CANOPY_EVERY_NODE)
    else
      ierr = canopy_forest_add_field(forest, "density"//c_null_char, CANOPY_FLOAT64, 1_c_int, &
                                     c_null_ptr, 0_c_size_t, 0_c_size_t, CANOPY_EVERY_NODE)
    end if
    call check(canopy_will_execute(insitu, int(step, c_int64_t), 0.5d0 * step, will) == CANOPY_OK, &
               "will_execute")
    call check(will == merge(1, 0, mod(step, 2) == 0), "will_execute says whether it runs")
    call check(canopy_execute(insitu, int(step, c_int64_t), 0.5d0 * step, forest) == CANOPY_OK, &
               "execute")
  end do
  call check(canopy_close(insitu) == CANOPY_OK .and. .not. c_associated(insitu), "close")
  call canopy_forest_destroy(forest)

  ! Leaves 2.0, 3.0 (root 0) and 2.5 (root 1) are in [1.5, 3.5]: rank 0's piece
  ! holds 2 or 3 of them (3 when it owns both roots).
  if (rank == 0) then
    write(piece, '(a,"/selection_000002/selection_000002_0.vtu")') trim(output)
    open(newunit=unit, file=trim(piece), access='stream', form='unformatted', iostat=ios)
    call check(ios == 0, "rank 0's piece of the step 2 selection exists")
    text = ''
    if (ios == 0) then
      read(unit, iostat=ios) text
      close(unit)
    end if
    if (size == 1) then
      call check(index(text, 'NumberOfCells="3"') > 0, "3 cells selected")
    else
      call check(index(text, 'NumberOfCells="2"') > 0, "2 cells selected on rank 0")
    end if
  end if
  call mpi_finalize(ierr)
  if (failures > 0) stop 1

contains

  subroutine check(condition, message)
    logical, intent(in) :: condition
    character(len=*), intent(in) :: message
    if (condition) then
      print '("ok: ",a)', message
    else
      print '("FAILED: ",a,": ",a)', message, canopy_last_error_message()
      failures = failures + 1
    end if
  end subroutine

end program fortran_api_test
