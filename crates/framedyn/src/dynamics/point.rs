//! The structureless material point on a frame bundle (paper §4–§5; SPEC §3.2).
//!
//! See [`PointModel`]. The helpers [`bundle_element_at`],
//! [`tangent_components`] and [`momentum_map_generator_check`] are shared by
//! the gyroscope models of this crate.

use nalgebra::{SMatrix, SVector};

use crate::body::Point;
use crate::bundle::FrameBundle;
use crate::dynamics::split::{SplitDispatch, Splittable};
use crate::dynamics::{position_force, System};
use crate::error::finite;
use crate::lie::{LieGroup, Product, ProductAlgebra, Rn};
use crate::potential::Potential;
use crate::{Error, Result};

/// Relative tolerance of the state constructors: tangency of a given velocity,
/// defect of a given bundle element, η-skewness of a momentum-map generator.
pub const STATE_TOLERANCE: f64 = 1e-9;

/// State of a [`PointModel`]: `(g, u)` — a bundle element `g` (the point `x`
/// with a parallel-transported frame `q`) and the velocity components
/// `u = (u₁ … u_N)` in that frame, `ẋ = Σ u_a q_a`.
pub type PointState<G, const N: usize> = Product<G, Rn<N>>;

/// A structureless point of mass `m` moving on the manifold `B` in the
/// position potential `V(x)`.
///
/// **State** [`PointState`] `= Product<B::Group, Rn<N>>`: the bundle element
/// `g` and the components `u` of the velocity in its frame `q`. The point has
/// no internal frame; `q` is carried only because the pair `(g, u)` is the
/// chart-free encoding of position and velocity: `x = position(g)`,
/// `ẋ = q·u`, with `q` parallel-transported along the path so that `u̇` is the
/// covariant acceleration.
///
/// **Equations** (the translational part of (a59) without spin; SPEC §3.2):
/// ```text
/// ġ = g · horizontal_lift(g, u)        (x moves with ẋ = q u, q parallel)
/// m u̇ = F̂,   F̂_a = −dV(q_a) = −q_aᵀ ∂V/∂x
/// ```
/// `∂V/∂x` is the gradient of `V` in ambient components (automatic
/// differentiation, [`Potential::gradient`]); on H² the frame is
/// Minkowski-orthonormal and spacelike, so `u` are ordinary orthonormal
/// components there too.
///
/// **Invariants**: the energy `E = (m/2)|u|² + V(x)` ([`System::energy`]) and,
/// for every ambient isometry generator `A` that leaves `V` invariant, the
/// momentum map `m⟨A x, ẋ⟩_η` ([`PointModel::momentum_map`]).
#[derive(Debug, Clone)]
pub struct PointModel<B, P, const N: usize, const E: usize> {
    bundle: B,
    body: Point,
    potential: P,
    metric: SMatrix<f64, E, E>,
    inv_mass: f64,
}

