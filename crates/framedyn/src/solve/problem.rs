//! The initial-value problem: a system, an initial state and a time span.

use super::SolveError;
use crate::dynamics::System;
use crate::lie::AlgebraVector;
use crate::method::GroupNumerics;

/// `ẏ = y·f(t, y)`, `y(t₀) = y₀`, on `[t₀, t_end]` (or `[t_end, t₀]`: the
/// integration runs backwards when `t_end < t₀`).
///
/// Validated on construction: `t₀`, `t_end` finite, `t_end ≠ t₀`, and `y₀`
/// a finite group element ([`state_is_finite`]).
#[derive(Debug, Clone)]
pub struct Problem<S: System> {
    system: S,
    y0: S::State,
    t0: f64,
    t_end: f64,
}

fn check_span(t0: f64, t_end: f64) -> Result<(), SolveError> {
    if !t0.is_finite() {
        return Err(SolveError::InvalidParameter { field: "t0", value: t0, allowed: "finite" });
    }
    if !t_end.is_finite() || t_end == t0 {
        return Err(SolveError::InvalidParameter { field: "t_end", value: t_end, allowed: "finite and ≠ t0" });
    }
    Ok(())
}

/// True if `y` is a finite group element: finite
/// [`LieGroup::constraint_defect`](crate::lie::LieGroup::constraint_defect) (matrix factors) and finite
/// [`GroupNumerics::tolerance_scale`] (the coordinates of additive factors,
/// whose constraint defect is identically 0).
#[inline]
pub fn state_is_finite<G: GroupNumerics>(y: &G) -> bool {
    y.constraint_defect().is_finite() && y.tolerance_scale().is_finite()
}

pub(crate) fn check_state<G: GroupNumerics>(y: &G) -> Result<(), SolveError> {
    if state_is_finite(y) {
        Ok(())
    } else {
        Err(SolveError::InvalidInitialState { defect: y.constraint_defect() })
    }
}

impl<S: System> Problem<S>
where
    S::State: GroupNumerics,
{
    /// The problem `ẏ = y·f(t, y)` of `system` from `y0` over `span = (t₀, t_end)`.
    /// Fails with [`SolveError`] for a non-finite or empty span or a
    /// non-finite initial state.
    ///
    /// ```
    /// use framedyn::body::Point;
    /// use framedyn::dynamics::{PointModel, System};
    /// use framedyn::manifold::{Manifold, Sphere2};
    /// use framedyn::method::Rkmk;
    /// use framedyn::potential::Free;
    /// use framedyn::solve::{solve, Options, Problem};
    /// use nalgebra::Vector2;
    ///
    /// let s2 = Sphere2::new(1.0)?;
    /// let model = PointModel::new(s2, Point::new(1.0)?, Free)?;
    /// let x = Vector2::new(1.0, 0.0);
    /// // (ṙ, φ̇) = (1, 0): unit speed along a meridian, through the south pole.
    /// let y0 = model.state(&s2.embed(&x), &s2.embed_tangent(&x, &Vector2::new(1.0, 0.0)))?;
    /// // A free point moves on a great circle with constant speed: period 2πR/|v| = 2π.
    /// let problem = Problem::new(model.clone(), y0, (0.0, 2.0 * std::f64::consts::PI)).unwrap();
    /// let sol = solve(&problem, &Rkmk::dopri5(), &Options::adaptive(1e-12, 1e-12)).unwrap();
    /// assert!((model.position(sol.last().1) - model.position(&y0)).norm() < 1e-9);
    /// assert!(Problem::new(model, y0, (1.0, f64::NAN)).is_err());
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(system: S, y0: S::State, span: (f64, f64)) -> Result<Self, SolveError> {
        check_span(span.0, span.1)?;
        check_state(&y0)?;
        Ok(Problem { system, y0, t0: span.0, t_end: span.1 })
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }

    /// The system, mutably (e.g. to change its parameters between solves).
    pub fn system_mut(&mut self) -> &mut S {
        &mut self.system
    }

    /// The initial state `y₀`.
    pub fn y0(&self) -> &S::State {
        &self.y0
    }

    /// The initial time `t₀`.
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// The final time `t_end`.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// The same problem from another initial state (validated).
    pub fn with_y0(mut self, y0: S::State) -> Result<Self, SolveError> {
        check_state(&y0)?;
        self.y0 = y0;
        Ok(self)
    }

    /// The same problem over another span (validated).
    pub fn with_span(mut self, span: (f64, f64)) -> Result<Self, SolveError> {
        check_span(span.0, span.1)?;
        self.t0 = span.0;
        self.t_end = span.1;
        Ok(self)
    }

    /// The system, initial state and span.
    pub fn into_parts(self) -> (S, S::State, (f64, f64)) {
        (self.system, self.y0, (self.t0, self.t_end))
    }
}
