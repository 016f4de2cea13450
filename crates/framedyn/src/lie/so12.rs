//! The proper orthochronous Lorentz group SO⁺(1,2) in 2 + 1 dimensions: the
//! isometry group of the hyperbolic plane H² and the group of its orthonormal
//! frame bundle.
//!
//! See [`So12`] for the representation, the algebra basis, the closed forms
//! and the numerics far from the identity.

use nalgebra::{DMatrix, Matrix3, SVector, Vector3};

use super::special::{cosc, dexpinv, sinc3, sinc_cosc};
use super::LieGroup;
use crate::{Error, Result};

/// The Minkowski metric `η = diag(1, 1, −1)` of ℝ^{2,1}.
const ETA: [f64; 3] = [1.0, 1.0, -1.0];

/// Tolerance of [`So12::new`] on the relative constraint defect.
pub const SO12_TOLERANCE: f64 = 1e-9;

/// An element of SO⁺(1,2), the proper orthochronous Lorentz group of
/// ℝ^{2,1}: the isometry group of the hyperbolic plane H² and the group of
/// its orthonormal frame bundle.
///
/// ## Representation
/// 3×3 real matrices `Λ` with `ΛᵀηΛ = η`, `η = diag(1, 1, −1)` (the last
/// coordinate is the timelike one), `det Λ = 1` and `Λ₃₃ ≥ 1`.
///
/// ## Algebra basis and brackets
/// The algebra coordinates `(b₁, b₂, ω)` (an `SVector<f64, 3>`) stand for
/// ```text
///     X = b₁ K₁ + b₂ K₂ + ω J = [[0, −ω, b₁],
///                                [ω,  0, b₂],
///                                [b₁, b₂, 0]]
/// ```
/// with the boosts `K₁ = e₁₃ + e₃₁`, `K₂ = e₂₃ + e₃₂` and the rotation
/// `J = e₂₁ − e₁₂` of the `(1, 2)` plane. The brackets are
/// `[J, K₁] = K₂`, `[J, K₂] = −K₁`, `[K₁, K₂] = −J`; in coordinates
/// `[x, y] = η (x × y)` (the Euclidean cross product with the third component
/// negated). The Casimir `s = ω² − b₁² − b₂²` classifies generators: elliptic
/// (`s > 0`, a rotation by the angle `√s` about a timelike axis), parabolic
/// (`s = 0`, `X ≠ 0`, nilpotent) and hyperbolic (`s < 0`, a boost of rapidity
/// `√−s`). The vector `w = (−b₂, b₁, ω)` spans the kernel of `X` (its axis);
/// `⟨w, w⟩_η = −s`, `X² = −s·I − w wᵀη` and `X³ = −s X`. The axis map
/// `X ↦ w` intertwines `Ad` with the defining representation:
/// `Ad_Λ X ↦ Λ w`.
///
/// ## Closed forms
/// With the coefficient functions of [`special`](super::special), all entire
/// in the signed squared angle `s` and therefore continuous across elliptic,
/// parabolic and hyperbolic generators:
/// - `exp X = I + sinc(s) X + cosc(s) X²`;
/// - `ad_X³ = −s ad_X` as well (the adjoint representation is equivalent to
///   the defining one), so `dexp_X = I + cosc(s) ad_X + sinc3(s) ad_X²` and
///   `dexp_X⁻¹ = I − ½ ad_X + dexpinv(s) ad_X²` (the Bernoulli series summed
///   in closed form; singular at `s = (2π)²`).
///
/// ## Conditioning far from the identity
/// An element with rapidity `β` has entries of size `cosh β`, and in double
/// precision the constraint `ΛᵀηΛ = η` can only hold to `≈ ε cosh²β` in
/// absolute terms. [`So12::constraint_defect`] therefore measures the defect
/// relative to `|Λ|²`, and [`So12::renormalize`] rebuilds the element from a
/// Cartan (KAK) decomposition whose parameters are extracted without the
/// cancellations of a Minkowski Gram–Schmidt (which loses all digits at
/// rapidities beyond ≈ 18).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct So12(Matrix3<f64>);