impl<B, P, const N: usize, const E: usize> PointModel<B, P, N, E>
where
    B: FrameBundle<N, E>,
    P: Potential<N, E>,
{
    /// The point `body` on `bundle` in the potential `potential`.
    ///
    /// Errors: [`Error::Constraint`] with field `"potential"` if
    /// `potential.uses_frame()` is true — a structureless point has no frame
    /// for `V(x, e)` to depend on.
    pub fn new(bundle: B, body: Point, potential: P) -> Result<Self> {
        if potential.uses_frame() {
            return Err(Error::Constraint {
                field: "potential",
                constraint: "a structureless point has no body frame: V must depend on the position only \
                             (Potential::uses_frame() == false)",
                defect: 1.0,
                tolerance: 0.0,
            });
        }
        let metric = bundle.ambient_metric();
        Ok(Self { bundle, inv_mass: 1.0 / body.mass(), body, potential, metric })
    }

    /// The manifold (and its frame bundle).
    pub fn bundle(&self) -> &B {
        &self.bundle
    }

    /// `1/m` (stored: the integrators multiply by it).
    #[inline]
    pub fn inv_mass(&self) -> f64 {
        self.inv_mass
    }

    /// The body parameters.
    pub fn body(&self) -> &Point {
        &self.body
    }

    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }

    /// The state at the embedded point `p` with ambient velocity `v`.
    ///
    /// The frame `q` of the bundle element is arbitrary (it has no physical
    /// meaning for a point); it is the paper's frame field `E(x)` where the
    /// chart is regular and a Gram–Schmidt frame at its singular points (the
    /// poles of S², the origin of H², the antipode of the S³ chart), see
    /// [`bundle_element_at`].
    ///
    /// Errors: [`Error::NotFinite`] (`"p"`, `"v"`); [`Error::Constraint`]
    /// with field `"p"` (not on the manifold) or `"v"` (not tangent at `p`,
    /// relative tolerance [`STATE_TOLERANCE`]).
    pub fn state(&self, p: &SVector<f64, E>, v: &SVector<f64, E>) -> Result<PointState<B::Group, N>> {
        let g = bundle_element_at(&self.bundle, p)?;
        let u = tangent_components(&self.bundle, &g, v, "v")?;
        Ok(Product(g, Rn(u)))
    }

    /// The state `(g, u)` from its parts, validated: `g` finite and within
    /// [`STATE_TOLERANCE`] of the bundle, `u` finite.
    ///
    /// Errors: [`Error::NotFinite`] (`"g"`, `"u"`), [`Error::Constraint`] (`"g"`).
    pub fn state_from_parts(&self, g: &B::Group, u: &SVector<f64, N>) -> Result<PointState<B::Group, N>> {
        check_bundle_element(&self.bundle, g)?;
        finite("u", u.iter())?;
        Ok(Product(*g, Rn(*u)))
    }

    /// The position `x` (ambient components).
    pub fn position(&self, y: &PointState<B::Group, N>) -> SVector<f64, E> {
        self.bundle.position(&y.0)
    }

    /// The velocity `ẋ = Σ u_a q_a` (ambient components).
    pub fn velocity(&self, y: &PointState<B::Group, N>) -> SVector<f64, E> {
        self.bundle.frame_vectors(&y.0) * y.1 .0
    }

    /// The velocity components `u` in the parallel frame `q`.
    pub fn velocity_components(&self, y: &PointState<B::Group, N>) -> SVector<f64, N> {
        y.1 .0
    }

    /// The kinetic energy `T = (m/2)|u|²`.
    pub fn kinetic_energy(&self, y: &PointState<B::Group, N>) -> f64 {
        0.5 * self.body.mass() * y.1 .0.norm_squared()
    }

    /// The potential energy `V(x)`.
    pub fn potential_energy(&self, y: &PointState<B::Group, N>) -> f64 {
        let x = self.bundle.position(&y.0);
        self.potential.value::<f64>(&x, &SMatrix::zeros(), &self.metric)
    }

    /// The force `F̂_a = −q_aᵀ ∂V/∂x` in the frame `q`.
    pub fn force(&self, y: &PointState<B::Group, N>) -> SVector<f64, N> {
        let x = self.bundle.position(&y.0);
        let grad = self.potential.gradient(&x, &SMatrix::zeros(), &self.metric);
        position_force(&self.bundle.frame_vectors(&y.0), &grad.dx)
    }

    /// The momentum map (Noether charge) of the one-parameter group of ambient
    /// isometries `exp(tA)`: `J_A = m⟨A x, ẋ⟩_η` (`η` the ambient metric).
    /// Conserved when `exp(tA)` maps the manifold to itself and leaves `V`
    /// invariant — e.g. `A` the rotation generator about the z axis on S², H²
    /// and T² (the paper's `p_φ`), any `A ∈ so(3)` on S², `so(1,2)` on H²,
    /// `so(4)` on S³.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] (field
    /// `"generator"`) unless `Aᵀη + ηA = 0` (relative tolerance [`STATE_TOLERANCE`]).
    pub fn momentum_map(&self, y: &PointState<B::Group, N>, generator: &SMatrix<f64, E, E>) -> Result<f64> {
        momentum_map_generator_check(&self.metric, generator)?;
        let x = self.bundle.position(&y.0);
        let v = self.velocity(y);
        Ok(self.body.mass() * (generator * x).dot(&(self.metric * v)))
    }
}

