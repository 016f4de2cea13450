//! The round sphere S²(R) in the paper's polar coordinates (§5.1).

use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

use super::{GeodesicDistance, Manifold, Tensor3, Tensor4};
use crate::{Error, Result};

/// The sphere of radius `R` centred at the origin of ℝ³ (paper §5.1).
///
/// **Chart** `x = (r, φ)`: `r` is the geodesic distance from the north pole
/// `(0, 0, R)`, `ϑ = r/R ∈ (0, π)`, `φ` the longitude (any finite value; `φ`
/// and `φ + 2π` are the same point).
/// - Embedding: `R(sin ϑ cos φ, sin ϑ sin φ, cos ϑ)`.
/// - Metric (a87): `ds² = dr² + R² sin²(r/R) dφ²`, Gaussian curvature `K = 1/R²`.
/// - Christoffel symbols: `Γ^r_φφ = −R sin ϑ cos ϑ` (the paper's printed
///   `−(R/2) sin ϑ` is a typo, SPEC §8), `Γ^φ_rφ = Γ^φ_φr = cot ϑ / R`, all
///   others zero.
/// - Riemann tensor: `R^i_jkl = K(δ^i_k g_jl − δ^i_l g_jk)`.
/// - Frame field (a90): `E_r = ∂_r`, `E_φ = (R sin ϑ)⁻¹ ∂_φ`, orthonormal and
///   positively oriented w.r.t. the outward normal: `E_r × E_φ = n = x/R`. In
///   ambient components `E_r = (cos ϑ cos φ, cos ϑ sin φ, −sin ϑ)`,
///   `E_φ = (−sin φ, cos φ, 0)`.
/// - Frame connection (`∇_{E_C} E_B = Γ^A_BC E_A`):
///   `Γ^φ_rφ = cot ϑ / R`, `Γ^r_φφ = −cot ϑ / R`, all others zero (so
///   `Γ^φ_φr = 0 ≠ Γ^φ_rφ`, as the paper notes).
///
/// **Poles.** The chart is singular at `r = 0` and `r = πR`. Chart points are
/// accepted when `0 < r/R < π` and `sin(r/R) >` [`Sphere2::POLE_TOLERANCE`];
/// [`Manifold::chart`], [`Manifold::chart_tangent`] and the bundle's
/// `to_chart` fail with [`Error::OutsideChart`] for embedded points whose
/// distance from the polar axis is `≤ POLE_TOLERANCE·R`. Away from that set
/// the chart map is backward stable, but its conditioning is that of polar
/// coordinates: a perturbation `δ` of the embedded point moves `φ` by up to
/// `δ/(R sin ϑ)`. Computations that pass near a pole should use the frame
/// bundle ([`FrameBundle`](crate::bundle::FrameBundle) for `Sphere2`), which
/// has no singularity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere2 {
    r: f64,
    /// `1/R`, kept so that the vector fields multiply instead of divide.
    inv_r: f64,
}

impl Sphere2 {
    /// Smallest `sin(r/R)` (distance from the polar axis over `R`) at which the
    /// polar chart is used; closer to a pole it reports [`Error::OutsideChart`].
    pub const POLE_TOLERANCE: f64 = 1e-12;
    /// Largest relative defect `||p| − R|/R` of an embedded point accepted by
    /// [`Manifold::chart`], [`GeodesicDistance::distance`] and the bundle's `from_frame`.
    pub const POINT_TOLERANCE: f64 = 1e-9;

    /// The sphere of radius `radius`; fails unless `radius` is finite and > 0.
    ///
    /// ```
    /// use framedyn::manifold::{Manifold, Sphere2};
    /// use nalgebra::Vector2;
    ///
    /// let s2 = Sphere2::new(2.0)?;
    /// let x = s2.embed(&Vector2::new(std::f64::consts::PI, 0.0)); // (r, φ): r = πR/2, the equator
    /// assert!((x.norm() - 2.0).abs() < 1e-15 && x[2].abs() < 1e-15);
    /// let err = Sphere2::new(-1.0).unwrap_err();
    /// assert!(err.to_string().contains("R") && err.to_string().contains("> 0"));
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(radius: f64) -> Result<Self> {
        let r = crate::error::positive("R", radius)?;
        Ok(Sphere2 { r, inv_r: 1.0 / r })
    }

    /// The radius `R`.
    #[inline]
    pub fn radius(&self) -> f64 {
        self.r
    }

    /// `1/R` (stored: the inner loops multiply by it).
    #[inline]
    pub fn inv_radius(&self) -> f64 {
        self.inv_r
    }

