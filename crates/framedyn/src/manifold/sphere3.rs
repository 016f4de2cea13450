//! The three-sphere S³(R) ⊂ ℝ⁴: see [`Sphere3`] for chart, embedding and frames.

use nalgebra::{Matrix3, Matrix4, Matrix4x3, Vector3, Vector4};

use super::{GeodesicDistance, Manifold, Tensor3, Tensor4};
use crate::error::{finite, positive};
use crate::lie::special::{cosc, dexpinv, sinc, sinc3};
use crate::{Error, Result};

/// The chart is accepted for `r/R < π − S3_CHART_MARGIN`. Near `r = πR` its
/// coefficients grow like `1/(π − r/R)` (all of S³ outside the chart is the
/// single point `−R·1`), so chart results there carry relative errors of about
/// `1e-16/(π − r/R)`.
pub const S3_CHART_MARGIN: f64 = 1e-6;

/// Relative defect `||p| − R|/R` accepted by [`Manifold::chart`],
/// [`Manifold::chart_tangent`] and [`GeodesicDistance::distance`].
pub const S3_POINT_TOLERANCE: f64 = 1e-9;

/// The three-sphere S³(R) ⊂ ℝ⁴ of radius `R` (the paper's §6, the "Einstein
/// universe").
///
/// ## Embedding and quaternions
/// A point is the unit quaternion `u ∈ SU(2)` scaled by `R`, components
/// **scalar first**: `x = R·u = R·(cos(r/R), sin(r/R) n̄) ∈ ℝ⁴` (the paper's
/// parametrisation after (a179) puts the scalar part last, as `x⁴`). The
/// quaternion basis is `1, e₁, e₂, e₃` with `e₁e₂ = e₃` (the paper's `I₂, −iσ_B`).
///
/// ## Chart
/// The paper's canonical coordinates of the first kind, rescaled (§6,
/// `r = Rk/2`): `r̄ = (R/2)·k̄ ∈ ℝ³`, `|r̄| = r`, `n̄ = r̄/r`, so that
/// `u = exp(k̄·a) = exp(r̄·e/R)` (a171). They are Riemann normal coordinates
/// centred at `R·1`, regular at `r̄ = 0` and singular only on the sphere
/// `r = πR`, which is the single antipodal point `−R·1`. The metric (a179) is
/// `g_ij = (R/r)² sin²(r/R) δ_ij + (1 − (R/r)² sin²(r/R)) n_i n_j`.
/// Every coefficient is evaluated through the entire functions of
/// [`special`](crate::lie::special) of `s = r²/R²` (or `4s`), never by dividing
/// by `r`. [`check_chart`](Manifold::check_chart) accepts `r < R(π − `[`S3_CHART_MARGIN`]`)`.
///
/// ## Frames
/// S³ is parallelizable; the paper uses the SU(2)-invariant orthonormal frames
/// of (a178a), (a178b) (SPEC §7, "S³ frames"):
/// - `ˡE(R)_A(x) = e_A·x/R` (quaternion product): the generators of **left**
///   translations, hence **right-invariant**, with
///   `[ˡE_A, ˡE_B] = −(2/R) ε_ABC ˡE_C` (b178a). This is [`Manifold::frame`],
///   also [`Sphere3::frame_l`]; chart components
///   `ˡE = (r/R)cot(r/R) I + (1 − (r/R)cot(r/R)) n̄n̄ᵀ − (1/R)[r̄]×`, connection
///   coefficients `Γ^A_{BC} = +(1/R) ε_ABC`.
/// - `ʳE(R)_A(x) = x·e_A/R`: generators of right translations, left-invariant,
///   `[ʳE_A, ʳE_B] = +(2/R) ε_ABC ʳE_C` (b178b), [`Sphere3::frame_r`]; chart
///   components as above with `+(1/R)[r̄]×`, `Γ^A_{BC} = −(1/R) ε_ABC`.
///
/// The two frames commute (b178c). Conserved quantities of the S³ gyroscope
/// depend on which one carries the internal configuration (SPEC §7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere3 {
    radius: f64,
    /// `1/R`, kept so that the vector fields multiply instead of divide.
    inv_radius: f64,
}

