//! The type-erased simulation engine: one generic implementation over the
//! models, instantiated once per manifold × body, behind [`DynEngine`].

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use nalgebra::{SMatrix, SVector};

use super::error::RunError;
use super::spec::Quantity;
use super::{Column, EventDirection, EventHit, Progress, RecordSink, RunSummary, SceneEvent, SceneStop};
use crate::method::NonFiniteSource;
use crate::bundle::FrameBundle;
use crate::dynamics::affine::{AffineBodyModel, InternalConstraint};
use crate::dynamics::gyroscope2::Z_ROTATION;
use crate::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, System};
use crate::manifold::{Hyperbolic2, Sphere2, Sphere3, Torus2};
use crate::method::{Alg, GroupNumerics, ImplicitMidpoint, Method, MethodInfo, Rkmk, Splitting, StepFault, StepOutput, StepRequest};
use crate::potential::Potential;
use crate::solve::{self, Adaptive, Options, Problem, Save, SolveError};

/// Steps per adaptive chunk (bounds the memory of a streamed adaptive run).
const CHUNK: usize = 1024;
/// Steps between checks of the cancel flag and progress reports (fixed steps).
const CHECK_EVERY: usize = 256;

/// The selected column groups.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sel([bool; 8]);

impl Sel {
    /// Every quantity.
    pub(crate) const ALL: Sel = Sel([true; 8]);

    pub(crate) fn new(qs: &[Quantity]) -> Self {
        let mut s = [false; 8];
        for q in qs {
            s[Quantity::ALL.iter().position(|a| a == q).unwrap_or(0)] = true;
        }
        Sel(s)
    }
    fn has(&self, q: Quantity) -> bool {
        self.0[Quantity::ALL.iter().position(|a| *a == q).unwrap_or(0)]
    }
}

/// Collects the values of a record and, on request, the column descriptions.
pub(crate) struct Row<'a> {
    cols: Option<&'a mut Vec<Column>>,
    vals: &'a mut Vec<f64>,
}

impl Row<'_> {
    fn put(&mut self, name: fmt::Arguments<'_>, unit: &'static str, v: f64) {
        if let Some(c) = self.cols.as_mut() {
            c.push(Column { name: name.to_string(), unit });
        }
        self.vals.push(v);
    }
}

/// Units of a chart coordinate and of its rate.
fn coord_units(name: &str) -> (&'static str, &'static str) {
    match name {
        "phi" | "theta" => ("rad", "rad/T"),
        _ => ("L", "L/T"),
    }
}

/// Generators of the ambient isometries recorded as momentum maps.
fn generators<const E: usize>() -> Vec<(String, SMatrix<f64, E, E>)> {
    if E == 3 {
        vec![("p_phi".into(), SMatrix::<f64, E, E>::from_fn(|i, j| Z_ROTATION[(i, j)]))]
    } else {
        let mut out = Vec::new();
        for a in 0..E {
            for b in a + 1..E {
                let m = SMatrix::<f64, E, E>::from_fn(|i, j| {
                    if i == a && j == b {
                        -1.0
                    } else if i == b && j == a {
                        1.0
                    } else {
                        0.0
                    }
                });
                out.push((format!("J_{a}{b}"), m));
            }
        }
        out
    }
}

/// A splitting step, if the model has exact free flows.
pub(crate) type SplitResult<S> = Option<Result<StepOutput<<S as System>::State>, StepFault>>;

/// What a model reports in a record, in the column order of the module docs,
/// and which model-specific methods it supports.
pub(crate) trait Observe: System<State: GroupNumerics + Send> + Clone + Send + 'static {
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>);
    /// One step of the splitting `m` (the model must be
    /// [`Splittable`](crate::method::Splittable)); `None` if the model has no
    /// exact free flow.
    fn split_step(&self, m: &Splitting, t: f64, y: &Self::State, h: f64) -> SplitResult<Self>;
}

/// Bundles on which the point model is splittable (constant curvature).
pub(crate) trait SplitPoint<const N: usize, const E: usize>: FrameBundle<N, E> + Sized {
    fn split<P: Potential<N, E>>(m: &Splitting, sys: &PointModel<Self, P, N, E>, t: f64, y: &<PointModel<Self, P, N, E> as System>::State, h: f64) -> SplitResult<PointModel<Self, P, N, E>>
    where
        PointModel<Self, P, N, E>: System,
        <PointModel<Self, P, N, E> as System>::State: GroupNumerics;
}

