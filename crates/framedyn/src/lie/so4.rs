//! SO(4), the rotations of ℝ⁴: see [`So4`] for the conventions.

use nalgebra::{DMatrix, Matrix4, Quaternion, Vector3, Vector4, Vector6};

use super::special::{cosc, dexpinv, sinc, sinc3};
use super::LieGroup;
use crate::{Error, Result};

/// Lie-algebra coordinates of [`So4`]: `(β₁, β₂, β₃, ω₁, ω₂, ω₃)`, see
/// [`So4`] ("Algebra basis") for the matrix they stand for.
pub type So4Algebra = Vector6<f64>;

/// A rotation of ℝ⁴ (an element of SO(4)), stored as its orthogonal 4×4 matrix,
/// with closed-form exponential, logarithm and `dexp`/`dexp⁻¹` through
/// `so(4) ≅ su(2) ⊕ su(2)`.
///
/// ## Quaternions
/// ℝ⁴ is identified with the quaternions, components **scalar first**:
/// `x = (x₀, x₁, x₂, x₃) = x₀ + x₁e₁ + x₂e₂ + x₃e₃`, Hamilton's product
/// `e₁e₂ = e₃` (the paper's basis `I₂, −iσ_B` of (a171)). Every `R ∈ SO(4)` acts as
/// `x ↦ p·x·q̄` for a pair of unit quaternions `(p, q)` determined up to a common
/// sign (Van Elfrinkhof). [`So4::quaternions`] extracts the pair,
/// [`So4::from_quaternions`] builds the rotation.
///
/// ## Storage
/// An element is stored as its 4×4 orthogonal matrix. For the frame bundle of
/// S³ (the main client) the columns are `[x/R | q₁ | q₂ | q₃]`: position and frame
/// are read off without arithmetic and composition is one 4×4 product. The
/// quaternion pair is computed only where it is needed (`log`, `renormalize`,
/// [`So4::quaternions`]).
///
/// ## Algebra basis
/// [`So4Algebra`] holds six coordinates `(β₁, β₂, β₃, ω₁, ω₂, ω₃)` of the skew matrix
/// ```text
///        ⎡ 0   −β₁  −β₂  −β₃ ⎤
///  X  =  ⎢ β₁   0   −ω₃   ω₂ ⎥     (rows/columns 0..3)
///        ⎢ β₂   ω₃   0   −ω₁ ⎥
///        ⎣ β₃  −ω₂   ω₁   0  ⎦
/// ```
/// i.e. `X = Σ β_a (E_{a0} − E_{0a}) + [ω]×` on the last three axes. On the frame
/// bundle of S³, `β` tilts `x/R` towards the `q_a` (translation, the horizontal
/// lift is `β = u/R`) and `ω` rotates `q₁, q₂, q₃` among themselves (vertical).
///
/// The same matrix acts as `X·x = a·x − x·b` with the pure quaternions
/// (vectors of ℝ³) `a = (ω + β)/2` (left, self-dual part for the orientation
/// `e₀e₁e₂e₃`) and `b = (ω − β)/2` (right, anti-self-dual part), see [`So4::left_right`]. Brackets split:
/// `[(a, b), (a', b')] = (2a×a', 2b×b')`, and `exp(X) x = p x q̄` with
/// `p = exp(a) = (cos|a|, sin|a| â)`, `q = exp(b)`. The rotation angles of `exp X`
/// are `|a| + |b|` and `||a| − |b||`, the eigenvalues of `ad_X` are
/// `0, ±2i|a|, ±2i|b|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct So4 {
    m: Matrix4<f64>,
}

/// Largest orthogonality defect accepted by [`So4::new`].
pub const SO4_TOLERANCE: f64 = 1e-9;

/// `p₀ + q₀` (with the sign of the pair chosen to make it ≥ 0) at or below
/// which [`So4::log`] reports that the logarithm is not unique: the sum is
/// `2cos((|a|+|b|)/2)·cos((|a|−|b|)/2)`, zero exactly when a rotation angle is π.
pub const SO4_LOG_CUT: f64 = 64.0 * f64::EPSILON;

