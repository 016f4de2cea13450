//! The tangent map of a method's one-step map, in the left trivialisation
//! (see the [module documentation](super)).

use nalgebra::{DMatrix, DVector};

use super::AnalysisError;
use crate::dynamics::System;
use crate::lie::{AlgebraVector, LieGroup};
use crate::method::{GroupNumerics, Method, StepRequest};
use crate::solve::{fault_error, StepSize};

/// The difference formula of the directional derivative of the one-step map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Difference {
    /// `(Φ(+ε) − Φ(−ε))/2ε`: 2 steps per column, error `O(ε²)`.
    #[default]
    Central2,
    /// `(8(Φ(+ε) − Φ(−ε)) − (Φ(+2ε) − Φ(−2ε)))/12ε`: 4 steps per column,
    /// error `O(ε⁴)`.
    Central4,
}

/// How the one-step map is linearised: exactly, on the tangent group, where
/// the system and the method allow it ([`exact`](Self::exact)); else by the
/// difference formula with the perturbation size `ε` (algebra units:
/// radians for rotations, the state's own units for the additive
/// components).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearisation {
    /// The difference formula (where the tangent map is differenced).
    pub difference: Difference,
    /// The perturbation size, [`MIN_EPS`](Self::MIN_EPS) `≤ ε ≤ 0.1`.
    pub eps: f64,
    /// Use the exact tangent map where it exists: the system has a
    /// [`tangent_field`](System::tangent_field) and the method a
    /// [`tangent_step`](Method::tangent_step). `false` differences every
    /// step (for comparison).
    pub exact: bool,
}

impl Default for Linearisation {
    /// Exact where available; else second-order central differences with
    /// `ε = 1e-5`: truncation `~ε²h` and round-off `~1e-16/ε`, about
    /// `1e-10` relative per step.
    fn default() -> Self {
        Linearisation { difference: Difference::Central2, eps: 1e-5, exact: true }
    }
}

impl Linearisation {
    /// The smallest `ε` accepted. A central difference's round-off is about
    /// `1e-16/ε` relative, so below `1e-12` the derivative has fewer than four
    /// correct digits, and at a subnormal `ε` the perturbation is lost
    /// entirely (the perturbed steps equal the unperturbed one).
    pub const MIN_EPS: f64 = 1e-12;

    /// Fourth-order central differences with `ε = 1e-3` (about `1e-12`
    /// relative per step, twice the cost of second-order differences) where
    /// the tangent maps are differenced; exact where they can be.
    pub fn fourth_order() -> Self {
        Linearisation { difference: Difference::Central4, eps: 1e-3, exact: true }
    }

    /// The same differences, used even where the exact tangent map exists.
    pub fn differenced(self) -> Self {
        Linearisation { exact: false, ..self }
    }

    /// What is used for `system` and `method` from `(t0, y0)`: `exact`
    /// stays true only if both have the exact tangent map.
    pub fn resolve<S, M>(&self, system: &S, method: &M, t0: f64, y0: &S::State) -> Linearisation
    where
        S: System,
        S::State: GroupNumerics,
        M: Method<S>,
    {
        Linearisation { exact: self.exact && exact_tangents(system, method, t0, y0), ..*self }
    }

    /// [`fourth_order`](Self::fourth_order) if `fourth_order`, else the
    /// default, with `ε = eps` if given, [`differenced`](Self::differenced)
    /// if `differenced` (the options `--fourth-order`, `--eps` and
    /// `--differenced` of the CLI, `fourth_order`, `eps` and `differenced`
    /// of the Python functions; checked by [`validate`](Self::validate)
    /// where it is used).
    pub fn chosen(fourth_order: bool, eps: Option<f64>, differenced: bool) -> Self {
        let mut l = if fourth_order { Linearisation::fourth_order() } else { Linearisation::default() };
        if let Some(eps) = eps {
            l.eps = eps;
        }
        if differenced {
            l = l.differenced();
        }
        l
    }

