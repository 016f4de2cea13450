//! Placeholder replaced by the S² work: parallel transport through the pole.
fn main() {}