    /// The Gaussian curvature `K = 1/R²`.
    #[inline]
    pub fn curvature(&self) -> f64 {
        self.inv_r * self.inv_r
    }

    /// The frame field (a90) at the chart point `x` in ambient components:
    /// columns `E_r = (cos ϑ cos φ, cos ϑ sin φ, −sin ϑ)`, `E_φ = (−sin φ, cos φ, 0)`.
    pub fn ambient_frame(&self, x: &Vector2<f64>) -> Matrix3x2<f64> {
        let (st, ct) = (x[0] / self.r).sin_cos();
        let (sp, cp) = x[1].sin_cos();
        Matrix3x2::new(ct * cp, -sp, ct * sp, cp, -st, 0.0)
    }

    /// Validates an embedded point: finite and within [`Self::POINT_TOLERANCE`]
    /// of the sphere.
    pub(crate) fn check_point(&self, field: &'static str, p: &Vector3<f64>) -> Result<()> {
        crate::error::finite(field, p.iter())?;
        let defect = self.point_defect(p);
        if defect > Self::POINT_TOLERANCE {
            return Err(Error::Constraint {
                field,
                constraint: "point on the sphere, |p| = R",
                defect,
                tolerance: Self::POINT_TOLERANCE,
            });
        }
        Ok(())
    }

    /// `(sin ϑ, cos ϑ)` of the chart point `x`.
    #[inline]
    fn sc(&self, x: &Vector2<f64>) -> (f64, f64) {
        (x[0] / self.r).sin_cos()
    }
}

/// `a·b − c·d` by Kahan's algorithm with fused multiply–adds: the rounding
/// error of `c·d` is recovered exactly, so the result is within 2 ulp even
/// under cancellation (Jeannerod, Louvet & Muller, Math. Comp. 82 (2013)).
#[inline]
fn diff_of_products(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let w = c * d;
    let e = (-c).mul_add(d, w);
    let f = a.mul_add(b, -w);
    f + e
}