/// Taylor coefficients of `h(t) = (2·dexpinv(t) − sinc3(t))/t`:
/// `h_k = 2|B_{2k+4}|/(2k+4)! − (−1)^{k+1}/(2k+5)!` (computed exactly in
/// rational arithmetic, rounded once). 18 terms reach full precision for `|t| < 4`.
const H_SERIES: [f64; 18] = [
    0.011111111111111112,
    -0.00013227513227513228,
    4.409171075837742e-06,
    1.670140559029448e-08,
    1.2174284661057148e-09,
    2.6000356688187376e-11,
    6.807475165188621e-13,
    1.7163903477309063e-14,
    4.349933126526758e-16,
    1.1017966975018752e-17,
    2.790893581857533e-19,
    7.069413987422036e-21,
    1.7907034865385057e-22,
    4.5359049045537536e-24,
    1.148958133775592e-25,
    2.910344951229633e-27,
    7.371989881330627e-29,
    1.867346851419009e-30,
];

/// `|t|` below which [`h_coef`] uses its series (the closed form cancels there).
const H_SERIES_MAX: f64 = 4.0;

/// `(2·dexpinv(t) − sinc3(t))/t`, entire up to its pole at `t = (2π)²`;
/// `= 1/90 − t/7560 + …`. The coefficient of `x_i x_j x_k` in the Christoffel
/// symbols of the normal-coordinate chart.
fn h_coef(t: f64) -> f64 {
    if t.abs() < H_SERIES_MAX {
        H_SERIES.iter().rev().fold(0.0, |acc, &c| acc * t + c)
    } else {
        (2.0 * dexpinv(t) - sinc3(t)) / t
    }
}

/// Quaternion product, scalar first.
#[inline]
fn qmul(a: &Vector4<f64>, b: &Vector4<f64>) -> Vector4<f64> {
    Vector4::new(
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    )
}

#[inline]
fn basis(a: usize) -> Vector4<f64> {
    let mut e = Vector4::zeros();
    e[a] = 1.0;
    e
}

#[inline]
fn cross_matrix(x: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -x[2], x[1], x[2], 0.0, -x[0], -x[1], x[0], 0.0)
}

#[inline]
fn levi_civita(a: usize, b: usize, c: usize) -> f64 {
    match (a, b, c) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (2, 1, 0) | (1, 0, 2) => -1.0,
        _ => 0.0,
    }
}

impl Sphere3 {
    /// S³ of radius `radius` (finite and > 0, else [`Error::InvalidParameter`]).
    ///
    /// ```
    /// use framedyn::manifold::{Manifold, Sphere3};
    /// use nalgebra::Vector3;
    ///
    /// let s3 = Sphere3::new(1.0)?;
    /// let x = s3.embed(&Vector3::new(0.3, -0.2, 0.5)); // rotation-vector chart r̄
    /// assert!((x.norm() - 1.0).abs() < 1e-15);
    /// assert!(Sphere3::new(0.0).is_err());
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(radius: f64) -> Result<Self> {
        let radius = positive("R", radius)?;
        Ok(Sphere3 { radius, inv_radius: 1.0 / radius })
    }

    /// The radius `R`.
    #[inline]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `1/R` (stored: the inner loops multiply by it).
    #[inline]
    pub fn inv_radius(&self) -> f64 {
        self.inv_radius
    }

    /// `s = r²/R²` at the chart point `x`.
    #[inline]
    fn s(&self, x: &Vector3<f64>) -> f64 {
        x.norm_squared() / (self.radius * self.radius)
    }

    /// Chart components of `ˡE(R)` (`sign = −1`) or `ʳE(R)` (`sign = +1`):
    /// `(r/R)cot(r/R) I + (1 − (r/R)cot(r/R)) n̄n̄ᵀ + sign·(1/R)[r̄]×`, with
    /// `1 − θcotθ = 4θ²·dexpinv(4θ²)`.
    fn frame_with_sign(&self, x: &Vector3<f64>, sign: f64) -> Matrix3<f64> {
        let r = self.radius;
        let s = self.s(x);
        let d = dexpinv(4.0 * s);
        Matrix3::identity() * (1.0 - 4.0 * s * d) + x * x.transpose() * (4.0 * d / (r * r))
            + cross_matrix(x) * (sign / r)
    }