/// Minkowski inner product `⟨a, b⟩_η = a₁b₁ + a₂b₂ − a₃b₃`.
#[inline]
pub fn minkowski_dot(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a[0] * b[0] + a[1] * b[1] - a[2] * b[2]
}

/// The Cartan (KAK) parameters of a Lorentz matrix,
/// `Λ = R(α)·B(β)·R(γ)` with `R` a rotation of the `(1, 2)` plane and `B(β)`
/// the boost of rapidity `β ≥ 0` along the first axis. The angles are stored
/// as unit vectors `(cos, sin)`; `sinh β` and `cosh β` are stored instead of
/// `β` so that no digits are lost for large rapidities.
///
/// For H² this is the polar chart: the point `Λe₃` has `ϑ = β`, `φ = α`, and
/// `R(γ)` is the rotation of the frame `(Λe₁, Λe₂)` relative to `(E_r, E_φ)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LorentzKak {
    /// `(cos α, sin α)`; `(1, 0)` when `β = 0` (then only `α + γ` matters).
    pub alpha: (f64, f64),
    /// `sinh β ≥ 0`.
    pub sinh_beta: f64,
    /// `cosh β ≥ 1`.
    pub cosh_beta: f64,
    /// `(cos γ, sin γ)`.
    pub gamma: (f64, f64),
}

impl LorentzKak {
    /// The rapidity `β = asinh(sinh β)`.
    pub fn beta(&self) -> f64 {
        self.sinh_beta.asinh()
    }

    /// The matrix `R(α)·B(β)·R(γ)`, assembled column by column so that every
    /// entry has a small relative error: the result satisfies the constraint
    /// to `≈ ε|Λ|²` however large `β` is.
    pub fn to_matrix(&self) -> Matrix3<f64> {
        let (ca, sa) = self.alpha;
        let (cg, sg) = self.gamma;
        let (sh, ch) = (self.sinh_beta, self.cosh_beta);
        // Columns of R(α)B(β): e_r = (cα chβ, sα chβ, shβ), e_φ = (−sα, cα, 0),
        // n = (cα shβ, sα shβ, chβ).
        let er = Vector3::new(ca * ch, sa * ch, sh);
        let ephi = Vector3::new(-sa, ca, 0.0);
        let n = Vector3::new(ca * sh, sa * sh, ch);
        let q1 = er * cg + ephi * sg;
        let q2 = ephi * cg - er * sg;
        Matrix3::from_columns(&[q1, q2, n])
    }

    /// Extracts the Cartan parameters of a matrix close to SO⁺(1,2).
    ///
    /// `β` comes from the spatial part of the timelike column (`sinh β` =
    /// its Euclidean length, accurate for small and large `β`), `α` from its
    /// direction, and `γ` from `sinh β·(Λ₃₁, −Λ₃₂) + (⟨e_φ, Λe₂⟩, ⟨e_φ, Λe₁⟩)
    /// = cosh²β·(cos γ, sin γ)`: the first term carries full relative precision
    /// for large `β`, the second for small `β`, and their sum for all `β`.
    /// The input is assumed finite, with a positive `(3, 3)` entry.
    pub fn of_matrix(m: &Matrix3<f64>) -> LorentzKak {
        let (nx, ny) = (m[(0, 2)], m[(1, 2)]);
        let rho = nx.hypot(ny);
        let alpha = if rho > 0.0 { (nx / rho, ny / rho) } else { (1.0, 0.0) };
        let ch = rho.hypot(1.0);
        let (ca, sa) = alpha;
        // ⟨e_φ, q₁⟩ and ⟨e_φ, q₂⟩ (e_φ has no timelike component).
        let ephi_q1 = -sa * m[(0, 0)] + ca * m[(1, 0)];
        let ephi_q2 = -sa * m[(0, 1)] + ca * m[(1, 1)];
        let vc = rho * m[(2, 0)] + ephi_q2;
        let vs = -rho * m[(2, 1)] + ephi_q1;
        let vn = vc.hypot(vs);
        let gamma = if vn > 0.0 { (vc / vn, vs / vn) } else { (1.0, 0.0) };
        LorentzKak { alpha, sinh_beta: rho, cosh_beta: ch, gamma }
    }
}

