//! The potentials of a scene: one enum per body dimension, dispatching to the
//! built-in potentials of [`crate::potential`] (so the integrators are
//! instantiated once per manifold × body, not once per potential).

use std::fmt;
use std::sync::Arc;

use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

use super::error::SceneError;
use super::spec::{PotentialKind, PotentialSpec};
use crate::potential::{
    Central, Centre, CosineFamily, Elastic, FnPotential, GradFnPotential, Gradient, InvariantPotential, Kepler, NeoHookean, Oscillator,
    Potential, RadialFunction, Scalar, Separable, SeparableFunctions, StVenantKirchhoff, TorusAngle,
};

/// A function of one variable given in a scene file:
/// `f(x) = Σₖ poly[k]·xᵏ + Σ a·cos(w·x) (for [a, w] in cos) + sec_2x / cos(2x)`.
///
/// The last term is the shear part `V_ε = 2κ/cos 2ε` of the elastic
/// potential (a131); the cosine terms give the integrable family of §5.1 and
/// periodic functions of the torus angle.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    /// Polynomial coefficients, lowest degree first.
    #[serde(default)]
    pub poly: Vec<f64>,
    /// Cosine terms `[a, w]`: `a·cos(w·x)`.
    #[serde(default)]
    pub cos: Vec<[f64; 2]>,
    /// Coefficient `c` of `c / cos(2x)`.
    #[serde(default)]
    pub sec_2x: f64,
}

impl Series {
    /// `f(x)` for any scalar type (exact derivatives by dual numbers).
    pub fn eval<D: Scalar>(&self, x: D) -> D {
        let mut s = D::from(0.0);
        for &c in self.poly.iter().rev() {
            s = s * x + c;
        }
        for &[a, w] in &self.cos {
            s += (x * w).cos() * a;
        }
        if self.sec_2x != 0.0 {
            s += (x * 2.0).cos().recip() * self.sec_2x;
        }
        s
    }

    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.poly.iter().chain(self.cos.iter().flatten()).all(|v| v.is_finite()) && self.sec_2x.is_finite()
    }
}

impl Series {
    /// `f` with the polynomial in `x` and the trigonometric terms in `θ`:
    /// `Σ poly[k]·xᵏ + Σ a·cos(w·θ) + sec_2x / cos(2θ)`.
    pub fn eval_angle<D: Scalar>(&self, x: D, theta: D) -> D {
        let mut s = D::from(0.0);
        for &c in self.poly.iter().rev() {
            s = s * x + c;
        }
        for &[a, w] in &self.cos {
            s += (theta * w).cos() * a;
        }
        if self.sec_2x != 0.0 {
            s += (theta * 2.0).cos().recip() * self.sec_2x;
        }
        s
    }

    /// The series as a function of a distance `r` on a manifold of radius
    /// `R = 1/inv_radius`: polynomial in `r`, trigonometric terms in the
    /// angle `r/R` ([`AngularSeries`]).
    pub fn per_radius(self, inv_radius: f64) -> AngularSeries {
        AngularSeries::new(self, inv_radius)
    }
}

/// A [`Series`] in the geodesic distance `r` from a centre on a manifold of
/// radius `R`: `V(r) = Σ poly[k]·rᵏ + Σ a·cos(w·r/R) + c / cos(2r/R)` — the
/// frequencies `w` are per radius, the units of the `cosine` family
/// (`cos(r/R)`), so that a scene means the same potential on a sphere of
/// any radius. (On T² the variable is the torus angle itself.)
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AngularSeries {
    /// The series.
    pub series: Series,
    /// `1/R`.
    pub inv_radius: f64,
}

impl AngularSeries {
    /// `series` in the distance, its angles `r/R` with `R = 1/inv_radius`.
    pub fn new(series: Series, inv_radius: f64) -> Self {
        AngularSeries { series, inv_radius }
    }

    /// `V(r)`.
    pub fn eval<D: Scalar>(&self, r: D) -> D {
        self.series.eval_angle(r, r * self.inv_radius)
    }
}

impl RadialFunction for AngularSeries {
    fn v<D: Scalar>(&self, r: D) -> D {
        self.eval(r)
    }
}

