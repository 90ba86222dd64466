//! Procedural test scenes built in code, each with the exact answer it is checked against.

pub mod penumbra;
