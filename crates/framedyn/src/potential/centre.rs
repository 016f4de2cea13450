//! The centre of a central potential on S², H² or S³, and the geodesic
//! distance `r` from it in ambient coordinates.

use nalgebra::{SMatrix, SVector};

use super::Scalar;
use crate::error::finite;
use crate::manifold::{Hyperbolic2, Manifold, Sphere2, Sphere3, H2_TOLERANCE, S3_POINT_TOLERANCE};
use crate::{Error, Result};

/// The two constant-curvature geometries a [`Centre`] can live in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Geometry {
    /// The round sphere S²(R) ⊂ ℝ³ or S³(R) ⊂ ℝ⁴ (curvature `+1/R²`).
    Sphere,
    /// The hyperbolic plane H²(R) on the hyperboloid in Minkowski ℝ^{2,1}
    /// (curvature `−1/R²`).
    Hyperbolic,
}

/// The centre `c` of a central potential `V(r)`, `r` the geodesic distance
/// from `c`, on S²(R), H²(R) or S³(R) (ambient dimension `E` = 3, 3, 4).
///
/// It stores an ambient isometry `M` that maps `c` to the pole, so that for a
/// point `x` of the manifold the rotated coordinates `y = M x` are
/// - `y₀ = R cos(r/R)` (sphere) or `R cosh(r/R)` (H²) — the *axial*
///   component `Z = ⟨x, c⟩/R` (sphere), `Z = −⟨x, c⟩_η/R` (H²);
/// - `y₁ … y_{E−1}` with `T = Σ_k y_k² = R² sin²(r/R)` (sphere) or
///   `R² sinh²(r/R)` (H²) — the *transverse* part, a sum of squares, so
///   `sin`/`sinh` of small distances keep full relative precision (no
///   `1 − cos²` cancellation).
///
/// The default centres are the poles of the paper's charts: `(0, 0, R)` on
/// S² and H², `(R, 0, 0, 0)` (the identity quaternion, `r̄ = 0`) on S³; for
/// them `M` is a permutation and `y` is exact. For other centres `M` is a
/// Householder reflection (sphere) or a boost (H²) computed once, and
/// `y` carries the rounding of one matrix–vector product (`≈ ε|x|` absolute;
/// on H² `|x| ≈ R cosh` grows with the distance of both `x` and `c` from the
/// pole, an intrinsic loss of the hyperboloid model).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Centre<const E: usize> {
    radius: f64,
    /// `1/R` (the gradients multiply by it).
    inv_radius: f64,
    geometry: Geometry,
    point: SVector<f64, E>,
    /// Row 0: axial direction; rows 1..E: transverse directions.
    rows: SMatrix<f64, E, E>,
}

/// `√t` with derivative parts set to zero at `t = 0` exactly, where `√` is
/// not differentiable: used for quantities (`R sin(r/R)`, `λ² − μ²`) whose
/// square is smooth and has a minimum 0 there, so every smooth even function
/// of them has zero derivative there anyway.
#[inline]
pub(crate) fn sqrt0<D: Scalar>(t: D) -> D {
    if t.re() == 0.0 {
        D::from(0.0)
    } else {
        t.sqrt()
    }
}

impl Centre<3> {
    /// The pole `(0, 0, R)` of the paper's chart on S² (§5.1): `r` is the
    /// paper's polar coordinate.
    pub fn sphere2(sphere: &Sphere2) -> Self {
        let r = sphere.radius();
        Self::euclidean(r, SVector::from([0.0, 0.0, r]))
    }

    /// The point `c` (ambient coordinates) of S² as centre. Fails with
    /// [`Error::NotFinite`] or [`Error::Constraint`] (field `"centre"`)
    /// unless `c` is finite and on the sphere to
    /// [`Sphere2::POINT_TOLERANCE`] (relative); it is then projected onto
    /// the sphere.
    pub fn sphere2_at(sphere: &Sphere2, c: &SVector<f64, 3>) -> Result<Self> {
        check_on(sphere, "centre", c, Sphere2::POINT_TOLERANCE, "on the sphere, |c| = R")?;
        let r = sphere.radius();
        Ok(Self::euclidean(r, c * (r / c.norm())))
    }

    /// The origin `(0, 0, R)` of the paper's chart on H² (§5.2).
    pub fn hyperbolic2(plane: &Hyperbolic2) -> Self {
        Self::boost(plane.radius(), 0.0, 0.0)
    }

