//! The spheroid (ellipsoid of revolution) in geodetic coordinates: see [`Spheroid`].

use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

use super::{Manifold, Tensor3, Tensor4};
use crate::error::{finite, positive};
use crate::{Error, Result};

/// The spheroid `(x² + y²)/a² + z²/c² = 1` ⊂ ℝ³: equatorial radius `a`, polar
/// radius `c` (oblate for `c < a`, prolate for `c > a`, the sphere of radius
/// `a` for `c = a`), with the metric induced by Euclidean ℝ³.
///
/// Everything below is written with the ratio `k = c/a` and the function
///
/// ```text
/// W(φ) = √(cos²φ + k² sin²φ),
/// ```
///
/// which is real and positive for every `k > 0`. (Geodesy writes
/// `W = √(1 − e² sin²φ)` with `e² = 1 − k²`; the eccentricity `e` is imaginary
/// for a prolate spheroid, so it is not used.)
///
/// # Chart: geodetic latitude and longitude
///
/// `x = (φ, λ)`, coordinate names `["lat", "lon"]`. The latitude `φ` is the
/// angle of the outward unit normal above the equatorial plane, the longitude
/// `λ` the angle about the `z` axis:
///
/// ```text
/// n(φ, λ) = (cos φ cos λ, cos φ sin λ, sin φ).
/// ```
///
/// *Embedding.* The point with outward normal `n` is found from the gradient of
/// `F(x) = xᵀDx − 1`, `D = diag(1/a², 1/a², 1/c²)`: `n = Dx/|Dx|`, so
/// `x = D⁻¹n/|Dx|`, and `xᵀDx = 1` gives `|Dx| = 1/√(nᵀD⁻¹n)`. With
/// `nᵀD⁻¹n = a²W²`:
///
/// ```text
/// x(n) = D⁻¹n / √(nᵀD⁻¹n) = (a² n_x, a² n_y, c² n_z) / (a W)
///      = (N cos φ cos λ, N cos φ sin λ, N k² sin φ),        N = a/W.
/// ```
///
/// The inverse, [`Manifold::chart`]: `n ∝ Dx` gives
/// `φ = atan2(z/c², ρ/a²) = atan2(a² z, c² ρ)`, `ρ = √(x² + y²)`,
/// `λ = atan2(y, x)`.
///
/// *Radii of curvature.* `x(φ, λ)` is a surface of revolution with distance
/// from the axis `F(φ) = N cos φ = a cos φ / W` and height
/// `Z(φ) = N k² sin φ = a k² sin φ / W`. From `(W²)′ = −2(1 − k²) sin φ cos φ`:
///
/// ```text
/// F′ = −a k² sin φ / W³ = −M sin φ,     Z′ = a k² cos φ / W³ = M cos φ,
/// ```
///
/// so the meridian has arc length `ds = M dφ` with the **meridian radius of
/// curvature** `M = a k²/W³ = c²/(a W³)` (`dφ/ds = 1/M` is the rate at which
/// the normal turns along the meridian), and the parallel `φ = const` has
/// radius `F = N cos φ` with the **prime-vertical radius** `N = a/W` (the
/// distance from the surface to the axis along the normal, Meusnier). At the
/// equator `M = c²/a`, `N = a`; at the poles `M = N = a²/c`.
///
/// *Metric.* `∂_φ x = M (−sin φ cos λ, −sin φ sin λ, cos φ) = M ê_north`,
/// `∂_λ x = F (−sin λ, cos λ, 0) = F ê_east`, orthogonal, hence
///
/// ```text
/// ds² = M² dφ² + N² cos²φ dλ².
/// ```
///
/// *Christoffel symbols* of `g = diag(A, B)`, `A = M²`, `B = F²` (functions of
/// `φ` only): `Γ^φ_φφ = A′/(2A) = M′/M`, `Γ^φ_λλ = −B′/(2A) = −FF′/M²`,
/// `Γ^λ_φλ = Γ^λ_λφ = B′/(2B) = F′/F`, the others zero. With `F′ = −M sin φ`,
/// `M′/M = −(3/2)(W²)′/W²` and `N/M = W²/k²`:
///
/// ```text
/// Γ^φ_φφ = 3(1 − k²) sin φ cos φ / W²,
/// Γ^φ_λλ = (N/M) sin φ cos φ = (W²/k²) sin φ cos φ,
/// Γ^λ_φλ = Γ^λ_λφ = −(M/N) tan φ = −(k²/W²) tan φ.
/// ```
///
/// For `k = 1` (`W = 1`) these are the sphere's symbols in latitude, and with
/// `r = R(π/2 − φ)` they become [`Sphere2`](super::Sphere2)'s.
///
/// *Gaussian curvature.* The shape operator of the outward normal is
/// diagonal in `(ê_east, ê_north)` with the principal curvatures `1/N`, `1/M`
/// (see [`FrameBundle`](crate::bundle::FrameBundle) for `Spheroid`, where it is
/// derived from the quadric), so
///
/// ```text
/// K(φ) = 1/(M N) = W⁴/c² = (a² cos²φ + c² sin²φ)² / (a⁴ c²):
/// ```
///
/// `1/c²` at the equator and `c²/a⁴` at the poles; positive everywhere. In two
/// dimensions the Riemann tensor is `K` times the metric combination,
/// `R^i_jkl = K(δ^i_k g_jl − δ^i_l g_jk)`. (Gauss–Bonnet: `∫K dA =
/// ∫∫ K M N cos φ dφ dλ = 4π`.)
///
/// # Frame field: east, north
///
/// `E = (E₁, E₂) = (ê_east, ê_north)`, chart components `E₁ = F⁻¹ ∂_λ`,
/// `E₂ = M⁻¹ ∂_φ`; ambient components `ê_east = (−sin λ, cos λ, 0)`,
/// `ê_north = (−sin φ cos λ, −sin φ sin λ, cos φ)`. With the outward normal
/// `(ê_east, ê_north, n)` is right-handed (east × north = up), the orientation
/// of S²'s `(E_r, E_φ, n)` (south × east = up): for `a = c` the frame is the
/// sphere's rotated by +90°, `(ê_east, ê_north) = (E_φ, −E_r)`, so spins and
/// frame angles mean the same on both manifolds. (The order `(north, east)`
/// would be left-handed, SPEC §9.)
///
/// *Frame connection* (`∇_{E_C} E_B = Γ^A_BC E_A`, index 0 = east, 1 = north).
/// The meridians are geodesics, `∇_{E₂}E₂ = 0`, and `E₁ = F⁻¹∂_λ` is invariant
/// along them, `∇_{E₂}E₁ = M⁻¹(−F′/F² + Γ^λ_λφ/F)∂_λ = 0`. Along a parallel,
/// `∇_{E₁}E₁ = F⁻²Γ^φ_λλ ∂_φ = −(F′/(FM)) E₂ = (tan φ/N) E₂` (the geodesic
/// curvature of the parallel, pointing to the nearer pole), and by
/// orthonormality `∇_{E₁}E₂ = −(tan φ/N) E₁`:
///
/// ```text
/// Γ^north_east,east = tan φ / N = W tan φ / a,     Γ^east_north,east = −tan φ / N,
/// ```
///
/// the others zero. Along a curve `ẋ = φ̇ M E₂ + λ̇ F E₁` the frame turns by
/// `DE/dt = E·Γ(E)(ẋ)` with `Γ(E)(ẋ) = λ̇ F (tan φ/N) ε = (sin φ) λ̇ ε`
/// (`ε = [[0, −1], [1, 0]]`, `F tan φ/N = sin φ`): SPEC §9's drive term
/// `(F′/h) λ̇ ε` with `h = M`, `F′ = −M sin φ`, whose sign is reversed by the
/// order (east, north); for `a = c` it is the sphere's `cos ϑ φ̇` (a91).
///
/// # Poles
///
/// The chart is singular at `φ = ±π/2`. Chart points are accepted when
/// `|φ| < π/2` and `cos φ >` [`Spheroid::POLE_TOLERANCE`];
/// [`Manifold::chart`] fails with [`Error::OutsideChart`] for embedded points
/// within `POLE_TOLERANCE·|p|` of the axis. The frame bundle
/// ([`FrameBundle`](crate::bundle::FrameBundle) for `Spheroid`) has no
/// singularity anywhere.
///
/// # Aspect ratio
///
/// [`Spheroid::new`] refuses `c/a` outside `[10⁻³, 10³]`
/// ([`Spheroid::MAX_ASPECT_RATIO`]). The frame
/// bundle stores the outward normal `n` and computes the position as `x(n)`;
/// the differential of `x(n)` is the inverse shape operator, whose norm is the
/// largest radius of curvature, `max(M, N) ≤ max(a, c)·r` with
/// `r = max(a/c, c/a)` (`a²/c` at the poles of an oblate spheroid, `c²/a` at the
/// equator of a prolate one). A round-off `ε` in `n` therefore moves the
/// position by up to `r·ε` relative to the size of the body: `≤ 2·10⁻¹³` for
/// `r ≤ 10³`. Beyond that the representation would silently lose digits
/// where the surface is flattest.
///
/// The spheroid does not implement the optional
/// [`GeodesicDistance`](super::GeodesicDistance) (its geodesics are checked
/// against Bessel's auxiliary-sphere solution in the test suite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spheroid {
    a: f64,
    c: f64,
    /// `k = c/a`.
    k: f64,
    /// `k² = (c/a)²`.
    k2: f64,
    /// `1 − k² = (a − c)(a + c)/a²` (exactly 0 for `a = c`).
    one_minus_k2: f64,
    /// `k⁻² − 1 = (a − c)(a + c)/c²` (exactly 0 for `a = c`).
    inv_k2_minus_one: f64,
}

