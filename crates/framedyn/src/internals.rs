//! Internals that the core's own tests check directly: numerical kernels
//! (matrix functions, series, quadrature rules) and parsing helpers whose
//! properties are tested on their own, not only through the public API.
//!
//! Not public API: hidden from the documentation, no stability promise.
//! The tests live in the integration suite (`tests/suite/internals/`)
//! because a unit-test binary of the library would compile the whole core
//! a second time (docs/development.md, "Why the core has no unit-test binary").

pub use crate::dynamics::affine::inertia::{inverse as matrix_inverse, trace_of_product};
pub use crate::lie::matrix::algebra::skew_index;
pub use crate::lie::matrix::expm::{expm, PADE13, PADE3, PADE5, PADE7, PADE9};
pub use crate::lie::matrix::log_pade::{log1p_pade, GAUSS_LEGENDRE, LOG_THETA};
pub use crate::lie::matrix::logm::{logm_switch, LOG_DB_MAX_ARG, LOG_DB_MAX_COND};
pub use crate::lie::matrix::lu::{det, Lu};
pub use crate::lie::matrix::norm::{amax, norm1};
pub use crate::lie::matrix::schur::real_schur;
pub use crate::lie::matrix::Mat;
pub use crate::manifold::geodesic::gauss_kronrod::{gauss_kronrod, WG, WGK};
pub use crate::manifold::geodesic::torus2::{clairaut_integrals, Family, Shooter, Shot, Target, FINE_TOL};
pub use crate::scenes::locate::toml_key_at;
pub use crate::solve::adaptive::error_norm;

/// The truncated Taylor series of the coordinate charts (`coords`).
pub mod series {
    pub use crate::coords::series::{
        cos, cot_defect, dsinc, horner, sinc, sinc2_defect, sinccos_defect, versc, COS, COT_DEFECT, DSINC, SINC,
        SINC2_DEFECT, SINCCOS_DEFECT, VERSC,
    };
}
