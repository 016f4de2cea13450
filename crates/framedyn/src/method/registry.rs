//! The method registry: every method of framedyn by name, as data.
//!
//! Each [`MethodEntry`] holds a method's scene name (`name = "rk4"` in a
//! scene file, `framedyn.methods()` in Python), its display name (what
//! summaries and [`MethodInfo::name`] show), its [`Family`], order, whether
//! it can step adaptively, what it [`Needs`] of a model, its parameters and
//! its constructor. Scene parsing, the command line's help, the Python
//! listing and the method table of the guide all read [`METHODS`]; the
//! typed constructors ([`Rkmk::rk4`], [`Splitting::strang`], …) take their
//! names from here. Adding a method is one entry in [`METHODS`] (and, for a
//! new type of method, one variant of [`AnyMethod`] or [`ChartMethod`]).
//!
//! ```
//! use framedyn::method::registry::{lookup, MethodParams};
//!
//! let entry = lookup("dop853").unwrap();
//! assert_eq!((entry.order, entry.adaptive), (8, true));
//! let method = entry.build(&MethodParams::default()).unwrap();
//! assert_eq!(method.display(), entry.display);
//! assert!(lookup("rk5").unwrap_err().to_string().contains("rk4"));
//! ```

use super::baseline::{ChartSystem, CoordinateRk};
use super::{Alg, GroupNumerics, ImplicitMidpoint, Method, MethodError, MethodInfo, Rkmk, Splitting, StepFault, StepOutput, StepRequest};
use crate::coords::Lagrangian;
use crate::dynamics::{SplitDispatch, System};

/// The kind of a method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Runge–Kutta–Munthe-Kaas ([`Rkmk`]): any model.
    Rkmk,
    /// Symplectic splitting with exact free flows ([`Splitting`]).
    Splitting,
    /// The implicit Lie midpoint rule ([`ImplicitMidpoint`]).
    Implicit,
    /// A classical Runge–Kutta method on the paper's chart equations
    /// ([`CoordinateRk`]): the baseline that fails at chart poles.
    Coordinate,
}

impl Family {
    /// The family's name in listings.
    pub fn label(self) -> &'static str {
        match self {
            Family::Rkmk => "RKMK",
            Family::Splitting => "splitting",
            Family::Implicit => "implicit",
            Family::Coordinate => "coordinate",
        }
    }
}

/// What a method needs of a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Needs {
    /// Nothing: any model.
    Nothing,
    /// Exact free flows ([`SplitDispatch`]): points and gyroscopes on S², H², S³.
    ExactFreeFlow,
    /// The paper's chart equations of the manifold × body
    /// ([`coords`](crate::coords)); fails where the chart is singular.
    Chart,
}

impl Needs {
    /// In words, for listings and error messages.
    pub fn describe(self) -> &'static str {
        match self {
            Needs::Nothing => "any model",
            Needs::ExactFreeFlow => "exact free flows: points and gyroscopes on S2, H2, S3",
            Needs::Chart => "the paper's chart equations (fails at chart poles)",
        }
    }
}

/// Parameters a method may take besides the step (scene `[method]` fields).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MethodParams {
    /// Newton tolerance of the implicit midpoint rule (default 1e-14).
    pub newton_tol: Option<f64>,
    /// Newton iterations of the implicit midpoint rule (default 30).
    pub newton_max_iter: Option<u32>,
}

/// One method of the registry.
#[derive(Debug, Clone, Copy)]
pub struct MethodEntry {
    /// The scene name, e.g. `"rk4"`.
    pub name: &'static str,
    /// The display name, e.g. `"RKMK4"` ([`MethodInfo::name`]).
    pub display: &'static str,
    /// The family.
    pub family: Family,
    /// Order of the propagated solution.
    pub order: u32,
    /// Order of the error estimate, for the methods that step adaptively.
    pub embedded_order: Option<u32>,
    /// Whether it can step adaptively (`rtol`/`atol`) as well as with a fixed `h`.
    pub adaptive: bool,
    /// What it needs of a model.
    pub needs: Needs,
    /// The names of the parameters it takes (scene `[method]` fields other
    /// than `name`, `h`, `rtol`, `atol`, `max_steps`).
    pub params: &'static [&'static str],
    /// One line: what it is for.
    pub summary: &'static str,
    build: fn(&MethodParams) -> Result<Built, MethodError>,
}