    /// Checks `ε`.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        if !(self.eps.is_finite() && self.eps >= Self::MIN_EPS && self.eps <= 0.1) {
            return Err(AnalysisError::invalid("eps", self.eps, "finite, ≥ 1e-12 and ≤ 0.1"));
        }
        Ok(())
    }

    /// Steps of the method per tangent column and step: 1 step of the
    /// tangent lift (about twice a plain step's cost) where exact, else the
    /// difference formula's 2 or 4 (as [`resolve`](Self::resolve)d).
    pub fn steps_per_column(&self) -> usize {
        match (self.exact, self.difference) {
            (true, _) => 1,
            (false, Difference::Central2) => 2,
            (false, Difference::Central4) => 4,
        }
    }

    /// How the tangent maps are taken, in words (the CLI's summaries).
    pub fn describe(&self) -> String {
        if self.exact {
            "exact (the method on the tangent group)".to_string()
        } else {
            let order = match self.difference {
                Difference::Central2 => 2,
                Difference::Central4 => 4,
            };
            format!("central differences of order {order}, eps = {:e}", self.eps)
        }
    }
}

/// True if `system` has an exact [`tangent_field`](System::tangent_field)
/// at `(t0, y0)` and `method` a [`tangent_step`](Method::tangent_step) for
/// it (asked with a step of size 0).
pub fn exact_tangents<S, M>(system: &S, method: &M, t0: f64, y0: &S::State) -> bool
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let zero = <<S::State as LieGroup>::Algebra as AlgebraVector>::zero();
    crate::dynamics::Linearised::new(system, t0, y0).is_some() && matches!(method.tangent_step(system, t0, y0, 0.0, &zero), Some(Ok(_)))
}

/// The state `y₀·exp(ξ)` for algebra coordinates `ξ`.
fn perturbed<G: LieGroup>(y0: &G, xi: &[f64]) -> G {
    y0.compose(&G::exp(&G::algebra_from_coords(xi)))
}

/// Algebra coordinates of `log(y⁻¹·z)` given `y⁻¹`.
fn difference<G: LieGroup>(y_inv: &G, z: &G) -> Result<DVector<f64>, AnalysisError> {
    Ok(DVector::from_vec(G::algebra_coords(&y_inv.compose(z).log()?)))
}

/// One step of `method` from `(t, y0)` with size `h`, and the images of the
/// tangent columns `cols` (`DOF` rows, algebra coordinates) under the
/// step's tangent map, written back into `cols`. Returns the new state.
/// `lin` is [`resolve`](Linearisation::resolve)d for this step (exact only
/// where the system and the method have the exact map); a loop over steps
/// resolves once instead ([`TangentFlow`]).
pub fn step_with_tangents<S, M>(system: &S, method: &M, t: f64, y0: &S::State, h: f64, cols: &mut DMatrix<f64>, lin: &Linearisation) -> Result<S::State, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    resolved_step(system, method, t, y0, h, cols, &lin.resolve(system, method, t, y0))
}

/// [`step_with_tangents`] with `lin` already resolved.
fn resolved_step<S, M>(system: &S, method: &M, t: f64, y0: &S::State, h: f64, cols: &mut DMatrix<f64>, lin: &Linearisation) -> Result<S::State, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let y1 = method.step(system, t, y0, h, StepRequest::plain()).map(|o| o.y).map_err(|f| AnalysisError::Solve(fault_error(f, t, h)))?;
    tangent_images(system, method, t, y0, &y1, h, cols, lin)?;
    Ok(y1)
}