// ---------------------------------------------------------------------------
// Quaternion helpers (scalar first, [w, x, y, z]).

type Q = [f64; 4];

#[inline]
fn qnorm(a: &Q) -> f64 {
    Vector4::new(a[0], a[1], a[2], a[3]).norm()
}

/// Exponential of the pure quaternion `v`: `(cos|v|, sin|v| v/|v|)`.
#[inline]
fn qexp(v: &Vector3<f64>) -> Q {
    let s = v.norm_squared();
    let c = sinc(s);
    [s.sqrt().cos(), c * v[0], c * v[1], c * v[2]]
}

/// Logarithm of the quaternion `p` (need not be exactly unit): the pure
/// quaternion `θ·v/|v|`, `θ = atan2(|v|, p₀) ∈ [0, π]`. Uses
/// `θ/|v| = 1/(|p|·sinc θ²)`, so no division by `|v|`. Not defined for `p₀ < 0`,
/// `v = 0` (caller excludes it).
#[inline]
fn qlog(p: &Q) -> Vector3<f64> {
    let v = Vector3::new(p[1], p[2], p[3]);
    let th = v.norm().atan2(p[0]);
    let k = 1.0 / (qnorm(p) * sinc(th * th));
    v * k
}

/// Matrix of `x ↦ p·x`.
#[inline]
fn lmat(p: &Q) -> Matrix4<f64> {
    Matrix4::new(
        p[0], -p[1], -p[2], -p[3], //
        p[1], p[0], -p[3], p[2], //
        p[2], p[3], p[0], -p[1], //
        p[3], -p[2], p[1], p[0],
    )
}

/// Matrix of `x ↦ x·c`.
#[inline]
fn rmat(c: &Q) -> Matrix4<f64> {
    Matrix4::new(
        c[0], -c[1], -c[2], -c[3], //
        c[1], c[0], c[3], -c[2], //
        c[2], -c[3], c[0], c[1], //
        c[3], c[2], -c[1], c[0],
    )
}

/// The rotation `x ↦ p·x·q̄` as a matrix (`p`, `q` unit).
#[inline]
fn pair_matrix(p: &Q, q: &Q) -> Matrix4<f64> {
    lmat(p) * rmat(&[q[0], -q[1], -q[2], -q[3]])
}

/// `e_a e_b = sign · e_c` for the quaternion basis `e₀ = 1, e₁, e₂, e₃`.
const fn basis_mul(a: usize, b: usize) -> (usize, f64) {
    if a == 0 {
        return (b, 1.0);
    }
    if b == 0 {
        return (a, 1.0);
    }
    if a == b {
        return (0, -1.0);
    }
    // a, b ∈ {1, 2, 3}, a ≠ b: e_a e_b = ε_abc e_c.
    let c = 6 - a - b;
    let cyclic = (a == 1 && b == 2) || (a == 2 && b == 3) || (a == 3 && b == 1);
    (c, if cyclic { 1.0 } else { -1.0 })
}

/// `ASSOC[m][n][j] = (i, s)` with `e_m·e_j·ē_n = s·e_i`: column `j` of the
/// signed permutation matrix `T^{mn}` of `x ↦ e_m x ē_n`. The 16 matrices
/// `T^{mn}` are an orthogonal basis of the 4×4 matrices (`⟨T, T'⟩ = 4δδ'`), and
/// `pair_matrix(p, q) = Σ p_m q_n T^{mn}`, so `p_m q_n = ¼⟨T^{mn}, R⟩`: the
/// associate matrix of Van Elfrinkhof.
const ASSOC: [[[(usize, f64); 4]; 4]; 4] = {
    let mut t = [[[(0usize, 0.0f64); 4]; 4]; 4];
    let mut m = 0;
    while m < 4 {
        let mut n = 0;
        while n < 4 {
            let mut j = 0;
            while j < 4 {
                let (c, s1) = basis_mul(m, j);
                let (d, s2) = basis_mul(c, n);
                let conj = if n == 0 { 1.0 } else { -1.0 };
                t[m][n][j] = (d, s1 * s2 * conj);
                j += 1;
            }
            n += 1;
        }
        m += 1;
    }
    t
};