impl So12 {
    /// The element with matrix `m`, validated: finite entries, relative
    /// constraint defect ([`Self::constraint_defect`]) at most
    /// [`SO12_TOLERANCE`], `det Λ > 0` and `Λ₃₃ > 0`.
    ///
    /// Errors: [`Error::NotFinite`] or [`Error::Constraint`] with field `"Lambda"`.
    pub fn new(m: Matrix3<f64>) -> Result<So12> {
        crate::error::finite("Lambda", m.iter())?;
        if m[(2, 2)] <= 0.0 {
            return Err(Error::Constraint {
                field: "Lambda",
                constraint: "Λ₃₃ ≥ 1 (orthochronous: maps the upper sheet of the hyperboloid to itself)",
                defect: 1.0 - m[(2, 2)],
                tolerance: SO12_TOLERANCE,
            });
        }
        if certainly_improper(&m) {
            return Err(Error::Constraint {
                field: "Lambda",
                constraint: "det Λ = +1 (proper)",
                defect: 2.0,
                tolerance: SO12_TOLERANCE,
            });
        }
        let d = metric_defect(&m);
        if d > SO12_TOLERANCE {
            return Err(Error::Constraint {
                field: "Lambda",
                constraint: "ΛᵀηΛ = η, η = diag(1, 1, −1) (relative to |Λ|²)",
                defect: d,
                tolerance: SO12_TOLERANCE,
            });
        }
        Ok(So12(m))
    }

    /// The element with matrix `m`, not validated (the caller guarantees
    /// `m ∈ SO⁺(1,2)` up to round-off).
    #[inline]
    pub const fn new_unchecked(m: Matrix3<f64>) -> So12 {
        So12(m)
    }

    /// The Lorentz matrix `Λ`.
    #[inline]
    pub fn matrix(&self) -> &Matrix3<f64> {
        &self.0
    }

    /// The Lorentz matrix `Λ`, by value.
    #[inline]
    pub fn into_matrix(self) -> Matrix3<f64> {
        self.0
    }

    /// The element `R(α)·B(β)·R(γ)` (see [`LorentzKak`]); any real `β` (a negative
    /// rapidity boosts along `−e₁`).
    pub fn from_kak(alpha: f64, beta: f64, gamma: f64) -> So12 {
        let (sa, ca) = alpha.sin_cos();
        let (sg, cg) = gamma.sin_cos();
        let (sb, cb) = (beta.abs().sinh(), beta.cosh());
        // A negative rapidity is a boost along −e₁: B(−β) = R(π)B(β)R(π).
        let (ca, sa, cg, sg) = if beta >= 0.0 { (ca, sa, cg, sg) } else { (-ca, -sa, -cg, -sg) };
        So12(LorentzKak { alpha: (ca, sa), sinh_beta: sb, cosh_beta: cb, gamma: (cg, sg) }.to_matrix())
    }

    /// The Cartan parameters of this element (see [`LorentzKak::of_matrix`]).
    pub fn kak(&self) -> LorentzKak {
        LorentzKak::of_matrix(&self.0)
    }

    /// The matrix `X` of the algebra element with coordinates `(b₁, b₂, ω)`.
    #[inline]
    pub fn hat(a: &Vector3<f64>) -> Matrix3<f64> {
        let (b1, b2, w) = (a[0], a[1], a[2]);
        Matrix3::new(0.0, -w, b1, w, 0.0, b2, b1, b2, 0.0)
    }

    /// The coordinates `(b₁, b₂, ω)` of the so(1,2) part of the matrix `x`
    /// (its η-antisymmetric part, i.e. the projection `(x − ηxᵀη)/2`).
    #[inline]
    pub fn vee(x: &Matrix3<f64>) -> Vector3<f64> {
        Vector3::new(0.5 * (x[(0, 2)] + x[(2, 0)]), 0.5 * (x[(1, 2)] + x[(2, 1)]), 0.5 * (x[(1, 0)] - x[(0, 1)]))
    }

