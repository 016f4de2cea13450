//! What the splitting methods ([`Splitting`](crate::method::Splitting)) need
//! of a model: the exact flows of its kinetic and its potential energy.
//!
//! `H = T + V` is split into the **drift** — the flow of `T` alone, the free
//! motion (geodesic flow of a point, free gyroscope) — and the **kick** — the
//! flow of `V` alone, which freezes the configuration and changes only the
//! momenta:
//! ```text
//! kick(h):   u ← u + h F̂/m,   s ← s + h·(−∂V/∂α)   (n = 2),   π ← π + h τ   (n = 3)
//! drift(h):  the exact free flow (below)
//! ```
//! Both are exact flows of Hamiltonian vector fields, so every composition of
//! them is symplectic, and, when `V` is invariant under an ambient isometry,
//! conserves its momentum map (e.g. `p_φ`) exactly: the kick changes `J_A` by
//! `−h·(derivative of V along A) = 0`, the drift is an exact flow of the
//! invariant `T`. The models implement [`Splittable`]
//! in their own files (point, n = 2 and n = 3 gyroscopes); the drift is
//! exact on bundles of constant curvature
//! ([`FrameBundle::exact_free_flow`](crate::bundle::FrameBundle::exact_free_flow):
//! S², H², S³), where [`Splittable::has_free_flow`] is true. Models without
//! one (affine bodies, points and gyroscopes on T²) are refused by the
//! splitting methods with a typed error.
//!
//! # Exact free flows on constant curvature
//! ([`FrameBundle::exact_free_flow`](crate::bundle::FrameBundle::exact_free_flow))
//! On S², H², S³ the horizontal lift `ξ(u)` and the vertical generator are
//! constant in the bundle group, and rotating the frame by `exp(τ·vertical(w))`
//! rotates the lift: `Ad_{exp(τR)} ξ(u) = ξ(exp(τw) u)` with `R = vertical(w)`.
//! The free equations in the parallel frame ([`gyroscope`](crate::dynamics::gyroscope))
//! `ġ = g ξ(u)`, `m u̇ = K s ε u` (n = 2) or `K π × u` (n = 3), `π̇ = 0` have
//! `u(t) = exp(t w) u₀` with `w = (K s/m) ε` resp. `hat(K π/m)`, hence
//! ```text
//! g(t) = g₀ · exp(t (ξ(u₀) + R)) · exp(−t R),     R = vertical(g₀, w)
//! ```
//! (differentiate: `g⁻¹ġ = Ad_{exp(tR)}(ξ(u₀) + R) − R = ξ(u(t))`). This is
//! the parallel-frame form of SPEC §4's `Q(t) = Q₀ exp(tΠ̂₀/K)·exp(t(1/I − 1/K)Π₃ê₃)`
//! for the symmetric top on S² (and the Lorentz top on H²): the internal
//! rotation `ρ` separates. For the point (`s = 0`) it is the geodesic flow
//! `g₀ exp(t ξ(u₀))`.
//!
//! **Internal rotation.** n = 2: `ρ(t) = ρ₀ U(t σ s/I)`. n = 3: with the
//! body momentum `M = ρᵀπ` and the principal axes `P_k`, moments `I_k` of the
//! inertia operator `𝕀`, the internal energy splits as
//! `σ|M|²/(2I₁) + Σ_{k=2,3} c_k (P_k·M)²/2`, `c_k = σ(1/I_k − 1/I₁)`; each
//! piece has the exact flow `ρ ↦ ρ·exp(t·a·hat(axis))` with `π` fixed
//! (a rotation about `M` resp. about `P_k`, whose component of `M` it keeps).
//! The first commutes with the others. For a **symmetric** `𝕀` (two equal
//! moments, chosen as `I₁ = I₂`) `c₂ = 0` and the drift is exact — the free
//! symmetric top. For an **asymmetric** `𝕀` the pieces `c₂`, `c₃` do not
//! commute (the exact free flow would need Jacobi elliptic functions): the
//! drift then composes them by the symmetric sixth-order Yoshida composition
//! of their Strang splitting ([`YOSHIDA6`]), i.e. it is exact up to
//! `O(h⁷)` per step, symmetric and symplectic — every method here keeps its
//! order ≤ 6 and its conservation properties.
//!
//!
//! [`SplitDispatch`] lets code that holds a method chosen at run time (the
//! method registry, scenes) ask any model for its split without knowing its
//! type: the models with a split answer with themselves, the others with
//! [`NoSplit`], a type that has no values.