/// The associate matrix `A_{mn} = ¼⟨T^{mn}, M⟩` (`= p_m q_n` for a rotation).
#[inline]
fn associate(mat: &Matrix4<f64>) -> Matrix4<f64> {
    let mut a = Matrix4::zeros();
    for (m, row) in ASSOC.iter().enumerate() {
        for (n, col) in row.iter().enumerate() {
            let mut s = 0.0;
            for (j, &(i, sign)) in col.iter().enumerate() {
                s += sign * mat[(i, j)];
            }
            a[(m, n)] = 0.25 * s;
        }
    }
    a
}

/// The unit pair `(p, q)` whose rotation is nearest to `mat` (the top singular
/// pair of the associate matrix, from its largest column and two power steps),
/// or `None` when `mat` is not finite or its associate matrix vanishes.
fn nearest_pair(mat: &Matrix4<f64>) -> Option<(Q, Q)> {
    if !mat.iter().all(|v| v.is_finite()) {
        return None;
    }
    let a = associate(mat);
    let mut best = 0;
    let mut best_norm = -1.0;
    for n in 0..4 {
        let c = a.column(n).norm_squared();
        if c > best_norm {
            best_norm = c;
            best = n;
        }
    }
    if best_norm <= 0.0 {
        return None;
    }
    let mut p: Vector4<f64> = a.column(best).into();
    p /= p.norm();
    let mut q = a.transpose() * p;
    q /= q.norm();
    p = a * q;
    p /= p.norm();
    q = a.transpose() * p;
    q /= q.norm();
    Some(([p[0], p[1], p[2], p[3]], [q[0], q[1], q[2], q[3]]))
}

/// `dexp` of one su(2) factor with bracket `[a, v] = 2a×v`.
#[inline]
fn dexp_factor(a: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let a2 = *a * 2.0;
    let s = a2.norm_squared();
    let adv = a2.cross(v);
    v + adv * cosc(s) + a2.cross(&adv) * sinc3(s)
}

/// `dexp⁻¹` of one su(2) factor with bracket `[a, v] = 2a×v`.
#[inline]
fn dexp_inv_factor(a: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let a2 = *a * 2.0;
    let s = a2.norm_squared();
    let adv = a2.cross(v);
    v - adv * 0.5 + a2.cross(&adv) * dexpinv(s)
}

impl So4 {
    /// The rotation with matrix `m`, validated: finite entries, `|mᵀm − I| ≤ 1e-9`
    /// and `det m > 0`. The stored matrix is the nearest rotation to `m` (it
    /// differs from `m` by at most the defect).
    pub fn new(m: Matrix4<f64>) -> Result<Self> {
        crate::error::finite("SO(4) matrix", m.iter())?;
        let orth = (m.transpose() * m - Matrix4::identity()).amax();
        if orth > SO4_TOLERANCE {
            return Err(Error::Constraint {
                field: "SO(4) matrix",
                constraint: "mᵀm = I",
                defect: orth,
                tolerance: SO4_TOLERANCE,
            });
        }
        let det = m.determinant();
        if det <= 0.0 {
            return Err(Error::Constraint {
                field: "SO(4) matrix",
                constraint: "det m = +1",
                defect: (det - 1.0).abs(),
                tolerance: SO4_TOLERANCE,
            });
        }
        Ok(So4 { m }.renormalize())
    }

    /// The element with matrix `m`, unchecked (the caller guarantees `m ∈ SO(4)`).
    #[inline]
    pub fn new_unchecked(m: Matrix4<f64>) -> Self {
        So4 { m }
    }

    /// The stored 4×4 matrix.
    #[inline]
    pub fn matrix(&self) -> &Matrix4<f64> {
        &self.m
    }

    /// The rotation `x ↦ p·x·q̄` (quaternions normalised first; both must be
    /// finite and non-zero).
    pub fn from_quaternions(p: &Quaternion<f64>, q: &Quaternion<f64>) -> Result<Self> {
        let pp = [p.w, p.i, p.j, p.k];
        let qq = [q.w, q.i, q.j, q.k];
        crate::error::finite("p", pp.iter())?;
        crate::error::finite("q", qq.iter())?;
        let (np, nq) = (qnorm(&pp), qnorm(&qq));
        for (field, n) in [("p", np), ("q", nq)] {
            if n == 0.0 {
                return Err(Error::Constraint { field, constraint: "quaternion ≠ 0", defect: 1.0, tolerance: 0.0 });
            }
        }
        let pp = pp.map(|v| v / np);
        let qq = qq.map(|v| v / nq);
        Ok(So4 { m: pair_matrix(&pp, &qq) })
    }