    /// The paper's `ˡE(R)` (a178a) at the chart point `x`: column `A` holds the
    /// chart components of `ˡE(R)_A`, the generator of left translations
    /// `x ↦ exp(t e_A/R)·x`, i.e. `ˡE(R)_A(x) = e_A·x/R`; right-invariant,
    /// `[ˡE_A, ˡE_B] = −(2/R) ε_ABC ˡE_C`. The same as [`Manifold::frame`].
    pub fn frame_l(&self, x: &Vector3<f64>) -> Matrix3<f64> {
        self.frame_with_sign(x, -1.0)
    }

    /// The paper's `ʳE(R)` (a178b) at the chart point `x`: generators of right
    /// translations, `ʳE(R)_A(x) = x·e_A/R`; left-invariant,
    /// `[ʳE_A, ʳE_B] = +(2/R) ε_ABC ʳE_C`. Its connection coefficients are
    /// [`Sphere3::frame_r_connection`].
    pub fn frame_r(&self, x: &Vector3<f64>) -> Matrix3<f64> {
        self.frame_with_sign(x, 1.0)
    }

    /// Connection coefficients of `ʳE(R)`: `Γ^A_{BC} = −(1/R) ε_ABC`
    /// (constant; `∇_X Y = ½[X, Y]` on invariant fields of a bi-invariant metric).
    pub fn frame_r_connection(&self) -> Tensor3<3> {
        self.eps_tensor(-1.0 / self.radius)
    }

    fn eps_tensor(&self, f: f64) -> Tensor3<3> {
        let mut t = [[[0.0; 3]; 3]; 3];
        for (a, ta) in t.iter_mut().enumerate() {
            for (b, tab) in ta.iter_mut().enumerate() {
                for (c, v) in tab.iter_mut().enumerate() {
                    *v = f * levi_civita(a, b, c);
                }
            }
        }
        t
    }

    /// Ambient components of `ˡE(R)_A = e_A·p/R` at the embedded point `p`
    /// (columns `A = 1, 2, 3`). Together with `p/R` they are the columns of an
    /// SO(4) matrix (right multiplication by `p/R`).
    pub fn frame_l_ambient(&self, p: &Vector4<f64>) -> Matrix4x3<f64> {
        let u = p / self.radius;
        Matrix4x3::from_columns(&[qmul(&basis(1), &u), qmul(&basis(2), &u), qmul(&basis(3), &u)])
    }

    /// Ambient components of `ʳE(R)_A = p·e_A/R` at the embedded point `p`.
    pub fn frame_r_ambient(&self, p: &Vector4<f64>) -> Matrix4x3<f64> {
        let u = p / self.radius;
        Matrix4x3::from_columns(&[qmul(&u, &basis(1)), qmul(&u, &basis(2)), qmul(&u, &basis(3))])
    }

    /// Validates an embedded point: finite and within [`S3_POINT_TOLERANCE`] of S³.
    fn check_point(&self, field: &'static str, p: &Vector4<f64>) -> Result<()> {
        finite(field, p.iter())?;
        let defect = self.point_defect(p);
        if defect > S3_POINT_TOLERANCE {
            return Err(Error::Constraint { field, constraint: "|p| = R", defect, tolerance: S3_POINT_TOLERANCE });
        }
        Ok(())
    }
}

impl Manifold<3, 4> for Sphere3 {
    const NAME: &'static str = "S3";

    fn coordinate_names(&self) -> [&'static str; 3] {
        ["r1", "r2", "r3"]
    }

    fn coordinate_units(&self) -> [&'static str; 3] {
        ["L", "L", "L"]
    }