impl Spheroid {
    /// Smallest `cos φ` at which the geodetic chart is used; closer to a pole
    /// it reports [`Error::OutsideChart`] (as [`Sphere2::POLE_TOLERANCE`](super::Sphere2::POLE_TOLERANCE)).
    pub const POLE_TOLERANCE: f64 = 1e-12;
    /// Largest [`Manifold::point_defect`] of an embedded point accepted by
    /// [`Manifold::chart`] and the bundle's `from_frame`.
    pub const POINT_TOLERANCE: f64 = 1e-9;
    /// Largest accepted `max(a/c, c/a)`: see "Aspect ratio" in the type docs.
    pub const MAX_ASPECT_RATIO: f64 = 1e3;

    /// The spheroid with equatorial radius `equatorial_radius` (`a`) and polar
    /// radius `polar_radius` (`c`).
    ///
    /// Errors: [`Error::InvalidParameter`] with field `"equatorial_radius"` or
    /// `"polar_radius"` unless the value is finite and > 0; with field
    /// `"polar_radius"` unless `10⁻³ ≤ c/a ≤ 10³` ([`Spheroid::MAX_ASPECT_RATIO`]).
    ///
    /// ```
    /// use framedyn::manifold::{Manifold, Spheroid};
    /// use nalgebra::Vector2;
    ///
    /// let earth_like = Spheroid::new(1.0, 0.99)?; // oblate
    /// let x = earth_like.embed(&Vector2::new(std::f64::consts::FRAC_PI_2 - 0.1, 0.3));
    /// assert!(earth_like.point_defect(&x) < 1e-15);
    /// assert!((earth_like.gaussian_curvature(0.0) - 1.0 / 0.99f64.powi(2)).abs() < 1e-15);
    /// let err = Spheroid::new(1.0, -2.0).unwrap_err();
    /// assert!(matches!(err, framedyn::Error::InvalidParameter { field: "polar_radius", .. }));
    /// assert!(Spheroid::new(1.0, 1e4).is_err()); // aspect ratio beyond 10³
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(equatorial_radius: f64, polar_radius: f64) -> Result<Self> {
        let a = positive("equatorial_radius", equatorial_radius)?;
        let c = positive("polar_radius", polar_radius)?;
        let k = c / a;
        if !(k >= 1.0 / Self::MAX_ASPECT_RATIO && k <= Self::MAX_ASPECT_RATIO) {
            return Err(Error::InvalidParameter {
                field: "polar_radius",
                value: c,
                allowed: "finite, > 0 and within a factor 1e3 of the equatorial radius (1e-3 ≤ c/a ≤ 1e3)",
            });
        }
        // a − c is exact when a and c are within a factor 2 (Sterbenz), so
        // these are accurate near the sphere; written so as not to overflow.
        let (da, dc) = ((a - c) / a, (a - c) / c);
        Ok(Spheroid { a, c, k, k2: k * k, one_minus_k2: da * (1.0 + k), inv_k2_minus_one: dc * (1.0 + a / c) })
    }

