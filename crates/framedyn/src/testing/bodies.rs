//! The affine bodies' parameters and internal initial state, shared by the
//! affine problems on S² and T² ([`s2_affine`](super::s2_affine),
//! [`t2_affine`](super::t2_affine), [`s2_tilted_affine`](super::s2_tilted_affine))
//! and, for the inertia, by every affine problem.

use nalgebra::{Matrix2, Vector2};

/// The affine bodies' inertia `J` (anisotropic, with an off-diagonal term, so
/// that no internal motion is trivially decoupled).
pub const AFFINE_INERTIA: Matrix2<f64> = Matrix2::new(0.3, 0.07, 0.07, 0.15);

/// The internal configuration `ρ₀` (det ρ₀ = 0.94: a sheared, stretched body).
pub const AFFINE_RHO0: Matrix2<f64> = Matrix2::new(1.1, 0.3, -0.2, 0.8);

/// The velocity components `u₀` in the parallel frame.
pub const AFFINE_U0: Vector2<f64> = Vector2::new(0.6, -0.9);

/// The internal velocity `ρ̇₀`.
pub const AFFINE_RHO_DOT0: Matrix2<f64> = Matrix2::new(0.4, -0.6, 0.5, 0.2);