    /// The point `c` of H² as centre. Fails with [`Error::NotFinite`] or
    /// [`Error::Constraint`] (field `"centre"`) unless `c` is finite and on
    /// the upper sheet to [`H2_TOLERANCE`] (relative to `|c|²`); it is then
    /// projected onto the sheet (spatial part kept).
    pub fn hyperbolic2_at(plane: &Hyperbolic2, c: &SVector<f64, 3>) -> Result<Self> {
        check_on(plane, "centre", c, H2_TOLERANCE, "on the upper sheet, −x² − y² + z² = R², z > 0")?;
        let r = plane.radius();
        Ok(Self::boost(r, c[0] / r, c[1] / r))
    }

    fn boost(r: f64, s1: f64, s2: f64) -> Self {
        // B = [u₁ | u₂ | ĉ] ∈ SO⁺(1,2) maps the pole to ĉ = (s₁, s₂, ch);
        // y = B⁻¹x = ηBᵀηx, with the axial row first.
        let ch = 1.0f64.hypot(s1.hypot(s2));
        let a = 1.0 / (1.0 + ch);
        let u1 = [1.0 + a * s1 * s1, a * s1 * s2, s1];
        let u2 = [a * s1 * s2, 1.0 + a * s2 * s2, s2];
        let rows = SMatrix::<f64, 3, 3>::new(
            -s1, -s2, ch, //
            u1[0], u1[1], -u1[2], //
            u2[0], u2[1], -u2[2],
        );
        Centre { radius: r, inv_radius: 1.0 / r, geometry: Geometry::Hyperbolic, point: SVector::from([s1 * r, s2 * r, ch * r]), rows }
    }
}

impl Centre<4> {
    /// The point `R·1 = (R, 0, 0, 0)` (scalar part first), the centre `r̄ = 0`
    /// of the chart of S³ (§6): `r = |r̄|`.
    pub fn sphere3(sphere: &Sphere3) -> Self {
        let r = sphere.radius();
        Self::euclidean(r, SVector::from([r, 0.0, 0.0, 0.0]))
    }

    /// The point `c` of S³ as centre; fails with [`Error::NotFinite`] or
    /// [`Error::Constraint`] (field `"centre"`) unless `c` is finite and on
    /// S³ to [`S3_POINT_TOLERANCE`] (relative); it is then projected onto S³.
    pub fn sphere3_at(sphere: &Sphere3, c: &SVector<f64, 4>) -> Result<Self> {
        check_on(sphere, "centre", c, S3_POINT_TOLERANCE, "on the sphere, |c| = R")?;
        let r = sphere.radius();
        Ok(Self::euclidean(r, c * (r / c.norm())))
    }
}

fn check_on<M: Manifold<N, E>, const N: usize, const E: usize>(
    m: &M,
    field: &'static str,
    c: &SVector<f64, E>,
    tolerance: f64,
    constraint: &'static str,
) -> Result<()> {
    finite(field, c.iter())?;
    let defect = m.point_defect(c);
    if defect > tolerance {
        return Err(Error::Constraint { field, constraint, defect, tolerance });
    }
    Ok(())
}

impl<const E: usize> Centre<E> {
    /// Euclidean case: `M` = the Householder reflection taking `ĉ = c/R` to
    /// `±e₀` with its first row replaced by `ĉ`, so that the rows are an
    /// orthonormal basis starting with `ĉ`.
    fn euclidean(r: f64, c: SVector<f64, E>) -> Self {
        let u = c / r;
        let sign = if u[0] >= 0.0 { 1.0 } else { -1.0 };
        let mut v = u;
        v[0] += sign;
        let vv = v.norm_squared();
        let mut rows = SMatrix::<f64, E, E>::identity() - v * v.transpose() * (2.0 / vv);
        rows.set_row(0, &u.transpose());
        Centre { radius: r, inv_radius: 1.0 / r, geometry: Geometry::Sphere, point: c, rows }
    }

    /// `1/R`.
    #[inline]
    pub fn inv_radius(&self) -> f64 {
        self.inv_radius
    }

    /// The axial component `y₀ = (M x)₀` alone (row 0 of `M` times `x`).
    #[inline]
    pub(crate) fn axial<D: Scalar>(&self, x: &SVector<D, E>) -> D {
        let mut s = D::from(0.0);
        for j in 0..E {
            let m = self.rows[(0, j)];
            if m != 0.0 {
                s += x[j] * m;
            }
        }
        s
    }

    /// [`Self::axial`] for plain numbers: one dot product, no tests for
    /// zero entries (exact all the same for the default centres, whose row 0
    /// is a unit vector).
    #[inline]
    pub(crate) fn axial_f64(&self, x: &SVector<f64, E>) -> f64 {
        self.rows.row(0).transpose().dot(x)
    }

    /// `∂y₀/∂x`: row 0 of `M` (the gradient of the axial component).
    #[inline]
    pub(crate) fn axial_row(&self) -> SVector<f64, E> {
        self.rows.row(0).transpose()
    }

