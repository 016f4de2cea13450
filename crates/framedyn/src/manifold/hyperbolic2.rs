//! The hyperbolic plane H²(R) (the paper's pseudosphere, §5.2): constant
//! curvature `K = −1/R²`, realised as the upper sheet of the hyperboloid
//! `−x² − y² + z² = R²`, `z > 0`, in Minkowski space ℝ^{2,1} with metric
//! `dx² + dy² − dz²` (tangent vectors are spacelike).
//!
//! See [`Hyperbolic2`] for the chart, the frame and the numerics far from
//! the origin.

use nalgebra::{SMatrix, SVector, Vector2, Vector3};

use super::{GeodesicDistance, Manifold, Tensor3, Tensor4};
use crate::error::{finite, positive};
use crate::lie::minkowski_dot;
use crate::{Error, Result};

/// Tolerance (relative) on points and tangent vectors accepted by `chart`,
/// `chart_tangent`, `distance` and the frame bundle's `from_frame`.
pub const H2_TOLERANCE: f64 = 1e-9;

/// Points whose spatial part is below this fraction of `z` are treated as the
/// chart origin `r = 0`: there the angle `φ` has no significant digit.
pub const H2_ORIGIN_TOLERANCE: f64 = 16.0 * f64::EPSILON;

/// The hyperbolic plane H²(R) of pseudoradius `R` (the paper's pseudosphere,
/// §5.2): constant curvature `K = −1/R²`, realised as the upper sheet of the
/// hyperboloid `−x² − y² + z² = R²`, `z > 0`, in Minkowski space ℝ^{2,1}
/// with metric `dx² + dy² − dz²` (tangent vectors are spacelike).
///
/// ## Chart and frame (as in the paper)
/// Polar coordinates `(r, φ)` about the "north pole" `(0, 0, R)`, `r` the
/// geodesic distance from it, `ϑ = r/R ∈ (0, ∞)`:
/// `x = (R sinh ϑ cos φ, R sinh ϑ sin φ, R cosh ϑ)`,
/// metric `dr² + R² sinh²ϑ dφ²`, orthonormal frame `E_r = ∂_r`,
/// `E_φ = (R sinh ϑ)⁻¹ ∂_φ` (singular at `r = 0`).
///
/// ## Precision far from the origin
/// A point at geodesic distance `r` has ambient coordinates of size
/// `R cosh ϑ`, so `⟨p, p⟩_η = −R²` can only hold to `≈ ε R² cosh²ϑ` in
/// double precision. Defects are therefore measured relative to `|p|²`, the
/// projection keeps the spatial part `(x, y)` and recomputes
/// `z = √(R² + x² + y²)` (no cancellation), and the chart and the distance are
/// computed from the spatial parts only, without forming Minkowski inner
/// products of large vectors. The orthogonal tangent projection is
/// intrinsically ill-conditioned far out (its Euclidean norm is `≈ 2cosh²ϑ`).
///
/// Its orthonormal frame bundle is SO⁺(1,2): see the `FrameBundle`
/// implementation below and [`H2Frame`](crate::bundle::H2Frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hyperbolic2 {
    radius: f64,
    /// `1/R`, kept so that the vector fields multiply instead of divide.
    inv_radius: f64,
}

impl Hyperbolic2 {
    /// H² with pseudoradius `radius`.
    ///
    /// Errors: [`Error::InvalidParameter`] with field `"R"` unless `radius` is
    /// finite and positive.
    ///
    /// ```
    /// use framedyn::manifold::{Hyperbolic2, Manifold};
    /// use nalgebra::Vector2;
    ///
    /// let h2 = Hyperbolic2::new(1.5)?;
    /// // The upper sheet of x₀² + x₁² − x₂² = −R² in Minkowski ℝ^{2,1}.
    /// let x = h2.embed(&Vector2::new(0.7, 0.3));
    /// assert!((x[0] * x[0] + x[1] * x[1] - x[2] * x[2] + 1.5 * 1.5).abs() < 1e-13 && x[2] > 0.0);
    /// assert!(matches!(Hyperbolic2::new(f64::NAN), Err(framedyn::Error::InvalidParameter { field: "R", .. })));
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(radius: f64) -> Result<Self> {
        let radius = positive("R", radius)?;
        Ok(Hyperbolic2 { radius, inv_radius: 1.0 / radius })
    }