    /// The equatorial radius `a`.
    #[inline]
    pub fn equatorial_radius(&self) -> f64 {
        self.a
    }

    /// The polar radius `c`.
    #[inline]
    pub fn polar_radius(&self) -> f64 {
        self.c
    }

    /// `k² = (c/a)²` (`= 1 − e²` in geodesy's notation).
    #[inline]
    pub fn axis_ratio_squared(&self) -> f64 {
        self.k2
    }

    /// `1 − k² = (a − c)(a + c)/a²` (geodesy's `e²`; negative when prolate),
    /// formed without cancellation: exactly 0 for `a = c`, accurate near it.
    #[inline]
    pub fn one_minus_k2(&self) -> f64 {
        self.one_minus_k2
    }

    /// `k⁻² − 1 = (a − c)(a + c)/c²` (geodesy's second eccentricity `e′²`;
    /// in `(−1, 0)` when prolate), formed without cancellation.
    #[inline]
    pub fn inv_k2_minus_one(&self) -> f64 {
        self.inv_k2_minus_one
    }

    /// `W(φ)² = cos²φ + k² sin²φ` (`a² W² = a² cos²φ + c² sin²φ`).
    #[inline]
    pub fn w_squared(&self, lat: f64) -> f64 {
        let (s, c) = lat.sin_cos();
        c * c + self.k2 * s * s
    }

