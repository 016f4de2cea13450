//! Tests of `crates/framedyn/src/lie/matrix/algebra.rs` (through `framedyn::__internals` where it is not public API).
use framedyn::__internals::skew_index;

#[test]
fn skew_index_enumerates_upper_triangle() {
    let got: Vec<_> = (0..6).map(skew_index::<4>).collect();
    assert_eq!(got, vec![(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]);
}