/// Bundles on which the 2-D gyroscope is splittable.
pub(crate) trait SplitGyro2: FrameBundle<2, 3> + Sized {
    fn split<P: Potential<2, 3>>(m: &Splitting, sys: &Gyroscope2Model<Self, P>, t: f64, y: &<Gyroscope2Model<Self, P> as System>::State, h: f64) -> SplitResult<Gyroscope2Model<Self, P>>
    where
        Gyroscope2Model<Self, P>: System,
        <Gyroscope2Model<Self, P> as System>::State: GroupNumerics;
}

/// Bundles on which the 3-D gyroscope is splittable.
pub(crate) trait SplitGyro3: FrameBundle<3, 4> + Sized {
    fn split<P: Potential<3, 4>>(m: &Splitting, sys: &Gyroscope3Model<Self, P>, t: f64, y: &<Gyroscope3Model<Self, P> as System>::State, h: f64) -> SplitResult<Gyroscope3Model<Self, P>>
    where
        Gyroscope3Model<Self, P>: System,
        <Gyroscope3Model<Self, P> as System>::State: GroupNumerics;
}

/// The splitting impls: `exact` bundles step with the method's exact free
/// flows, `none` bundles (T², whose curvature varies) have none.
macro_rules! split_impls {
    ($tr:path, $n:literal, $e:literal, $model:ty; exact: $($b:ty),+; none: $($nb:ty),*) => {
        $(impl $tr for $b {
            fn split<P: Potential<$n, $e>>(m: &Splitting, sys: &$model, t: f64, y: &<$model as System>::State, h: f64) -> SplitResult<$model>
            where
                $model: System,
                <$model as System>::State: GroupNumerics,
            {
                Some(Method::step(m, sys, t, y, h, StepRequest::plain()))
            }
        })+
        $(impl $tr for $nb {
            fn split<P: Potential<$n, $e>>(_: &Splitting, _: &$model, _: f64, _: &<$model as System>::State, _: f64) -> SplitResult<$model>
            where
                $model: System,
                <$model as System>::State: GroupNumerics,
            {
                None
            }
        })*
    };
}

split_impls!(SplitPoint<2, 3>, 2, 3, PointModel<Self, P, 2, 3>; exact: Sphere2, Hyperbolic2; none: Torus2);
split_impls!(SplitPoint<3, 4>, 3, 4, PointModel<Self, P, 3, 4>; exact: Sphere3; none:);
split_impls!(SplitGyro2, 2, 3, Gyroscope2Model<Self, P>; exact: Sphere2, Hyperbolic2; none: Torus2);
split_impls!(SplitGyro3, 3, 4, Gyroscope3Model<Self, P>; exact: Sphere3; none:);

#[allow(clippy::too_many_arguments)]
fn observe_common<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    sel: Sel,
    t: f64,
    x: &SVector<f64, E>,
    v: &SVector<f64, E>,
    frame: Option<&SMatrix<f64, E, N>>,
    row: &mut Row<'_>,
    extra_coords: impl FnOnce(&mut Row<'_>),
) {
    row.put(format_args!("t"), "T", t);
    if sel.has(Quantity::Position) {
        for i in 0..E {
            row.put(format_args!("x{i}"), "L", x[i]);
        }
    }
    if sel.has(Quantity::Velocity) {
        for i in 0..E {
            row.put(format_args!("v{i}"), "L/T", v[i]);
        }
    }
    if sel.has(Quantity::Frame) {
        if let Some(e) = frame {
            for a in 0..N {
                for i in 0..E {
                    row.put(format_args!("e{}_{i}", a + 1), "1", e[(i, a)]);
                }
            }
        }
    }
    if sel.has(Quantity::Coordinates) {
        let names = bundle.coordinate_names();
        let (c, cd) = match bundle.chart(x) {
            Ok(c) => {
                let cd = bundle.chart_tangent(x, v).unwrap_or(SVector::from_element(f64::NAN));
                (c, cd)
            }
            Err(_) => (SVector::from_element(f64::NAN), SVector::from_element(f64::NAN)),
        };
        for i in 0..N {
            row.put(format_args!("{}", names[i]), coord_units(names[i]).0, c[i]);
        }
        for i in 0..N {
            row.put(format_args!("{}_dot", names[i]), coord_units(names[i]).1, cd[i]);
        }
        extra_coords(row);
    }
}

fn observe_tail<S: System, const E: usize>(
    sys: &S,
    sel: Sel,
    y: &S::State,
    row: &mut Row<'_>,
    momentum_map: impl Fn(&SMatrix<f64, E, E>) -> f64,
) {
    if sel.has(Quantity::Energy) {
        row.put(format_args!("energy"), "M L^2/T^2", sys.energy(y));
    }
    if sel.has(Quantity::MomentumMap) {
        for (name, g) in generators::<E>() {
            row.put(format_args!("{name}"), "M L^2/T", momentum_map(&g));
        }
    }
    if sel.has(Quantity::Defect) {
        row.put(format_args!("defect"), "1", sys.defect(y));
    }
}

