//! Tests of the matrix-of-restitution solver against independent references.

mod acceptance;
mod analytic;
mod common;
mod inverse;
mod oracle;
mod tolerance;