    /// The unit quaternions `(p, q)` with `R x = p·x·q̄`, the common sign chosen
    /// so that `p₀ + q₀ ≥ 0` (the sign of the principal logarithm). For a stored
    /// matrix slightly off SO(4) this is the pair of the nearest rotation.
    /// Fails only for a non-finite matrix.
    pub fn quaternions(&self) -> Result<(Quaternion<f64>, Quaternion<f64>)> {
        let (p, q) = self.signed_pair()?;
        Ok((Quaternion::new(p[0], p[1], p[2], p[3]), Quaternion::new(q[0], q[1], q[2], q[3])))
    }

    fn signed_pair(&self) -> Result<(Q, Q)> {
        let (mut p, mut q) = nearest_pair(&self.m)
            .ok_or(Error::NotFinite { field: "SO(4) matrix" })?;
        if p[0] + q[0] < 0.0 {
            p = p.map(|v| -v);
            q = q.map(|v| -v);
        }
        Ok((p, q))
    }

    /// The su(2) ⊕ su(2) components `(a, b) = ((ω + β)/2, (ω − β)/2)` of an
    /// algebra element: `X·x = a·x − x·b` (pure quaternions).
    #[inline]
    pub fn left_right(x: &So4Algebra) -> (Vector3<f64>, Vector3<f64>) {
        let beta = Vector3::new(x[0], x[1], x[2]);
        let omega = Vector3::new(x[3], x[4], x[5]);
        ((omega + beta) * 0.5, (omega - beta) * 0.5)
    }

    /// Inverse of [`Self::left_right`]: `β = a − b`, `ω = a + b`.
    #[inline]
    pub fn from_left_right(a: &Vector3<f64>, b: &Vector3<f64>) -> So4Algebra {
        let beta = a - b;
        let omega = a + b;
        So4Algebra::new(beta[0], beta[1], beta[2], omega[0], omega[1], omega[2])
    }

    /// The skew 4×4 matrix of an algebra element (module documentation).
    #[inline]
    pub fn hat(x: &So4Algebra) -> Matrix4<f64> {
        Matrix4::new(
            0.0, -x[0], -x[1], -x[2], //
            x[0], 0.0, -x[5], x[4], //
            x[1], x[5], 0.0, -x[3], //
            x[2], -x[4], x[3], 0.0,
        )
    }

    /// Coordinates of the skew part `(m − mᵀ)/2` of a 4×4 matrix.
    #[inline]
    pub fn vee(m: &Matrix4<f64>) -> So4Algebra {
        So4Algebra::new(
            0.5 * (m[(1, 0)] - m[(0, 1)]),
            0.5 * (m[(2, 0)] - m[(0, 2)]),
            0.5 * (m[(3, 0)] - m[(0, 3)]),
            0.5 * (m[(3, 2)] - m[(2, 3)]),
            0.5 * (m[(1, 3)] - m[(3, 1)]),
            0.5 * (m[(2, 1)] - m[(1, 2)]),
        )
    }
}

impl LieGroup for So4 {
    type Algebra = So4Algebra;
    const DOF: usize = 6;
    const NAME: &'static str = "SO(4)";

