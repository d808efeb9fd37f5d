! Canopy's C API from Fortran through the canopy module (iso_c_binding): a 2x1
! forest whose first root is refined once, the selection pipeline on a value
! range, run on every rank (rank r owns root r; other ranks none). Checks the
! return codes, will_execute, error messages, and the extracts' content.
!
! Borrowed arrays are read in place: at step 2 the density values and an x
! coordinate are changed after canopy_forest_add_field (canopy_forest_create)
! and before canopy_execute, and each rank's piece of the step 2 extract must
! carry the changed values (selected cells, density, velocity and point
! ranges), its step 0 piece the original ones. A binding that kept a copy (or a temporary
! the compiler passed for an array argument) would show the old values.
! Usage: canopy_fortran_api_test SELECTION_SCRIPT OUTPUT_DIR
program fortran_api_test
  use iso_c_binding
  use mpi
  use canopy
  implicit none
  character(len=4096) :: script, output
  integer :: ierr, rank, size, failures, step, first
  type(c_ptr) :: options, insitu, forest
  real(c_double), target :: x(3) = [0d0, 1d0, 2d0], y(2) = [0d0, 1d0], z(1) = [0d0]
  integer(c_int8_t), target :: refined(5) = [1_c_int8_t, 0_c_int8_t, 0_c_int8_t, 0_c_int8_t, &
                                             0_c_int8_t], leaf(1) = [0_c_int8_t]
  ! Root 0: coarse value, then 4 leaves; root 1: one leaf.
  real(c_double), target :: density(6) = [0.5d0, 1d0, 2d0, 3d0, 4d0, 2.5d0]
  ! A two-component field, one array per component.
  real(c_double), target :: u(6) = [1d0, 2d0, 3d0, 4d0, 5d0, 6d0], v(6) = 0d0
  type(c_ptr) :: components(2)
  integer(c_int) :: will
  integer(c_size_t) :: nodes
  character(len=:), allocatable :: piece
  logical :: owns_root0, owns_root1

  failures = 0
  call mpi_init(ierr)
  call mpi_comm_rank(MPI_COMM_WORLD, rank, ierr)
  call mpi_comm_size(MPI_COMM_WORLD, size, ierr)
  call get_command_argument(1, script)
  call get_command_argument(2, output)
  owns_root0 = rank == 0
  owns_root1 = rank == mod(1, size)
  nodes = 0
  if (owns_root0) nodes = 5
  if (owns_root1) nodes = nodes + 1
  first = merge(1, 6, owns_root0)

  call check(canopy_options_create(options) == CANOPY_OK .and. c_associated(options), "options")
  call check(canopy_options_add_script_argument(options, "--x=1"//c_null_char) &
             == CANOPY_INVALID_ARGUMENT, "an argument before any script is refused")
  call check(index(canopy_last_error_message(), "add a script first") > 0, "and the message says so")
  call check(canopy_options_add_script(options, trim(script)//c_null_char) == CANOPY_OK, "script")
  ierr = canopy_options_add_script_argument(options, "--selection=range"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--value-field=density"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--value-range=1.5,3.5"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--frequency=2"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--fields=density,velocity"//c_null_char)
  call check(canopy_options_set_output_directory(options, trim(output)//c_null_char) == CANOPY_OK, &
             "output directory")
  call check(canopy_options_set_channel(options, "grid"//c_null_char) == CANOPY_OK, "channel")
  call check(canopy_options_set_verbosity(options, -10_c_int) == CANOPY_OK, "verbosity")
  call check(canopy_options_set_step_summary(options, 0_c_int) == CANOPY_OK, "step summary")
  call check(canopy_options_set_step_time_limit(options, 120.0_c_double) == CANOPY_OK, "time limit")
  call check(canopy_open_f(int(MPI_COMM_WORLD, c_int), options, insitu) == CANOPY_OK, "open")
  call canopy_options_destroy(options)

  call check(canopy_forest_create(2_c_int, 2_c_int, 8_c_int, c_loc(x), 3_c_size_t, c_loc(y), &
                                  2_c_size_t, c_loc(z), 1_c_size_t, forest) == CANOPY_OK &
             .and. c_associated(forest), "forest")
  ! Fortran's c_size_t is signed: a negative count is refused, not taken as huge.
  call check(canopy_forest_add_tree(forest, 0_c_int64_t, c_loc(refined), -5_c_size_t, &
                                    c_null_ptr, c_null_ptr) == CANOPY_INVALID_ARGUMENT, &
             "a negative number of nodes is refused")
  call check(index(canopy_last_error_message(), "is negative") > 0, "and the message says so")
  call check(canopy_forest_add_partial_tree(forest, -1_c_int64_t, c_loc(refined), 5_c_size_t, &
                                            c_null_ptr, c_null_ptr, c_null_ptr) &
             == CANOPY_INVALID_ARGUMENT, "a partial tree with a negative root is refused")

  do step = 0, 2
    call check(canopy_forest_clear(forest) == CANOPY_OK, "clear")
    if (owns_root0) then
      call check(canopy_forest_add_tree(forest, 0_c_int64_t, c_loc(refined), 5_c_size_t, &
                                        c_null_ptr, c_null_ptr) == CANOPY_OK, "root 0")
    end if
    if (owns_root1) then
      ! The whole tree is this rank's: no absent array.
      call check(canopy_forest_add_partial_tree(forest, 1_c_int64_t, c_loc(leaf), 1_c_size_t, &
                                                c_null_ptr, c_null_ptr, c_null_ptr) == CANOPY_OK, &
                 "root 1")
    end if
    if (nodes > 0) then
      call check(canopy_forest_add_field(forest, "density"//c_null_char, CANOPY_FLOAT64, 1_c_int, &
                                         c_loc(density(first)), 0_c_size_t, nodes, &
                                         CANOPY_EVERY_NODE) == CANOPY_OK, "density")
      components = [c_loc(u(first)), c_loc(v(first))]
    else
      call check(canopy_forest_add_field(forest, "density"//c_null_char, CANOPY_FLOAT64, 1_c_int, &
                                         c_null_ptr, 0_c_size_t, 0_c_size_t, CANOPY_EVERY_NODE) &
                 == CANOPY_OK, "density (no nodes)")
      components = [c_null_ptr, c_null_ptr]
    end if
    call check(canopy_forest_add_field_soa(forest, "velocity"//c_null_char, CANOPY_FLOAT64, &
                                           2_c_int, components, nodes, CANOPY_EVERY_NODE) &
               == CANOPY_OK, "velocity (one array per component)")
    if (step == 2) then
      ! After the calls that borrowed them, before the step reads them.
      density(3) = 1.75d0  ! a leaf of root 0, still selected
      density(5) = 3.25d0  ! a leaf of root 0, now selected
      x(3) = 3d0           ! root 1's right edge
      u(4) = 10d0          ! velocity of a selected leaf of root 0
    end if
    call check(canopy_will_execute(insitu, int(step, c_int64_t), 0.5d0 * step, will) == CANOPY_OK, &
               "will_execute")
    call check(will == merge(1, 0, mod(step, 2) == 0), "will_execute says whether it runs")
    call check(canopy_execute(insitu, int(step, c_int64_t), 0.5d0 * step, forest) == CANOPY_OK, &
               "execute")
  end do
  call check(canopy_close(insitu) == CANOPY_OK .and. .not. c_associated(insitu), "close")
  call canopy_forest_destroy(forest)

  ! Each rank's own piece. Selected: leaves in [1.5, 3.5]. Step 0: 2.0, 3.0 (root 0),
  ! 2.5 (root 1). Step 2: 1.75, 3.0, 3.25 (root 0), 2.5 (root 1), root 1 now 2 wide.
  if (owns_root0 .and. owns_root1) then
    piece = read_piece(0)
    call check(has(piece, 'NumberOfCells="3"'), "step 0: 3 cells")
    call check(has(piece, 'Name="density" format="binary" RangeMin="2" RangeMax="3"'), &
               "step 0: the original densities")
    call check(has(piece, 'RangeMax="2.236067977'), "step 0: the original points, up to (2, 1)")
    call check(has(piece, 'Name="velocity" NumberOfComponents="2" format="binary" RangeMin="3" &
                          &RangeMax="6"'), "step 0: the original velocities")
    piece = read_piece(2)
    call check(has(piece, 'NumberOfCells="4"'), "step 2: 4 cells, with the changed densities")
    call check(has(piece, 'Name="density" format="binary" RangeMin="1.75" RangeMax="3.25"'), &
               "step 2: the changed densities")
    call check(has(piece, 'RangeMax="3.162277660'), "step 2: the changed x, points up to (3, 1)")
  else if (owns_root0) then
    piece = read_piece(0)
    call check(has(piece, 'NumberOfCells="2"'), "step 0: 2 cells on rank 0")
    call check(has(piece, 'Name="density" format="binary" RangeMin="2" RangeMax="3"'), &
               "step 0: the original densities")
    call check(has(piece, 'Name="velocity" NumberOfComponents="2" format="binary" RangeMin="3" &
                          &RangeMax="4"'), "step 0: the original velocities")
    piece = read_piece(2)
    call check(has(piece, 'NumberOfCells="3"'), "step 2: 3 cells on rank 0, changed densities")
    call check(has(piece, 'Name="density" format="binary" RangeMin="1.75" RangeMax="3.25"'), &
               "step 2: the changed densities")
  else if (owns_root1) then
    piece = read_piece(0)
    call check(has(piece, 'NumberOfCells="1"'), "step 0: root 1's cell")
    call check(has(piece, 'RangeMax="2.236067977'), "step 0: the original points, up to (2, 1)")
    piece = read_piece(2)
    call check(has(piece, 'NumberOfCells="1"'), "step 2: root 1's cell")
    call check(has(piece, 'RangeMax="3.162277660'), "step 2: the changed x, points up to (3, 1)")
  end if
  if (owns_root0) then
    call check(has(piece, 'Name="velocity" NumberOfComponents="2" format="binary" RangeMin="3" &
                          &RangeMax="10"'), "step 2: the changed velocity (one array per component)")
  else if (owns_root1) then
    call check(has(piece, 'Name="velocity" NumberOfComponents="2" format="binary" RangeMin="6" &
                          &RangeMax="6"'), "step 2: root 1's velocity (one array per component)")
  end if
  ! The main program's variables are never deallocated for it (LeakSanitizer, in the
  ! sanitizer build, reports the last piece read otherwise).
  if (allocated(piece)) deallocate(piece)
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

  logical function has(text, words)
    character(len=*), intent(in) :: text, words
    has = index(text, words) > 0
  end function

  !> This rank's piece of selection_<step>.pvtu ("" if missing).
  function read_piece(at_step) result(text)
    integer, intent(in) :: at_step
    character(len=:), allocatable :: text
    character(len=4352) :: path
    integer :: unit, ios, length
    write(path, '(a,"/selection_",i6.6,"/selection_",i6.6,"_",i0,".vtu")') trim(output), &
      at_step, at_step, rank
    inquire(file=trim(path), size=length)
    if (length <= 0) then
      print '("missing: ",a)', trim(path)
      text = ''
      return
    end if
    allocate(character(len=length) :: text)
    open(newunit=unit, file=trim(path), access='stream', form='unformatted', status='old', &
         iostat=ios)
    if (ios == 0) read(unit, iostat=ios) text
    if (ios /= 0) text = ''
    close(unit)
  end function

end program fortran_api_test