    /// The radius (pseudoradius on H²) `R` of the manifold.
    #[inline]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Sphere or hyperbolic plane.
    #[inline]
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// The centre `c` (ambient coordinates, on the manifold).
    #[inline]
    pub fn point(&self) -> &SVector<f64, E> {
        &self.point
    }

    /// The rotated coordinates `y = M x` (see the type documentation).
    #[inline]
    pub(crate) fn rotate<D: Scalar>(&self, x: &SVector<D, E>) -> SVector<D, E> {
        SVector::from_fn(|k, _| {
            let mut s = D::from(0.0);
            for j in 0..E {
                let m = self.rows[(k, j)];
                if m != 0.0 {
                    s += x[j] * m;
                }
            }
            s
        })
    }

    /// `Mᵀ w`: pulls a covector given in the rotated coordinates back to the
    /// ambient ones.
    #[inline]
    pub(crate) fn pull_back(&self, w: &SVector<f64, E>) -> SVector<f64, E> {
        self.rows.transpose() * w
    }

    /// `(Z, T)`: `Z = R cos(r/R)` (`R cosh(r/R)` on H²), `T = R² sin²(r/R)`
    /// (`R² sinh²(r/R)`), for a point `x` of the manifold; see the type
    /// documentation for their extension off the manifold (`Z` linear, `T`
    /// quadratic in `x`).
    #[inline]
    pub fn axial_transverse<D: Scalar>(&self, x: &SVector<D, E>) -> (D, D) {
        let y = self.rotate(x);
        (y[0], transverse_sq(&y))
    }

    /// `cos(r/R)` on S²/S³, `cosh(r/R)` on H²: `Z/R`, linear in `x`.
    #[inline]
    pub fn cos_r<D: Scalar>(&self, x: &SVector<D, E>) -> D {
        self.axial(x) * self.inv_radius
    }

    /// The geodesic distance `r` of `x` from the centre:
    /// `R·atan2(√T, Z)` on S²/S³ (accurate for every `r ∈ [0, πR]`),
    /// `R·asinh(√T/R)` on H² (accurate at every distance). `r` is not
    /// differentiable at the centre itself; there its derivative parts are
    /// set to zero (the derivative of every smooth function of `r²`).
    pub fn distance<D: Scalar>(&self, x: &SVector<D, E>) -> D {
        let (z, t) = self.axial_transverse(x);
        let s = sqrt0(t);
        match self.geometry {
            Geometry::Sphere => s.atan2(z) * self.radius,
            Geometry::Hyperbolic => (s * (1.0 / self.radius)).asinh() * self.radius,
        }
    }

    /// `∂r/∂x` of [`Self::distance`] in closed form, with `r`; zero at the
    /// centre.
    pub(crate) fn distance_gradient(&self, x: &SVector<f64, E>) -> (f64, SVector<f64, E>) {
        let y = self.rotate(x);
        let z = y[0];
        let t = transverse_sq(&y);
        let s = sqrt0(t);
        let r = self.radius;
        // dS = Σ y_k dy_k / S (zero at S = 0), dZ = dy₀.
        let mut w = SVector::<f64, E>::zeros();
        match self.geometry {
            Geometry::Sphere => {
                let den = t + z * z;
                if s != 0.0 {
                    for k in 1..E {
                        w[k] = r * z * y[k] / (s * den);
                    }
                }
                w[0] = -r * s / den;
                (s.atan2(z) * r, self.pull_back(&w))
            }
            Geometry::Hyperbolic => {
                let q = s * (1.0 / r);
                if s != 0.0 {
                    let f = 1.0 / (s * (1.0 + q * q).sqrt());
                    for k in 1..E {
                        w[k] = y[k] * f;
                    }
                }
                (q.asinh() * r, self.pull_back(&w))
            }
        }
    }
}

