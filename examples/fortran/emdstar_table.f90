! Fortran bindings (iso_c_binding) to the C ABI of the emdstar matrix-of-restitution
! table reader, crates/table-capi/include/emdstar_table.h.
!
! Build (after `cargo build --release -p emdstar-table-capi`):
!   gfortran examples/fortran/emdstar_table.f90 examples/fortran/lookup.f90 \
!       target/release/libemdstar_table_c.a -lpthread -ldl -lm -o lookup_f
module emdstar_table
  use, intrinsic :: iso_c_binding
  implicit none
  private

  integer(c_int), parameter, public :: EMDSTAR_MODEL_LINEAR = 0, EMDSTAR_MODEL_HERTZ = 1
  integer(c_int), parameter, public :: EMDSTAR_STATUS_OK = 0, EMDSTAR_STATUS_OUT_OF_BOX = 1, &
       EMDSTAR_STATUS_NOT_TABULATED = 2, EMDSTAR_STATUS_INVALID_INPUT = 3, &
       EMDSTAR_STATUS_WRONG_MODEL = 4, EMDSTAR_STATUS_BAD_FILE = 5, &
       EMDSTAR_STATUS_SOLVE_FAILED = 6
  integer(c_int), parameter, public :: EMDSTAR_NO_FALLBACK = 0, EMDSTAR_EXACT_FALLBACK = 1

  !> The matrix of restitution of one impact (EmdstarMor).
  type, bind(c), public :: emdstar_mor
     real(c_double) :: eps_r, one_minus_eps_r, eps_rdot, eps_phi, eps_t, time_scale
     integer(c_int) :: source
  end type emdstar_mor

  public :: emdstar_table_open, emdstar_table_open_default, emdstar_table_close
  public :: emdstar_pair_linear, emdstar_pair_hertz, emdstar_pair_free
  public :: emdstar_pair_lookup, emdstar_pair_fallbacks, emdstar_last_error

  interface
     type(c_ptr) function emdstar_table_open_c(path) bind(c, name="emdstar_table_open")
       import :: c_ptr, c_char
       character(kind=c_char), dimension(*), intent(in) :: path
     end function emdstar_table_open_c

     type(c_ptr) function emdstar_table_open_default(model) &
          bind(c, name="emdstar_table_open_default")
       import :: c_ptr, c_int
       integer(c_int), value :: model
     end function emdstar_table_open_default

     subroutine emdstar_table_close(table) bind(c, name="emdstar_table_close")
       import :: c_ptr
       type(c_ptr), value :: table
     end subroutine emdstar_table_close

     type(c_ptr) function emdstar_pair_linear(table, stiffness, damping, r1, m1, r2, m2) &
          bind(c, name="emdstar_pair_linear")
       import :: c_ptr, c_double
       type(c_ptr), value :: table
       real(c_double), value :: stiffness, damping, r1, m1, r2, m2
     end function emdstar_pair_linear

     type(c_ptr) function emdstar_pair_hertz(table, young, poisson, dissipation, &
          r1, m1, r2, m2) bind(c, name="emdstar_pair_hertz")
       import :: c_ptr, c_double
       type(c_ptr), value :: table
       real(c_double), value :: young, poisson, dissipation, r1, m1, r2, m2
     end function emdstar_pair_hertz

     subroutine emdstar_pair_free(pair) bind(c, name="emdstar_pair_free")
       import :: c_ptr
       type(c_ptr), value :: pair
     end subroutine emdstar_pair_free

     integer(c_int) function emdstar_pair_lookup(pair, normal_speed, tangential_speed, &
          exact_fallback, mor) bind(c, name="emdstar_pair_lookup")
       import :: c_ptr, c_double, c_int, emdstar_mor
       type(c_ptr), value :: pair
       real(c_double), value :: normal_speed, tangential_speed
       integer(c_int), value :: exact_fallback
       type(emdstar_mor), intent(out) :: mor
     end function emdstar_pair_lookup

     integer(c_int64_t) function emdstar_pair_fallbacks(pair) &
          bind(c, name="emdstar_pair_fallbacks")
       import :: c_ptr, c_int64_t
       type(c_ptr), value :: pair
     end function emdstar_pair_fallbacks

     type(c_ptr) function emdstar_last_error_c() bind(c, name="emdstar_table_last_error")
       import :: c_ptr
     end function emdstar_last_error_c
  end interface

contains

  !> Opens a table file; c_null_ptr on failure (see emdstar_last_error).
  type(c_ptr) function emdstar_table_open(path)
    character(len=*), intent(in) :: path
    emdstar_table_open = emdstar_table_open_c(trim(path) // c_null_char)
  end function emdstar_table_open

  !> The last error message of this thread.
  function emdstar_last_error() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char), pointer :: chars(:)
    type(c_ptr) :: p
    integer :: n
    p = emdstar_last_error_c()
    call c_f_pointer(p, chars, [4096])
    n = 0
    do while (n < 4096)
       if (chars(n + 1) == c_null_char) exit
       n = n + 1
    end do
    allocate(character(len=n) :: msg)
    msg = transfer(chars(1:n), msg)
  end function emdstar_last_error

end module emdstar_table
