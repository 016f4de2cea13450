//! The paper's charts and frame fields, written once over the scalar type.

use nalgebra::{SMatrix, SVector};
use std::f64::consts::PI;
use std::fmt::Debug;

use super::series;
use crate::error::{finite, positive};
use crate::potential::Scalar;
use crate::{Error, Result};

/// Largest relative distance of an ambient point from the manifold accepted
/// by [`ChartGeometry::chart_point`] (and hence by
/// [`from_ambient`](super::from_ambient)).
pub const CHART_POINT_TOLERANCE: f64 = 1e-9;

/// Connection coefficients `Γ^A_{BC} = T[A][B][C]` with scalar type `D`.
pub type Connection<D, const N: usize> = [[[D; N]; N]; N];

/// A chart of an `N`-dimensional manifold embedded in an `E`-dimensional
/// flat space, with the paper's orthonormal frame field, written generically
/// over the scalar type `D` (`f64` or any dual number of `num_dual`), so that
/// Lagrangians built from it can be differentiated automatically to any order.
///
/// Conventions are those of [`Manifold`](crate::manifold::Manifold): column
/// `A` of [`frame`](Self::frame) holds the chart components `E^i_A`; the
/// coframe is its inverse `E^A_i`; `Γ^A_{BC}` =
/// `frame_connection(x)[A][B][C]` with `∇_{E_C} E_B = Γ^A_{BC} E_A`.
///
/// The implementations are an independent re-derivation of the paper's
/// formulas, not calls into the `f64` [`Manifold`](crate::manifold::Manifold)
/// implementations (the test suite compares the two).
pub trait ChartGeometry<const N: usize, const E: usize>: Clone + Debug + Send + Sync {
    /// Name of the manifold, e.g. `"S2"`.
    const NAME: &'static str;