    #[inline]
    fn identity() -> Self {
        So4 { m: Matrix4::identity() }
    }

    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        So4 { m: self.m * rhs.m }
    }

    #[inline]
    fn inverse(&self) -> Self {
        So4 { m: self.m.transpose() }
    }

    /// Closed form: `exp(X) x = exp(a)·x·exp(−b)` with `(a, b)` = [`So4::left_right`].
    #[inline]
    fn exp(x: &So4Algebra) -> Self {
        let (a, b) = So4::left_right(x);
        So4 { m: pair_matrix(&qexp(&a), &qexp(&b)) }
    }

    /// Principal logarithm (rotation angles `|a| ± |b|` in `(−π, π)`), from the
    /// quaternion pair (associate matrix) and quaternion logarithms. Fails with
    /// [`Error::LogUndefined`] when a rotation angle is π to within round-off
    /// (`p₀ + q₀ ≤` [`SO4_LOG_CUT`]): there the logarithm is not unique.
    fn log(&self) -> Result<So4Algebra> {
        let (p, q) = self.signed_pair().map_err(|_| Error::LogUndefined {
            group: "SO(4)",
            reason: "element is not finite",
        })?;
        if p[0] + q[0] <= SO4_LOG_CUT {
            return Err(Error::LogUndefined {
                group: "SO(4)",
                reason: "a rotation angle equals π (p₀ + q₀ = 0): the logarithm is not unique",
            });
        }
        Ok(So4::from_left_right(&qlog(&p), &qlog(&q)))
    }

    #[inline]
    fn adjoint(&self, x: &So4Algebra) -> So4Algebra {
        So4::vee(&(self.m * So4::hat(x) * self.m.transpose()))
    }

    #[inline]
    fn bracket(x: &So4Algebra, y: &So4Algebra) -> So4Algebra {
        let (b1, w1) = (Vector3::new(x[0], x[1], x[2]), Vector3::new(x[3], x[4], x[5]));
        let (b2, w2) = (Vector3::new(y[0], y[1], y[2]), Vector3::new(y[3], y[4], y[5]));
        let beta = w1.cross(&b2) - w2.cross(&b1);
        let omega = w1.cross(&w2) + b1.cross(&b2);
        So4Algebra::new(beta[0], beta[1], beta[2], omega[0], omega[1], omega[2])
    }

    /// Closed form on each su(2) factor (`ad_a = [2a]×`, angle `φ = 2|a|`):
    /// `dexp = I + cosc(φ²) ad + sinc3(φ²) ad²`.
    fn dexp(x: &So4Algebra, v: &So4Algebra) -> So4Algebra {
        let (a, b) = So4::left_right(x);
        let (va, vb) = So4::left_right(v);
        So4::from_left_right(&dexp_factor(&a, &va), &dexp_factor(&b, &vb))
    }

    /// Closed form on each su(2) factor: `dexp⁻¹ = I − ½ad + dexpinv(φ²) ad²`,
    /// `φ = 2|a|`; singular when `|a|` or `|b|` reaches π.
    fn dexp_inv(x: &So4Algebra, v: &So4Algebra) -> So4Algebra {
        let (a, b) = So4::left_right(x);
        let (va, vb) = So4::left_right(v);
        So4::from_left_right(&dexp_inv_factor(&a, &va), &dexp_inv_factor(&b, &vb))
    }

    /// `c = (β₁, β₂, β₃, ω₁, ω₂, ω₃)`; missing entries are taken as 0.
    fn algebra_from_coords(c: &[f64]) -> So4Algebra {
        So4Algebra::from_fn(|i, _| c.get(i).copied().unwrap_or(0.0))
    }

    fn algebra_coords(x: &So4Algebra) -> Vec<f64> {
        x.as_slice().to_vec()
    }

    fn to_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_column_slice(4, 4, self.m.as_slice())
    }

    fn algebra_to_matrix(x: &So4Algebra) -> DMatrix<f64> {
        DMatrix::from_column_slice(4, 4, So4::hat(x).as_slice())
    }

    /// `max(max|mᵀm − I|, |det m − 1|)`.
    fn constraint_defect(&self) -> f64 {
        let orth = (self.m.transpose() * self.m - Matrix4::identity()).amax();
        orth.max((self.m.determinant() - 1.0).abs())
    }

    /// The nearest rotation (Frobenius norm), rebuilt from the unit quaternion
    /// pair: the top singular vectors of the associate matrix (exact to second
    /// order in the defect). Non-finite input is returned unchanged.
    fn renormalize(&self) -> Self {
        match nearest_pair(&self.m) {
            Some((p, q)) => So4 { m: pair_matrix(&p, &q) },
            None => *self,
        }
    }
}
