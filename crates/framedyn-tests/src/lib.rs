//! The framedyn core's integration suite (`tests/suite`), examples
//! (`examples/`) and criterion benchmark (`benches/step_cost.rs`), as
//! targets of an unpublished crate. See `crates/framedyn-tests/Cargo.toml`.