    /// The pseudoradius `R`.
    #[inline]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `1/R` (stored: the inner loops multiply by it).
    #[inline]
    pub fn inv_radius(&self) -> f64 {
        self.inv_radius
    }

    /// The Gaussian curvature `K = −1/R²`.
    #[inline]
    pub fn curvature(&self) -> f64 {
        -(self.inv_radius * self.inv_radius)
    }

    /// Validates an embedded point: finite and on the upper sheet to
    /// [`H2_TOLERANCE`] (relative, [`Manifold::point_defect`]).
    pub(crate) fn check_point(&self, field: &'static str, p: &Vector3<f64>) -> Result<()> {
        finite(field, p.iter())?;
        let d = self.point_defect(p);
        if d > H2_TOLERANCE {
            return Err(Error::Constraint {
                field,
                constraint: "on the upper sheet: −x² − y² + z² = R², z > 0 (relative to |p|²)",
                defect: d,
                tolerance: H2_TOLERANCE,
            });
        }
        Ok(())
    }

    /// Relative tangency defect `|⟨w, p⟩_η| / (|w| |p|)` (Euclidean norms; 0 for `w = 0`).
    pub(crate) fn tangency_defect(p: &Vector3<f64>, w: &Vector3<f64>) -> f64 {
        let scale = w.norm() * p.norm();
        if scale == 0.0 {
            0.0
        } else {
            minkowski_dot(p, w).abs() / scale
        }
    }

    /// `OutsideChart` unless the point (with spatial length `rho` and last
    /// coordinate `z`) is away from the origin.
    pub(crate) fn check_not_origin(rho: f64, z: f64) -> Result<()> {
        if rho <= H2_ORIGIN_TOLERANCE * z {
            Err(Error::OutsideChart {
                manifold: "H2",
                reason: "at (or within round-off of) the origin r = 0, where φ and E_φ are undefined",
            })
        } else {
            Ok(())
        }
    }

    /// `(sinh ϑ, cosh ϑ)` at the chart point `x`.
    #[inline]
    fn sh_ch(&self, x: &SVector<f64, 2>) -> (f64, f64) {
        let t = x[0] / self.radius;
        (t.sinh(), t.cosh())
    }
}