impl Manifold<2, 3> for Sphere2 {
    const NAME: &'static str = "S2";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["r", "phi"]
    }

    fn coordinate_units(&self) -> [&'static str; 2] {
        ["L", "rad"]
    }

    /// `Ok` iff `r`, `φ` are finite, `0 < r/R < π` and
    /// `sin(r/R) >` [`Sphere2::POLE_TOLERANCE`].
    fn check_chart(&self, x: &Vector2<f64>) -> Result<()> {
        crate::error::finite("x = (r, phi)", x.iter())?;
        let t = x[0] / self.r;
        if !(t > 0.0 && t < std::f64::consts::PI) {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "r must lie in (0, πR): the poles r = 0 and r = πR are coordinate singularities",
            });
        }
        if t.sin() <= Self::POLE_TOLERANCE {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "sin(r/R) ≤ 1e-12: point within POLE_TOLERANCE of a pole, where the polar chart is singular",
            });
        }
        Ok(())
    }

    /// `diag(1, R² sin²(r/R))` (a87).
    fn metric(&self, x: &Vector2<f64>) -> Matrix2<f64> {
        let rs = self.r * self.sc(x).0;
        Matrix2::new(1.0, 0.0, 0.0, rs * rs)
    }

    /// `Γ^r_φφ = −R sin ϑ cos ϑ`, `Γ^φ_rφ = Γ^φ_φr = cot ϑ / R`.
    fn christoffel(&self, x: &Vector2<f64>) -> Tensor3<2> {
        let (s, c) = self.sc(x);
        let mut g = [[[0.0; 2]; 2]; 2];
        g[0][1][1] = -self.r * s * c;
        g[1][0][1] = c / (self.r * s);
        g[1][1][0] = g[1][0][1];
        g
    }

    /// `R^i_jkl = K(δ^i_k g_jl − δ^i_l g_jk)`, `K = 1/R²`.
    fn riemann(&self, x: &Vector2<f64>) -> Tensor4<2> {
        let g = self.metric(x);
        let k = self.curvature();
        let mut out = [[[[0.0; 2]; 2]; 2]; 2];
        for (i, oi) in out.iter_mut().enumerate() {
            for (j, oj) in oi.iter_mut().enumerate() {
                for (kk, ok) in oj.iter_mut().enumerate() {
                    for (l, v) in ok.iter_mut().enumerate() {
                        let dik = if i == kk { 1.0 } else { 0.0 };
                        let dil = if i == l { 1.0 } else { 0.0 };
                        *v = k * (dik * g[(j, l)] - dil * g[(j, kk)]);
                    }
                }
            }
        }
        out
    }

    /// `E = [[1, 0], [0, 1/(R sin ϑ)]]` (columns `E_r`, `E_φ`), (a90).
    fn frame(&self, x: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(1.0, 0.0, 0.0, 1.0 / (self.r * self.sc(x).0))
    }

    /// `Γ^φ_rφ = cot ϑ / R`, `Γ^r_φφ = −cot ϑ / R` (indices `r = 0`, `φ = 1`).
    fn frame_connection(&self, x: &Vector2<f64>) -> Tensor3<2> {
        let (s, c) = self.sc(x);
        let k = c / (self.r * s);
        let mut g = [[[0.0; 2]; 2]; 2];
        g[1][0][1] = k;
        g[0][1][1] = -k;
        g
    }

    fn ambient_metric(&self) -> Matrix3<f64> {
        Matrix3::identity()
    }

    /// `R(sin ϑ cos φ, sin ϑ sin φ, cos ϑ)`.
    fn embed(&self, x: &Vector2<f64>) -> Vector3<f64> {
        let (st, ct) = self.sc(x);
        let (sp, cp) = x[1].sin_cos();
        Vector3::new(st * cp, st * sp, ct) * self.r
    }

    /// `v^r E_r + v^φ R sin ϑ E_φ` in ambient components.
    fn embed_tangent(&self, x: &Vector2<f64>, v: &Vector2<f64>) -> Vector3<f64> {
        let e = self.ambient_frame(x);
        e.column(0) * v[0] + e.column(1) * (v[1] * self.r * self.sc(x).0)
    }

    /// `r = R·atan2(√(p₁² + p₂²), p₃)`, `φ = atan2(p₂, p₁) ∈ (−π, π]`. Fails
    /// for non-finite `p`, for `p` off the sphere by more than
    /// [`Sphere2::POINT_TOLERANCE`] (relative), and near the poles (see
    /// [`Sphere2::POLE_TOLERANCE`]).
    fn chart(&self, p: &Vector3<f64>) -> Result<Vector2<f64>> {
        self.check_point("p", p)?;
        let rho = p[0].hypot(p[1]);
        let x = Vector2::new(self.r * rho.atan2(p[2]), p[1].atan2(p[0]));
        if rho <= Self::POLE_TOLERANCE * p.norm() {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "point within POLE_TOLERANCE·R of the polar axis, where φ is undefined",
            });
        }
        self.check_chart(&x)?;
        Ok(x)
    }

    /// `(w·E_r, w·E_φ/(R sin ϑ))` at `x = chart(p)` (the normal part of `w` is
    /// ignored). Fails where [`Manifold::chart`] fails or `w` is not finite.
    fn chart_tangent(&self, p: &Vector3<f64>, w: &Vector3<f64>) -> Result<Vector2<f64>> {
        let x = self.chart(p)?;
        crate::error::finite("w", w.iter())?;
        let e = self.ambient_frame(&x);
        Ok(Vector2::new(e.column(0).dot(w), e.column(1).dot(w) / (self.r * self.sc(&x).0)))
    }

    /// `||p| − R|/R` (`+∞` for non-finite `p`).
    fn point_defect(&self, p: &Vector3<f64>) -> f64 {
        let d = (p.norm() - self.r).abs() / self.r;
        if d.is_finite() {
            d
        } else {
            f64::INFINITY
        }
    }

    /// `R·p/|p|` (non-finite for `p = 0`, where no nearest point is defined).
    fn project_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        p * (self.r / p.norm())
    }

    /// `w − (w·n) n`, `n = p/|p|`.
    fn project_tangent(&self, p: &Vector3<f64>, w: &Vector3<f64>) -> Vector3<f64> {
        let n = p / p.norm();
        w - n * n.dot(w)
    }
}

impl GeodesicDistance<2, 3> for Sphere2 {
    /// `R·atan2(|p × q|, p·q)`, the angle between the two given vectors
    /// (their lengths do not matter). Unlike `acos` it is accurate for nearby
    /// and for nearly antipodal points; the cross product is formed with
    /// Kahan's FMA difference of products (each component within 2 ulp), so
    /// even for nearby points the result is accurate to a few ulp *relative*
    /// to the distance between the given floating-point points. Fails for
    /// non-finite points or points off the sphere by more than
    /// [`Sphere2::POINT_TOLERANCE`].
    fn distance(&self, p: &Vector3<f64>, q: &Vector3<f64>) -> Result<f64> {
        self.check_point("p", p)?;
        self.check_point("q", q)?;
        let cross = Vector3::new(
            diff_of_products(p[1], q[2], p[2], q[1]),
            diff_of_products(p[2], q[0], p[0], q[2]),
            diff_of_products(p[0], q[1], p[1], q[0]),
        );
        Ok(self.r * cross.norm().atan2(p.dot(q)))
    }
}
