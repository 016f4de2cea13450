//! The potentials of a scene: one enum per body dimension, dispatching to the
//! built-in potentials of [`crate::potential`] (so the integrators are
//! instantiated once per manifold × body, not once per potential).

use std::fmt;
use std::sync::Arc;

use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

use crate::potential::{
    Central, CosineFamily, Elastic, FnPotential, GradFnPotential, Gradient, InvariantPotential, Kepler, NeoHookean, Oscillator,
    Potential, RadialFunction, Scalar, Separable, SeparableFunctions, StVenantKirchhoff,
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

impl RadialFunction for Series {
    fn v<D: Scalar>(&self, r: D) -> D {
        self.eval(r)
    }
}

/// The three functions `V_r, V_ϱ, V_ε` of a separable potential (b128).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SeparableSeries {
    /// `V_r(r)` (geodesic distance, or the torus angle `ϑ` on T²).
    pub v_r: Series,
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
        Central(Central<Series, 3>),
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
        Central(Central<Series, 4>),
        /// Neo-Hookean energy of the Green tensor.
        NeoHookean(InvariantPotential<NeoHookean>),
        /// Saint Venant–Kirchhoff energy of the Green tensor.
        StVenantKirchhoff(InvariantPotential<StVenantKirchhoff>),
    }
);
