//! Coordinate baselines: what a user would otherwise write — the paper's
//! Euler–Lagrange equations in a chart, integrated by a classical
//! Runge–Kutta method — exposed as a [`System`] and [`Method`]s like any
//! other, so that a problem can be solved by them and compared honestly with
//! the Lie-group methods.
//!
//! - [`ChartSystem`]: the state `(q, q̇) ∈ ℝ^Q × ℝ^Q` of a coordinate
//!   [`Lagrangian`] (e.g. [`coords::Gyroscope2`],
//!   [`coords::PointLagrangian`]) with
//!   `q̈ = M⁻¹(∂L/∂q − C q̇)` from [`coords::accelerations`] (exact derivatives
//!   by automatic differentiation).
//! - [`CoordinateRk`]: a classical explicit Runge–Kutta method on it —
//!   [`CoordinateRk::rk4`] (fixed step, order 4) and [`CoordinateRk::dopri5`]
//!   (Dormand–Prince 5(4) \[DP80\], adaptive with the embedded pair, dense
//!   output of order 4; the same cited [`tableau`] data as
//!   the RKMK engine). DOP853 is not provided.
//!
//! **Where they fail.** At the poles of S² and the origin of H²'s polar chart
//! the mass matrix degenerates like `sin²ϑ` and `φ̇ ~ p_φ/sin²ϑ`: a fixed step
//! jumps over the passage (O(1) error), an adaptive one must shrink `h` like
//! `sin²ϑ_min`, and where the chart is singular (or `cond M > 1e14`) the step
//! fails with [`StepFault::OutsideChart`] (→ [`SolveError::OutsideChart`](crate::solve::SolveError::OutsideChart)
//! with `t` and `h`). The evaluation of `q̈` allocates (the dynamic LU of
//! [`coords`]); these are baselines, not production paths.
//!
//! \[DP80\] J. R. Dormand, P. J. Prince, *A family of embedded Runge–Kutta
//! formulae*, J. Comput. Appl. Math. 6 (1980) 19–26.

use nalgebra::SVector;

use super::tableau::{self, Tableau, DENSE_DEGREE};
use super::{Alg, DensePoly, Method, MethodInfo, NonFiniteSource, StepCost, StepFault, StepOutput, StepRequest};
use crate::coords::{self, Lagrangian};
use crate::dynamics::{NoSplit, SplitDispatch, System};
use crate::lie::{AlgebraVector, LieGroup, Product, ProductAlgebra, Rn};
use crate::Error;

/// The state `(q, q̇)` of a [`ChartSystem`].
pub type ChartState<const Q: usize> = Product<Rn<Q>, Rn<Q>>;

/// The Euler–Lagrange equations of a coordinate Lagrangian as a first-order
/// system on `ℝ^Q × ℝ^Q` (additive group: `exp` is the identity, so the Lie
/// machinery reduces to classical Runge–Kutta).
#[derive(Debug, Clone)]
pub struct ChartSystem<L, const Q: usize> {
    lagrangian: L,
}

impl<L: Lagrangian<Q>, const Q: usize> ChartSystem<L, Q> {
    /// The system of `lagrangian`.
    pub fn new(lagrangian: L) -> Self {
        ChartSystem { lagrangian }
    }

    /// The Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lagrangian
    }

    /// The state `(q, q̇)`.
    pub fn state(q: &SVector<f64, Q>, qdot: &SVector<f64, Q>) -> ChartState<Q> {
        Product(Rn(*q), Rn(*qdot))
    }

    /// `(q̇, q̈)`, or the chart's typed error ([`Error::OutsideChart`], the
    /// mass-matrix [`Error::Constraint`], [`Error::NotFinite`]).
    pub fn try_vector_field(&self, y: &ChartState<Q>) -> crate::Result<ProductAlgebra<SVector<f64, Q>, SVector<f64, Q>>> {
        let (q, qd) = (&y.0 .0, &y.1 .0);
        let acc = coords::accelerations(&self.lagrangian, q, qd)?;
        Ok(ProductAlgebra(*qd, acc))
    }
}

impl<L, const Q: usize> System for ChartSystem<L, Q>
where
    L: Lagrangian<Q> + Send + Sync,
{
    type State = ChartState<Q>;

    /// `(q̇, q̈)`; NaN where the chart is singular (use
    /// [`ChartSystem::try_vector_field`] for the typed error, as
    /// [`CoordinateRk`] does).
    fn vector_field(&self, _t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra {
        self.try_vector_field(y)
            .unwrap_or_else(|_| ProductAlgebra(SVector::repeat(f64::NAN), SVector::repeat(f64::NAN)))
    }

    /// `E = q̇·∂L/∂q̇ − L` ([`coords::energy`]); NaN outside the chart.
    fn energy(&self, y: &Self::State) -> f64 {
        coords::energy(&self.lagrangian, &y.0 .0, &y.1 .0).unwrap_or(f64::NAN)
    }

    /// 0 (no constraints) for a finite state, NaN otherwise.
    fn defect(&self, y: &Self::State) -> f64 {
        if y.0 .0.iter().chain(y.1 .0.iter()).all(|v| v.is_finite()) {
            0.0
        } else {
            f64::NAN
        }
    }
}

/// The chart equations have no exact free flows.
impl<L, const Q: usize> SplitDispatch for ChartSystem<L, Q>
where
    L: Lagrangian<Q> + Send + Sync,
{
    type Split = NoSplit<ChartState<Q>>;
    fn as_splittable(&self) -> Option<&Self::Split> {
        None
    }
}

/// A classical explicit Runge–Kutta method on a [`ChartSystem`], failing
/// with a typed [`StepFault::OutsideChart`] where the chart is singular.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoordinateRk<const S: usize> {
    name: &'static str,
    tableau: &'static Tableau<S>,
}