    /// Names of the chart coordinates, e.g. `["r", "phi"]`.
    fn coordinate_names(&self) -> [&'static str; N];
    /// `Ok` where the chart and the frame field are regular, else
    /// [`Error::NotFinite`] or [`Error::OutsideChart`].
    fn check_chart(&self, x: &SVector<f64, N>) -> Result<()>;

    /// Metric components `g_ij(x)`.
    fn metric<D: Scalar>(&self, x: &SVector<D, N>) -> SMatrix<D, N, N>;
    /// The paper's orthonormal frame field: column `A` = chart components `E^i_A`.
    fn frame<D: Scalar>(&self, x: &SVector<D, N>) -> SMatrix<D, N, N>;
    /// The dual coframe `E^A_i` (the inverse of [`frame`](Self::frame)): row
    /// `A` maps a chart vector to its `E_A` component, e.g. the co-moving
    /// translational velocity `V̂^A = E^A_i ẋ^i` (a74) when `φ = 1`.
    fn coframe<D: Scalar>(&self, x: &SVector<D, N>) -> SMatrix<D, N, N>;
    /// Connection coefficients `Γ^A_{BC}(x)` of the frame field (the paper's
    /// `Γ(E)` of (a74)).
    fn frame_connection<D: Scalar>(&self, x: &SVector<D, N>) -> Connection<D, N>;

    /// The metric of the flat ambient space.
    fn ambient_metric(&self) -> SMatrix<f64, E, E>;
    /// Embedding `X(x)`.
    fn embed<D: Scalar>(&self, x: &SVector<D, N>) -> SVector<D, E>;
    /// Jacobian `∂X/∂x^i` of the embedding (column `i`).
    fn embed_jacobian<D: Scalar>(&self, x: &SVector<D, N>) -> SMatrix<D, E, N>;
    /// Chart coordinates of the ambient point `p`, which must lie on the
    /// manifold to [`CHART_POINT_TOLERANCE`] (relative); fails with a typed
    /// error off the manifold or where the chart is singular.
    fn chart_point(&self, p: &SVector<f64, E>) -> Result<SVector<f64, N>>;

    /// Ambient components of the frame vectors `E_A` (columns): the embedding
    /// Jacobian times [`frame`](Self::frame).
    fn ambient_frame<D: Scalar>(&self, x: &SVector<D, N>) -> SMatrix<D, E, N> {
        self.embed_jacobian(x) * self.frame(x)
    }

    /// The matrix `Γ(E)(w)^A_B = Γ^A_{BC} w^C` for frame components `w` of a
    /// tangent vector: `∇_w E_B = E_A Γ(E)(w)^A_B`. With `w = V̂` it is the
    /// drive term of the co-moving velocity (a74), (a81).
    fn connection_matrix<D: Scalar>(&self, x: &SVector<D, N>, w: &SVector<D, N>) -> SMatrix<D, N, N> {
        let g = self.frame_connection(x);
        SMatrix::from_fn(|a, b| {
            let mut s = D::from(0.0);
            for (c, wc) in w.iter().enumerate() {
                s += g[a][b][c] * *wc;
            }
            s
        })
    }
}

fn zero_connection<D: Scalar, const N: usize>() -> Connection<D, N> {
    [[[D::from(0.0); N]; N]; N]
}

/// Relative defect of an ambient point on a surface given by `f(p) = 0`,
/// with `f` normalised by `scale`: `|f(p)|/scale`, `+∞` if not finite.
fn defect(value: f64, scale: f64) -> f64 {
    let d = value.abs() / scale;
    if d.is_finite() {
        d
    } else {
        f64::INFINITY
    }
}

fn check_defect(field: &'static str, constraint: &'static str, d: f64) -> Result<()> {
    if d > CHART_POINT_TOLERANCE {
        Err(Error::Constraint { field, constraint, defect: d, tolerance: CHART_POINT_TOLERANCE })
    } else {
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// S²
// ---------------------------------------------------------------------------

/// The paper's polar chart of the sphere S²(R) (§5.1), generic over the scalar.
///
/// Coordinates `x = (r, φ)`, `ϑ = r/R ∈ (0, π)`:
/// - embedding `X = R(sin ϑ cos φ, sin ϑ sin φ, cos ϑ)`, Jacobian columns
///   `∂_r X = (cos ϑ cos φ, cos ϑ sin φ, −sin ϑ)`,
///   `∂_φ X = R sin ϑ (−sin φ, cos φ, 0)`;
/// - metric (a87) `g = diag(1, R² sin²ϑ)`;
/// - frame (a90) `E_r = ∂_r`, `E_φ = (R sin ϑ)⁻¹ ∂_φ`, coframe
///   `diag(1, R sin ϑ)`;
/// - frame connection `Γ^φ_{rφ} = −Γ^r_{φφ} = cot ϑ / R`, all others zero
///   (the paper's aholonomic coefficients after (a91)), so that the drive
///   term of a gyroscope is `ω_dr = cos ϑ φ̇` (a91).
///
/// Regular for `0 < ϑ < π` with `sin ϑ >` [`SphereChart::POLE_TOLERANCE`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereChart {
    radius: f64,
}

impl SphereChart {
    /// Smallest `sin(r/R)` accepted by [`ChartGeometry::check_chart`]:
    /// closer to a pole the chart is treated as singular.
    pub const POLE_TOLERANCE: f64 = 1e-12;

    /// The chart of the sphere of radius `radius` (finite, > 0; else
    /// [`Error::InvalidParameter`] with field `"R"`).
    pub fn new(radius: f64) -> Result<Self> {
        Ok(Self { radius: positive("R", radius)? })
    }
    /// The radius `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }
}

impl ChartGeometry<2, 3> for SphereChart {
    const NAME: &'static str = "S2";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["r", "phi"]
    }

    /// `Ok` iff `(r, φ)` finite, `0 < r/R < π` and `sin(r/R) >`
    /// [`SphereChart::POLE_TOLERANCE`].
    fn check_chart(&self, x: &SVector<f64, 2>) -> Result<()> {
        finite("x = (r, phi)", x.iter())?;
        let t = x[0] / self.radius;
        if !(t > 0.0 && t < PI) || t.sin() <= Self::POLE_TOLERANCE {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "r must satisfy 0 < r/R < π and sin(r/R) > 1e-12: the poles are coordinate singularities of (r, φ) and of E_φ",
            });
        }
        Ok(())
    }

    fn metric<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rs = (x[0] / self.radius).sin() * self.radius;
        SMatrix::<D, 2, 2>::new(D::from(1.0), D::from(0.0), D::from(0.0), rs * rs)
    }

    fn frame<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rs = (x[0] / self.radius).sin() * self.radius;
        SMatrix::<D, 2, 2>::new(D::from(1.0), D::from(0.0), D::from(0.0), rs.recip())
    }

    fn coframe<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rs = (x[0] / self.radius).sin() * self.radius;
        SMatrix::<D, 2, 2>::new(D::from(1.0), D::from(0.0), D::from(0.0), rs)
    }

    fn frame_connection<D: Scalar>(&self, x: &SVector<D, 2>) -> Connection<D, 2> {
        let (s, c) = (x[0] / self.radius).sin_cos();
        let k = c / (s * self.radius);
        let mut g = zero_connection();
        g[1][0][1] = k;
        g[0][1][1] = -k;
        g
    }

    fn ambient_metric(&self) -> SMatrix<f64, 3, 3> {
        SMatrix::identity()
    }

    fn embed<D: Scalar>(&self, x: &SVector<D, 2>) -> SVector<D, 3> {
        let (st, ct) = (x[0] / self.radius).sin_cos();
        let (sp, cp) = x[1].sin_cos();
        SVector::<D, 3>::new(st * cp, st * sp, ct) * D::from(self.radius)
    }

    fn embed_jacobian<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 3, 2> {
        let (st, ct) = (x[0] / self.radius).sin_cos();
        let (sp, cp) = x[1].sin_cos();
        let rs = st * self.radius;
        SMatrix::<D, 3, 2>::new(ct * cp, -rs * sp, ct * sp, rs * cp, -st, D::from(0.0))
    }

    /// `r = R atan2(√(p₁² + p₂²), p₃)`, `φ = atan2(p₂, p₁)`.
    fn chart_point(&self, p: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        finite("p", p.iter())?;
        let d = defect(p.norm() - self.radius, self.radius);
        check_defect("p", "on the sphere: |p| = R", d)?;
        let rho = p[0].hypot(p[1]);
        let x = SVector::<f64, 2>::new(self.radius * rho.atan2(p[2]), p[1].atan2(p[0]));
        self.check_chart(&x)?;
        Ok(x)
    }
}