impl<B, P, const N: usize, const E: usize> System for PointModel<B, P, N, E>
where
    B: FrameBundle<N, E>,
    P: Potential<N, E>,
{
    type State = PointState<B::Group, N>;

    /// `(horizontal_lift(g, u), F̂/m)`.
    #[inline]
    fn vector_field(&self, _t: f64, y: &Self::State) -> <Self::State as LieGroup>::Algebra {
        let (g, u) = (&y.0, &y.1 .0);
        let xi = self.bundle.horizontal_lift(g, u);
        let x = self.bundle.position(g);
        let grad = self.potential.gradient(&x, &SMatrix::zeros(), &self.metric);
        let f = position_force(&self.bundle.frame_vectors(g), &grad.dx);
        ProductAlgebra(xi, f * self.inv_mass)
    }

    /// `Df[(η, δu)] = (lift(δu) + D_g lift(u)[η], δF̂/m)` with
    /// `δF̂ = −(δq)ᵀ∂V/∂x − qᵀ(∂²V/∂x²)δx` and `(δx, δq)` the bundle's
    /// frame velocity along `η` ([`force_derivative`](super::force_derivative)).
    fn tangent_field(&self, t: f64, y: &Self::State, xi: &<Self::State as LieGroup>::Algebra) -> Option<super::FieldAndDerivative<Self::State>> {
        if !self.potential.second_derivatives() {
            return None;
        }
        let (g, u) = (&y.0, &y.1 .0);
        let (eta, du) = (&xi.0, &xi.1);
        let d = super::force_derivative(&self.bundle, &self.potential, &self.metric, g, &SMatrix::zeros(), eta, &SMatrix::zeros());
        let dlift = self.bundle.horizontal_lift(g, du) + self.bundle.lift_derivative(g, u, eta);
        Some((self.vector_field(t, y), ProductAlgebra(dlift, d.d_force * self.inv_mass)))
    }

    /// `E = (m/2)|u|² + V(x)`.
    fn energy(&self, y: &Self::State) -> f64 {
        self.kinetic_energy(y) + self.potential_energy(y)
    }

    /// [`FrameBundle::bundle_defect`] of `g`; `NaN` if the state is not finite.
    fn defect(&self, y: &Self::State) -> f64 {
        combine_defects(&[
            self.bundle.bundle_defect(&y.0),
            finite_defect(self.bundle.position(&y.0).iter()),
            finite_defect(y.1 .0.iter()),
        ])
    }

    /// `q ↦ qk`, `u ↦ kᵀu`: `(vertical(g, w), −w·u)`.
    fn gauge(&self, y: &Self::State) -> Vec<<Self::State as LieGroup>::Algebra> {
        crate::dynamics::skew_basis::<N>().iter().map(|w| ProductAlgebra(self.bundle.vertical(&y.0, w), -(w * y.1 .0))).collect()
    }
}

/// `0` if every value is finite, else `NaN`.
pub(crate) fn finite_defect<'a, I: IntoIterator<Item = &'a f64>>(values: I) -> f64 {
    if values.into_iter().all(|v| v.is_finite()) {
        0.0
    } else {
        f64::NAN
    }
}

/// The largest defect; `NaN` if any defect is `NaN` (a plain `f64::max` would
/// hide it).
pub(crate) fn combine_defects(defects: &[f64]) -> f64 {
    let mut worst: f64 = 0.0;
    for &d in defects {
        if d.is_nan() {
            return f64::NAN;
        }
        worst = worst.max(d);
    }
    worst
}

/// Validates a bundle element given by the user: finite group matrix
/// ([`LieGroup::to_matrix`]) and [`FrameBundle::bundle_defect`] ≤ [`STATE_TOLERANCE`].
pub(crate) fn check_bundle_element<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g: &B::Group,
) -> Result<()> {
    finite("g", g.to_matrix().iter())?;
    let defect = bundle.bundle_defect(g);
    if defect.is_nan() || defect > STATE_TOLERANCE {
        return Err(Error::Constraint {
            field: "g",
            constraint: "element of the frame bundle (group constraint)",
            defect,
            tolerance: STATE_TOLERANCE,
        });
    }
    Ok(())
}