    /// The Casimir `s = ω² − b₁² − b₂²` of the algebra element `a`: positive
    /// for elliptic (rotation angle `√s`), zero for parabolic, negative for
    /// hyperbolic (rapidity `√−s`) generators. Computed as
    /// `(ω − |b|)(ω + |b|)` to limit cancellation near the parabolic cone.
    #[inline]
    pub fn casimir(a: &Vector3<f64>) -> f64 {
        let nb = a[0].hypot(a[1]);
        (a[2] - nb) * (a[2] + nb)
    }

    /// The axis `w = (−b₂, b₁, ω)` of the algebra element `a` (the kernel of
    /// `X`); `Ad_Λ` acts on it as `w ↦ Λw`.
    #[inline]
    pub fn axis(a: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(-a[1], a[0], a[2])
    }

    /// The algebra element whose axis is `w` (inverse of [`Self::axis`]).
    #[inline]
    pub fn from_axis(w: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(w[1], -w[0], w[2])
    }

    /// The Minkowski-type bilinear form associated with the Casimir,
    /// `⟨x, y⟩_C = ω_x ω_y − b_x·b_y` (so `⟨x, x⟩_C = s`); it is `−½` times
    /// the trace form `tr(XY)` and is Ad-invariant.
    #[inline]
    pub fn casimir_form(x: &Vector3<f64>, y: &Vector3<f64>) -> f64 {
        x[2] * y[2] - x[0] * y[0] - x[1] * y[1]
    }

    /// Largest absolute entry of `Λ`.
    fn max_entry(&self) -> f64 {
        self.0.amax()
    }
}

/// True if the matrix is certainly improper (`det Λ < 0`), judged by the 2×2
/// spatial minor `det(Λ_{ij})_{i,j ≤ 2}`: for `Λ ∈ O(1,2)` it equals
/// `det Λ · Λ₃₃` with `|·| = Λ₃₃ ≥ 1`, and unlike `det Λ` it is evaluated
/// without catastrophic cancellation up to rapidities ≈ 36. Beyond that the
/// O(1) transverse parts of the columns are below the round-off of their
/// O(cosh β) entries, a double-precision matrix no longer encodes the
/// orientation, and the minor is not trusted (`false`).
fn certainly_improper(m: &Matrix3<f64>) -> bool {
    let (p, q) = (m[(0, 0)] * m[(1, 1)], m[(0, 1)] * m[(1, 0)]);
    let minor = p - q;
    minor <= 0.0 && minor.abs() > 4.0 * f64::EPSILON * (p.abs() + q.abs())
}

/// `max|ΛᵀηΛ − η| / max(1, max|Λ|²)`.
fn metric_defect(m: &Matrix3<f64>) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..3 {
        for j in i..3 {
            let mut g = 0.0;
            for k in 0..3 {
                g += ETA[k] * m[(k, i)] * m[(k, j)];
            }
            let target = if i == j { ETA[i] } else { 0.0 };
            worst = worst.max((g - target).abs());
        }
    }
    let scale = m.amax().powi(2).max(1.0);
    worst / scale
}

impl LieGroup for So12 {
    type Algebra = SVector<f64, 3>;
    const DOF: usize = 3;
    const NAME: &'static str = "SO+(1,2)";