// ---------------------------------------------------------------------------
// H²
// ---------------------------------------------------------------------------

/// The paper's polar chart of the hyperbolic plane H²(R) (§5.2), the upper
/// sheet of `−x² − y² + z² = R²` in Minkowski space `ℝ^{2,1}`
/// (`η = diag(1, 1, −1)`), generic over the scalar.
///
/// Coordinates `x = (r, φ)`, `ϑ = r/R > 0`:
/// - embedding `X = (R sh ϑ cos φ, R sh ϑ sin φ, R ch ϑ)`, Jacobian columns
///   `∂_r X = (ch ϑ cos φ, ch ϑ sin φ, sh ϑ)`, `∂_φ X = R sh ϑ (−sin φ, cos φ, 0)`;
/// - metric `diag(1, R² sh²ϑ)` (the paper's line 4571 prints the
///   translational energy without the `R²`; SPEC §8);
/// - frame `E_r = ∂_r`, `E_φ = (R sh ϑ)⁻¹ ∂_φ`, coframe `diag(1, R sh ϑ)`;
/// - frame connection `Γ^φ_{rφ} = −Γ^r_{φφ} = cth ϑ / R`, so that the
///   gyroscope drive term is `ch ϑ φ̇` (§5.2, (a135)).
///
/// Regular for `r > 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HyperbolicChart {
    radius: f64,
}