/// The images of the tangent columns `cols` under the tangent map of the
/// step of `method` from `(t, y0)` with size `h` that ended at `y1`, written
/// back into `cols`. The step size is held fixed: with error-controlled
/// steps this is the derivative of the accepted step at its size, a step of
/// the discrete variational equation (the controller's choice of `h`
/// depends on the state too, but a perturbed state at another `h` would be
/// compared at another time).
#[allow(clippy::too_many_arguments)]
pub(crate) fn tangent_images<S, M>(system: &S, method: &M, t: f64, y0: &S::State, y1: &S::State, h: f64, cols: &mut DMatrix<f64>, lin: &Linearisation) -> Result<(), AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    if lin.exact {
        return exact_images(system, method, t, y0, h, cols);
    }
    let step = |y: &S::State| method.step(system, t, y, h, StepRequest::plain()).map(|o| o.y).map_err(|f| AnalysisError::Solve(fault_error(f, t, h)));
    let y1_inv = y1.inverse();
    let mut xi = vec![0.0; S::State::DOF];
    for j in 0..cols.ncols() {
        let n = cols.column(j).norm();
        if n == 0.0 {
            continue;
        }
        // The image of y₀·exp(s·c/|c|), relative to y₁, for s = k·ε.
        let mut image = |k: f64| -> Result<DVector<f64>, AnalysisError> {
            let s = k * lin.eps / n;
            for (x, c) in xi.iter_mut().zip(cols.column(j).iter()) {
                *x = s * c;
            }
            difference(&y1_inv, &step(&perturbed(y0, &xi))?)
        };
        let d = match lin.difference {
            Difference::Central2 => (image(1.0)? - image(-1.0)?) * (n / (2.0 * lin.eps)),
            Difference::Central4 => {
                let near = image(1.0)? - image(-1.0)?;
                let far = image(2.0)? - image(-2.0)?;
                (near * 8.0 - far) * (n / (12.0 * lin.eps))
            }
        };
        cols.set_column(j, &d);
    }
    Ok(())
}

/// [`tangent_images`] by the method's exact tangent map: one step of the
/// tangent lift per column. The tangent map is linear, so a column is
/// stepped at unit length and scaled back (its size does not reach the
/// vector field's derivative, only the result's).
fn exact_images<S, M>(system: &S, method: &M, t: f64, y0: &S::State, h: f64, cols: &mut DMatrix<f64>) -> Result<(), AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let mut c = vec![0.0; S::State::DOF];
    for j in 0..cols.ncols() {
        let n = cols.column(j).norm();
        if n == 0.0 {
            continue;
        }
        for (x, v) in c.iter_mut().zip(cols.column(j).iter()) {
            *x = v / n;
        }
        let xi0 = <S::State as LieGroup>::algebra_from_coords(&c);
        let (_, xi1) = match method.tangent_step(system, t, y0, h, &xi0) {
            Some(r) => r.map_err(|f| AnalysisError::Solve(fault_error(f, t, h)))?,
            None => return Err(AnalysisError::invalid("linearisation", "exact", "differenced: the method has no exact tangent map")),
        };
        let image = <S::State as LieGroup>::algebra_coords(&xi1);
        for (i, v) in image.iter().enumerate() {
            cols[(i, j)] = v * n;
        }
    }
    Ok(())
}

/// A trajectory with tangent vectors carried along: fixed steps of a method
/// and the tangent map of each step (see the [module documentation](super)).
#[derive(Debug)]
pub struct TangentFlow<'a, S: System, M> {
    system: &'a S,
    method: &'a M,
    lin: Linearisation,
    t: f64,
    y: S::State,
    cols: DMatrix<f64>,
}

/// A copy that shares the system and the method (neither is cloned).
impl<S: System, M> Clone for TangentFlow<'_, S, M> {
    fn clone(&self) -> Self {
        TangentFlow { system: self.system, method: self.method, lin: self.lin, t: self.t, y: self.y, cols: self.cols.clone() }
    }
}