/// The three functions `V_r, V_ϱ, V_ε` of a separable potential (b128).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SeparableSeries {
    /// `V_r(r)`: of the geodesic distance with frequencies per radius
    /// ([`AngularSeries`]), or of the torus angle `ϑ` on T² (`inv_radius = 1`).
    pub v_r: AngularSeries,
    /// `V_ϱ(ϱ)`.
    pub v_rho: Series,
    /// `V_ε(ε)`.
    pub v_eps: Series,
}

impl SeparableFunctions for SeparableSeries {
    fn v_r<D: Scalar>(&self, r: D) -> D {
        self.v_r.eval(r)
    }
    fn v_rho<D: Scalar>(&self, rho: D) -> D {
        self.v_rho.eval(rho)
    }
    fn v_eps<D: Scalar>(&self, eps: D) -> D {
        self.v_eps.eval(eps)
    }
}

/// A potential given as a closure of the embedding position `x` (`E`
/// numbers) and the body frame (`E·N` numbers, column-major: the frame
/// vectors one after the other). Without a [`UserGradientFn`] its gradient is
/// taken by Ridders-extrapolated central differences ([`FnPotential`]), much
/// slower than the built-ins.
pub type UserPotentialFn = Arc<dyn Fn(&[f64], &[f64]) -> f64 + Send + Sync>;

/// The gradient of a user potential, supplied by the user:
/// `grad(x, e, dx, de)` writes `∂V/∂xⁱ` into `dx` (`E` numbers) and
/// `∂V/∂e` into `de` (`E·N` numbers, the same layout as `e`; ignored for
/// potentials that do not use the frame). Partial derivatives in the
/// ambient components, the metric not applied ([`GradFnPotential`]).
pub type UserGradientFn = Arc<dyn Fn(&[f64], &[f64], &mut [f64], &mut [f64]) + Send + Sync>;

/// A user potential as given: its value and, optionally, its gradient
/// (without one the gradient is taken by finite differences).
#[derive(Clone)]
pub struct UserFunctions {
    /// `V(x, e)`.
    pub value: UserPotentialFn,
    /// `(∂V/∂x, ∂V/∂e)`, if the user supplies it.
    pub gradient: Option<UserGradientFn>,
}

type UserClosure<const N: usize, const E: usize> =
    Box<dyn Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> f64 + Send + Sync>;
type UserGradClosure<const N: usize, const E: usize> =
    Box<dyn Fn(&SVector<f64, E>, &SMatrix<f64, E, N>, &SMatrix<f64, E, E>) -> (SVector<f64, E>, SMatrix<f64, E, N>) + Send + Sync>;

/// The two ways a user potential is differentiated.
enum UserKind<const N: usize, const E: usize> {
    /// Finite differences of the value closure.
    Differenced(FnPotential<UserClosure<N, E>, N, E>),
    /// The user's own gradient.
    Supplied(GradFnPotential<UserClosure<N, E>, UserGradClosure<N, E>, N, E>),
}

/// A user potential ([`UserPotentialFn`], optionally with its
/// [`UserGradientFn`]) wrapped as a [`Potential`].
#[derive(Clone)]
pub struct UserPotential<const N: usize, const E: usize>(Arc<UserKind<N, E>>);

impl<const N: usize, const E: usize> fmt::Debug for UserPotential<N, E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match &*self.0 {
            UserKind::Differenced(_) => "UserPotential(differenced gradient)",
            UserKind::Supplied(_) => "UserPotential(supplied gradient)",
        })
    }
}

impl<const N: usize, const E: usize> UserPotential<N, E> {
    /// `V = value(x, e)`, with the supplied gradient if any, else by finite
    /// differences; `length_scale` is the length over which `V` varies (the
    /// manifold's radius), used for the first difference step (and checked
    /// to be finite and > 0 only then).
    pub fn new(user: UserFunctions, uses_frame: bool, length_scale: f64) -> crate::Result<Self> {
        let UserFunctions { value: f, gradient: grad } = user;
        let value = move |x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, _g: &SMatrix<f64, E, E>| f(x.as_slice(), e.as_slice());
        let closure: UserClosure<N, E> = Box::new(value);
        Ok(UserPotential(Arc::new(match grad {
            None => UserKind::Differenced(FnPotential::new(closure, uses_frame, length_scale)?),
            Some(grad) => {
                let g: UserGradClosure<N, E> = Box::new(move |x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, _g: &SMatrix<f64, E, E>| {
                    let (mut dx, mut de) = (SVector::<f64, E>::zeros(), SMatrix::<f64, E, N>::zeros());
                    grad(x.as_slice(), e.as_slice(), dx.as_mut_slice(), de.as_mut_slice());
                    (dx, de)
                });
                UserKind::Supplied(GradFnPotential::new(closure, g, uses_frame))
            }
        })))
    }
}