impl HyperbolicChart {
    /// The chart of H² with pseudoradius `radius` (finite, > 0; else
    /// [`Error::InvalidParameter`] with field `"R"`).
    pub fn new(radius: f64) -> Result<Self> {
        Ok(Self { radius: positive("R", radius)? })
    }
    /// The pseudoradius `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }
}

impl ChartGeometry<2, 3> for HyperbolicChart {
    const NAME: &'static str = "H2";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["r", "phi"]
    }

    /// `Ok` iff `(r, φ)` finite and `r > 0`.
    fn check_chart(&self, x: &SVector<f64, 2>) -> Result<()> {
        finite("x = (r, phi)", x.iter())?;
        if x[0] > 0.0 {
            Ok(())
        } else {
            Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "r must be > 0: the origin r = 0 is a coordinate singularity of (r, φ) and of E_φ",
            })
        }
    }

    fn metric<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rs = (x[0] / self.radius).sinh() * self.radius;
        SMatrix::<D, 2, 2>::new(D::from(1.0), D::from(0.0), D::from(0.0), rs * rs)
    }

    fn frame<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rs = (x[0] / self.radius).sinh() * self.radius;
        SMatrix::<D, 2, 2>::new(D::from(1.0), D::from(0.0), D::from(0.0), rs.recip())
    }

    fn coframe<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rs = (x[0] / self.radius).sinh() * self.radius;
        SMatrix::<D, 2, 2>::new(D::from(1.0), D::from(0.0), D::from(0.0), rs)
    }

    fn frame_connection<D: Scalar>(&self, x: &SVector<D, 2>) -> Connection<D, 2> {
        let t = x[0] / self.radius;
        let k = t.cosh() / (t.sinh() * self.radius);
        let mut g = zero_connection();
        g[1][0][1] = k;
        g[0][1][1] = -k;
        g
    }

    fn ambient_metric(&self) -> SMatrix<f64, 3, 3> {
        SMatrix::from_diagonal(&SVector::<f64, 3>::new(1.0, 1.0, -1.0))
    }

    fn embed<D: Scalar>(&self, x: &SVector<D, 2>) -> SVector<D, 3> {
        let t = x[0] / self.radius;
        let (sp, cp) = x[1].sin_cos();
        let sh = t.sinh();
        SVector::<D, 3>::new(sh * cp, sh * sp, t.cosh()) * D::from(self.radius)
    }

    fn embed_jacobian<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 3, 2> {
        let t = x[0] / self.radius;
        let (sh, ch) = (t.sinh(), t.cosh());
        let (sp, cp) = x[1].sin_cos();
        let rs = sh * self.radius;
        SMatrix::<D, 3, 2>::new(ch * cp, -rs * sp, ch * sp, rs * cp, sh, D::from(0.0))
    }

    /// `r = R asinh(√(p₁² + p₂²)/R)`, `φ = atan2(p₂, p₁)`; the point must lie
    /// on the upper sheet (defect `|⟨p, p⟩_η + R²|/|p|²`).
    fn chart_point(&self, p: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        finite("p", p.iter())?;
        let q = p[0] * p[0] + p[1] * p[1] - p[2] * p[2] + self.radius * self.radius;
        let d = if p[2] > 0.0 { defect(q, p.norm_squared()) } else { f64::INFINITY };
        check_defect("p", "on the upper sheet: −x² − y² + z² = R², z > 0", d)?;
        let rho = p[0].hypot(p[1]);
        let x = SVector::<f64, 2>::new(self.radius * (rho / self.radius).asinh(), p[1].atan2(p[0]));
        self.check_chart(&x)?;
        Ok(x)
    }
}

// ---------------------------------------------------------------------------
// T²
// ---------------------------------------------------------------------------

