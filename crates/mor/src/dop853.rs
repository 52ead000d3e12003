//! Dormand–Prince 8(5,3) integrator (being implemented).