    /// The meridian radius of curvature `M(φ) = a k²/W³ = a²c²/(a²cos²φ + c²sin²φ)^{3/2}`.
    #[inline]
    pub fn meridian_radius(&self, lat: f64) -> f64 {
        let w2 = self.w_squared(lat);
        self.a * self.k2 / (w2 * w2.sqrt())
    }

    /// The prime-vertical radius of curvature `N(φ) = a/W = a²/√(a²cos²φ + c²sin²φ)`.
    #[inline]
    pub fn prime_vertical_radius(&self, lat: f64) -> f64 {
        self.a / self.w_squared(lat).sqrt()
    }

    /// The Gaussian curvature `K(φ) = 1/(M N) = W⁴/c² = (a²cos²φ + c²sin²φ)²/(a⁴c²)`
    /// at geodetic latitude `lat` (derivation in the type docs).
    #[inline]
    pub fn gaussian_curvature(&self, lat: f64) -> f64 {
        let w2 = self.w_squared(lat);
        let kc = w2 / self.c;
        kc * kc
    }

    /// The outward unit normal `n(φ, λ) = (cos φ cos λ, cos φ sin λ, sin φ)`.
    #[inline]
    pub fn normal(&self, x: &Vector2<f64>) -> Vector3<f64> {
        let (sp, cp) = x[0].sin_cos();
        let (sl, cl) = x[1].sin_cos();
        Vector3::new(cp * cl, cp * sl, sp)
    }

    /// The point with outward normal direction `n` (any non-zero length: the
    /// map is homogeneous of degree 0): `x(n) = (a² n_x, a² n_y, c² n_z)/(a W)`,
    /// `W = √(n_x² + n_y² + k² n_z²)`, the inverse of the Gauss map (type
    /// docs). It lies on the spheroid to round-off for every `n`, since
    /// `x(n)ᵀD x(n) = 1` identically. Evaluated as `(a n_x/W, a n_y/W, c t/W)`
    /// with `t = k n_z`, `W = √(n_x² + n_y² + t²)`: at the poles `W = √(t·t) = |t|`
    /// exactly (a correctly rounded square root of a square), so the poles are
    /// `(0, 0, ±c)` to the last bit, and for `a = c` this is S²'s `R n`.
    #[inline]
    pub fn point_with_normal(&self, n: &Vector3<f64>) -> Vector3<f64> {
        let t = self.k * n[2];
        let w = (n[0] * n[0] + n[1] * n[1] + t * t).sqrt();
        Vector3::new(self.a * (n[0] / w), self.a * (n[1] / w), self.c * (t / w))
    }

    /// The unit outward normal at the embedded point `p` (or, for `p` off the
    /// surface, the normal of the level set of `xᵀDx` through it):
    /// `Dp/|Dp| ∝ (p_x, p_y, p_z/k²)`.
    #[inline]
    pub fn normal_at(&self, p: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(p[0], p[1], p[2] / self.k2).normalize()
    }

    /// The frame field in ambient components at the chart point `x`:
    /// columns `ê_east = (−sin λ, cos λ, 0)`, `ê_north = (−sin φ cos λ,
    /// −sin φ sin λ, cos φ)` (ENU with the outward normal).
    pub fn ambient_frame(&self, x: &Vector2<f64>) -> Matrix3x2<f64> {
        let (sp, cp) = x[0].sin_cos();
        let (sl, cl) = x[1].sin_cos();
        Matrix3x2::new(-sl, -sp * cl, cl, -sp * sl, 0.0, cp)
    }