/// The paper's angle chart of the ring torus T²(L, R), `L > R > 0` (§5.3),
/// generic over the scalar.
///
/// Coordinates `x = (θ, φ)`, global (any finite angles), `ρ = L + R cos θ`:
/// - embedding `X = (ρ cos φ, ρ sin φ, R sin θ)`, Jacobian columns
///   `∂_θ X = R(−sin θ cos φ, −sin θ sin φ, cos θ)`, `∂_φ X = ρ(−sin φ, cos φ, 0)`;
/// - metric `diag(R², ρ²)`;
/// - frame (as printed, in this order) `E_θ = R⁻¹∂_θ`, `E_φ = ρ⁻¹∂_φ`,
///   coframe `diag(R, ρ)`;
/// - frame connection `Γ^φ_{θφ} = −Γ^θ_{φφ} = −sin θ/ρ`, all others zero.
///
/// With this ordering `Γ(E)(V̂) = −sin θ φ̇ ε` (`ε = [[0, −1], [1, 0]]`), so
/// the gyroscope's angular velocity is `ω = ψ̇ − sin θ φ̇`; the paper's
/// `ψ̇ + sin θ φ̇` (lines 5362, 5486) holds for the order `(E_φ, E_θ)`
/// (SPEC §8; the dynamics are equivalent under `ψ → −ψ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorusChart {
    big_l: f64,
    small_r: f64,
}

impl TorusChart {
    /// The chart of the torus with tube-centre distance `big_l` (`L`) and tube
    /// radius `small_r` (`R`). Errors: [`Error::InvalidParameter`] with field
    /// `"R"` unless `R` is finite and > 0, with field `"L"` unless `L` is
    /// finite and > `R`.
    pub fn new(big_l: f64, small_r: f64) -> Result<Self> {
        let small_r = positive("R", small_r)?;
        if !(big_l.is_finite() && big_l > small_r) {
            return Err(Error::InvalidParameter { field: "L", value: big_l, allowed: "finite and > R (ring torus)" });
        }
        Ok(Self { big_l, small_r })
    }
    /// `L`, the distance of the tube centre from the axis.
    pub fn big_l(&self) -> f64 {
        self.big_l
    }
    /// `R`, the tube radius.
    pub fn small_r(&self) -> f64 {
        self.small_r
    }
    fn rho<D: Scalar>(&self, theta: D) -> D {
        theta.cos() * self.small_r + self.big_l
    }
}

impl ChartGeometry<2, 3> for TorusChart {
    const NAME: &'static str = "T2";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["theta", "phi"]
    }

    /// `Ok` iff both angles are finite (the chart is global).
    fn check_chart(&self, x: &SVector<f64, 2>) -> Result<()> {
        finite("x = (theta, phi)", x.iter())
    }

    fn metric<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rho = self.rho(x[0]);
        SMatrix::<D, 2, 2>::new(D::from(self.small_r * self.small_r), D::from(0.0), D::from(0.0), rho * rho)
    }

    fn frame<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rho = self.rho(x[0]);
        SMatrix::<D, 2, 2>::new(D::from(1.0 / self.small_r), D::from(0.0), D::from(0.0), rho.recip())
    }

    fn coframe<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let rho = self.rho(x[0]);
        SMatrix::<D, 2, 2>::new(D::from(self.small_r), D::from(0.0), D::from(0.0), rho)
    }

    fn frame_connection<D: Scalar>(&self, x: &SVector<D, 2>) -> Connection<D, 2> {
        let k = x[0].sin() / self.rho(x[0]);
        let mut g = zero_connection();
        g[1][0][1] = -k;
        g[0][1][1] = k;
        g
    }

    fn ambient_metric(&self) -> SMatrix<f64, 3, 3> {
        SMatrix::identity()
    }

    fn embed<D: Scalar>(&self, x: &SVector<D, 2>) -> SVector<D, 3> {
        let rho = self.rho(x[0]);
        let (sp, cp) = x[1].sin_cos();
        SVector::<D, 3>::new(rho * cp, rho * sp, x[0].sin() * self.small_r)
    }

    fn embed_jacobian<D: Scalar>(&self, x: &SVector<D, 2>) -> SMatrix<D, 3, 2> {
        let (st, ct) = x[0].sin_cos();
        let (sp, cp) = x[1].sin_cos();
        let rho = self.rho(x[0]);
        let r = self.small_r;
        SMatrix::<D, 3, 2>::new(-st * cp * r, -rho * sp, -st * sp * r, rho * cp, ct * r, D::from(0.0))
    }

    /// `φ = atan2(p₂, p₁)`, `θ = atan2(p₃, √(p₁² + p₂²) − L)`; the point must
    /// lie on the torus (defect `|dist(p, centre circle) − R|/R`).
    fn chart_point(&self, p: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        finite("p", p.iter())?;
        let rxy = p[0].hypot(p[1]);
        let d = defect((rxy - self.big_l).hypot(p[2]) - self.small_r, self.small_r);
        check_defect("p", "on the torus: (√(x² + y²) − L)² + z² = R²", d)?;
        Ok(SVector::<f64, 2>::new(p[2].atan2(rxy - self.big_l), p[1].atan2(p[0])))
    }
}

