! The MoR of two linear spring-dashpot spheres from the embedded default table, and
! the explicit exact fallback for an impact outside the table's box.
program lookup
  use, intrinsic :: iso_c_binding
  use emdstar_table
  implicit none
  type(c_ptr) :: table, pair, bad
  type(emdstar_mor) :: mor
  integer(c_int) :: st
  real(c_double), parameter :: pi = 3.14159265358979323846d0
  real(c_double) :: r, m

  table = emdstar_table_open_default(EMDSTAR_MODEL_LINEAR)
  if (.not. c_associated(table)) then
     print '(a)', 'open failed: ' // emdstar_last_error()
     stop 1
  end if
  r = 0.005d0
  m = 4d0 / 3d0 * pi * r**3 * 2500d0
  pair = emdstar_pair_linear(table, 1d5, 0.1d0, r, m, r, m)
  if (.not. c_associated(pair)) then
     print '(a)', 'pair failed: ' // emdstar_last_error()
     stop 1
  end if
  st = emdstar_pair_lookup(pair, 1d0, 0.5d0, EMDSTAR_NO_FALLBACK, mor)
  if (st /= EMDSTAR_STATUS_OK) then
     print '(a)', 'lookup failed: ' // emdstar_last_error()
     stop 1
  end if
  print '(a, es20.12)', 'eps_n = ', -mor%eps_rdot
  print '(a, es14.6, a)', 'duration = ', mor%eps_t * mor%time_scale, ' s'
  st = emdstar_pair_lookup(pair, 1d-5, 0d0, EMDSTAR_NO_FALLBACK, mor)
  print '(a, i0)', 'out of box: status ', st
  st = emdstar_pair_lookup(pair, 1d-5, 0d0, EMDSTAR_EXACT_FALLBACK, mor)
  print '(a, i0, a, i0, a, i0)', 'with fallback: status ', st, ', source ', mor%source, &
       ', fallbacks ', emdstar_pair_fallbacks(pair)
  call emdstar_pair_free(pair)
  call emdstar_table_close(table)
  bad = emdstar_table_open('/nonexistent/table.npz')
  print '(a, l1, a)', 'bad file is null: ', .not. c_associated(bad), ' (' // emdstar_last_error() // ')'
end program lookup
