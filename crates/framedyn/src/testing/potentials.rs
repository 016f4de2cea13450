//! The small potentials of the reference problems: a uniform field and the
//! axial tilt with a frame coupling. Both are written once here, generic over
//! the dimensions, so that every problem, bench and test evaluates the same
//! expression (with the same floating-point operations).

use nalgebra::{SMatrix, SVector};

use crate::potential::{Potential, Scalar};

/// `V = a·x₂`: a uniform field along the ambient axis 2 (z in ℝ³ and
/// ℝ^{2,1}).
///
/// On S², H² and T² it is invariant under the rotations about the z axis,
/// so `p_φ` is conserved; on the torus the z axis is the symmetry axis, the
/// only one it has. A position-only potential ([`Potential::uses_frame`] is
/// `false`): the internal rotation of a gyroscope is free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformField {
    /// Field strength `a` (energy per unit length along z).
    pub a: f64,
}

impl<const N: usize, const E: usize> Potential<N, E> for UniformField {
    fn uses_frame(&self) -> bool {
        false
    }
    fn value<D: Scalar>(&self, x: &SVector<D, E>, _e: &SMatrix<D, E, N>, _m: &SMatrix<f64, E, E>) -> D {
        x[2] * self.a
    }
}

/// `V = a·x[axis]/R + b·e₁[axis]`: a tilt of the position along the ambient
/// axis `axis` plus a frame coupling (the first body axis `e₁`, a dipole, in
/// a uniform field along the same axis).
///
/// The coupling makes the internal rotation and the translation exchange
/// energy, and the generator direction of the flow turn quickly — what the
/// order and truncation measurements need (a constant generator is
/// integrated exactly by every RKMK method and proves nothing, SPEC §4).
/// Invariant under the ambient isometries that fix the axis `axis` (and
/// act on the frame), so the momentum map of rotations in a plane not
/// containing that axis is conserved. [`Potential::uses_frame`] is `b ≠ 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axial {
    /// Tilt strength `a` (the position term is `a·x[axis]/R`).
    pub a: f64,
    /// Frame-coupling strength `b`.
    pub b: f64,
    /// The length `R` that scales the position term (the manifold's radius,
    /// or the tube radius of the torus).
    pub radius: f64,
    /// The ambient axis (0-based) of the tilt and of the coupling.
    pub axis: usize,
}

impl<const N: usize, const E: usize> Potential<N, E> for Axial {
    fn uses_frame(&self) -> bool {
        self.b != 0.0
    }
    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, _m: &SMatrix<f64, E, E>) -> D {
        x[self.axis] * (self.a / self.radius) + e[(self.axis, 0)] * self.b
    }
}