impl Manifold<2, 3> for Hyperbolic2 {
    const NAME: &'static str = "H2";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["r", "phi"]
    }

    fn coordinate_units(&self) -> [&'static str; 2] {
        ["L", "rad"]
    }

    /// `Ok` for finite `(r, φ)` with `r > 0`; [`Error::NotFinite`] (field
    /// `"x"`) or [`Error::OutsideChart`] (`r ≤ 0`: the origin, where `E_φ` is
    /// singular, or outside the coordinate range) otherwise.
    fn check_chart(&self, x: &SVector<f64, 2>) -> Result<()> {
        finite("x", x.iter())?;
        if x[0] > 0.0 {
            Ok(())
        } else {
            Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "r ≤ 0: polar coordinates are singular at the origin r = 0 and undefined for r < 0",
            })
        }
    }

    /// `diag(1, R² sinh²(r/R))`.
    fn metric(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        let (sh, _) = self.sh_ch(x);
        let f = self.radius * sh;
        SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, f * f)
    }

    /// `Γ^r_φφ = −R sinh ϑ cosh ϑ`, `Γ^φ_rφ = Γ^φ_φr = coth ϑ / R`.
    fn christoffel(&self, x: &SVector<f64, 2>) -> Tensor3<2> {
        let (sh, ch) = self.sh_ch(x);
        let mut g = [[[0.0; 2]; 2]; 2];
        g[0][1][1] = -self.radius * sh * ch;
        g[1][0][1] = ch / (sh * self.radius);
        g[1][1][0] = g[1][0][1];
        g
    }

    /// `R^i_{jkl} = K (δ^i_k g_{jl} − δ^i_l g_{jk})`, `K = −1/R²`.
    fn riemann(&self, x: &SVector<f64, 2>) -> Tensor4<2> {
        let g = self.metric(x);
        let k = self.curvature();
        let delta = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                std::array::from_fn(|kk| {
                    std::array::from_fn(|l| k * (delta(i, kk) * g[(j, l)] - delta(i, l) * g[(j, kk)]))
                })
            })
        })
    }

    /// Columns `E_r = (1, 0)`, `E_φ = (0, 1/(R sinh ϑ))`.
    fn frame(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        let (sh, _) = self.sh_ch(x);
        SMatrix::<f64, 2, 2>::new(1.0, 0.0, 0.0, 1.0 / (self.radius * sh))
    }

    /// `∇_{E_φ} E_r = (coth ϑ / R) E_φ`, `∇_{E_φ} E_φ = −(coth ϑ / R) E_r`,
    /// `∇_{E_r} E_r = ∇_{E_r} E_φ = 0` (the frame is parallel along radii):
    /// `Γ^φ_{rφ} = −Γ^r_{φφ} = coth ϑ / R`.
    fn frame_connection(&self, x: &SVector<f64, 2>) -> Tensor3<2> {
        let (sh, ch) = self.sh_ch(x);
        let c = ch / (sh * self.radius);
        let mut g = [[[0.0; 2]; 2]; 2];
        g[1][0][1] = c;
        g[0][1][1] = -c;
        g
    }

    /// `η = diag(1, 1, −1)`.
    fn ambient_metric(&self) -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))
    }

    /// `(R sinh ϑ cos φ, R sinh ϑ sin φ, R cosh ϑ)`.
    fn embed(&self, x: &SVector<f64, 2>) -> SVector<f64, 3> {
        let (sh, ch) = self.sh_ch(x);
        let (s, c) = x[1].sin_cos();
        Vector3::new(self.radius * sh * c, self.radius * sh * s, self.radius * ch)
    }

    /// `v_r (cos φ cosh ϑ, sin φ cosh ϑ, sinh ϑ) + v_φ R sinh ϑ (−sin φ, cos φ, 0)`.
    fn embed_tangent(&self, x: &SVector<f64, 2>, v: &SVector<f64, 2>) -> SVector<f64, 3> {
        let (sh, ch) = self.sh_ch(x);
        let (s, c) = x[1].sin_cos();
        let f = self.radius * sh * v[1];
        Vector3::new(v[0] * c * ch - f * s, v[0] * s * ch + f * c, v[0] * sh)
    }

    /// `r = R asinh(ρ/R)`, `φ = atan2(y, x)` with `ρ = √(x² + y²)`: accurate
    /// to a few ulps at any distance.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] (field `"p"`) if
    /// `p` is not on the upper sheet to [`H2_TOLERANCE`];
    /// [`Error::OutsideChart`] at the origin (`ρ ≤ 16ε·z`, no digit of `φ`).
    fn chart(&self, p: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        self.check_point("p", p)?;
        let rho = p[0].hypot(p[1]);
        Self::check_not_origin(rho, p[2])?;
        Ok(Vector2::new(self.radius * (rho / self.radius).asinh(), p[1].atan2(p[0])))
    }

    /// `(ṙ, φ̇)` of the tangent vector `w` at `p`, from the spatial parts
    /// only: `ṙ = R (x w₁ + y w₂)/(ρ z)`, `φ̇ = (x w₂ − y w₁)/ρ²`. Exact for
    /// tangent `w`, whose last component is `(x w₁ + y w₂)/z`; no
    /// cancellation far out.
    ///
    /// Errors: as [`Self::chart`] for `p`; [`Error::NotFinite`] /
    /// [`Error::Constraint`] (field `"w"`) unless `|⟨w, p⟩_η| ≤ 1e-9·|w||p|`.
    fn chart_tangent(&self, p: &SVector<f64, 3>, w: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        self.check_point("p", p)?;
        finite("w", w.iter())?;
        let td = Self::tangency_defect(p, w);
        if td > H2_TOLERANCE {
            return Err(Error::Constraint {
                field: "w",
                constraint: "tangent to H² at p: ⟨w, p⟩_η = 0 (relative to |w||p|)",
                defect: td,
                tolerance: H2_TOLERANCE,
            });
        }
        let rho = p[0].hypot(p[1]);
        Self::check_not_origin(rho, p[2])?;
        let (ux, uy) = (p[0] / rho, p[1] / rho);
        let w_rho = ux * w[0] + uy * w[1];
        let w_phi = ux * w[1] - uy * w[0];
        Ok(Vector2::new(self.radius * w_rho / p[2], w_phi / rho))
    }

    /// `|⟨p, p⟩_η + R²| / |p|²` (Euclidean `|p|`, which is `≥ R` on the sheet):
    /// the defect relative to the round-off floor `≈ ε|p|²`. `+∞` for
    /// non-finite `p` or `z ≤ 0` (lower sheet / not a point of H²).
    fn point_defect(&self, p: &SVector<f64, 3>) -> f64 {
        if !p.iter().all(|v| v.is_finite()) || p[2] <= 0.0 {
            return f64::INFINITY;
        }
        let r2 = self.radius * self.radius;
        (minkowski_dot(p, p) + r2).abs() / p.norm_squared()
    }

    /// The point of the upper sheet with the same spatial part:
    /// `(x, y, √(R² + x² + y²))`. Accurate at any distance (no cancellation)
    /// and the identity on the sheet up to round-off; for a point displaced by
    /// `δ` it moves it by `O(δ)`. Non-finite input is returned unchanged.
    fn project_point(&self, p: &SVector<f64, 3>) -> SVector<f64, 3> {
        if !p.iter().all(|v| v.is_finite()) {
            return *p;
        }
        Vector3::new(p[0], p[1], self.radius.hypot(p[0].hypot(p[1])))
    }

    /// Minkowski-orthogonal projection onto `T_pH²`: `w + ⟨w, n⟩_η n` with
    /// `n` the unit normal at the projected point. Its Euclidean norm is
    /// `≈ 2cosh²ϑ`, so round-off in `w` is amplified by that much far out.
    fn project_tangent(&self, p: &SVector<f64, 3>, w: &SVector<f64, 3>) -> SVector<f64, 3> {
        let n = self.project_point(p) / self.radius;
        w + n * minkowski_dot(w, &n)
    }
}

