! A block forest from Fortran through the canopy module: a 2D forest (xy-plane) of
! 2x2 roots, root 0 refined once, every leaf a block of 4x4 cells with 2 ghost
! cells per side, rank r owning the roots with mod(root, size) == r. The fields,
! the ways Fortran codes keep blocks:
!   density   one allocatable array per block, blk(b)%rho(i, j), from
!             canopy_forest_add_block_field with c_loc of each block;
!   pressure, velocity   FLASH's unk(var, i, j, 1, block) with room for MAXBLOCKS
!             blocks: variable 1, and variables 2-3 as a 2-component field, from
!             canopy_forest_add_block_field_array (strides of all 3 variables);
!   magnetic  bx(i, j, block) and by(i, j, block) as 2 float components, from
!             canopy_forest_add_block_field_components with addresses(block, comp).
! Strides come from canopy_block_strides_packed. The selection pipeline selects
! every leaf (a value range on density); each rank decodes its own piece of the
! extract (base64) and checks every cell's values against the arrays, found from
! the cell's position: step 0 with the blocks in their default order, step 1 in
! the reverse order (canopy_forest_add_block_tree's 0-based block_index) and with
! values changed after the fields were added (borrowed arrays are read then).
! Also: refusals with their messages, and a failed step (a block field with too few
! blocks) that names the problem.
! Usage: canopy_fortran_api_blocks_test SELECTION_SCRIPT OUTPUT_DIR
program fortran_api_blocks_test
  use iso_c_binding
  use mpi
  use canopy
  implicit none
  integer, parameter :: n = 4, g = 2, e = n + 2 * g, nvar = 3, maxblocks = 8, roots = 4
  type :: block_t
    real(c_double), allocatable :: rho(:, :)
  end type
  character(len=4096) :: script, output
  integer :: ierr, rank, ranks, failures, step, r, b, i, j, nodes
  type(c_ptr) :: options, insitu, forest
  real(c_double), target :: x(3) = [0d0, 1d0, 2d0], y(3) = [0d0, 1d0, 3d0], z(1) = [0.5d0]
  integer(c_int8_t), target :: refined(5) = [1_c_int8_t, 0_c_int8_t, 0_c_int8_t, 0_c_int8_t, &
                                             0_c_int8_t], leaf(1) = [0_c_int8_t]
  integer(c_int64_t), target :: reversed(5, roots)
  type(block_t), allocatable, target :: blk(:)
  real(c_double), allocatable, target :: unk(:, :, :, :, :)
  real(c_float), allocatable, target :: bx(:, :, :), by(:, :, :)
  type(c_ptr), allocatable :: addresses(:), component_addresses(:, :), holes(:)
  type(canopy_block_strides) :: strides, unk_strides, float_strides
  integer(c_size_t) :: block_bytes
  logical :: owned(0:roots - 1)
  integer :: first_block(0:roots - 1), blocks

  failures = 0
  call mpi_init(ierr)
  call mpi_comm_rank(MPI_COMM_WORLD, rank, ierr)
  call mpi_comm_size(MPI_COMM_WORLD, ranks, ierr)
  call get_command_argument(1, script)
  call get_command_argument(2, output)

  ! Blocks in the default order: present leaves breadth-first, tree by tree.
  blocks = 0
  do r = 0, roots - 1
    owned(r) = mod(r, ranks) == rank
    first_block(r) = blocks
    if (owned(r)) blocks = blocks + merge(4, 1, r == 0)
  end do
  ! The reverse order, 0-based (entries of refined nodes ignored).
  reversed = -1
  do r = 0, roots - 1
    if (r == 0) then
      do i = 2, 5
        reversed(i, 1) = blocks - 1 - (first_block(0) + i - 2)
      end do
    else
      reversed(1, r + 1) = blocks - 1 - first_block(r)
    end if
  end do
  call fill()

  call check(canopy_options_create(options) == CANOPY_OK, "options")
  call check(canopy_options_add_script(options, trim(script)//c_null_char) == CANOPY_OK, "script")
  ierr = canopy_options_add_script_argument(options, "--selection=range"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--value-field=density"//c_null_char)
  ierr = canopy_options_add_script_argument(options, "--value-range=0,1e9"//c_null_char)
  ierr = canopy_options_set_output_directory(options, trim(output)//c_null_char)
  ierr = canopy_options_set_step_time_limit(options, 120.0_c_double)
  call check(canopy_open_f(int(MPI_COMM_WORLD, c_int), options, insitu) == CANOPY_OK, "open")
  call canopy_options_destroy(options)

  ! 2 levels of trees and 2 inside blocks of 4 cells across.
  call check(canopy_forest_create(2_c_int, 2_c_int, 4_c_int, c_loc(x), 3_c_size_t, c_loc(y), &
                                  3_c_size_t, c_loc(z), 1_c_size_t, forest) == CANOPY_OK, "forest")
  call check(canopy_forest_set_blocks(forest, 6_c_int) == CANOPY_INVALID_ARGUMENT, &
             "6 cells per side refused")
  call check(has(canopy_last_error_message(), "power of the branch factor 2"), &
             "not a power of the branch factor 2")
  call check(canopy_forest_set_blocks(forest, int(n, c_int)) == CANOPY_OK, "blocks of 4x4 cells")

  ! density: rho(i, j) of each block, [j][i] in C: variable outermost, one component.
  call check(canopy_block_strides_packed(2_c_int, int(n, c_int), int(g, c_int), 1_c_int, &
                                         CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, strides, &
                                         block_bytes) == CANOPY_OK, "strides of rho(i, j)")
  call check(all(strides%cell_bytes == [8_c_size_t, 64_c_size_t, 0_c_size_t]) .and. &
             all(strides%ghost_cells == [2, 2, 0]) .and. block_bytes == 512, &
             "rho(i, j): 8 bytes along i, 64 along j, 2 ghosts, 512 bytes a block")
  ! unk(var, i, j, 1, block): variable innermost, all nvar variables.
  call check(canopy_block_strides_packed(2_c_int, int(n, c_int), int(g, c_int), int(nvar, c_int), &
                                         CANOPY_FLOAT64, CANOPY_VARIABLE_INNERMOST, unk_strides, &
                                         block_bytes) == CANOPY_OK, "strides of unk")
  call check(block_bytes == 8 * size(unk(:, :, :, :, 1)) .and. &
             unk_strides%component_bytes == 8 .and. unk_strides%cell_bytes(1) == 8 * nvar, &
             "unk's strides: a whole unk(:, :, :, :, b) per block, variables 8 bytes apart")
  call check(canopy_block_strides_packed(2_c_int, int(n, c_int), int(g, c_int), 1_c_int, &
                                         CANOPY_FLOAT32, CANOPY_VARIABLE_OUTERMOST, float_strides, &
                                         block_bytes) == CANOPY_OK, "strides of bx(i, j, b)")
  call check(canopy_block_strides_packed(4_c_int, int(n, c_int), int(g, c_int), 1_c_int, &
                                         CANOPY_FLOAT32, CANOPY_VARIABLE_OUTERMOST, strides, &
                                         block_bytes) == CANOPY_INVALID_ARGUMENT, &
             "strides_packed refuses dimension 4")
  call check(has(canopy_last_error_message(), "dimension must be 1, 2 or 3, got 4"), "saying why")
  call check(all(strides%cell_bytes == [8_c_size_t, 64_c_size_t, 0_c_size_t]) .and. &
             all(strides%ghost_cells == [2, 2, 0]) .and. block_bytes == 256, &
             "and leaving strides and block_bytes as they were")

  do step = 0, 1
    call describe(step == 1)
    if (step == 1 .and. blocks > 0) then
      ! After the calls that borrowed them, before the step reads them.
      blk(1)%rho(g + 2, g + 3) = 0.5d0
      unk(3, g + 4, g + 1, 1, blocks) = -42d0
      bx(g + 1, g + 4, blocks) = 7.75
    end if
    call check(canopy_execute(insitu, int(step, c_int64_t), 0.5d0 * step, forest) == CANOPY_OK, &
               "execute")
    call check_piece(step, step == 1)
  end do

  ! Too few blocks on rank 0: every rank skips the step, rank 0 says why.
  call describe(.false.)
  if (rank == 0) then
    allocate(addresses(1))
    addresses(1) = c_loc(blk(1)%rho)
    ! strides: still rho's (describe's), the refused call above changed nothing.
    call check(canopy_forest_add_block_field(forest, "short"//c_null_char, CANOPY_FLOAT64, &
                                             1_c_int, addresses, 1_c_size_t, strides) &
               == CANOPY_OK, "a field of 1 block (the forest has more)")
    deallocate(addresses)
  end if
  call check(canopy_execute(insitu, 2_c_int64_t, 1d0, forest) == CANOPY_STEP_FAILED, &
             "too few blocks fail the step")
  if (rank == 0) call check(has(canopy_last_error_message(), &
                                "'short': 1 blocks given but the forest has"), "saying why")

  call check(canopy_close(insitu) == CANOPY_OK, "close")
  call canopy_forest_destroy(forest)
  deallocate(blk, unk, bx, by)
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

  !> Every array: interior cells a value naming block entry, cell and variable;
  !> ghost cells -1e6, which no check expects.
  subroutine fill()
    integer :: k, v
    real(c_double) :: code
    allocate(blk(max(blocks, 1)), unk(nvar, e, e, 1, maxblocks), bx(e, e, max(blocks, 1)), &
             by(e, e, max(blocks, 1)))
    unk = -1d6
    bx = -1e6
    by = -1e6
    do k = 1, blocks
      allocate(blk(k)%rho(e, e))
      blk(k)%rho = -1d6
      do j = 0, n - 1
        do i = 0, n - 1
          code = 1 + i + 10 * j + 1000 * k + 100000 * rank
          blk(k)%rho(g + 1 + i, g + 1 + j) = code
          do v = 1, nvar
            unk(v, g + 1 + i, g + 1 + j, 1, k) = code + 0.25d0 * v
          end do
          bx(g + 1 + i, g + 1 + j, k) = real(-code - 0.125d0, c_float)
          by(g + 1 + i, g + 1 + j, k) = real(-code - 0.375d0, c_float)
        end do
      end do
    end do
  end subroutine

  !> The trees (reverse: with the reversed block order) and the four fields;
  !> refused calls in between must change nothing.
  subroutine describe(reverse)
    logical, intent(in) :: reverse
    integer :: k
    call check(canopy_forest_clear(forest) == CANOPY_OK, "clear")
    do r = 0, roots - 1
      if (.not. owned(r)) cycle
      nodes = merge(5, 1, r == 0)
      if (reverse) then
        call check(canopy_forest_add_block_tree(forest, int(r, c_int64_t), &
                                                merge(c_loc(refined), c_loc(leaf), r == 0), &
                                                int(nodes, c_size_t), c_null_ptr, c_null_ptr, &
                                                c_loc(reversed(1, r + 1))) == CANOPY_OK, &
                   "a block tree with its block_index")
      else
        call check(canopy_forest_add_tree(forest, int(r, c_int64_t), &
                                          merge(c_loc(refined), c_loc(leaf), r == 0), &
                                          int(nodes, c_size_t), c_null_ptr, c_null_ptr) &
                   == CANOPY_OK, "a tree of the block forest")
      end if
    end do
    allocate(addresses(max(blocks, 1)), component_addresses(max(blocks, 1), 2), &
             holes(max(blocks, 1)))
    do k = 1, blocks
      addresses(k) = c_loc(blk(k)%rho)
      component_addresses(k, 1) = c_loc(bx(1, 1, k))
      component_addresses(k, 2) = c_loc(by(1, 1, k))
    end do
    holes = c_null_ptr
    ierr = canopy_block_strides_packed(2_c_int, int(n, c_int), int(g, c_int), 1_c_int, &
                                       CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, strides, &
                                       block_bytes)
    if (blocks > 0) then
      call check(canopy_forest_add_block_field(forest, "density"//c_null_char, CANOPY_FLOAT64, &
                                               1_c_int, holes, int(blocks, c_size_t), strides) &
                 == CANOPY_INVALID_ARGUMENT, "a table of null addresses refused")
      call check(has(canopy_last_error_message(), "block_addresses[0] (block 0) is NULL"), &
                 "naming the first")
    end if
    call check(canopy_forest_add_block_field(forest, "density"//c_null_char, CANOPY_FLOAT64, &
                                             1_c_int, addresses, int(blocks, c_size_t), strides) &
               == CANOPY_OK, "density: c_loc of each block's array")
    ierr = canopy_block_strides_packed(2_c_int, int(n, c_int), int(g, c_int), int(nvar, c_int), &
                                       CANOPY_FLOAT64, CANOPY_VARIABLE_INNERMOST, unk_strides, &
                                       block_bytes)
    call check(canopy_forest_add_block_field_array(forest, "pressure"//c_null_char, &
                                                   CANOPY_FLOAT64, 1_c_int, &
                                                   c_loc(unk(1, 1, 1, 1, 1)), &
                                                   block_bytes, int(maxblocks, c_size_t), &
                                                   unk_strides) == CANOPY_OK, &
               "pressure: unk's variable 1, MAXBLOCKS blocks")
    call check(canopy_forest_add_block_field_array(forest, "velocity"//c_null_char, &
                                                   CANOPY_FLOAT64, 2_c_int, &
                                                   c_loc(unk(2, 1, 1, 1, 1)), &
                                                   block_bytes, int(maxblocks, c_size_t), &
                                                   unk_strides) == CANOPY_OK, &
               "velocity: unk's variables 2 and 3")
    call check(canopy_forest_add_block_field_components(forest, "magnetic"//c_null_char, &
                                                        CANOPY_FLOAT32, 2_c_int, &
                                                        component_addresses, &
                                                        int(blocks, c_size_t), float_strides) &
               == CANOPY_OK, "magnetic: bx and by, addresses(block, component)")
    call check(canopy_forest_add_field(forest, "density"//c_null_char, CANOPY_FLOAT64, 1_c_int, &
                                       c_loc(unk), 0_c_size_t, 1_c_size_t, CANOPY_LEAVES_ONLY) &
               == CANOPY_INVALID_ARGUMENT, "a field of tuples refused in a block forest")
    deallocate(addresses, component_addresses, holes)
  end subroutine

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

  !> The values of the DataArray named `name` (inline binary: base64 of a UInt64
  !> byte count, then the values) as doubles; empty when missing.
  function decode(text, name) result(values)
    character(len=*), intent(in) :: text, name
    real(c_double), allocatable :: values(:)
    character(len=*), parameter :: alphabet = &
      'ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/'
    character(len=:), allocatable :: bytes
    integer :: at, start, finish, p, v, held, count, length, size_of
    integer(c_int64_t) :: bits, payload
    character(len=7) :: kind
    allocate(values(0))
    at = index(text, 'Name="'//name//'"')
    if (at == 0) return
    start = index(text(1:at), '<DataArray', back=.true.)
    p = index(text(start:), 'type="')
    kind = text(start + p + 5:start + p + 11)
    start = at + index(text(at:), '>')
    finish = start + index(text(start:), '<') - 2
    allocate(character(len=(finish - start + 1) * 3 / 4 + 3) :: bytes)
    bits = 0
    held = 0
    length = 0
    do p = start, finish
      v = index(alphabet, text(p:p)) - 1
      if (v < 0) cycle  ! white space, padding
      bits = ior(ishft(bits, 6), int(v, c_int64_t))
      held = held + 6
      if (held >= 8) then
        held = held - 8
        length = length + 1
        bytes(length:length) = achar(iand(ishft(bits, -held), 255_c_int64_t))
        bits = iand(bits, ishft(1_c_int64_t, held) - 1)
      end if
    end do
    if (length < 8) return
    payload = transfer(bytes(1:8), payload)
    size_of = merge(4, 8, kind == 'Float32')
    count = int(payload) / size_of
    if (8 + count * size_of > length) return
    deallocate(values)
    if (kind == 'Float32') then
      values = real(transfer(bytes(9:8 + count * 4), 0.0_c_float, count), c_double)
    else if (kind == 'Float64') then
      values = transfer(bytes(9:8 + count * 8), 0.0_c_double, count)
    else
      values = real(transfer(bytes(9:8 + count * 8), 0_c_int64_t, count), c_double)
    end if
  end function

  !> Every cell of this rank's piece of the step against the arrays.
  subroutine check_piece(at_step, reverse)
    integer, intent(in) :: at_step
    logical, intent(in) :: reverse
    character(len=:), allocatable :: text
    real(c_double), allocatable :: points(:), connectivity(:), offsets(:), density(:), &
                                   pressure(:), velocity(:), magnetic(:)
    real(c_double) :: low(2), high(2), u(2), width, expected(6), got(6)
    integer :: c, v, a, from, point, root(2), root_index, levels, cell(2), entry, child, &
               bad_position, bad_value, cells, k
    logical :: seen(max(blocks, 1) * n * n)
    character(len=160) :: label
    real(c_double), pointer :: axis(:)
    text = read_piece(at_step)
    write(label, '("step ",i0,": rank ",i0,"''s piece of the extract is written")') at_step, rank
    call check(len(text) > 0, trim(label))
    if (len(text) == 0) return
    points = decode(text, "Points")
    connectivity = decode(text, "connectivity")
    offsets = decode(text, "offsets")
    density = decode(text, "density")
    pressure = decode(text, "pressure")
    velocity = decode(text, "velocity")
    magnetic = decode(text, "magnetic")
    cells = size(offsets)
    write(label, '("step ",i0,": ",i0," cells, every block cell of the ",i0," blocks")') &
      at_step, cells, blocks
    call check(cells == blocks * n * n, trim(label))
    write(label, '("step ",i0,": every field has its values")') at_step
    call check(size(density) == cells .and. size(pressure) == cells .and. &
               size(velocity) == 2 * cells .and. size(magnetic) == 2 * cells, trim(label))
    if (size(density) /= cells .or. size(pressure) /= cells .or. size(velocity) /= 2 * cells &
        .or. size(magnetic) /= 2 * cells) cells = 0
    bad_position = 0
    bad_value = 0
    seen = .false.
    do c = 1, cells
      low = huge(1d0)
      high = -huge(1d0)
      from = 1
      if (c > 1) from = int(offsets(c - 1)) + 1
      do v = from, int(offsets(c))
        point = int(connectivity(v))
        low = min(low, points(3 * point + 1:3 * point + 2))
        high = max(high, points(3 * point + 1:3 * point + 2))
      end do
      ! The root, then root 0's child, then the cell within the block.
      do a = 1, 2
        if (a == 1) then
          axis => x
        else
          axis => y
        end if
        root(a) = merge(1, 0, 0.5d0 * (low(a) + high(a)) > axis(2))
        u(a) = (0.5d0 * (low(a) + high(a)) - axis(root(a) + 1)) / &
               (axis(root(a) + 2) - axis(root(a) + 1))
      end do
      root_index = root(1) + 2 * root(2)
      if (.not. owned(root_index)) then
        bad_position = bad_position + 1
        cycle
      end if
      levels = merge(2, 1, root_index == 0)
      child = 0
      if (root_index == 0) then
        do a = 1, 2
          k = merge(1, 0, u(a) >= 0.5d0)
          child = child + k * 2**(a - 1)
          u(a) = 2 * u(a) - k
        end do
      end if
      do a = 1, 2
        if (a == 1) then
          axis => x
        else
          axis => y
        end if
        width = (axis(root(a) + 2) - axis(root(a) + 1)) / (levels * n)
        cell(a) = int(u(a) * n)
        if (abs(high(a) - low(a) - width) > 1d-12 .or. cell(a) < 0 .or. cell(a) >= n) &
          bad_position = bad_position + 1
      end do
      entry = first_block(root_index) + child
      if (reverse) entry = blocks - 1 - entry
      if (entry < 0 .or. entry >= blocks .or. cell(1) < 0 .or. cell(1) >= n .or. cell(2) < 0 &
          .or. cell(2) >= n) cycle
      k = entry * n * n + cell(2) * n + cell(1) + 1
      if (seen(k)) bad_position = bad_position + 1
      seen(k) = .true.
      i = g + 1 + cell(1)
      j = g + 1 + cell(2)
      b = entry + 1
      expected = [blk(b)%rho(i, j), unk(1, i, j, 1, b), unk(2, i, j, 1, b), unk(3, i, j, 1, b), &
                  real(bx(i, j, b), c_double), real(by(i, j, b), c_double)]
      got = [density(c), pressure(c), velocity(2 * c - 1), velocity(2 * c), magnetic(2 * c - 1), &
             magnetic(2 * c)]
      do v = 1, 6
        if (got(v) /= expected(v)) then
          bad_value = bad_value + 1
          if (bad_value <= 5) print '("  step ",i0," rank ",i0,": block ",i0," cell (",i0,", ", &
                                     &i0,"): value ",i0," is ",g0,", the array has ",g0)', &
            at_step, rank, entry, cell(1), cell(2), v, got(v), expected(v)
        end if
      end do
    end do
    write(label, '("step ",i0,": every cell is a block cell of this rank, once")') at_step
    call check(bad_position == 0, trim(label))
    write(label, '("step ",i0,": every value of every field is the array''s (block order ",a,")")') &
      at_step, trim(merge('reversed', 'default ', reverse))
    call check(bad_value == 0, trim(label))
    ! The main program's variables are never deallocated for it (LeakSanitizer).
    deallocate(text)
  end subroutine

end program fortran_api_blocks_test
