//! The integration test suite, one binary with a module per theme (one link
//! step instead of many on a small machine).

mod adaptive;
mod common;
mod enclosures;
mod hemicube;
mod substructuring;