impl<'a, S, M> TangentFlow<'a, S, M>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    /// A trajectory from `(t0, y0)` with tangent columns `cols` (`DOF` rows,
    /// algebra coordinates of `ξ` in `δy = y·ξ`; any number of columns).
    pub fn new(system: &'a S, method: &'a M, t0: f64, y0: S::State, cols: DMatrix<f64>, lin: Linearisation) -> Result<Self, AnalysisError> {
        lin.validate()?;
        super::check_start(t0, &y0)?;
        if cols.nrows() != S::State::DOF {
            return Err(AnalysisError::invalid("columns", format!("{} rows", cols.nrows()), format!("{} rows (the state group's dimension)", S::State::DOF)));
        }
        if cols.iter().any(|x| !x.is_finite()) {
            return Err(AnalysisError::invalid("columns", "(a non-finite entry)", "finite"));
        }
        let lin = lin.resolve(system, method, t0, &y0);
        Ok(TangentFlow { system, method, lin, t: t0, y: y0, cols })
    }

    /// One step of size `h` (finite, ≠ 0). A failed step leaves everything unchanged.
    pub fn step(&mut self, h: f64) -> Result<(), AnalysisError> {
        if !(h.is_finite() && h != 0.0) {
            return Err(AnalysisError::invalid("h", h, "finite and ≠ 0"));
        }
        let mut cols = self.cols.clone();
        let y = resolved_step(self.system, self.method, self.t, &self.y, h, &mut cols, &self.lin)?;
        self.y = y;
        self.cols = cols;
        self.t += h;
        Ok(())
    }

    /// The linearisation used, [`resolve`](Linearisation::resolve)d for the
    /// system and the method (`exact` tells whether the tangent maps are exact).
    pub fn linearisation(&self) -> &Linearisation {
        &self.lin
    }
    /// Current time.
    pub fn t(&self) -> f64 {
        self.t
    }
    /// Current state.
    pub fn state(&self) -> &S::State {
        &self.y
    }
    /// The tangent columns at the current state.
    pub fn columns(&self) -> &DMatrix<f64> {
        &self.cols
    }
    /// The tangent columns, mutably (re-orthonormalisation).
    pub fn columns_mut(&mut self) -> &mut DMatrix<f64> {
        &mut self.cols
    }
}

/// The derivative of the `n`-step map of `method` (steps `h`) at `y0`, in
/// the left trivialisation at both ends: the `DOF × DOF` matrix `D` with
/// `Φ(y₀·exp(ξ)) = Φ(y₀)·exp(Dξ + O(|ξ|²))`. Also returns the final state.
pub fn flow_derivative<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, h: f64, n: usize, lin: &Linearisation) -> Result<(DMatrix<f64>, S::State), AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let dof = S::State::DOF;
    let mut flow = TangentFlow::new(system, method, t0, *y0, DMatrix::identity(dof, dof), *lin)?;
    for i in 0..n {
        let t1 = t0 + h * (i + 1) as f64;
        let hi = t1 - flow.t();
        flow.step(hi)?;
    }
    Ok((flow.cols, flow.y))
}

/// The derivative of the flow of `method` over `duration` from `(t0, y0)`
/// with fixed or error-controlled steps (`step`; the steps of a run of the
/// same settings, chosen for the trajectory alone), in the left
/// trivialisation at both ends, as [`flow_derivative`]: the product of the
/// tangent maps of the accepted steps. Also returns the final state and the
/// number of steps.
pub fn tangent_flow<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, step: &StepSize, duration: f64, lin: &Linearisation) -> Result<(DMatrix<f64>, S::State, usize), AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    lin.validate()?;
    super::check_start(t0, y0)?;
    super::walk::plan(step, duration, super::MAX_STEPS)?;
    let lin = &lin.resolve(system, method, t0, y0);
    let dof = S::State::DOF;
    let mut cols = DMatrix::identity(dof, dof);
    let mut y = *y0;
    let walked = super::walk::walk(system, method, t0, y0, step, duration, super::MAX_STEPS, None, |s| {
        tangent_images(system, method, s.t0, s.y0, s.y1, s.h, &mut cols, lin)?;
        y = *s.y1;
        Ok(super::walk::Next::Go)
    })?;
    Ok((cols, y, walked.steps))
}