impl MethodEntry {
    /// The method, with `params` (each checked: a parameter the method does
    /// not take is an error naming it, a value out of range names the range).
    pub fn build(&self, params: &MethodParams) -> Result<Built, MethodError> {
        for (field, given) in [("newton_tol", params.newton_tol.is_some()), ("newton_max_iter", params.newton_max_iter.is_some())] {
            if given && !self.params.contains(&field) {
                return Err(MethodError::Unsupported { method: self.display, reason: "takes no Newton options (newton_tol, newton_max_iter are for implicit_midpoint)" });
            }
        }
        (self.build)(params)
    }
}

/// A built method: a Lie-group method for the frame-bundle models, or a
/// coordinate method for the chart equations.
#[derive(Debug, Clone, Copy)]
pub enum Built {
    /// Integrates the frame-bundle models ([`AnyMethod`]).
    Group(AnyMethod),
    /// Integrates the chart equations ([`ChartMethod`]).
    Chart(ChartMethod),
}

impl Built {
    /// The display name.
    pub fn display(&self) -> &'static str {
        match self {
            Built::Group(m) => m.display(),
            Built::Chart(m) => m.display(),
        }
    }
}

/// Every Lie-group method of the registry as one type: a [`Method`] for any
/// model ([`SplitDispatch`] tells whether a splitting applies; a model
/// without exact free flows is refused by [`Method::check`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyMethod {
    /// Lie–Euler.
    Rkmk1(Rkmk<1>),
    /// Heun.
    Rkmk2(Rkmk<2>),
    /// Kutta 3.
    Rkmk3(Rkmk<3>),
    /// RKMK4.
    Rkmk4(Rkmk<4>),
    /// DOPRI5, Butcher 6.
    Rkmk7(Rkmk<7>),
    /// DOP853.
    Rkmk12(Rkmk<12>),
    /// A splitting.
    Split(Splitting),
    /// The implicit midpoint rule.
    Implicit(ImplicitMidpoint),
}

impl AnyMethod {
    /// The display name.
    pub fn display(&self) -> &'static str {
        match self {
            AnyMethod::Rkmk1(m) => m.name(),
            AnyMethod::Rkmk2(m) => m.name(),
            AnyMethod::Rkmk3(m) => m.name(),
            AnyMethod::Rkmk4(m) => m.name(),
            AnyMethod::Rkmk7(m) => m.name(),
            AnyMethod::Rkmk12(m) => m.name(),
            AnyMethod::Split(m) => m.method_info().name,
            AnyMethod::Implicit(_) => IMPLICIT_MIDPOINT.display,
        }
    }
}