    /// Validates an embedded point: finite and within [`Self::POINT_TOLERANCE`]
    /// of the spheroid.
    pub(crate) fn check_point(&self, field: &'static str, p: &Vector3<f64>) -> Result<()> {
        finite(field, p.iter())?;
        let defect = self.point_defect(p);
        if defect > Self::POINT_TOLERANCE {
            return Err(Error::Constraint {
                field,
                constraint: "point on the spheroid, (x² + y²)/a² + z²/c² = 1",
                defect,
                tolerance: Self::POINT_TOLERANCE,
            });
        }
        Ok(())
    }
}

/// The nearest point `(x₀, x₁)` of the ellipse `(x₀/e₀)² + (x₁/e₁)² = 1`,
/// `e₀ ≥ e₁ > 0`, to the point `(y₀, y₁)` with `y₀, y₁ ≥ 0` (first quadrant).
///
/// Method (D. Eberly, "Distance from a point to an ellipse, an ellipsoid, or a
/// hyperellipsoid", 2013). The nearest point satisfies
/// `y − x ∥ ∇((x₀/e₀)² + (x₁/e₁)²)`, i.e. `x_i = e_i² y_i/(τ + e_i²)` for a
/// multiplier `τ`, and lies on the ellipse. With `z_i = y_i/e_i`,
/// `r₀ = (e₀/e₁)²` and `t = τ/e₁² + 1`:
///
/// ```text
/// G(t) = (r₀ z₀ / (t + r₀ − 1))² + (z₁ / t)² − 1 = 0,     x₀ = r₀ y₀/(t + r₀ − 1),  x₁ = y₁/t.
/// ```
///
/// For `y₀, y₁ > 0` the nearest point is in the open quadrant and corresponds
/// to the root with `t > 0`; on `t > 0`, `G` is convex and strictly decreasing
/// from `+∞` to `−1`, so the root is unique. It is bracketed by
/// `t_lo = max(z₁, r₀z₀ − r₀ + 1)` (where one term alone is ≥ 1) and
/// `t_hi = |(r₀z₀, z₁)|` (where both denominators are ≥ `t_hi`), and found by
/// Newton's method safeguarded with bisection (geometric bisection while the
/// bracket spans more than a factor 4, so a root near `t = 0` costs
/// `O(log log)` steps). The boundary cases `y₁ = 0` (on the major axis: the
/// nearest point leaves the axis when `y₀ < (e₀² − e₁²)/e₀`, inside the
/// evolute) and `y₀ = 0` (the minor vertex) are closed forms.
fn nearest_on_ellipse(e0: f64, e1: f64, y0: f64, y1: f64) -> (f64, f64) {
    let d01 = (e0 - e1) * (e0 + e1); // e₀² − e₁² ≥ 0, without cancellation
    if y1 > 0.0 {
        if y0 > 0.0 {
            let (z0, z1) = (y0 / e0, y1 / e1);
            let r0 = (e0 / e1) * (e0 / e1);
            let r0m1 = d01 / (e1 * e1); // r₀ − 1
            let a0 = r0 * z0;
            let g = |t: f64| {
                let (p, q) = (a0 / (t + r0m1), z1 / t);
                (p * p + q * q - 1.0, -2.0 * (p * p / (t + r0m1) + q * q / t))
            };
            let mut lo = z1.max(a0 - r0m1);
            let mut hi = a0.hypot(z1);
            let mut t = lo;
            let mut last_step = hi - lo;
            for _ in 0..200 {
                let (gv, dg) = g(t);
                if gv == 0.0 {
                    lo = t;
                    hi = t;
                    break;
                }
                if gv > 0.0 {
                    lo = lo.max(t);
                } else {
                    hi = hi.min(t);
                }
                if !(hi - lo > 2.0 * f64::EPSILON * hi) {
                    break;
                }
                let newton = t - gv / dg;
                if newton > lo && newton < hi && (newton - t).abs() < 0.5 * last_step {
                    last_step = (newton - t).abs();
                    t = newton;
                } else {
                    let mid = if lo > 0.0 && hi > 4.0 * lo { (lo * hi).sqrt() } else { 0.5 * (lo + hi) };
                    last_step = (mid - t).abs();
                    t = mid;
                }
            }
            let t = if lo == hi { lo } else { t.clamp(lo, hi) };
            let (x0, x1) = (r0 * y0 / (t + r0m1), y1 / t);
            // Back onto the ellipse exactly (radial rescaling by 1 + O(ε)).
            let s = (x0 / e0).hypot(x1 / e1);
            (x0 / s, x1 / s)
        } else {
            (0.0, e1)
        }
    } else if y0 * e0 < d01 {
        let x0 = e0 * e0 * y0 / d01;
        let r = x0 / e0;
        (x0, e1 * ((1.0 - r) * (1.0 + r)).max(0.0).sqrt())
    } else {
        (e0, 0.0)
    }
}

