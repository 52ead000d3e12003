//! Tests of the matrix-of-restitution solver against independent references.

mod common;
mod explore;