// ---------------------------------------------------------------------------
// S³
// ---------------------------------------------------------------------------

/// The rotation-vector (normal-coordinate) chart of the three-sphere S³(R)
/// (§6), the same chart as [`Sphere3`](crate::manifold::Sphere3), generic
/// over the scalar.
///
/// Coordinates `x = r̄ ∈ ℝ³`, `r = |r̄|`, `ϑ = r/R < π`, `n = r̄/r`; the
/// point is `R·u`, `u = (cos ϑ, sin ϑ n)` a unit quaternion, scalar first.
/// With `σ = sin ϑ/ϑ`:
/// - embedding `X = (R cos ϑ, σ r̄)`;
/// - metric (a179) `g = σ² (1 − nnᵀ) + nnᵀ`;
/// - frame: the paper's `ˡE(R)_A(x) = e_A·x/R` (quaternion product; the
///   generators of left translations, right-invariant, (a178a)), in chart
///   components `E = ϑ cot ϑ (1 − nnᵀ) + nnᵀ − [r̄]×/R`, and coframe
///   `E⁻¹ = σ cos ϑ (1 − nnᵀ) + nnᵀ + σ² [r̄]×/R`;
/// - frame connection `Γ^A_{BC} = ε_{ABC}/R` (constant: `∇_X Y = ½[X, Y]`
///   on invariant fields with `[ˡE_A, ˡE_B] = −(2/R) ε_{ABC} ˡE_C`, (b178a)).
///
/// All coefficients are entire functions of `ϑ²` evaluated by series near
/// `r̄ = 0`, so the chart (and its automatic derivatives) is regular there.
/// Regular for `r/R < π −` [`Sphere3Chart::CHART_MARGIN`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere3Chart {
    radius: f64,
}

impl Sphere3Chart {
    /// Distance (in `ϑ`) from the antipode `ϑ = π` inside which
    /// [`ChartGeometry::check_chart`] reports the chart singular.
    pub const CHART_MARGIN: f64 = 1e-6;

    /// The chart of S³ of radius `radius` (finite, > 0; else
    /// [`Error::InvalidParameter`] with field `"R"`).
    pub fn new(radius: f64) -> Result<Self> {
        Ok(Self { radius: positive("R", radius)? })
    }
    /// The radius `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }
    fn s<D: Scalar>(&self, x: &SVector<D, 3>) -> D {
        (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / (self.radius * self.radius)
    }
}

fn hat<D: Scalar>(x: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
    let z = D::from(0.0);
    SMatrix::<D, 3, 3>::new(z, -x[2], x[1], x[2], z, -x[0], -x[1], x[0], z)
}

fn outer<D: Scalar>(x: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
    SMatrix::from_fn(|i, j| x[i] * x[j])
}

impl ChartGeometry<3, 4> for Sphere3Chart {
    const NAME: &'static str = "S3";

    fn coordinate_names(&self) -> [&'static str; 3] {
        ["r1", "r2", "r3"]
    }

