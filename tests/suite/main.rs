//! The integration test suite, one binary with a module per theme (one link
//! step instead of many on a small machine).

mod common;
mod enclosures;
mod hemicube;
mod progressive;
mod substructuring;
