//! Tests of the core's internals (numerical kernels, parsing helpers), through
//! the hidden `framedyn::__internals` module: the library has no unit-test
//! binary of its own, which would compile the whole core a second time
//! (docs/development.md, "Why the core has no unit-test binary").

mod affine_inertia;
mod body;
mod coords_series;
mod gauss_kronrod;
mod matrix_algebra;
mod matrix_expm;
mod matrix_log_pade;
mod matrix_logm;
mod matrix_lu;
mod matrix_schur;
mod potential;
mod scene_locate;
mod scene_spec;
mod scene_summary;
mod special;
mod torus_geodesic;

/// Uniform pseudo-random numbers in [−1, 1) (xorshift64), for the suite.
pub(crate) fn xorshift(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}