    /// `Ok` iff `r̄` is finite and `|r̄|/R < π −` [`Sphere3Chart::CHART_MARGIN`].
    fn check_chart(&self, x: &SVector<f64, 3>) -> Result<()> {
        finite("x = r̄", x.iter())?;
        if x.norm() / self.radius >= PI - Self::CHART_MARGIN {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "|r̄|/R must be < π − 1e-6: the rotation-vector chart is singular at the antipode −R·1",
            });
        }
        Ok(())
    }

    /// `σ² 1 + ((1 − σ²)/ϑ²) r̄r̄ᵀ/R²`.
    fn metric<D: Scalar>(&self, x: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let s = self.s(x);
        let sc = series::sinc(s);
        SMatrix::identity() * (sc * sc) + outer(x) * (series::sinc2_defect(s) / (self.radius * self.radius))
    }

    /// `(1 − ϑ²·c) 1 + c·r̄r̄ᵀ/R² − [r̄]×/R`, `c = (1 − ϑ cot ϑ)/ϑ²`.
    fn frame<D: Scalar>(&self, x: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let s = self.s(x);
        let c = series::cot_defect(s);
        let r = self.radius;
        SMatrix::identity() * (D::from(1.0) - s * c) + outer(x) * (c / (r * r)) - hat(x) * D::from(1.0 / r)
    }

    /// `σ cos ϑ 1 + ((1 − σ cos ϑ)/ϑ²) r̄r̄ᵀ/R² + σ² [r̄]×/R`.
    fn coframe<D: Scalar>(&self, x: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let s = self.s(x);
        let sc = series::sinc(s);
        let r = self.radius;
        SMatrix::identity() * (sc * series::cos(s))
            + outer(x) * (series::sinccos_defect(s) / (r * r))
            + hat(x) * (sc * sc / r)
    }

    /// `Γ^A_{BC} = ε_{ABC}/R`.
    fn frame_connection<D: Scalar>(&self, _x: &SVector<D, 3>) -> Connection<D, 3> {
        let k = 1.0 / self.radius;
        let mut g = zero_connection();
        for (a, b, c) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
            g[a][b][c] = D::from(k);
            g[a][c][b] = D::from(-k);
        }
        g
    }

    fn ambient_metric(&self) -> SMatrix<f64, 4, 4> {
        SMatrix::identity()
    }

    /// `(R cos ϑ, σ r̄)`.
    fn embed<D: Scalar>(&self, x: &SVector<D, 3>) -> SVector<D, 4> {
        let s = self.s(x);
        let sc = series::sinc(s);
        SVector::<D, 4>::new(series::cos(s) * self.radius, sc * x[0], sc * x[1], sc * x[2])
    }

    /// Row 0: `−σ r̄ᵀ/R`; rows 1–3: `σ 1 + ((cos ϑ − σ)/ϑ²) r̄r̄ᵀ/R²`.
    fn embed_jacobian<D: Scalar>(&self, x: &SVector<D, 3>) -> SMatrix<D, 4, 3> {
        let s = self.s(x);
        let sc = series::sinc(s);
        let r = self.radius;
        let d = series::dsinc(s) / (r * r);
        SMatrix::from_fn(|i, j| {
            if i == 0 {
                -sc * x[j] / r
            } else {
                let k = i - 1;
                let diag = if k == j { sc } else { D::from(0.0) };
                diag + d * x[k] * x[j]
            }
        })
    }

    /// `r̄ = R ϑ p⃗/|p⃗|` with `ϑ = atan2(|p⃗|, p₀)`, evaluated as
    /// `R p⃗/(|p| σ(ϑ))` (regular at `p⃗ = 0`).
    fn chart_point(&self, p: &SVector<f64, 4>) -> Result<SVector<f64, 3>> {
        finite("p", p.iter())?;
        let d = defect(p.norm() - self.radius, self.radius);
        check_defect("p", "on the sphere: |p| = R", d)?;
        let v = SVector::<f64, 3>::new(p[1], p[2], p[3]);
        let t = v.norm().atan2(p[0]);
        if t >= PI - Self::CHART_MARGIN {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "point at (or within 1e-6 rad of) the antipode −R·1, where the rotation-vector chart is singular",
            });
        }
        Ok(v * (self.radius / (p.norm() * series::sinc(t * t))))
    }
}