use std::convert::Infallible;
use std::marker::PhantomData;

use super::System;
use crate::lie::LieGroup;

/// Yoshida's sixth-order composition weights, solution A of \[Yo90\]
/// (`w₃, w₂, w₁, w₀, w₁, w₂, w₃`; `w₀ = 1 − 2(w₁ + w₂ + w₃)`): the method
/// [`Splitting::yoshida6`](crate::method::Splitting::yoshida6), and the
/// composition of the asymmetric top's internal drift.
///
/// \[Yo90\] H. Yoshida, *Construction of higher order symplectic integrators*,
/// Phys. Lett. A 150 (1990) 262–268.
pub const YOSHIDA6: [f64; 7] = [
    0.784_513_610_477_557_3,
    0.235_573_213_359_358_13,
    -1.177_679_984_178_871,
    1.315_186_320_683_911_2,
    -1.177_679_984_178_871,
    0.235_573_213_359_358_13,
    0.784_513_610_477_557_3,
];

/// A system whose Hamiltonian `T + V` splits into two exactly (or, see
/// [`Splittable::drift_exact`], to order 6) integrable parts.
pub trait Splittable: System {
    /// The flow of `V` over time `h`: the momenta change by `h` times the
    /// generalised forces at the frozen configuration.
    fn kick(&self, y: &Self::State, h: f64) -> Self::State;
    /// The flow of `T` over time `h`: the free motion, when
    /// [`Self::has_free_flow`]; otherwise the flow of the frozen horizontal
    /// lift, which is not the free flow (the splitting methods refuse it).
    fn drift(&self, y: &Self::State, h: f64) -> Self::State;
    /// True if [`Self::drift`] is the free flow (the bundle has exact free
    /// flows); the splitting methods refuse the system otherwise.
    fn has_free_flow(&self) -> bool;
    /// True if [`Splittable::drift`] is the exact free flow; false if it is a
    /// symmetric symplectic approximation with local error `O(h⁷)`.
    fn drift_exact(&self) -> bool {
        true
    }
    /// Group exponentials per drift.
    fn drift_exps(&self) -> u32;
}

/// Any system's answer to "do you split?": the models with a split
/// ([`Splittable`]) return themselves when [`Splittable::has_free_flow`],
/// the others have `Split = NoSplit<State>` and return `None`.
pub trait SplitDispatch: System {
    /// The split view of the system.
    type Split: Splittable<State = Self::State>;
    /// The split, if the system has one here.
    fn as_splittable(&self) -> Option<&Self::Split>;
}

/// The split of a system that has none: a type without values, so its
/// methods can never run.
pub struct NoSplit<G>(Infallible, PhantomData<fn() -> G>);

impl<G: LieGroup> System for NoSplit<G> {
    type State = G;
    fn vector_field(&self, _: f64, _: &G) -> G::Algebra {
        match self.0 {}
    }
    fn energy(&self, _: &G) -> f64 {
        match self.0 {}
    }
    fn defect(&self, _: &G) -> f64 {
        match self.0 {}
    }
}

impl<G: LieGroup> Splittable for NoSplit<G> {
    fn kick(&self, _: &G, _: f64) -> G {
        match self.0 {}
    }
    fn drift(&self, _: &G, _: f64) -> G {
        match self.0 {}
    }
    fn has_free_flow(&self) -> bool {
        match self.0 {}
    }
    fn drift_exps(&self) -> u32 {
        match self.0 {}
    }
}