/// Checks that `generator` is finite and an infinitesimal isometry of the
/// ambient metric `η`: `max|Aᵀη + ηA| ≤` [`STATE_TOLERANCE`]`·max(1, max|A|)`.
///
/// Errors: [`Error::NotFinite`] / [`Error::Constraint`] with field `"generator"`.
pub fn momentum_map_generator_check<const E: usize>(
    metric: &SMatrix<f64, E, E>,
    generator: &SMatrix<f64, E, E>,
) -> Result<()> {
    finite("generator", generator.iter())?;
    let skew = (generator.transpose() * metric + metric * generator).amax() / generator.amax().max(1.0);
    if skew > STATE_TOLERANCE {
        return Err(Error::Constraint {
            field: "generator",
            constraint: "infinitesimal isometry of the ambient metric: Aᵀη + ηA = 0",
            defect: skew,
            tolerance: STATE_TOLERANCE,
        });
    }
    Ok(())
}

/// A bundle element over the embedded point `p` (some positively oriented
/// orthonormal frame at `p`), for building initial states.
///
/// Where the chart is regular it is `from_chart(chart(p), I)`, i.e. the
/// paper's frame field `E(x)` (accurate even far out on H², where the bundle
/// uses a Cartan decomposition). At the chart's singular points
/// ([`Error::OutsideChart`]: the poles of S², the origin of H², the antipode
/// of the S³ chart) the frame is built by Gram–Schmidt (in the ambient metric,
/// which is positive definite on the tangent spaces) from the tangential parts
/// of the ambient basis vectors, largest first, and its orientation is fixed by
/// [`FrameBundle::from_frame`] (the last vector is reversed if the first
/// attempt is rejected).
///
/// Errors: those of [`Manifold::chart`](crate::manifold::Manifold::chart) for
/// `p` ([`Error::NotFinite`], [`Error::Constraint`] with field `"p"` when `p`
/// is not on the manifold).
///
/// *Proposed shared API*: this belongs on `FrameBundle` (`element_at(p)`);
/// it is here until then.
pub fn bundle_element_at<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    p: &SVector<f64, E>,
) -> Result<B::Group> {
    match bundle.chart(p) {
        Ok(x) => bundle.from_chart(&x, &SMatrix::identity()),
        Err(Error::OutsideChart { .. }) => gram_schmidt_element(bundle, p),
        Err(e) => Err(e),
    }
}

/// Gram–Schmidt frame at `p` (see [`bundle_element_at`]).
fn gram_schmidt_element<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    p: &SVector<f64, E>,
) -> Result<B::Group> {
    let metric = bundle.ambient_metric();
    let dot = |a: &SVector<f64, E>, b: &SVector<f64, E>| a.dot(&(metric * b));
    let mut cand: [SVector<f64, E>; E] = [SVector::zeros(); E];
    for (i, c) in cand.iter_mut().enumerate() {
        let mut ei = SVector::<f64, E>::zeros();
        ei[i] = 1.0;
        *c = bundle.project_tangent(p, &ei);
    }
    let mut used = [false; E];
    let mut q = SMatrix::<f64, E, N>::zeros();
    for a in 0..N {
        // Orthogonalise the unused candidates against the chosen vectors
        // (twice, for stability) and take the longest.
        let mut best: Option<(usize, f64)> = None;
        for i in 0..E {
            if used[i] {
                continue;
            }
            for _ in 0..2 {
                for b in 0..a {
                    let qb: SVector<f64, E> = q.column(b).into();
                    let c = dot(&cand[i], &qb);
                    cand[i] -= qb * c;
                }
            }
            let n2 = dot(&cand[i], &cand[i]);
            if n2.is_finite() && best.is_none_or(|(_, m)| n2 > m) {
                best = Some((i, n2));
            }
        }
        match best {
            Some((i, n2)) if n2 > 0.0 => {
                used[i] = true;
                q.set_column(a, &(cand[i] / n2.sqrt()));
            }
            _ => {
                return Err(Error::Constraint {
                    field: "p",
                    constraint: "a point of the manifold with an N-dimensional tangent space",
                    defect: f64::NAN,
                    tolerance: STATE_TOLERANCE,
                })
            }
        }
    }
    match bundle.from_frame(p, &q) {
        Ok(g) => Ok(g),
        Err(_) => {
            let last = -q.column(N - 1);
            q.set_column(N - 1, &last);
            bundle.from_frame(p, &q)
        }
    }
}