impl<S> Method<S> for AnyMethod
where
    S: SplitDispatch,
    S::State: GroupNumerics,
{
    fn info(&self) -> MethodInfo {
        match self {
            AnyMethod::Rkmk1(m) => Method::<S>::info(m),
            AnyMethod::Rkmk2(m) => Method::<S>::info(m),
            AnyMethod::Rkmk3(m) => Method::<S>::info(m),
            AnyMethod::Rkmk4(m) => Method::<S>::info(m),
            AnyMethod::Rkmk7(m) => Method::<S>::info(m),
            AnyMethod::Rkmk12(m) => Method::<S>::info(m),
            AnyMethod::Split(m) => m.method_info(),
            AnyMethod::Implicit(m) => Method::<S>::info(m),
        }
    }

    fn check(&self, sys: &S) -> Result<(), MethodError> {
        match self {
            AnyMethod::Split(m) => match sys.as_splittable() {
                Some(s) => Method::<S::Split>::check(m, s),
                None => Err(MethodError::Unsupported { method: m.method_info().name, reason: Needs::ExactFreeFlow.describe() }),
            },
            _ => Ok(()),
        }
    }

    /// The RKMK methods and the implicit midpoint rule step the tangent
    /// lift; a splitting has no exact tangent map (`None`).
    fn tangent_step(&self, sys: &S, t: f64, y: &S::State, h: f64, xi0: &Alg<S>) -> Option<super::TangentStep<S>> {
        match self {
            AnyMethod::Rkmk1(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Rkmk2(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Rkmk3(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Rkmk4(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Rkmk7(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Rkmk12(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Implicit(m) => Method::<S>::tangent_step(m, sys, t, y, h, xi0),
            AnyMethod::Split(_) => None,
        }
    }

    // A dispatch, called (not inlined) from the driver's loops: inlined, it
    // would copy every method's step into every loop of every model
    // (docs/development.md, "What the core's size is made of"). The
    // implicit midpoint rule is called directly: its step is not inlined
    // anywhere.
    fn step(&self, sys: &S, t: f64, y: &S::State, h: f64, req: StepRequest<Alg<S>>) -> Result<StepOutput<S::State>, StepFault> {
        match self {
            AnyMethod::Rkmk1(m) => own_step(m, sys, t, y, h, req),
            AnyMethod::Rkmk2(m) => own_step(m, sys, t, y, h, req),
            AnyMethod::Rkmk3(m) => own_step(m, sys, t, y, h, req),
            AnyMethod::Rkmk4(m) => own_step(m, sys, t, y, h, req),
            AnyMethod::Rkmk7(m) => own_step(m, sys, t, y, h, req),
            AnyMethod::Rkmk12(m) => own_step(m, sys, t, y, h, req),
            AnyMethod::Implicit(m) => m.step(sys, t, y, h, req),
            AnyMethod::Split(m) => match sys.as_splittable() {
                Some(s) => own_step(m, s, t, y, h, req),
                None => Err(StepFault::Unsupported { method: m.method_info().name, reason: Needs::ExactFreeFlow.describe() }),
            },
        }
    }
}

/// One method's step as a function of its own (per model and method), so
/// that [`AnyMethod::step`] is a dispatch over calls rather than every
/// method's step inlined into one function: LLVM optimises several functions
/// of ordinary size faster, and with better inlining inside them, than one
/// function of tens of thousands of lines.
#[inline(never)]
fn own_step<S: System, M: Method<S>>(m: &M, sys: &S, t: f64, y: &S::State, h: f64, req: StepRequest<Alg<S>>) -> Result<StepOutput<S::State>, StepFault> {
    m.step(sys, t, y, h, req)
}

/// The coordinate methods of the registry as one type: a [`Method`] for the
/// chart equations of any [`Lagrangian`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ChartMethod {
    /// Classical RK4 in coordinates.
    Rk4(CoordinateRk<4>),
    /// Dormand–Prince 5(4) in coordinates.
    Dopri5(CoordinateRk<7>),
}

impl ChartMethod {
    /// The display name.
    pub fn display(&self) -> &'static str {
        match self {
            ChartMethod::Rk4(m) => m.name(),
            ChartMethod::Dopri5(m) => m.name(),
        }
    }
}

impl<L, const Q: usize> Method<ChartSystem<L, Q>> for ChartMethod
where
    L: Lagrangian<Q> + Send + Sync,
{
    fn info(&self) -> MethodInfo {
        match self {
            ChartMethod::Rk4(m) => Method::<ChartSystem<L, Q>>::info(m),
            ChartMethod::Dopri5(m) => Method::<ChartSystem<L, Q>>::info(m),
        }
    }

    fn step(
        &self,
        sys: &ChartSystem<L, Q>,
        t: f64,
        y: &<ChartSystem<L, Q> as crate::dynamics::System>::State,
        h: f64,
        req: StepRequest<Alg<ChartSystem<L, Q>>>,
    ) -> Result<StepOutput<<ChartSystem<L, Q> as crate::dynamics::System>::State>, StepFault> {
        match self {
            ChartMethod::Rk4(m) => m.step(sys, t, y, h, req),
            ChartMethod::Dopri5(m) => m.step(sys, t, y, h, req),
        }
    }
}

macro_rules! entry {
    ($id:ident, $name:literal, $display:literal, $family:ident, $order:literal, $emb:expr, $adaptive:literal, $needs:ident, $params:expr, $summary:literal, $build:expr) => {
        #[doc = concat!("`", $name, "`: ", $display, ". ", $summary)]
        pub const $id: MethodEntry = MethodEntry {
            name: $name,
            display: $display,
            family: Family::$family,
            order: $order,
            embedded_order: $emb,
            adaptive: $adaptive,
            needs: Needs::$needs,
            params: $params,
            summary: $summary,
            build: $build,
        };
    };
}

fn group(m: AnyMethod) -> Result<Built, MethodError> {
    Ok(Built::Group(m))
}

entry!(LIE_EULER, "lie_euler", "RKMK Lie-Euler", Rkmk, 1, None, false, Nothing, &[], "order 1: tests, teaching", |_| group(AnyMethod::Rkmk1(Rkmk::lie_euler())));
entry!(HEUN, "heun", "RKMK Heun", Rkmk, 2, None, false, Nothing, &[], "order 2, 2 evaluations per step: cheap low accuracy", |_| group(AnyMethod::Rkmk2(Rkmk::heun())));
entry!(KUTTA3, "kutta3", "RKMK Kutta3", Rkmk, 3, None, false, Nothing, &[], "order 3, one commutator per stage", |_| group(AnyMethod::Rkmk3(Rkmk::kutta3())));
entry!(RK4, "rk4", "RKMK4", Rkmk, 4, None, false, Nothing, &[], "order 4 in the two-commutator form: fixed-step accuracy on any model", |_| group(AnyMethod::Rkmk4(Rkmk::rk4())));
entry!(
    DOPRI5,
    "dopri5",
    "RKMK DOPRI5",
    Rkmk,
    5,
    Some(4),
    true,
    Nothing,
    &[],
    "Dormand-Prince 5(4): adaptive with rtol/atol (tolerance per step), dense output of order 4, events",
    |_| group(AnyMethod::Rkmk7(Rkmk::dopri5()))
);
entry!(
    DOP853,
    "dop853",
    "RKMK DOP853",
    Rkmk,
    8,
    Some(7),
    true,
    Nothing,
    &[],
    "Hairer's DOP853 8(5,3): adaptive, dense output of order 7; the adaptive method whose error stays closest to tol",
    |_| group(AnyMethod::Rkmk12(Rkmk::dop853()))
);
entry!(BUTCHER6, "butcher6", "RKMK Butcher6", Rkmk, 6, None, false, Nothing, &[], "order 6, 7 evaluations per step: high-accuracy references", |_| group(AnyMethod::Rkmk7(Rkmk::butcher6())));
entry!(STRANG, "strang", "Strang splitting", Splitting, 2, None, false, ExactFreeFlow, &[], "1 kick, 2 drifts: long runs at loose accuracy, energy bounded, momentum maps exact", |_| group(AnyMethod::Split(Splitting::strang())));
entry!(YOSHIDA4, "yoshida4", "Yoshida 4 splitting", Splitting, 4, None, false, ExactFreeFlow, &[], "the triple jump of Strang", |_| group(AnyMethod::Split(Splitting::yoshida4())));
entry!(SUZUKI4, "suzuki4", "Suzuki 4 splitting", Splitting, 4, None, false, ExactFreeFlow, &[], "Suzuki's five-fold composition: smaller error than Yoshida 4", |_| group(AnyMethod::Split(Splitting::suzuki4())));
entry!(BLANES_MOAN4, "blanes_moan4", "Blanes-Moan 4 splitting", Splitting, 4, None, false, ExactFreeFlow, &[], "the optimised six-kick method S6 of Blanes and Moan: long runs", |_| group(AnyMethod::Split(Splitting::blanes_moan4())));
entry!(YOSHIDA6, "yoshida6", "Yoshida 6 splitting", Splitting, 6, None, false, ExactFreeFlow, &[], "Yoshida's seven-fold composition", |_| group(AnyMethod::Split(Splitting::yoshida6())));
entry!(BLANES_MOAN6, "blanes_moan6", "Blanes-Moan 6 splitting", Splitting, 6, None, false, ExactFreeFlow, &[], "the optimised ten-kick method S10 of Blanes and Moan: long runs at tight accuracy", |_| group(AnyMethod::Split(Splitting::blanes_moan6())));
entry!(
    BLANES_MOAN_RKN4,
    "blanes_moan_rkn4",
    "Blanes-Moan RKN 4 splitting",
    Splitting,
    4,
    None,
    false,
    ExactFreeFlow,
    &[],
    "the Runge-Kutta-Nystrom method SRKN6b of Blanes and Moan",
    |_| group(AnyMethod::Split(Splitting::blanes_moan_rkn4()))
);
entry!(
    BLANES_MOAN_RKN6,
    "blanes_moan_rkn6",
    "Blanes-Moan RKN 6 splitting",
    Splitting,
    6,
    None,
    false,
    ExactFreeFlow,
    &[],
    "the Runge-Kutta-Nystrom method SRKN11b of Blanes and Moan: the fastest on S2, H2, S3 at 1e-6 ... 1e-10",
    |_| group(AnyMethod::Split(Splitting::blanes_moan_rkn6()))
);
entry!(
    IMPLICIT_MIDPOINT,
    "implicit_midpoint",
    "implicit Lie midpoint",
    Implicit,
    2,
    None,
    false,
    Nothing,
    &["newton_tol", "newton_max_iter"],
    "symmetric, energy bounded on any model (Newton with newton_tol, default 1e-14, and newton_max_iter, default 30)",
    |p| {
        let m = ImplicitMidpoint::new().with_newton(p.newton_tol.unwrap_or(1e-14), p.newton_max_iter.unwrap_or(30))?;
        group(AnyMethod::Implicit(m))
    }
);
entry!(
    COORDINATE_RK4,
    "coordinate_rk4",
    "coordinate RK4",
    Coordinate,
    4,
    None,
    false,
    Chart,
    &[],
    "classical RK4 on the paper's chart equations: the baseline, fails at chart poles",
    |_| Ok(Built::Chart(ChartMethod::Rk4(CoordinateRk::rk4())))
);
entry!(
    COORDINATE_DOPRI5,
    "coordinate_dopri5",
    "coordinate DOPRI5",
    Coordinate,
    5,
    Some(4),
    true,
    Chart,
    &[],
    "Dormand-Prince 5(4) on the paper's chart equations: the baseline, fails at chart poles",
    |_| Ok(Built::Chart(ChartMethod::Dopri5(CoordinateRk::dopri5())))
);

/// Every method, in the order of listings.
pub const METHODS: &[MethodEntry] = &[
    LIE_EULER,
    HEUN,
    KUTTA3,
    RK4,
    DOPRI5,
    DOP853,
    BUTCHER6,
    STRANG,
    YOSHIDA4,
    SUZUKI4,
    BLANES_MOAN4,
    YOSHIDA6,
    BLANES_MOAN6,
    BLANES_MOAN_RKN4,
    BLANES_MOAN_RKN6,
    IMPLICIT_MIDPOINT,
    COORDINATE_RK4,
    COORDINATE_DOPRI5,
];

/// The entry called `name`, or [`MethodError::Unknown`] listing the names.
pub fn lookup(name: &str) -> Result<&'static MethodEntry, MethodError> {
    METHODS.iter().find(|e| e.name == name).ok_or_else(|| MethodError::Unknown { name: name.to_string(), allowed: names().join(", ") })
}

/// The scene names of every method, in the order of [`METHODS`].
pub fn names() -> Vec<&'static str> {
    METHODS.iter().map(|e| e.name).collect()
}

/// The method table of the guide and `framedyn methods`, in Markdown:
/// name, display name, family, order, stepping, what it needs, what it is for.
pub fn markdown_table() -> String {
    let mut out = String::from("| `name` | method | family | order | stepping | needs | use it for |\n|---|---|---|---|---|---|---|\n");
    for e in METHODS {
        let order = match e.embedded_order {
            Some(q) => format!("{} ({q})", e.order),
            None => e.order.to_string(),
        };
        let stepping = if e.adaptive { "fixed `h` or adaptive `rtol`/`atol`" } else { "fixed `h`" };
        out.push_str(&format!("| `{}` | {} | {} | {} | {} | {} | {} |\n", e.name, e.display, e.family.label(), order, stepping, e.needs.describe(), e.summary));
    }
    out
}