/// Where a potential that depends on the position only through the axial
/// component `Z = (M x)₀` of a [`Centre`] reads it: a [`Centre`] (any point,
/// `Z` a dot product with the runtime row `M₀`), or a [`Pole`] (the chart's
/// pole, `Z` one coordinate of `x` fixed at compile time).
///
/// Both give the same numbers bit for bit at the poles (the row `M₀` of a
/// default centre is a coordinate unit vector); a [`Pole`] lets the compiler
/// drop every product that only feeds the other coordinates — at an RKMK
/// stage, most of the stage frame `Q₀ exp(θ)`, since the models' force
/// ([`position_force`](crate::dynamics::position_force)) skips the
/// gradient's zero entries (see `docs/performance.md`).
pub trait Axis<const E: usize>: core::fmt::Debug + Clone + Copy + PartialEq + Send + Sync {
    /// The centre as a [`Centre`] (radius, geometry, point, distance).
    fn centre(&self) -> &Centre<E>;
    /// `Z = M₀·x`, with derivative parts for dual numbers.
    fn axial<D: Scalar>(&self, x: &SVector<D, E>) -> D;
    /// `Z = M₀·x` for plain numbers.
    fn axial_f64(&self, x: &SVector<f64, E>) -> f64;
    /// `s·M₀` with `+0` where `M₀` is zero (not `0·s`, which is `−0` for
    /// `s < 0` and NaN for infinite `s`): the gradient of a function of `Z`
    /// alone. For a [`Pole`] the zeros are constants, and the compiler
    /// drops the products they multiply.
    fn scaled_row(&self, s: f64) -> SVector<f64, E>;
}

impl<const E: usize> Axis<E> for Centre<E> {
    #[inline]
    fn centre(&self) -> &Centre<E> {
        self
    }
    #[inline]
    fn axial<D: Scalar>(&self, x: &SVector<D, E>) -> D {
        Centre::axial(self, x)
    }
    #[inline]
    fn axial_f64(&self, x: &SVector<f64, E>) -> f64 {
        Centre::axial_f64(self, x)
    }
    #[inline]
    fn scaled_row(&self, s: f64) -> SVector<f64, E> {
        Centre::axial_row(self).map(|m| if m != 0.0 { m * s } else { 0.0 })
    }
}

/// The pole of the paper's chart as a centre known at compile time:
/// `(0, 0, R)` on S² and H² (`Z = x₂`), `(R, 0, 0, 0)` on S³ (`Z = x₀`).
///
/// The same centre as [`Centre::sphere2`], [`Centre::hyperbolic2`] and
/// [`Centre::sphere3`], with the same values and gradients bit for bit
/// (tested), for potentials generic over [`Axis`] such as
/// [`CosineFamily`](super::CosineFamily): with a [`Pole`] the axial
/// component is one coordinate instead of a dot product with runtime data,
/// and the compiler drops the work that only feeds the others. Choose it in
/// Rust code whose centre is the pole; scenes and Python use [`Centre`].
///
/// ```
/// use framedyn::manifold::Sphere2;
/// use framedyn::potential::{Centre, CosineFamily, Pole};
/// let s2 = Sphere2::new(2.0)?;
/// let about_pole = CosineFamily::new(0.0, 0.5, Pole::sphere2(&s2))?;
/// let about_centre = CosineFamily::new(0.0, 0.5, Centre::sphere2(&s2))?;
/// assert_eq!(about_pole.centre(), about_centre.centre());
/// # Ok::<(), framedyn::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pole<const E: usize> {
    centre: Centre<E>,
}

impl Pole<3> {
    /// The pole `(0, 0, R)` of S² ([`Centre::sphere2`]).
    pub fn sphere2(sphere: &Sphere2) -> Self {
        Pole { centre: Centre::sphere2(sphere) }
    }

    /// The origin `(0, 0, R)` of H² ([`Centre::hyperbolic2`]).
    pub fn hyperbolic2(plane: &Hyperbolic2) -> Self {
        Pole { centre: Centre::hyperbolic2(plane) }
    }
}

impl Pole<4> {
    /// The centre `(R, 0, 0, 0)` of S³ ([`Centre::sphere3`]).
    pub fn sphere3(sphere: &Sphere3) -> Self {
        Pole { centre: Centre::sphere3(sphere) }
    }
}

/// `Axis` of a [`Pole`] whose axial row is the unit vector `e_K`.
macro_rules! pole_axis {
    ($e:literal, $k:literal) => {
        impl Axis<$e> for Pole<$e> {
            #[inline]
            fn centre(&self) -> &Centre<$e> {
                &self.centre
            }
            #[inline(always)]
            fn axial<D: Scalar>(&self, x: &SVector<D, $e>) -> D {
                x[$k]
            }
            #[inline(always)]
            fn axial_f64(&self, x: &SVector<f64, $e>) -> f64 {
                x[$k]
            }
            #[inline(always)]
            fn scaled_row(&self, s: f64) -> SVector<f64, $e> {
                SVector::ith($k, s)
            }
        }
    };
}
pole_axis!(3, 2);
pole_axis!(4, 0);

/// `Σ_{k ≥ 1} y_k²`.
#[inline]
pub(crate) fn transverse_sq<D: Scalar, const E: usize>(y: &SVector<D, E>) -> D {
    let mut t = D::from(0.0);
    for k in 1..E {
        t += y[k] * y[k];
    }
    t
}