/// Components `u = qᵀη v` of the ambient vector `v` in the frame `q` of `g`,
/// after checking that `v` is finite and tangent at the point of `g`: the
/// residual `v − q u` must be ≤ [`STATE_TOLERANCE`] relative to
/// `max|v|·max(1, max|q|²)` (the factor `|q|²` is the round-off of the
/// projection on H² far from the origin, where frame vectors grow like
/// `cosh(r/R)`).
///
/// Errors: [`Error::NotFinite`] / [`Error::Constraint`] naming `field`.
pub fn tangent_components<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    g: &B::Group,
    v: &SVector<f64, E>,
    field: &'static str,
) -> Result<SVector<f64, N>> {
    finite(field, v.iter())?;
    let q = bundle.frame_vectors(g);
    let u = q.transpose() * bundle.ambient_metric() * v;
    let residual = (v - q * u).amax();
    let scale = v.amax() * q.amax().powi(2).max(1.0);
    let defect = if scale > 0.0 { residual / scale } else { 0.0 };
    if defect.is_nan() || defect > STATE_TOLERANCE {
        return Err(Error::Constraint {
            field,
            constraint: "vector tangent to the manifold at the point",
            defect,
            tolerance: STATE_TOLERANCE,
        });
    }
    Ok(u)
}

/// `err` with the field name `from` replaced by `to` (for errors of the
/// bundle's `from_frame` about `q` when the user passed the body frame `e`).
pub(crate) fn rename_field(err: Error, from: &'static str, to: &'static str) -> Error {
    let swap = |f: &'static str| if f == from { to } else { f };
    match err {
        Error::NotFinite { field } => Error::NotFinite { field: swap(field) },
        Error::Constraint { field, constraint, defect, tolerance } => {
            Error::Constraint { field: swap(field), constraint, defect, tolerance }
        }
        Error::InvalidParameter { field, value, allowed } => {
            Error::InvalidParameter { field: swap(field), value, allowed }
        }
        other => other,
    }
}

// -- splitting ---------------------------------------------------------------

/// The kick and the geodesic flow of the point; exact on S², H², S³.
impl<B, P, const N: usize, const E: usize> Splittable for PointModel<B, P, N, E>
where
    B: FrameBundle<N, E>,
    P: Potential<N, E>,
{
    /// `u ← u + hF̂/m`.
    #[inline(always)]
    fn kick(&self, y: &Self::State, h: f64) -> Self::State {
        Product(y.0, Rn(y.1 .0 + self.force(y) * (h * self.inv_mass())))
    }

    /// The geodesic flow `g ← g₀ exp(h ξ(u₀))`, `u` unchanged.
    #[inline(always)]
    fn drift(&self, y: &Self::State, h: f64) -> Self::State {
        let xi = self.bundle().horizontal_lift(&y.0, &y.1 .0);
        Product(y.0.compose(&B::Group::exp(&(xi * h))), y.1)
    }

    fn has_free_flow(&self) -> bool {
        self.bundle().exact_free_flow()
    }

    fn drift_exps(&self) -> u32 {
        1
    }
}

impl<B, P, const N: usize, const E: usize> SplitDispatch for PointModel<B, P, N, E>
where
    B: FrameBundle<N, E>,
    P: Potential<N, E>,
{
    type Split = Self;
    #[inline(always)]
    fn as_splittable(&self) -> Option<&Self> {
        self.has_free_flow().then_some(self)
    }
}