    fn check_chart(&self, x: &Vector3<f64>) -> Result<()> {
        finite("x", x.iter())?;
        if x.norm() / self.radius >= std::f64::consts::PI - S3_CHART_MARGIN {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "|r̄| ≥ πR (the antipode −R·1 of the chart centre): rotation-vector coordinates are singular",
            });
        }
        Ok(())
    }

    /// `g = sinc(s)² I + sinc3(s)(1 + sinc(s))/R² · r̄r̄ᵀ`, `s = r²/R²`: the
    /// paper's (a179) with `1 − sinc² = s·sinc3·(1 + sinc)`.
    fn metric(&self, x: &Vector3<f64>) -> Matrix3<f64> {
        let r = self.radius;
        let s = self.s(x);
        let sc = sinc(s);
        Matrix3::identity() * (sc * sc) + x * x.transpose() * (sinc3(s) * (1.0 + sc) / (r * r))
    }

    /// For `g = A(ρ)I + B(ρ)xxᵀ` with `g(n̄, n̄) = 1`, `ρ = |x|²`:
    /// `Γ^i_{jk} = α(x_jδ_ik + x_kδ_ij) + δ·δ_jk x_i + γ x_i x_j x_k` with
    /// `α = A'/A = −4·dexpinv(4s)/R²`, `δ = B − A' = 4·sinc3(4s)/R²`,
    /// `γ = B' − 2A'B/A = −(2α + δ)/ρ = 16·h(4s)/R⁴` (`h` by series near 0).
    fn christoffel(&self, x: &Vector3<f64>) -> Tensor3<3> {
        let r2 = self.radius * self.radius;
        let t = 4.0 * self.s(x);
        let alpha = -4.0 * dexpinv(t) / r2;
        let delta = 4.0 * sinc3(t) / r2;
        let gamma = 16.0 * h_coef(t) / (r2 * r2);
        let mut out = [[[0.0; 3]; 3]; 3];
        for (i, oi) in out.iter_mut().enumerate() {
            for (j, oij) in oi.iter_mut().enumerate() {
                for (k, v) in oij.iter_mut().enumerate() {
                    let mut val = gamma * x[i] * x[j] * x[k];
                    if i == k {
                        val += alpha * x[j];
                    }
                    if i == j {
                        val += alpha * x[k];
                    }
                    if j == k {
                        val += delta * x[i];
                    }
                    *v = val;
                }
            }
        }
        out
    }

    /// Constant curvature `K = 1/R²`: `R^i_{jkl} = K(δ^i_k g_jl − δ^i_l g_jk)`.
    fn riemann(&self, x: &Vector3<f64>) -> Tensor4<3> {
        let k = 1.0 / (self.radius * self.radius);
        let g = self.metric(x);
        let mut out = [[[[0.0; 3]; 3]; 3]; 3];
        for (i, oi) in out.iter_mut().enumerate() {
            for (j, oij) in oi.iter_mut().enumerate() {
                for (kk, oijk) in oij.iter_mut().enumerate() {
                    for (l, v) in oijk.iter_mut().enumerate() {
                        let mut val = 0.0;
                        if i == kk {
                            val += g[(j, l)];
                        }
                        if i == l {
                            val -= g[(j, kk)];
                        }
                        *v = k * val;
                    }
                }
            }
        }
        out
    }

    /// `ˡE(R)` (a178a): see [`Sphere3::frame_l`].
    fn frame(&self, x: &Vector3<f64>) -> Matrix3<f64> {
        self.frame_l(x)
    }

    /// `Γ^A_{BC} = +(1/R) ε_ABC` for `ˡE(R)`: `∇_{E_C}E_B = ½[E_C, E_B]` with
    /// (b178a).
    fn frame_connection(&self, _x: &Vector3<f64>) -> Tensor3<3> {
        self.eps_tensor(1.0 / self.radius)
    }

    fn ambient_metric(&self) -> Matrix4<f64> {
        Matrix4::identity()
    }

    /// `R·(cos(r/R), sin(r/R) n̄) = (R cos(r/R), sinc(s)·r̄)` (scalar part first).
    fn embed(&self, x: &Vector3<f64>) -> Vector4<f64> {
        let s = self.s(x);
        let sc = sinc(s);
        Vector4::new(self.radius * s.sqrt().cos(), sc * x[0], sc * x[1], sc * x[2])
    }

    /// `(−sinc(s)(r̄·v)/R, (sinc3(s) − cosc(s))(r̄·v)/R²·r̄ + sinc(s)·v)`
    /// (`d sinc/ds = (sinc3 − cosc)/2`).
    fn embed_tangent(&self, x: &Vector3<f64>, v: &Vector3<f64>) -> Vector4<f64> {
        let r = self.radius;
        let s = self.s(x);
        let sc = sinc(s);
        let xv = x.dot(v);
        let w = x * ((sinc3(s) - cosc(s)) * xv / (r * r)) + v * sc;
        Vector4::new(-sc * xv / r, w[0], w[1], w[2])
    }

    /// `r̄ = R·p⃗/(|p|·sinc(θ²))`, `θ = atan2(|p⃗|, p₀)`. Fails with
    /// [`Error::NotFinite`]/[`Error::Constraint`] for a point off S³ and with
    /// [`Error::OutsideChart`] within [`S3_CHART_MARGIN`] of the antipode `−R·1`.
    fn chart(&self, p: &Vector4<f64>) -> Result<Vector3<f64>> {
        self.check_point("p", p)?;
        let v = Vector3::new(p[1], p[2], p[3]);
        let th = v.norm().atan2(p[0]);
        if th >= std::f64::consts::PI - S3_CHART_MARGIN {
            return Err(Error::OutsideChart {
                manifold: Self::NAME,
                reason: "point at (or next to) the antipode −R·1 of the chart centre: rotation-vector coordinates are singular",
            });
        }
        Ok(v * (self.radius / (p.norm() * sinc(th * th))))
    }

    /// Components `c_A = ⟨ˡE_A, w⟩` in the frame `ˡE_A = e_A·p/|p|`, mapped to
    /// the chart by [`Sphere3::frame_l`]; a normal part of `w` is ignored.
    fn chart_tangent(&self, p: &Vector4<f64>, w: &Vector4<f64>) -> Result<Vector3<f64>> {
        let x = self.chart(p)?;
        finite("w", w.iter())?;
        let u = p / p.norm();
        let c = Vector3::from_fn(|a, _| qmul(&basis(a + 1), &u).dot(w));
        Ok(self.frame_l(&x) * c)
    }

    fn point_defect(&self, p: &Vector4<f64>) -> f64 {
        (p.norm() - self.radius).abs() / self.radius
    }

    /// `R·p/|p|`; the point `R·1` for `p = 0`; non-finite input is returned as is.
    fn project_point(&self, p: &Vector4<f64>) -> Vector4<f64> {
        let n = p.norm();
        if n == 0.0 {
            basis(0) * self.radius
        } else if !n.is_finite() {
            *p
        } else {
            p * (self.radius / n)
        }
    }

    /// `w − p (p·w)/|p|²` (`w` itself for `p = 0`).
    fn project_tangent(&self, p: &Vector4<f64>, w: &Vector4<f64>) -> Vector4<f64> {
        let n2 = p.norm_squared();
        if n2 == 0.0 {
            *w
        } else {
            w - p * (p.dot(w) / n2)
        }
    }
}

impl GeodesicDistance<3, 4> for Sphere3 {
    /// `R·atan2(|p ∧ q|, p·q)`, with the six components of the bivector
    /// `p ∧ q` (accurate for close and for antipodal points).
    fn distance(&self, p: &Vector4<f64>, q: &Vector4<f64>) -> Result<f64> {
        self.check_point("p", p)?;
        self.check_point("q", q)?;
        let mut w2 = 0.0;
        for i in 0..4 {
            for j in (i + 1)..4 {
                let c = p[i] * q[j] - p[j] * q[i];
                w2 += c * c;
            }
        }
        Ok(self.radius * w2.sqrt().atan2(p.dot(q)))
    }
}