impl CoordinateRk<4> {
    /// The classical RK4 in coordinates (order 4, 4 evaluations).
    pub const fn rk4() -> Self {
        CoordinateRk { name: super::registry::COORDINATE_RK4.display, tableau: &tableau::RK4 }
    }
}

impl CoordinateRk<7> {
    /// Dormand–Prince 5(4) in coordinates: order 5, embedded order 4, FSAL,
    /// dense output of order 4.
    pub const fn dopri5() -> Self {
        CoordinateRk { name: super::registry::COORDINATE_DOPRI5.display, tableau: &tableau::DOPRI5 }
    }
}

impl<const S: usize> CoordinateRk<S> {
    /// The display name ([`MethodInfo::name`]).
    pub const fn name(&self) -> &'static str {
        self.name
    }
}

fn chart_fault(e: &Error, t_eval: f64) -> StepFault {
    match e {
        Error::OutsideChart { reason, .. } => StepFault::OutsideChart { reason, t_eval },
        Error::Constraint { constraint, .. } => StepFault::OutsideChart { reason: constraint, t_eval },
        _ => StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval },
    }
}

impl<L, const Q: usize, const S: usize> Method<ChartSystem<L, Q>> for CoordinateRk<S>
where
    L: Lagrangian<Q> + Send + Sync,
{
    fn info(&self) -> MethodInfo {
        let t = self.tableau;
        MethodInfo {
            name: self.name,
            order: t.order,
            embedded_order: t.embedded.map(|e| e.order),
            dense_order: t.dense.map_or(t.order.min(3), |d| d.order),
            stages: S,
            fsal: t.is_fsal(),
            radius_limit: f64::INFINITY,
        }
    }

    fn step(
        &self,
        sys: &ChartSystem<L, Q>,
        t: f64,
        y0: &ChartState<Q>,
        h: f64,
        req: StepRequest<Alg<ChartSystem<L, Q>>>,
    ) -> Result<StepOutput<ChartState<Q>>, StepFault> {
        type A<const Q: usize> = ProductAlgebra<SVector<f64, Q>, SVector<f64, Q>>;
        let tab = self.tableau;
        let mut cost = StepCost::default();
        let eval = |y: &ChartState<Q>, te: f64, cost: &mut StepCost| -> Result<A<Q>, StepFault> {
            cost.rhs += 1;
            let f = sys.try_vector_field(y).map_err(|e| chart_fault(&e, te))?;
            if f.is_finite() {
                Ok(f)
            } else {
                Err(StepFault::NonFinite { source: NonFiniteSource::VectorField, t_eval: te })
            }
        };
        let k0 = match req.f_start {
            Some(f) => f,
            None => eval(y0, t, &mut cost)?,
        };
        let mut k = [k0; S];
        let fsal = tab.is_fsal();
        let n = if req.error || req.dense || (fsal && req.f_end) { S } else { tab.solution_stages() };
        for i in 1..n {
            let mut th = A::<Q>::zero();
            for j in 0..i {
                if tab.a[i][j] != 0.0 {
                    th = th + k[j] * (h * tab.a[i][j]);
                }
            }
            k[i] = eval(&y0.compose(&ChartState::<Q>::exp(&th)), t + tab.c[i] * h, &mut cost)?;
        }
        let mut theta = A::<Q>::zero();
        for i in 0..n {
            theta = theta + k[i] * (h * tab.b[i]);
        }
        let y1 = y0.compose(&ChartState::<Q>::exp(&theta));
        if !theta.is_finite() {
            return Err(StepFault::NonFinite { source: NonFiniteSource::State, t_eval: t + h });
        }
        let error = match (&tab.embedded, req.error) {
            (Some(e), true) => {
                let mut d = A::<Q>::zero();
                for i in 0..S {
                    d = d + k[i] * (h * (tab.b[i] - e.b_hat[i]));
                }
                Some(d)
            }
            _ => None,
        };
        let f_end = if req.f_end {
            if fsal && n == S {
                Some(k[S - 1])
            } else {
                Some(eval(&y1, t + h, &mut cost)?)
            }
        } else {
            None
        };
        let dense = match (&tab.dense, req.dense) {
            (Some(dw), true) => {
                let mut coeffs = [A::<Q>::zero(); DENSE_DEGREE];
                let mut degree = 0;
                for (m, c) in coeffs.iter_mut().enumerate() {
                    if dw.coeffs[m].iter().any(|&w| w != 0.0) {
                        for i in 0..S {
                            *c = *c + k[i] * (h * dw.coeffs[m][i]);
                        }
                        degree = m + 1;
                    }
                }
                Some(DensePoly { coeffs, degree })
            }
            (None, true) => {
                // Cubic Hermite (additive group: θ is the increment itself).
                let f1 = match f_end {
                    Some(f) => f,
                    None => eval(&y1, t + h, &mut cost)?,
                };
                let (d0, d1) = (k0 * h, f1 * h);
                let mut coeffs = [A::<Q>::zero(); DENSE_DEGREE];
                coeffs[0] = d0;
                coeffs[1] = theta * 3.0 - d0 * 2.0 - d1;
                coeffs[2] = d0 + d1 - theta * 2.0;
                Some(DensePoly { coeffs, degree: 3 })
            }
            _ => None,
        };
        Ok(StepOutput { y: y1, theta, f_start: k0, f_end, error, dense, cost })
    }
}