impl GeodesicDistance<2, 3> for Hyperbolic2 {
    /// Geodesic distance `d`, from
    /// `sinh²(d/2R) = sinh²((ϑ₁ − ϑ₂)/2) + sinh ϑ₁ sinh ϑ₂ sin²(Δφ/2)`
    /// (the hyperbolic law of cosines in half-angle form, equal to
    /// `|p − q|²_η/(4R²)` on the sheet), evaluated from the spatial parts
    /// `s₁, s₂` without cancellation:
    /// `sinh(ϑ₁ − ϑ₂) = (|s₁|² − |s₂|²)/(|s₁| z₂ + z₁|s₂|)` and
    /// `sinh ϑ₁ sinh ϑ₂ sin²(Δφ/2) = |s₁||s₂| |ŝ₁ − ŝ₂|²/(4R²)`.
    /// Accurate to a few ulps for close points and far from the origin.
    ///
    /// Errors: [`Error::NotFinite`] / [`Error::Constraint`] (fields `"p"`,
    /// `"q"`) for points not on the upper sheet to [`H2_TOLERANCE`].
    fn distance(&self, p: &SVector<f64, 3>, q: &SVector<f64, 3>) -> Result<f64> {
        self.check_point("p", p)?;
        self.check_point("q", q)?;
        let r = self.radius;
        let (a, b) = (p[0].hypot(p[1]), q[0].hypot(q[1]));
        let (za, zb) = (r.hypot(a), r.hypot(b));
        let den = a * zb + za * b;
        let sinh_dt = if den > 0.0 { (a - b) * (a + b) / den } else { 0.0 };
        let half = 0.5 * sinh_dt.asinh();
        let radial = half.sinh();
        let angular = if a > 0.0 && b > 0.0 {
            let chord = Vector2::new(p[0] / a - q[0] / b, p[1] / a - q[1] / b).norm();
            // √(|s₁||s₂|)·|ŝ₁ − ŝ₂|/(2R), squared below.
            (a.sqrt() * b.sqrt()) * chord / (2.0 * r)
        } else {
            0.0
        };
        Ok(2.0 * r * radial.hypot(angular).asinh())
    }
}