impl<const N: usize, const E: usize> Potential<N, E> for UserPotential<N, E> {
    fn uses_frame(&self) -> bool {
        match &*self.0 {
            UserKind::Differenced(p) => p.uses_frame(),
            UserKind::Supplied(p) => p.uses_frame(),
        }
    }
    fn second_derivatives(&self) -> bool {
        false
    }
    fn value<D: Scalar>(&self, x: &SVector<D, E>, e: &SMatrix<D, E, N>, g: &SMatrix<f64, E, E>) -> D {
        match &*self.0 {
            UserKind::Differenced(p) => p.value(x, e, g),
            UserKind::Supplied(p) => p.value(x, e, g),
        }
    }
    fn gradient(&self, x: &SVector<f64, E>, e: &SMatrix<f64, E, N>, g: &SMatrix<f64, E, E>) -> Gradient<N, E> {
        match &*self.0 {
            UserKind::Differenced(p) => p.gradient(x, e, g),
            UserKind::Supplied(p) => p.gradient(x, e, g),
        }
    }
}

macro_rules! scene_potential {
    ($(#[$doc:meta])* $name:ident, $n:literal, $e:literal, { $($(#[$vdoc:meta])* $var:ident($ty:ty)),* $(,)? }) => {
        $(#[$doc])*
        #[derive(Debug, Clone)]
        pub enum $name {
            /// `V = 0`.
            Free,
            $($(#[$vdoc])* $var($ty),)*
            /// A user closure (from Python).
            User(UserPotential<$n, $e>),
            /// `Σ cₖ Vₖ`.
            Sum(Vec<(f64, $name)>),
        }

        impl Potential<$n, $e> for $name {
            fn uses_frame(&self) -> bool {
                match self {
                    $name::Free => false,
                    $($name::$var(p) => Potential::<$n, $e>::uses_frame(p),)*
                    $name::User(p) => Potential::<$n, $e>::uses_frame(p),
                    $name::Sum(terms) => terms.iter().any(|(_, p)| p.uses_frame()),
                }
            }

            fn second_derivatives(&self) -> bool {
                match self {
                    $name::Free => true,
                    $($name::$var(p) => Potential::<$n, $e>::second_derivatives(p),)*
                    $name::User(_) => false,
                    $name::Sum(terms) => terms.iter().all(|(_, p)| p.second_derivatives()),
                }
            }

            fn value<D: Scalar>(&self, x: &SVector<D, $e>, e: &SMatrix<D, $e, $n>, g: &SMatrix<f64, $e, $e>) -> D {
                match self {
                    $name::Free => D::from(0.0),
                    $($name::$var(p) => Potential::<$n, $e>::value(p, x, e, g),)*
                    $name::User(p) => Potential::<$n, $e>::value(p, x, e, g),
                    $name::Sum(terms) => {
                        let mut s = D::from(0.0);
                        for (c, p) in terms {
                            s += p.value(x, e, g) * *c;
                        }
                        s
                    }
                }
            }

            fn gradient(&self, x: &SVector<f64, $e>, e: &SMatrix<f64, $e, $n>, g: &SMatrix<f64, $e, $e>) -> Gradient<$n, $e> {
                match self {
                    $name::Free => Gradient { value: 0.0, dx: SVector::zeros(), de: SMatrix::zeros() },
                    $($name::$var(p) => Potential::<$n, $e>::gradient(p, x, e, g),)*
                    $name::User(p) => Potential::<$n, $e>::gradient(p, x, e, g),
                    $name::Sum(terms) => {
                        let mut out = Gradient { value: 0.0, dx: SVector::zeros(), de: SMatrix::zeros() };
                        for (c, p) in terms {
                            let gr = p.gradient(x, e, g);
                            out.value += c * gr.value;
                            out.dx += gr.dx * *c;
                            out.de += gr.de * *c;
                        }
                        out
                    }
                }
            }
        }
    };
}

scene_potential!(
    /// The potentials of bodies with two frame vectors in ℝ³ (S², H², T²).
    Potential2, 2, 3, {
        /// Bertrand oscillator (b88).
        Oscillator(Oscillator<3>),
        /// Bertrand "Kepler" potential (c88).
        Kepler(Kepler<3>),
        /// `α̂ cos² + β̂ cos` (§5.1).
        Cosine(CosineFamily<3>),
        /// Central `V(r)`.
        Central(Central<AngularSeries, 3>),
        /// The elastic potential (a131).
        Elastic(Elastic),
        /// Separable `V_r + V_ϱ + V_ε/ϱ²` (b128).
        Separable(Separable<SeparableSeries>),
    }
);

scene_potential!(
    /// The potentials of bodies with three frame vectors in ℝ⁴ (S³).
    Potential3, 3, 4, {
        /// Bertrand oscillator (b133).
        Oscillator(Oscillator<4>),
        /// Bertrand "Kepler" potential.
        Kepler(Kepler<4>),
        /// `α̂ cos² + β̂ cos`.
        Cosine(CosineFamily<4>),
        /// Central `V(r)`.
        Central(Central<AngularSeries, 4>),
        /// Neo-Hookean energy of the Green tensor.
        NeoHookean(InvariantPotential<NeoHookean>),
        /// Saint Venant–Kirchhoff energy of the Green tensor.
        StVenantKirchhoff(InvariantPotential<StVenantKirchhoff>),
    }
);

// -- building from the scene file --------------------------------------------

pub(crate) fn kind_name(k: PotentialKind) -> &'static str {
    match k {
        PotentialKind::None => "none",
        PotentialKind::Oscillator => "oscillator",
        PotentialKind::Kepler => "kepler",
        PotentialKind::Cosine => "cosine",
        PotentialKind::Central => "central",
        PotentialKind::Elastic => "elastic",
        PotentialKind::Separable => "separable",
        PotentialKind::NeoHookean => "neo_hookean",
        PotentialKind::StVenantKirchhoff => "st_venant_kirchhoff",
        PotentialKind::Sum => "sum",
    }
}

fn req(v: Option<f64>, path: &str, field: &str) -> Result<f64, SceneError> {
    v.ok_or_else(|| SceneError::invalid(format!("{path}.{field}"), "(missing)", "required for this kind of potential"))
}

fn series(v: &Option<Series>, path: &str, field: &str) -> Result<Series, SceneError> {
    let s = v.clone().ok_or_else(|| SceneError::invalid(format!("{path}.{field}"), "(missing)", "required: { poly = [...], cos = [[a, w], ...], sec_2x = c }"))?;
    if !s.is_finite() {
        return Err(SceneError::invalid(format!("{path}.{field}"), "(non-finite coefficient)", "coefficients must be finite"));
    }
    Ok(s)
}

/// The parameters of a `[potential]` table (other than `kind` and `scale`).
const POTENTIAL_FIELDS: [&str; 12] = ["kappa", "alpha", "alpha_hat", "beta_hat", "lambda", "mu", "centre", "v", "v_r", "v_rho", "v_eps", "terms"];

/// A core error raised while building the potential at `path`, placed at
/// the parameter it names (`mu`, `beta_hat`, …) when that is one of the
/// table's, else at `fallback`: a constructor taking several parameters
/// knows which one is wrong.
fn core_error(path: &str, fallback: &str, e: crate::Error) -> SceneError {
    let named = match &e {
        crate::Error::InvalidParameter { field, .. } | crate::Error::NotFinite { field } => Some(*field),
        _ => None,
    };
    let field = named.filter(|f| POTENTIAL_FIELDS.contains(f) && fallback != "centre").unwrap_or(fallback);
    SceneError::from_core(&format!("{path}.{field}"), e)
}

/// Rejects parameters that the potential's kind does not use.
fn check_fields(p: &PotentialSpec, path: &str) -> Result<(), SceneError> {
    let used: &[&str] = match p.kind {
        PotentialKind::None => &[],
        PotentialKind::Oscillator => &["kappa", "centre"],
        PotentialKind::Kepler => &["alpha", "centre"],
        PotentialKind::Cosine => &["alpha_hat", "beta_hat", "centre"],
        PotentialKind::Central => &["v", "centre"],
        PotentialKind::Elastic => &["kappa"],
        PotentialKind::Separable => &["v_r", "v_rho", "v_eps", "centre"],
        PotentialKind::NeoHookean | PotentialKind::StVenantKirchhoff => &["lambda", "mu"],
        PotentialKind::Sum => &["terms"],
    };
    let given = [
        ("kappa", p.kappa.is_some()),
        ("alpha", p.alpha.is_some()),
        ("alpha_hat", p.alpha_hat.is_some()),
        ("beta_hat", p.beta_hat.is_some()),
        ("lambda", p.lambda.is_some()),
        ("mu", p.mu.is_some()),
        ("centre", p.centre.is_some()),
        ("v", p.v.is_some()),
        ("v_r", p.v_r.is_some()),
        ("v_rho", p.v_rho.is_some()),
        ("v_eps", p.v_eps.is_some()),
        ("terms", p.terms.is_some()),
    ];
    for (f, g) in given {
        if g && !used.contains(&f) {
            return Err(SceneError::invalid(
                format!("{path}.{f}"),
                "(given)",
                format!("kind = \"{}\" takes only: {}", kind_name(p.kind), if used.is_empty() { "no parameters".to_string() } else { used.join(", ") }),
            ));
        }
    }
    if let Some(s) = p.scale {
        if !s.is_finite() {
            return Err(SceneError::invalid(format!("{path}.scale"), s, "must be finite"));
        }
    }
    Ok(())
}

fn scaled2(p: &PotentialSpec, base: Potential2) -> Potential2 {
    match p.scale {
        Some(s) if s != 1.0 => Potential2::Sum(vec![(s, base)]),
        _ => base,
    }
}

fn scaled3(p: &PotentialSpec, base: Potential3) -> Potential3 {
    match p.scale {
        Some(s) if s != 1.0 => Potential3::Sum(vec![(s, base)]),
        _ => base,
    }
}

/// What a manifold offers the potential families of a scene with two frame
/// vectors in ℝ³ (its entry in [`manifolds`](super::manifolds) fills it in).
pub(crate) struct SurfacePotentials<'a> {
    /// The manifold's name in messages (`"S2"`, …).
    pub name: &'static str,
    /// The centre of central potentials: `None` the chart's pole, `Some(c)`
    /// the point `c`; `None` for a manifold without closed-form geodesic
    /// distances (no central potentials there).
    pub centre: Option<&'a dyn Fn(Option<&SVector<f64, 3>>) -> crate::Result<Centre<3>>>,
    /// T²: the torus angle `ϑ`, the variable of `separable` (`V_r(ϑ)`) and
    /// `cosine` (`α̂ cos²ϑ + β̂ cos ϑ`).
    pub torus: Option<TorusAngle>,
    /// Where there are no central potentials and no torus angle (the
    /// spheroid): the axis of the `cosine` family, `V = α̂ Z² + β̂ Z` with
    /// `Z = z/ℓ` the height along the symmetry axis in units of `ℓ` (its
    /// `axial` component over its radius).
    pub cosine: Option<Centre<3>>,
    /// The length scale of the manifold (difference steps of user potentials).
    pub length: f64,
}

/// The allowed potential kinds on a surface, for messages.
fn surface_kinds(s: &SurfacePotentials<'_>) -> &'static str {
    match (&s.centre, &s.torus, &s.cosine) {
        (Some(_), _, _) => "none, oscillator, kepler, cosine, central, elastic, separable, sum",
        (None, Some(_), _) => "none, cosine, elastic, separable (V_r of the torus angle), sum",
        (None, None, Some(_)) => "none, cosine (of the height along the axis), elastic, sum",
        (None, None, None) => "none, elastic, sum",
    }
}

/// The scene potential `p` (at `path`) on a surface.
pub(crate) fn build_potential2(p: &PotentialSpec, path: &str, s: &SurfacePotentials<'_>) -> Result<Potential2, SceneError> {
    check_fields(p, path)?;
    let core = |field: &str, e| core_error(path, field, e);
    let unavailable = || {
        SceneError::invalid(format!("{path}.kind"), format!("\"{}\"", kind_name(p.kind)), format!("not available on {}; allowed there: {}", s.name, surface_kinds(s)))
    };
    let centre = || -> Result<Centre<3>, SceneError> {
        let make = s.centre.ok_or_else(unavailable)?;
        match &p.centre {
            None => make(None).map_err(|e| core("centre", e)),
            Some(c) => make(Some(&vec_n::<3>(c, &format!("{path}.centre"))?)).map_err(|e| core("centre", e)),
        }
    };
    let base = match p.kind {
        PotentialKind::None => Potential2::Free,
        PotentialKind::Oscillator => Potential2::Oscillator(Oscillator::new(req(p.kappa, path, "kappa")?, centre()?).map_err(|e| core("kappa", e))?),
        PotentialKind::Kepler => Potential2::Kepler(Kepler::new(req(p.alpha, path, "alpha")?, centre()?).map_err(|e| core("alpha", e))?),
        PotentialKind::Cosine => match (&s.centre, &s.torus, &s.cosine) {
            (None, Some(angle), _) => {
                if p.centre.is_some() {
                    return Err(SceneError::invalid(format!("{path}.centre"), "(given)", format!("on {} the cosine family is a function of the torus angle; no centre", s.name)));
                }
                let (a, b) = (p.alpha_hat.unwrap_or(0.0), p.beta_hat.unwrap_or(0.0));
                for (f, v) in [("alpha_hat", a), ("beta_hat", b)] {
                    if !v.is_finite() {
                        return Err(SceneError::invalid(format!("{path}.{f}"), v, "must be finite"));
                    }
                }
                // α̂ cos²ϑ + β̂ cos ϑ = α̂/2 + (α̂/2) cos 2ϑ + β̂ cos ϑ.
                let v_r = Series { poly: vec![0.5 * a], cos: vec![[0.5 * a, 2.0], [b, 1.0]], sec_2x: 0.0 };
                Potential2::Separable(Separable::torus(SeparableSeries { v_r: v_r.per_radius(1.0), ..SeparableSeries::default() }, *angle))
            }
            (None, None, Some(axis)) => {
                if p.centre.is_some() {
                    return Err(SceneError::invalid(format!("{path}.centre"), "(given)", format!("on {} the cosine family is a function of the height along the axis; no centre", s.name)));
                }
                Potential2::Cosine(CosineFamily::new(p.alpha_hat.unwrap_or(0.0), p.beta_hat.unwrap_or(0.0), *axis).map_err(|e| core("alpha_hat", e))?)
            }
            _ => Potential2::Cosine(CosineFamily::new(p.alpha_hat.unwrap_or(0.0), p.beta_hat.unwrap_or(0.0), centre()?).map_err(|e| core("alpha_hat", e))?),
        },
        PotentialKind::Central => {
            let c = centre()?;
            Potential2::Central(Central::new(AngularSeries::new(series(&p.v, path, "v")?, c.inv_radius()), c))
        }
        PotentialKind::Elastic => Potential2::Elastic(Elastic::new(req(p.kappa, path, "kappa")?).map_err(|e| core("kappa", e))?),
        PotentialKind::Separable => {
            let v_rho = p.v_rho.as_ref().map(|_| series(&p.v_rho, path, "v_rho")).transpose()?.unwrap_or_default();
            let v_eps = p.v_eps.as_ref().map(|_| series(&p.v_eps, path, "v_eps")).transpose()?.unwrap_or_default();
            let v_r = p.v_r.as_ref().map(|_| series(&p.v_r, path, "v_r")).transpose()?.unwrap_or_default();
            match (&s.centre, &s.torus) {
                (None, Some(angle)) => {
                    if p.centre.is_some() {
                        return Err(SceneError::invalid(format!("{path}.centre"), "(given)", format!("on {} the separable potential uses the torus angle; no centre", s.name)));
                    }
                    Potential2::Separable(Separable::torus(SeparableSeries { v_r: v_r.per_radius(1.0), v_rho, v_eps }, *angle))
                }
                _ => {
                    let c = centre()?;
                    let v_r = v_r.per_radius(c.inv_radius());
                    Potential2::Separable(Separable::new(SeparableSeries { v_r, v_rho, v_eps }, c))
                }
            }
        }
        PotentialKind::Sum => {
            let terms = p.terms.as_ref().ok_or_else(|| SceneError::invalid(format!("{path}.terms"), "(missing)", "kind = \"sum\" needs terms = [...]"))?;
            let mut out = Vec::new();
            for (i, t) in terms.iter().enumerate() {
                out.push((1.0, build_potential2(t, &format!("{path}.terms[{i}]"), s)?));
            }
            Potential2::Sum(out)
        }
        PotentialKind::NeoHookean | PotentialKind::StVenantKirchhoff => {
            return Err(SceneError::invalid(
                format!("{path}.kind"),
                format!("\"{}\"", kind_name(p.kind)),
                "invariant potentials of the Green tensor are for three-dimensional bodies (S3); on surfaces use elastic or separable",
            ))
        }
    };
    Ok(scaled2(p, base))
}

/// What a three-dimensional manifold offers the potential families.
pub(crate) struct SpacePotentials<'a> {
    /// The manifold's name in messages (`"S3"`).
    pub name: &'static str,
    /// The centre of central potentials (as [`SurfacePotentials::centre`]).
    pub centre: Option<&'a dyn Fn(Option<&SVector<f64, 4>>) -> crate::Result<Centre<4>>>,
    /// The length scale of the manifold.
    pub length: f64,
}

/// The scene potential `p` (at `path`) on a three-dimensional manifold.
pub(crate) fn build_potential3(p: &PotentialSpec, path: &str, s: &SpacePotentials<'_>) -> Result<Potential3, SceneError> {
    check_fields(p, path)?;
    let core = |field: &str, e| core_error(path, field, e);
    let centre = || -> Result<Centre<4>, SceneError> {
        let make = s.centre.ok_or_else(|| SceneError::invalid(format!("{path}.kind"), format!("\"{}\"", kind_name(p.kind)), format!("central potentials are not available on {}", s.name)))?;
        match &p.centre {
            None => make(None).map_err(|e| core("centre", e)),
            Some(c) => make(Some(&vec_n::<4>(c, &format!("{path}.centre"))?)).map_err(|e| core("centre", e)),
        }
    };
    let base = match p.kind {
        PotentialKind::None => Potential3::Free,
        PotentialKind::Oscillator => Potential3::Oscillator(Oscillator::new(req(p.kappa, path, "kappa")?, centre()?).map_err(|e| core("kappa", e))?),
        PotentialKind::Kepler => Potential3::Kepler(Kepler::new(req(p.alpha, path, "alpha")?, centre()?).map_err(|e| core("alpha", e))?),
        PotentialKind::Cosine => Potential3::Cosine(
            CosineFamily::new(p.alpha_hat.unwrap_or(0.0), p.beta_hat.unwrap_or(0.0), centre()?).map_err(|e| core("alpha_hat", e))?,
        ),
        PotentialKind::Central => {
            let c = centre()?;
            Potential3::Central(Central::new(AngularSeries::new(series(&p.v, path, "v")?, c.inv_radius()), c))
        }
        PotentialKind::NeoHookean => Potential3::NeoHookean(InvariantPotential::new(
            NeoHookean::new(req(p.lambda, path, "lambda")?, req(p.mu, path, "mu")?).map_err(|e| core("lambda", e))?,
        )),
        PotentialKind::StVenantKirchhoff => Potential3::StVenantKirchhoff(InvariantPotential::new(
            StVenantKirchhoff::new(req(p.lambda, path, "lambda")?, req(p.mu, path, "mu")?).map_err(|e| core("lambda", e))?,
        )),
        PotentialKind::Sum => {
            let terms = p.terms.as_ref().ok_or_else(|| SceneError::invalid(format!("{path}.terms"), "(missing)", "kind = \"sum\" needs terms = [...]"))?;
            let mut out = Vec::new();
            for (i, t) in terms.iter().enumerate() {
                out.push((1.0, build_potential3(t, &format!("{path}.terms[{i}]"), s)?));
            }
            Potential3::Sum(out)
        }
        PotentialKind::Elastic | PotentialKind::Separable => {
            return Err(SceneError::invalid(
                format!("{path}.kind"),
                format!("\"{}\"", kind_name(p.kind)),
                format!("on {} allowed: none, oscillator, kepler, cosine, central, neo_hookean, st_venant_kirchhoff, sum (elastic and separable are the 2-D potentials (a131), (b128))", s.name),
            ))
        }
    };
    Ok(scaled3(p, base))
}

/// `n` numbers as a vector (each finite), or an error naming `path`.
pub(crate) fn vec_n<const K: usize>(v: &[f64], path: &str) -> Result<SVector<f64, K>, SceneError> {
    if v.len() != K {
        return Err(SceneError::invalid(path, format!("an array of {} numbers", v.len()), format!("must have exactly {K} numbers")));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(SceneError::invalid(format!("{path}[{i}]"), v[i], "must be finite"));
    }
    Ok(SVector::from_column_slice(v))
}