/// The space the tangent vectors of an analysis live in: the state group's
/// algebra, or with `quotient` its quotient by the gauge directions
/// ([`System::gauge`]) — the physical phase space. The gauge directions
/// depend on the state, so they are taken at the start for the dimension
/// and the initial frame, and at every step's end by [`Space::project`].
pub(crate) struct Space {
    quotient: bool,
    /// An orthonormal basis of the gauge directions at the start, with `quotient`.
    gauge0: Option<DMatrix<f64>>,
    /// The state group's `DOF`: the rows of a tangent vector.
    rows: usize,
    /// The dimension: `DOF`, less the gauge directions with `quotient`.
    pub dimension: usize,
}

impl Space {
    /// The space of `system`'s tangent vectors at `(t0, y0)`.
    pub(crate) fn at_start<S: System>(system: &S, y0: &S::State, t0: f64, quotient: bool) -> Result<Self, AnalysisError> {
        let gauge0 = if quotient { gauge_basis(system, y0, t0)? } else { None };
        let dimension = S::State::DOF - gauge0.as_ref().map_or(0, |g| g.ncols());
        Ok(Space { quotient, gauge0, rows: S::State::DOF, dimension })
    }

    /// What [`Space::dimension`] is, for an error naming its bound.
    pub(crate) fn describe(&self) -> &'static str {
        if self.gauge0.is_some() {
            "the phase space's dimension: the state group's less its gauge directions"
        } else {
            "the state group's dimension"
        }
    }

    /// `k` seeded random orthonormal vectors of the space at the start (the
    /// group's [`random_frame`](super::lyapunov::random_frame), their gauge
    /// components removed and orthonormalised again).
    pub(crate) fn random_frame(&self, k: usize, seed: u64, t0: f64) -> Result<DMatrix<f64>, AnalysisError> {
        let mut q = super::lyapunov::random_frame(self.rows, k, seed);
        if let Some(g) = &self.gauge0 {
            project_out(&mut q, g);
            super::lyapunov::orthonormalise(&mut q, t0)?;
        }
        Ok(q)
    }

    /// Removes from `cols` their components along the gauge directions at
    /// `(t, y)` (with `quotient`; else nothing): after every step, so that
    /// the vectors stay in the quotient.
    pub(crate) fn project<S: System>(&self, system: &S, y: &S::State, t: f64, cols: &mut DMatrix<f64>) -> Result<(), AnalysisError> {
        if self.quotient {
            if let Some(g) = gauge_basis(system, y, t)? {
                project_out(cols, &g);
            }
        }
        Ok(())
    }
}

/// An orthonormal basis of the gauge directions of `system` at `y`
/// ([`System::gauge`]), as columns of algebra coordinates; `None` if it has
/// none.
fn gauge_basis<S>(system: &S, y: &S::State, t: f64) -> Result<Option<DMatrix<f64>>, AnalysisError>
where
    S: System,
{
    let directions = system.gauge(y);
    if directions.is_empty() {
        return Ok(None);
    }
    let mut g = DMatrix::zeros(S::State::DOF, directions.len());
    for (j, d) in directions.iter().enumerate() {
        g.set_column(j, &DVector::from_vec(S::State::algebra_coords(d)));
    }
    super::lyapunov::orthonormalise(&mut g, t)?;
    Ok(Some(g))
}

/// `q ← q − G·(Gᵀq)` for orthonormal columns `G`. One pass: what
/// cancellation leaves along `G` is round-off relative to the column, and
/// the analyses project after every step, so it never accumulates.
fn project_out(q: &mut DMatrix<f64>, g: &DMatrix<f64>) {
    let c = g.transpose() * &*q;
    *q -= g * c;
}