impl<B, P, const N: usize, const E: usize> Observe for PointModel<B, P, N, E>
where
    B: SplitPoint<N, E> + 'static,
    P: Potential<N, E> + Clone + 'static,
    PointModel<B, P, N, E>: System<State = crate::dynamics::PointState<B::Group, N>>,
    crate::dynamics::PointState<B::Group, N>: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v) = (self.position(y), self.velocity(y));
        observe_common::<B, N, E>(self.bundle(), sel, t, &x, &v, None, row, |_| {});
        observe_tail::<Self, E>(self, sel, y, row, |g| self.momentum_map(y, g).unwrap_or(f64::NAN));
    }
    fn split_step(&self, m: &Splitting, t: f64, y: &Self::State, h: f64) -> SplitResult<Self> {
        B::split(m, self, t, y, h)
    }
}

impl<B, P> Observe for Gyroscope2Model<B, P>
where
    B: SplitGyro2 + 'static,
    P: Potential<2, 3> + Clone + 'static,
    <Gyroscope2Model<B, P> as System>::State: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v, e) = (self.position(y), self.velocity(y), self.body_frame(y));
        observe_common::<B, 2, 3>(self.bundle(), sel, t, &x, &v, Some(&e), row, |row| {
            let alpha = match self.bundle().to_chart(&y.0 .0) {
                Ok((_, u)) => u[(1, 0)].atan2(u[(0, 0)]) + self.internal_angle(y),
                Err(_) => f64::NAN,
            };
            row.put(format_args!("alpha"), "rad", alpha);
        });
        if sel.has(Quantity::Momenta) {
            row.put(format_args!("spin"), "M L^2/T", self.spin(y));
        }
        observe_tail::<Self, 3>(self, sel, y, row, |g| self.momentum_map(y, g).unwrap_or(f64::NAN));
    }
    fn split_step(&self, m: &Splitting, t: f64, y: &Self::State, h: f64) -> SplitResult<Self> {
        B::split(m, self, t, y, h)
    }
}

impl<B, P> Observe for Gyroscope3Model<B, P>
where
    B: SplitGyro3 + 'static,
    P: Potential<3, 4> + Clone + 'static,
    <Gyroscope3Model<B, P> as System>::State: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v, e) = (self.position(y), self.velocity(y), self.body_frame(y));
        observe_common::<B, 3, 4>(self.bundle(), sel, t, &x, &v, Some(&e), row, |_| {});
        if sel.has(Quantity::Momenta) {
            let s = self.spin_body(y);
            for a in 0..3 {
                row.put(format_args!("spin_{}", a + 1), "M L^2/T", s[a]);
            }
        }
        observe_tail::<Self, 4>(self, sel, y, row, |g| self.momentum_map(y, g).unwrap_or(f64::NAN));
    }
    fn split_step(&self, m: &Splitting, t: f64, y: &Self::State, h: f64) -> SplitResult<Self> {
        B::split(m, self, t, y, h)
    }
}

impl<B, V, C, const N: usize, const E: usize> Observe for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E> + 'static,
    V: Potential<N, E> + Clone + 'static,
    C: InternalConstraint<N>,
    C::Body: Clone,
    AffineBodyModel<B, V, C, N, E>: System<State = crate::dynamics::affine::BodyState<B, C, N, E>> + Clone,
    crate::dynamics::affine::BodyState<B, C, N, E>: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v, e) = (self.position(y), self.velocity(y), self.body_frame(y));
        observe_common::<B, N, E>(self.bundle(), sel, t, &x, &v, Some(&e), row, |row| {
            let s = self.stretches(y);
            for a in 0..N {
                row.put(format_args!("stretch_{}", a + 1), "1", s[a]);
            }
        });
        if sel.has(Quantity::Momenta) {
            let k = self.hypermomentum(y);
            for a in 0..N {
                for b in 0..N {
                    row.put(format_args!("k_{}{}", a + 1, b + 1), "M L^2/T", k[(a, b)]);
                }
            }
        }
        observe_tail::<Self, E>(self, sel, y, row, |g| self.noether_charge(y, g).unwrap_or(f64::NAN));
    }
    /// Affine bodies have no exact free flow.
    fn split_step(&self, _: &Splitting, _: f64, _: &Self::State, _: f64) -> SplitResult<Self> {
        None
    }
}

