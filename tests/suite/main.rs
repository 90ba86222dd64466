//! The integration test suite, one binary with a module per theme (one link
//! step instead of many on a small machine).

mod common;
mod enclosures;
mod hemicube;
mod penumbra;
mod penumbra_failure;
mod penumbra_golden;
mod penumbra_metrics;
mod probe;
mod substructuring;