impl Manifold<2, 3> for Spheroid {
    const NAME: &'static str = "spheroid";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["lat", "lon"]
    }

    fn coordinate_units(&self) -> [&'static str; 2] {
        ["rad", "rad"]
    }

    /// `Ok` iff `φ`, `λ` are finite, `|φ| < π/2` and `cos φ >`
    /// [`Spheroid::POLE_TOLERANCE`].
    fn check_chart(&self, x: &Vector2<f64>) -> Result<()> {
        finite("x = (lat, lon)", x.iter())?;
        if !(x[0].abs() < std::f64::consts::FRAC_PI_2) {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "the latitude must lie in (−π/2, π/2): the poles lat = ±π/2 are coordinate singularities",
            });
        }
        if x[0].cos() <= Self::POLE_TOLERANCE {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "cos(lat) ≤ 1e-12: point within POLE_TOLERANCE of a pole, where the geodetic chart is singular",
            });
        }
        Ok(())
    }

    /// `diag(M², N² cos²φ)`.
    fn metric(&self, x: &Vector2<f64>) -> Matrix2<f64> {
        let m = self.meridian_radius(x[0]);
        let f = self.prime_vertical_radius(x[0]) * x[0].cos();
        Matrix2::new(m * m, 0.0, 0.0, f * f)
    }

    /// `Γ^φ_φφ = 3(1 − k²) sin φ cos φ/W²`, `Γ^φ_λλ = (W²/k²) sin φ cos φ`,
    /// `Γ^λ_φλ = Γ^λ_λφ = −(k²/W²) tan φ` (indices `φ = 0`, `λ = 1`).
    fn christoffel(&self, x: &Vector2<f64>) -> Tensor3<2> {
        let (s, c) = x[0].sin_cos();
        let w2 = c * c + self.k2 * s * s;
        let mut g = [[[0.0; 2]; 2]; 2];
        g[0][0][0] = 3.0 * self.one_minus_k2 * s * c / w2;
        g[0][1][1] = w2 / self.k2 * s * c;
        g[1][0][1] = -self.k2 / w2 * (s / c);
        g[1][1][0] = g[1][0][1];
        g
    }

    /// `R^i_jkl = K(δ^i_k g_jl − δ^i_l g_jk)`, `K = W⁴/c²`.
    fn riemann(&self, x: &Vector2<f64>) -> Tensor4<2> {
        let g = self.metric(x);
        let k = self.gaussian_curvature(x[0]);
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

    /// Columns `E₁ = (0, 1/(N cos φ))` (east), `E₂ = (1/M, 0)` (north).
    fn frame(&self, x: &Vector2<f64>) -> Matrix2<f64> {
        let m = self.meridian_radius(x[0]);
        let f = self.prime_vertical_radius(x[0]) * x[0].cos();
        Matrix2::new(0.0, 1.0 / m, 1.0 / f, 0.0)
    }

    /// `Γ^north_{east,east} = tan φ/N`, `Γ^east_{north,east} = −tan φ/N`
    /// (indices east = 0, north = 1), the others zero.
    fn frame_connection(&self, x: &Vector2<f64>) -> Tensor3<2> {
        let t = x[0].tan() / self.prime_vertical_radius(x[0]);
        let mut g = [[[0.0; 2]; 2]; 2];
        g[1][0][0] = t;
        g[0][1][0] = -t;
        g
    }

    fn ambient_metric(&self) -> Matrix3<f64> {
        Matrix3::identity()
    }

    /// `(N cos φ cos λ, N cos φ sin λ, N k² sin φ)`.
    fn embed(&self, x: &Vector2<f64>) -> Vector3<f64> {
        self.point_with_normal(&self.normal(x))
    }

    /// `v^φ M ê_north + v^λ N cos φ ê_east`.
    fn embed_tangent(&self, x: &Vector2<f64>, v: &Vector2<f64>) -> Vector3<f64> {
        let e = self.ambient_frame(x);
        let m = self.meridian_radius(x[0]);
        let f = self.prime_vertical_radius(x[0]) * x[0].cos();
        e.column(1) * (v[0] * m) + e.column(0) * (v[1] * f)
    }

    /// `φ = atan2(a² z, c² ρ) = atan2(z, k² ρ)`, `λ = atan2(y, x) ∈ (−π, π]`.
    /// Fails for non-finite `p`, for `p` off the spheroid by more than
    /// [`Spheroid::POINT_TOLERANCE`] ([`Manifold::point_defect`]), and near the
    /// poles (see [`Spheroid::POLE_TOLERANCE`]).
    fn chart(&self, p: &Vector3<f64>) -> Result<Vector2<f64>> {
        self.check_point("p", p)?;
        let rho = p[0].hypot(p[1]);
        if rho <= Self::POLE_TOLERANCE * p.norm() {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "point within POLE_TOLERANCE·|p| of the polar axis, where the longitude is undefined",
            });
        }
        let x = Vector2::new(p[2].atan2(self.k2 * rho), p[1].atan2(p[0]));
        self.check_chart(&x)?;
        Ok(x)
    }

    /// `(w·ê_north / M, w·ê_east / (N cos φ))` at `x = chart(p)` (the normal
    /// part of `w` is ignored). Fails where [`Manifold::chart`] fails or `w`
    /// is not finite.
    fn chart_tangent(&self, p: &Vector3<f64>, w: &Vector3<f64>) -> Result<Vector2<f64>> {
        let x = self.chart(p)?;
        finite("w", w.iter())?;
        let e = self.ambient_frame(&x);
        let m = self.meridian_radius(x[0]);
        let f = self.prime_vertical_radius(x[0]) * x[0].cos();
        Ok(Vector2::new(e.column(1).dot(w) / m, e.column(0).dot(w) / f))
    }

    /// The relative radial defect `|√(pᵀDp) − 1|` (`+∞` for non-finite `p`):
    /// `p/√(pᵀDp)` is the point of the spheroid on the ray through `p`, so
    /// this is `||p| − r|/r`, `r` the radius of the spheroid in the direction of
    /// `p` — the sphere's `||p| − R|/R`. For `p = x + δn` near the surface it is
    /// `|δ|/h + O(δ²)`, `h = x·n ∈ [min(a, c), max(a, c)]` the distance of the
    /// tangent plane from the centre.
    fn point_defect(&self, p: &Vector3<f64>) -> f64 {
        let s = p[0].hypot(p[1]).hypot(p[2] * (self.a / self.c)) / self.a;
        let d = (s - 1.0).abs();
        if d.is_finite() {
            d
        } else {
            f64::INFINITY
        }
    }

    /// The nearest point of the spheroid (Euclidean distance): by symmetry it
    /// lies in the meridian plane of `p`, where it is the nearest point of the
    /// meridian ellipse to `(ρ, |z|)` (a robust one-dimensional root, see
    /// `nearest_on_ellipse` in the source), with the sign of `z` restored. Where
    /// the nearest point is not unique (on the axis inside a prolate spheroid,
    /// in the equatorial plane inside an oblate one, the centre) one of them is
    /// returned. Non-finite `p` gives a non-finite result.
    fn project_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        if !p.iter().all(|v| v.is_finite()) {
            return Vector3::from_element(f64::NAN);
        }
        let rho = p[0].hypot(p[1]);
        let h = p[2].abs();
        let (xr, xz) = if self.a >= self.c {
            nearest_on_ellipse(self.a, self.c, rho, h)
        } else {
            let (z, r) = nearest_on_ellipse(self.c, self.a, h, rho);
            (r, z)
        };
        let (ux, uy) = if rho > 0.0 { (p[0] / rho, p[1] / rho) } else { (1.0, 0.0) };
        Vector3::new(xr * ux, xr * uy, xz.copysign(p[2]))
    }

    /// `w − (w·n) n` with `n` = [`Spheroid::normal_at`]`(p)`.
    fn project_tangent(&self, p: &Vector3<f64>, w: &Vector3<f64>) -> Vector3<f64> {
        let n = self.normal_at(p);
        w - n * n.dot(w)
    }
}