/// The methods available in scenes (a closed set of types, selected by name).
#[derive(Debug, Clone, Copy)]
pub(crate) enum MethodChoice {
    LieEuler(Rkmk<1>),
    Heun(Rkmk<2>),
    Kutta3(Rkmk<3>),
    Rk4(Rkmk<4>),
    Dopri5(Rkmk<7>),
    Dop853(Rkmk<12>),
    Butcher6(Rkmk<7>),
    /// A splitting method (only for models with exact free flows) and its name.
    Split(Splitting, &'static str),
    /// The implicit Lie midpoint rule (any model).
    Implicit(ImplicitMidpoint),
}

/// A [`MethodChoice`] as one [`Method`] for any observed model: the
/// type-level dispatch of the model-specific methods.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Chosen(pub MethodChoice);

impl<S: Observe> Method<S> for Chosen {
    fn info(&self) -> MethodInfo {
        match &self.0 {
            MethodChoice::LieEuler(m) => Method::<S>::info(m),
            MethodChoice::Heun(m) => Method::<S>::info(m),
            MethodChoice::Kutta3(m) => Method::<S>::info(m),
            MethodChoice::Rk4(m) => Method::<S>::info(m),
            MethodChoice::Dopri5(m) | MethodChoice::Butcher6(m) => Method::<S>::info(m),
            MethodChoice::Dop853(m) => Method::<S>::info(m),
            MethodChoice::Implicit(m) => Method::<S>::info(m),
            // The scene's name for the method, else as the splitting reports.
            MethodChoice::Split(m, name) => MethodInfo { name, ..m.method_info() },
        }
    }

    fn step(&self, sys: &S, t: f64, y: &S::State, h: f64, req: StepRequest<Alg<S>>) -> Result<StepOutput<S::State>, StepFault> {
        match &self.0 {
            MethodChoice::LieEuler(m) => m.step(sys, t, y, h, req),
            MethodChoice::Heun(m) => m.step(sys, t, y, h, req),
            MethodChoice::Kutta3(m) => m.step(sys, t, y, h, req),
            MethodChoice::Rk4(m) => m.step(sys, t, y, h, req),
            MethodChoice::Dopri5(m) | MethodChoice::Butcher6(m) => m.step(sys, t, y, h, req),
            MethodChoice::Dop853(m) => m.step(sys, t, y, h, req),
            MethodChoice::Implicit(m) => m.step(sys, t, y, h, req),
            // `Engine::new` refuses a splitting for a model without one, so
            // `None` does not occur; it is reported, not hidden, if it does.
            MethodChoice::Split(m, _) => sys
                .split_step(m, t, y, h)
                .unwrap_or(Err(StepFault::OutsideChart { reason: "no exact free flow for a splitting method on this model", t_eval: t })),
        }
    }
}

/// How a run samples its records.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Sampling {
    Every(u64),
    Times(Vec<f64>),
}

/// Step-size policy of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Stepping {
    Fixed(f64),
    Adaptive { rtol: f64, atol: f64 },
}

/// Everything a run needs besides the engine.
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    pub t0: f64,
    pub t_end: f64,
    pub stepping: Stepping,
    pub sampling: Sampling,
    pub max_steps: u64,
    pub sel: Sel,
    pub events: Vec<SceneEvent>,
}

/// The bookkeeping of a run: sink, cancel flag, progress, summary.
pub(crate) struct Ctx<'a> {
    pub sink: &'a mut dyn RecordSink,
    pub cancel: &'a AtomicBool,
    pub progress: &'a mut dyn FnMut(&Progress),
    pub summary: RunSummary,
    pub buf: Vec<f64>,
    pub last_recorded_t: Option<f64>,
    pub last_progress: Instant,
    /// Columns of the momentum maps in a record, and their first values.
    pub mm_idx: Vec<usize>,
    pub mm0: Vec<f64>,
    /// Per event: last non-zero sign of `g`, and its last value.
    pub ev_sign: Vec<f64>,
    pub ev_g: Vec<f64>,
    /// A full record (every quantity) for the event functions.
    pub full: Vec<f64>,
}