    #[inline]
    fn identity() -> Self {
        So12(Matrix3::identity())
    }

    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        So12(self.0 * rhs.0)
    }

    /// `Λ⁻¹ = ηΛᵀη` (exact: only sign changes).
    #[inline]
    fn inverse(&self) -> Self {
        let mut t = self.0.transpose();
        for i in 0..3 {
            for j in 0..3 {
                t[(i, j)] *= ETA[i] * ETA[j];
            }
        }
        So12(t)
    }

    /// `exp X = I + sinc(s) X + cosc(s) X²`, `s` the Casimir; continuous
    /// across elliptic, parabolic and hyperbolic generators.
    fn exp(a: &Self::Algebra) -> Self {
        let s = So12::casimir(a);
        let x = So12::hat(a);
        let (sa, ca) = sinc_cosc(s);
        So12(Matrix3::identity() + x * sa + (x * x) * ca)
    }

    /// The principal logarithm: the generator `X` with `exp X = Λ` whose
    /// rotation angle (elliptic case) lies in `[0, π)`; it is unique and
    /// exists for every element except the rotations by `π` (trace `−1`,
    /// two logarithms `±π·X̂`). Every element of SO⁺(1,2) ≅ PSL(2, ℝ) is an
    /// exponential; a trace below `−1` means the matrix is not a Lorentz
    /// matrix.
    ///
    /// Method. Write `A = (Λ − Λ⁻¹)/2 = sinc(s)·X` (the η-antisymmetric part,
    /// `Λ⁻¹ = ηΛᵀη`) and `c = (tr Λ − 1)/2 = cos√s` (`cosh√−s` if `s < 0`).
    /// - `c ≥ 0`: the Casimir of `A` is `σ = sinc(s)²·s`, i.e. `sin²θ` or
    ///   `−sinh²β`. Elliptic (`σ > 0`): `θ = atan2(√σ, c)`, `X = A·θ/sin θ`;
    ///   otherwise `β = asinh √−σ`, `X = A·β/sinh β` (`= A` at `σ = 0`). Only
    ///   the antisymmetric part enters near the identity and the parabolic
    ///   cone, where `σ` is accurate to `ε·|A|·|Λ|` and the factor is
    ///   continuous (→ 1), so classification errors there are harmless.
    /// - `c < 0` (elliptic, `θ > π/2`; `θ/sin θ` is ill-conditioned near `π`):
    ///   the symmetric part gives the unit timelike axis `ŵ` through
    ///   `ŵŵᵀ = (c·I − (Λ + Λ⁻¹)/2)·η/(1 − c)`, the antisymmetric part its
    ///   sign and `sin θ = ⟨A, X̂⟩_C`, and `θ = atan2(sin θ, c)`.
    ///
    /// Errors: [`Error::LogUndefined`] for non-finite entries, a trace below
    /// `−1` beyond round-off, or a rotation angle within round-off of `π`.
    fn log(&self) -> Result<Self::Algebra> {
        let m = &self.0;
        let undefined = |reason: &'static str| Err(Error::LogUndefined { group: Self::NAME, reason });
        if !m.iter().all(|v| v.is_finite()) {
            return undefined("the matrix has non-finite entries");
        }
        let scale = self.max_entry().max(1.0);
        let eps = f64::EPSILON;
        let inv = self.inverse().0;
        // A = (Λ − Λ⁻¹)/2 is the η-antisymmetric part of Λ: its coordinates are vee(Λ).
        let a = So12::vee(m);
        let c = 0.5 * (m.trace() - 1.0);
        if c >= 0.0 {
            let sigma = So12::casimir(&a);
            let factor = if sigma > 0.0 {
                let sn = sigma.sqrt();
                let th = sn.atan2(c);
                // θ/sin θ, with sin θ = √σ; series near 0 (θ ≤ π/2 here).
                if th < 1e-4 {
                    1.0 + th * th / 6.0
                } else {
                    th / sn
                }
            } else {
                let sh = (-sigma).sqrt();
                if sh < 1e-4 {
                    1.0 - sh * sh / 6.0
                } else {
                    sh.asinh() / sh
                }
            };
            return Ok(a * factor);
        }
        if c < -1.0 - 64.0 * eps * scale * scale {
            return undefined("trace below −1: not a Lorentz matrix, no real logarithm");
        }
        let c = c.max(-1.0);
        // P = ŵŵᵀ = (c I − S) η / (1 − c), S = (Λ + Λ⁻¹)/2; ŵ₃² = 1 + ŵ₁² + ŵ₂² ≥ 1
        // makes column 3 the best conditioned.
        let sym = (m + inv) * 0.5;
        let col = |i: usize| (if i == 2 { c } else { 0.0 } - sym[(i, 2)]) * ETA[2] / (1.0 - c);
        let p22 = col(2);
        if p22.is_nan() || p22 <= 0.0 {
            return undefined("the symmetric part has no timelike axis: not a Lorentz matrix");
        }
        let nrm = p22.sqrt();
        let w = Vector3::new(col(0) / nrm, col(1) / nrm, nrm);
        let mut unit = So12::from_axis(&w);
        let mut sin_t = So12::casimir_form(&a, &unit);
        if sin_t < 0.0 {
            unit = -unit;
            sin_t = -sin_t;
        }
        if sin_t <= 32.0 * eps * scale * unit.amax().max(1.0) {
            return undefined("rotation by π: the logarithm is not unique (±π·X)");
        }
        let th = sin_t.atan2(c);
        Ok(unit * th)
    }

    /// `Ad_Λ a = Λ X Λ⁻¹`, computed on the axis vector: `w ↦ Λw`.
    #[inline]
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        So12::from_axis(&(self.0 * So12::axis(a)))
    }

    /// `[x, y] = η (x × y)`.
    #[inline]
    fn bracket(x: &Self::Algebra, y: &Self::Algebra) -> Self::Algebra {
        let c = x.cross(y);
        Vector3::new(c[0], c[1], -c[2])
    }

    /// `dexp_a v = v + cosc(s) ad_a v + sinc3(s) ad_a² v` (closed form of the
    /// series, from `ad_a³ = −s ad_a`).
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        let s = So12::casimir(a);
        let ad = Self::bracket(a, v);
        let ad2 = Self::bracket(a, &ad);
        v + ad * cosc(s) + ad2 * sinc3(s)
    }

    /// `dexp_a⁻¹ v = v − ½ ad_a v + dexpinv(s) ad_a² v` (closed form of the
    /// Bernoulli series; singular at `s = (2π)²`, i.e. rotations by `2π`).
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        let s = So12::casimir(a);
        let ad = Self::bracket(a, v);
        let ad2 = Self::bracket(a, &ad);
        v - ad * 0.5 + ad2 * dexpinv(s)
    }

    /// Coordinates `(b₁, b₂, ω)`.
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        Vector3::new(c[0], c[1], c[2])
    }

    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        vec![a[0], a[1], a[2]]
    }

    fn to_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(3, 3, self.0.as_slice())
    }

    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        DMatrix::from_column_slice(3, 3, So12::hat(a).as_slice())
    }

    /// `max|ΛᵀηΛ − η| / max(1, max|Λ|²)`: the metric defect relative to the
    /// size of the entries, the best that double precision can hold for large
    /// boosts (≈ 1e-16 for an element rounded to double). `+∞` if an entry is
    /// not finite or the matrix lies in another component of O(1,2)
    /// (`Λ₃₃ ≤ 0`, or `det Λ < 0` detected through the spatial minor
    /// `det Λ·Λ₃₃`, which does not cancel up to rapidities ≈ 36; beyond that
    /// a double-precision matrix does not encode the orientation).
    fn constraint_defect(&self) -> f64 {
        let m = &self.0;
        if !m.iter().all(|v| v.is_finite()) || m[(2, 2)] <= 0.0 || certainly_improper(m) {
            return f64::INFINITY;
        }
        metric_defect(m)
    }

    /// Projection back onto the group, accurate for any boost: the Cartan
    /// parameters are extracted with [`LorentzKak::of_matrix`] (no Minkowski inner
    /// product of large vectors is formed) and the element is rebuilt by
    /// [`LorentzKak::to_matrix`]. For an input within `δ` (relative) of the group the
    /// result differs from it by `O(δ)` relative to `|Λ|` and satisfies the
    /// constraint to `≈ ε|Λ|²`. Keeps the spatial part of the timelike column
    /// and recomputes its last entry. Non-finite input is returned unchanged.
    fn renormalize(&self) -> Self {
        if !self.0.iter().all(|v| v.is_finite()) {
            return *self;
        }
        So12(LorentzKak::of_matrix(&self.0).to_matrix())
    }
}