impl Ctx<'_> {
    fn note(&mut self, energy: f64, defect: f64) {
        if self.summary.records == 0 {
            self.mm0 = self.mm_idx.iter().map(|&j| self.buf[j]).collect();
        }
        for (k, &j) in self.mm_idx.iter().enumerate() {
            let d = (self.buf[j] - self.mm0[k]).abs();
            let m = &mut self.summary.momentum_map_drift;
            *m = if d.is_nan() || m.is_nan() { f64::NAN } else { m.max(d) };
        }
        let s = &mut self.summary;
        if s.records == 0 {
            s.energy_initial = energy;
        }
        let d = (energy - s.energy_initial).abs();
        s.energy_drift = if d.is_nan() || s.energy_drift.is_nan() { f64::NAN } else { s.energy_drift.max(d) };
        s.max_defect = if defect.is_nan() || s.max_defect.is_nan() { f64::NAN } else { s.max_defect.max(defect) };
        s.records += 1;
    }

    pub(crate) fn progress(&mut self, plan: &Plan, t: f64, force: bool) {
        let now = Instant::now();
        if force || now.duration_since(self.last_progress).as_millis() >= 50 {
            self.last_progress = now;
            let span = plan.t_end - plan.t0;
            let p = Progress { t, t0: plan.t0, t_end: plan.t_end, fraction: ((t - plan.t0) / span).clamp(0.0, 1.0), steps: self.summary.steps };
            (self.progress)(&p);
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// The object-safe face of an engine.
pub(crate) trait DynEngine: Send {
    fn columns(&self, sel: Sel) -> Vec<Column>;
    fn row(&self, sel: Sel, out: &mut Vec<f64>);
    fn t(&self) -> f64;
    fn energy(&self) -> f64;
    fn defect(&self) -> f64;
    fn step(&mut self, h: f64) -> Result<(), SolveError>;
    fn reset(&mut self);
    fn method_name(&self) -> &'static str;
    fn run(&mut self, plan: &Plan, ctx: &mut Ctx<'_>) -> Result<(), RunError>;
}

pub(crate) struct Engine<S: Observe> {
    problem: Problem<S>,
    method: MethodChoice,
    t: f64,
    y: S::State,
}

impl<S: Observe> Engine<S> {
    pub(crate) fn new(system: S, y0: S::State, span: (f64, f64), method: MethodChoice) -> Result<Self, SolveError> {
        if let MethodChoice::Split(m, name) = &method {
            if system.split_step(m, span.0, &y0, 0.0).is_none() {
                return Err(SolveError::InvalidOptions { reason: format!("{name}: splitting needs exact free flows (S2, H2, S3; point or gyroscope)") });
            }
        }
        let problem = Problem::new(system, y0, span)?;
        Ok(Engine { t: span.0, y: *problem.y0(), problem, method })
    }

    fn record(&self, plan: &Plan, ctx: &mut Ctx<'_>, t: f64, y: &S::State) -> Result<(), RunError> {
        if ctx.last_recorded_t == Some(t) {
            return Ok(());
        }
        let sys = self.problem.system();
        let mut buf = std::mem::take(&mut ctx.buf);
        buf.clear();
        sys.observe(plan.sel, t, y, &mut Row { cols: None, vals: &mut buf });
        let res = ctx.sink.record(&buf);
        ctx.buf = buf;
        res?;
        ctx.note(sys.energy(y), sys.defect(y));
        ctx.last_recorded_t = Some(t);
        Ok(())
    }

    /// `f` of the full record (every quantity) at `(t, y)`, observed into
    /// the reused buffer `ctx.full`.
    fn with_full_record<R>(&self, ctx: &mut Ctx<'_>, t: f64, y: &S::State, f: impl FnOnce(&[f64]) -> R) -> R {
        let mut full = std::mem::take(&mut ctx.full);
        full.clear();
        self.problem.system().observe(Sel::ALL, t, y, &mut Row { cols: None, vals: &mut full });
        let r = f(&full);
        ctx.full = full;
        r
    }

    /// `g_k(t, y)` of every event into `out`.
    fn event_values(&self, plan: &Plan, ctx: &mut Ctx<'_>, t: f64, y: &S::State, out: &mut Vec<f64>) {
        out.clear();
        self.with_full_record(ctx, t, y, |full| out.extend(plan.events.iter().map(|e| (e.g)(t, full))));
    }

    fn event_value(&self, plan: &Plan, ctx: &mut Ctx<'_>, k: usize, t: f64, y: &S::State) -> f64 {
        self.with_full_record(ctx, t, y, |full| (plan.events[k].g)(t, full))
    }

    /// The signs of the events at the start of a run.
    fn events_start(&self, plan: &Plan, ctx: &mut Ctx<'_>, t: f64, y: &S::State) -> Result<(), RunError> {
        if plan.events.is_empty() {
            return Ok(());
        }
        let mut g = Vec::new();
        self.event_values(plan, ctx, t, y, &mut g);
        if g.iter().any(|v| !v.is_finite()) {
            return Err(RunError::Integration(SolveError::NonFinite { what: NonFiniteSource::Event, t_eval: t, t, h: 0.0 }));
        }
        ctx.ev_sign = g.iter().map(|v| if *v == 0.0 { 0.0 } else { v.signum() }).collect();
        ctx.ev_g = g;
        Ok(())
    }

    /// Checks the events over the accepted step `(t0, y(t0)) → (t1, y1)`;
    /// `at(τ)` is the state at `τ` in between (the method's sub-step or dense
    /// output). Reports the crossings in time order to the sink and returns
    /// the first terminal one (its time, state and name).
    fn events_on_step(
        &self,
        plan: &Plan,
        ctx: &mut Ctx<'_>,
        t0: f64,
        t1: f64,
        y1: &S::State,
        at: &dyn Fn(f64) -> Option<S::State>,
    ) -> Result<Option<(f64, S::State, String)>, RunError> {
        if plan.events.is_empty() {
            return Ok(None);
        }
        let h = t1 - t0;
        let nonfinite = |t_eval: f64| RunError::Integration(SolveError::NonFinite { what: NonFiniteSource::Event, t_eval, t: t0, h });
        let mut g1 = Vec::new();
        self.event_values(plan, ctx, t1, y1, &mut g1);
        let mut hits: Vec<(f64, usize, bool, S::State)> = Vec::new();
        for (k, e) in plan.events.iter().enumerate() {
            let (s0, g0, g) = (ctx.ev_sign[k], ctx.ev_g[k], g1[k]);
            if !g.is_finite() {
                return Err(nonfinite(t1));
            }
            let s1 = if g == 0.0 { 0.0 } else { g.signum() };
            ctx.ev_g[k] = g;
            if s0 == 0.0 {
                ctx.ev_sign[k] = s1;
                continue;
            }
            if s1 == s0 {
                continue;
            }
            // A sign change (or a zero at the step's end).
            ctx.ev_sign[k] = if s1 == 0.0 { -s0 } else { s1 };
            let rising = s0 < 0.0;
            let wanted = match e.direction {
                EventDirection::Either => true,
                EventDirection::Rising => rising,
                EventDirection::Falling => !rising,
            };
            if !wanted || g0 == 0.0 {
                // g0 = 0: this zero was reported at the end of the last step.
                continue;
            }
            let (tr, yr) = if s1 == 0.0 {
                (t1, *y1)
            } else {
                let mut bad = None;
                let (tr, _) = {
                    let mut f = |tau: f64| -> f64 {
                        match at(tau) {
                            Some(y) => {
                                let v = self.event_value(plan, ctx, k, tau, &y);
                                if !v.is_finite() {
                                    bad = Some(tau);
                                }
                                v
                            }
                            None => {
                                bad = Some(tau);
                                f64::NAN
                            }
                        }
                    };
                    crate::solve::event::brent(&mut f, t0, t1, g0, g, 0.0)
                };
                if let Some(tb) = bad {
                    return Err(nonfinite(tb));
                }
                match at(tr) {
                    Some(y) => (tr, y),
                    None => return Err(nonfinite(tr)),
                }
            };
            hits.push((tr, k, rising, yr));
        }
        let dir = h.signum();
        hits.sort_by(|a, b| (dir * a.0).total_cmp(&(dir * b.0)));
        let mut stop = None;
        for (tr, k, rising, yr) in hits {
            let e = &plan.events[k];
            let mut row = Vec::new();
            self.problem.system().observe(plan.sel, tr, &yr, &mut Row { cols: None, vals: &mut row });
            ctx.sink.event(&EventHit { index: k, name: e.name.clone(), t: tr, row, rising, terminal: e.terminal })?;
            ctx.summary.events += 1;
            if e.terminal {
                stop = Some((tr, yr, e.name.clone()));
                break;
            }
        }
        Ok(stop)
    }

    /// Ends a run at a terminal event.
    fn stop_at_event(&mut self, plan: &Plan, ctx: &mut Ctx<'_>, hit: (f64, S::State, String)) -> Result<(), RunError> {
        let (t, y, name) = hit;
        self.t = t;
        self.y = y;
        self.record(plan, ctx, t, &y)?;
        ctx.summary.stop = SceneStop::Event(name);
        Ok(())
    }

    fn run_fixed<M: Method<S>>(&mut self, m: &M, h: f64, plan: &Plan, ctx: &mut Ctx<'_>) -> Result<(), RunError> {
        let (t0, t_end) = (plan.t0, plan.t_end);
        let span = t_end - t0;
        let dir = span.signum();
        let n = (span.abs() / h).ceil().max(1.0);
        if n > plan.max_steps as f64 {
            return Err(RunError::Integration(SolveError::MaxSteps { t: t0, h, max_steps: plan.max_steps as usize }));
        }
        let n = n as u64;
        let (every, times): (u64, &[f64]) = match &plan.sampling {
            Sampling::Every(k) => (*k, &[]),
            Sampling::Times(ts) => (0, ts.as_slice()),
        };
        let mut k = 0usize;
        let mut t = self.t;
        let mut y = self.y;
        let record_due = |t: f64, k: &mut usize| {
            let mut due = false;
            while *k < times.len() && dir * (times[*k] - t) <= 0.0 {
                due = true;
                *k += 1;
            }
            due
        };
        if every > 0 || record_due(t, &mut k) {
            self.record(plan, ctx, t, &y)?;
        }
        self.events_start(plan, ctx, t, &y)?;
        let mut i = 0u64;
        let mut since_check = 0usize;
        while i < n {
            let grid = if i + 1 == n { t_end } else { t0 + span * ((i + 1) as f64 / n as f64) };
            let target = if k < times.len() && dir * (times[k] - grid) < 0.0 { times[k] } else { grid };
            let step_h = target - t;
            let out = match m.step(self.problem.system(), t, &y, step_h, StepRequest::plain()) {
                Ok(o) => o,
                Err(f) => {
                    self.t = t;
                    self.y = y;
                    return Err(RunError::Integration(solve::fault_error(f, t, step_h)));
                }
            };
            ctx.summary.rhs_evals += out.cost.rhs as u64;
            ctx.summary.steps += 1;
            if !plan.events.is_empty() {
                let (tp, yp) = (t, y);
                let sys = self.problem.system();
                let at = |tau: f64| m.step(sys, tp, &yp, tau - tp, StepRequest::plain()).ok().map(|o| o.y);
                if let Some(hit) = self.events_on_step(plan, ctx, tp, target, &out.y, &at)? {
                    return self.stop_at_event(plan, ctx, hit);
                }
            }
            t = target;
            y = out.y;
            if target == grid {
                i += 1;
            }
            let due_time = record_due(t, &mut k);
            let due_every = every > 0 && (i % every == 0 || i == n) && target == grid;
            if due_time || due_every {
                self.t = t;
                self.y = y;
                self.record(plan, ctx, t, &y)?;
            }
            since_check += 1;
            if since_check >= CHECK_EVERY {
                since_check = 0;
                self.t = t;
                self.y = y;
                ctx.progress(plan, t, false);
                if ctx.cancelled() {
                    ctx.summary.stop = SceneStop::Cancelled;
                    self.record(plan, ctx, t, &y)?;
                    return Ok(());
                }
            }
        }
        self.t = t;
        self.y = y;
        if every > 0 {
            self.record(plan, ctx, t, &y)?;
        }
        Ok(())
    }

    fn run_adaptive<const ST: usize>(&mut self, m: &Rkmk<ST>, rtol: f64, atol: f64, plan: &Plan, ctx: &mut Ctx<'_>) -> Result<(), RunError> {
        let t_end = plan.t_end;
        let dir = (t_end - plan.t0).signum();
        let (every, times): (u64, &[f64]) = match &plan.sampling {
            Sampling::Every(k) => (*k, &[]),
            Sampling::Times(ts) => (0, ts.as_slice()),
        };
        let mut k = 0usize;
        let mut at_start = every > 0;
        while k < times.len() && dir * (times[k] - self.t) <= 0.0 {
            k += 1;
            at_start = true;
        }
        if at_start {
            let y = self.y;
            self.record(plan, ctx, self.t, &y)?;
        }
        let y = self.y;
        self.events_start(plan, ctx, self.t, &y)?;
        let with_events = !plan.events.is_empty();
        let mut h0: Option<f64> = None;
        let mut step_index = 0u64;
        loop {
            let remaining = plan.max_steps.saturating_sub(ctx.summary.steps);
            if remaining == 0 {
                return Err(RunError::Integration(SolveError::MaxSteps {
                    t: self.t,
                    h: h0.unwrap_or(f64::NAN),
                    max_steps: plan.max_steps as usize,
                }));
            }
            let chunk = (CHUNK as u64).min(remaining) as usize;
            let problem = self.problem.clone().with_span((self.t, t_end)).and_then(|p| p.with_y0(self.y)).map_err(RunError::Integration)?;
            let mut ad = Adaptive::new(rtol, atol);
            ad.h0 = h0;
            let opts = Options::adaptive_with(ad).max_steps(chunk).save(Save::Steps).dense(!times.is_empty() || with_events);
            let (sol, err) = match solve::solve(&problem, m, &opts) {
                Ok(sol) => (sol, None),
                Err(f) => (*f.solution, Some(f.error)),
            };
            let st = sol.stats();
            ctx.summary.rejected += st.rejected as u64;
            ctx.summary.rhs_evals += st.rhs_evals as u64;
            let ts = sol.times();
            let ys = sol.states();
            if ts.len() >= 2 {
                h0 = Some((ts[ts.len() - 1] - ts[ts.len() - 2]).abs());
            }
            let (t_last, y_last) = sol.last();
            let y_last = *y_last;
            for j in 1..ts.len() {
                if ts[j] == ts[j - 1] {
                    continue;
                }
                let hit = if with_events {
                    let at = |tau: f64| sol.sample(tau);
                    self.events_on_step(plan, ctx, ts[j - 1], ts[j], &ys[j], &at)?
                } else {
                    None
                };
                // Records at requested times inside this step (up to a
                // terminal event), from the dense output.
                let t_lim = hit.as_ref().map_or(ts[j], |h| h.0);
                while k < times.len() && dir * (times[k] - t_lim) <= 0.0 {
                    if let Some(yk) = sol.sample(times[k]) {
                        self.record(plan, ctx, times[k], &yk)?;
                    }
                    k += 1;
                }
                step_index += 1;
                ctx.summary.steps += 1;
                if let Some(hit) = hit {
                    return self.stop_at_event(plan, ctx, hit);
                }
                if every > 0 && (step_index % every == 0) {
                    self.record(plan, ctx, ts[j], &ys[j])?;
                }
            }
            self.t = t_last;
            self.y = y_last;
            ctx.progress(plan, self.t, false);
            match err {
                None => {
                    if every > 0 {
                        self.record(plan, ctx, self.t, &y_last)?;
                    }
                    return Ok(());
                }
                Some(SolveError::MaxSteps { .. }) if self.t != t_end => {}
                Some(e) => return Err(RunError::Integration(e)),
            }
            if ctx.cancelled() {
                ctx.summary.stop = SceneStop::Cancelled;
                self.record(plan, ctx, self.t, &y_last)?;
                return Ok(());
            }
        }
    }
}

impl<S: Observe> DynEngine for Engine<S> {
    fn columns(&self, sel: Sel) -> Vec<Column> {
        let mut cols = Vec::new();
        let mut vals = Vec::new();
        self.problem.system().observe(sel, self.t, &self.y, &mut Row { cols: Some(&mut cols), vals: &mut vals });
        cols
    }

    fn row(&self, sel: Sel, out: &mut Vec<f64>) {
        out.clear();
        self.problem.system().observe(sel, self.t, &self.y, &mut Row { cols: None, vals: out });
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn energy(&self) -> f64 {
        self.problem.system().energy(&self.y)
    }

    fn defect(&self) -> f64 {
        self.problem.system().defect(&self.y)
    }

    fn step(&mut self, h: f64) -> Result<(), SolveError> {
        if !(h.is_finite() && h != 0.0) {
            return Err(SolveError::InvalidParameter { field: "h", value: h, allowed: "finite and ≠ 0" });
        }
        let sys = self.problem.system();
        let out = Chosen(self.method).step(sys, self.t, &self.y, h, StepRequest::plain())
            .map_err(|f| solve::fault_error(f, self.t, h))?;
        self.t += h;
        self.y = out.y;
        Ok(())
    }

    fn reset(&mut self) {
        self.t = self.problem.t0();
        self.y = *self.problem.y0();
    }

    fn method_name(&self) -> &'static str {
        Method::<S>::info(&Chosen(self.method)).name
    }

    fn run(&mut self, plan: &Plan, ctx: &mut Ctx<'_>) -> Result<(), RunError> {
        self.reset();
        let method = self.method;
        let result = match plan.stepping {
            Stepping::Fixed(h) => self.run_fixed(&Chosen(method), h, plan, ctx),
            Stepping::Adaptive { rtol, atol } => match &method {
                MethodChoice::Dopri5(m) => self.run_adaptive(m, rtol, atol, plan, ctx),
                MethodChoice::Dop853(m) => self.run_adaptive(m, rtol, atol, plan, ctx),
                _ => Err(RunError::Integration(SolveError::InvalidOptions {
                    reason: "adaptive stepping needs an embedded pair (dopri5, dop853)".into(),
                })),
            },
        };
        if let Err(RunError::Integration(_)) = &result {
            // Keep the partial output: the last good state is always recorded.
            let y = self.y;
            let t = self.t;
            self.record(plan, ctx, t, &y)?;
        }
        ctx.summary.t_reached = self.t;
        result
    }
}

/// Boxes an engine for `system` from `y0`.
pub(crate) fn boxed<S: Observe>(
    system: S,
    y0: S::State,
    span: (f64, f64),
    method: MethodChoice,
) -> Result<Box<dyn DynEngine>, SolveError> {
    Ok(Box::new(Engine::new(system, y0, span, method)?))
}
