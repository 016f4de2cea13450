//! Parametrisations of the internal configuration `φ` (the body frame relative
//! to the paper's frame field, `e = E(x)·φ`), generic over the scalar.

use nalgebra::{SMatrix, SVector};
use num_dual::Dual;
use std::f64::consts::TAU;
use std::fmt::Debug;

use super::series;
use crate::error::finite;
use crate::potential::Scalar;
use crate::{Error, Result};

/// Largest defect `‖φᵀφ − 1‖` accepted by the `coordinates` of rigid
/// (orthogonal) parametrisations.
pub const ORTHOGONALITY_TOLERANCE: f64 = 1e-9;

/// A parametrisation `ξ ∈ ℝ^K ↦ φ(ξ)` of (part of) the fibre of the frame
/// bundle: `φ ∈ SO(N)` for a gyroscope ([`Fibre::RIGID`]), `φ ∈ GL⁺(N)` for
/// an affine body. The body frame is `e_A = E_B φ^B_A` (§4: `e = E·φ`).
pub trait Fibre<const N: usize, const K: usize>: Clone + Debug + Send + Sync {
    /// Name, e.g. `"SO(2) angle"`.
    const NAME: &'static str;
    /// True if `φ(ξ)` is always orthogonal (a gyroscope's fibre).
    const RIGID: bool;

    /// Names of the internal coordinates, e.g. `["psi"]`.
    fn coordinate_names(&self) -> [&'static str; K];
    /// `Ok` where the parametrisation is defined, else a typed error naming
    /// the offending coordinate.
    fn check(&self, xi: &SVector<f64, K>) -> Result<()>;
    /// The matrix `φ(ξ)`.
    fn matrix<D: Scalar>(&self, xi: &SVector<D, K>) -> SMatrix<D, N, N>;
    /// Coordinates `ξ` of the matrix `φ` (one branch where several exist);
    /// fails with a typed error where `φ` is not in the image or the
    /// parametrisation is singular.
    fn coordinates(&self, phi: &SMatrix<f64, N, N>) -> Result<SVector<f64, K>>;

    /// `φ(ξ)` and its rate `φ̇ = Σ_k ∂φ/∂ξ^k ξ̇^k`, exactly, by one evaluation
    /// with nested dual numbers.
    fn matrix_and_rate<D: Scalar>(&self, xi: &SVector<D, K>, xi_dot: &SVector<D, K>) -> (SMatrix<D, N, N>, SMatrix<D, N, N>) {
        let xd = SVector::<Dual<D>, K>::from_fn(|k, _| Dual::new(xi[k], xi_dot[k]));
        let m = self.matrix(&xd);
        (m.map(|v| v.re), m.map(|v| v.eps))
    }
}

fn rot2<D: Scalar>(a: D) -> SMatrix<D, 2, 2> {
    let (s, c) = a.sin_cos();
    SMatrix::<D, 2, 2>::new(c, -s, s, c)
}

fn orthogonality_defect<const N: usize>(phi: &SMatrix<f64, N, N>) -> f64 {
    let d = (phi.transpose() * phi - SMatrix::<f64, N, N>::identity()).amax();
    if d.is_finite() {
        d
    } else {
        f64::INFINITY
    }
}

fn check_rotation<const N: usize>(phi: &SMatrix<f64, N, N>) -> Result<()> {
    finite("phi", phi.iter())?;
    let d = orthogonality_defect(phi);
    if d > ORTHOGONALITY_TOLERANCE || nalgebra::DMatrix::from_column_slice(N, N, phi.as_slice()).determinant() <= 0.0 {
        return Err(Error::Constraint {
            field: "phi",
            constraint: "φ ∈ SO(n): φᵀφ = 1, det φ = +1",
            defect: if d > ORTHOGONALITY_TOLERANCE { d } else { f64::INFINITY },
            tolerance: ORTHOGONALITY_TOLERANCE,
        });
    }
    Ok(())
}

fn check_det_positive(phi: &SMatrix<f64, 2, 2>) -> Result<f64> {
    finite("phi", phi.iter())?;
    let det = phi.determinant();
    if det > 0.0 {
        Ok(det)
    } else {
        Err(Error::Constraint { field: "phi", constraint: "det φ > 0 (φ ∈ GL⁺(2))", defect: -det, tolerance: 0.0 })
    }
}

/// A planar rotation `φ = U(ψ) = [[cos ψ, −sin ψ], [sin ψ, cos ψ]]`: the
/// internal angle of a two-dimensional gyroscope (§5.1, before (a91)).
/// Global (any finite `ψ`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PlaneRotation;

impl Fibre<2, 1> for PlaneRotation {
    const NAME: &'static str = "SO(2) angle";
    const RIGID: bool = true;

    fn coordinate_names(&self) -> [&'static str; 1] {
        ["psi"]
    }
    /// `Ok` iff `ψ` is finite.
    fn check(&self, xi: &SVector<f64, 1>) -> Result<()> {
        finite("psi", xi.iter())
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 1>) -> SMatrix<D, 2, 2> {
        rot2(xi[0])
    }
    /// `ψ = atan2(φ₂₁, φ₁₁) ∈ (−π, π]`; fails unless `φ ∈ SO(2)` to
    /// [`ORTHOGONALITY_TOLERANCE`].
    fn coordinates(&self, phi: &SMatrix<f64, 2, 2>) -> Result<SVector<f64, 1>> {
        check_rotation(phi)?;
        Ok(SVector::<f64, 1>::new(phi[(1, 0)].atan2(phi[(0, 0)])))
    }
}

/// A rotation `φ = exp([κ]×) ∈ SO(3)` by its rotation vector `κ ∈ ℝ³`
/// (the paper's canonical coordinates of the first kind, §6, (a172)):
/// `φ = 1 + (sin θ/θ)[κ]× + ((1 − cos θ)/θ²)[κ]×²`, `θ = |κ|`, with series
/// near `θ = 0`. Regular (a local diffeomorphism) for
/// `|κ| < 2π −` [`RotationVector::MARGIN`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RotationVector;

impl RotationVector {
    /// Distance from `|κ| = 2π` (where `d exp` is singular) inside which
    /// [`Fibre::check`] rejects `κ`.
    pub const MARGIN: f64 = 1e-6;
}

impl Fibre<3, 3> for RotationVector {
    const NAME: &'static str = "SO(3) rotation vector";
    const RIGID: bool = true;

    fn coordinate_names(&self) -> [&'static str; 3] {
        ["kappa1", "kappa2", "kappa3"]
    }
    /// `Ok` iff `κ` is finite and `|κ| < 2π − 1e-6`.
    fn check(&self, xi: &SVector<f64, 3>) -> Result<()> {
        finite("kappa", xi.iter())?;
        let n = xi.norm();
        if n >= TAU - Self::MARGIN {
            return Err(Error::InvalidParameter {
                field: "|kappa|",
                value: n,
                allowed: "< 2π − 1e-6 (the rotation-vector chart of SO(3) is singular at |κ| = 2π)",
            });
        }
        Ok(())
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let s = xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2];
        let z = D::from(0.0);
        let k = SMatrix::<D, 3, 3>::new(z, -xi[2], xi[1], xi[2], z, -xi[0], -xi[1], xi[0], z);
        SMatrix::identity() + k * series::sinc(s) + k * k * series::versc(s)
    }
    /// The principal rotation vector (`|κ| ≤ π`) from the unit quaternion of
    /// `φ` (Shepperd's method, accurate at every angle); fails unless
    /// `φ ∈ SO(3)` to [`ORTHOGONALITY_TOLERANCE`].
    fn coordinates(&self, phi: &SMatrix<f64, 3, 3>) -> Result<SVector<f64, 3>> {
        check_rotation(phi)?;
        let m = phi;
        let tr = m.trace();
        let diag = [m[(0, 0)], m[(1, 1)], m[(2, 2)]];
        let (w, v) = if tr >= diag[0] && tr >= diag[1] && tr >= diag[2] {
            let w = 0.5 * (1.0 + tr).sqrt();
            let f = 0.25 / w;
            (w, SVector::<f64, 3>::new((m[(2, 1)] - m[(1, 2)]) * f, (m[(0, 2)] - m[(2, 0)]) * f, (m[(1, 0)] - m[(0, 1)]) * f))
        } else {
            let i = if diag[0] >= diag[1] && diag[0] >= diag[2] {
                0
            } else if diag[1] >= diag[2] {
                1
            } else {
                2
            };
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let vi = 0.5 * (1.0 + m[(i, i)] - m[(j, j)] - m[(k, k)]).sqrt();
            let f = 0.25 / vi;
            let mut v = SVector::<f64, 3>::zeros();
            v[i] = vi;
            v[j] = (m[(j, i)] + m[(i, j)]) * f;
            v[k] = (m[(k, i)] + m[(i, k)]) * f;
            ((m[(k, j)] - m[(j, k)]) * f, v)
        };
        let (w, v) = if w < 0.0 { (-w, -v) } else { (w, v) };
        // κ = θ v/|v| with θ = 2 atan2(|v|, w), i.e. 2v/sinc(θ/2).
        let half = v.norm().atan2(w);
        Ok(v * (2.0 / series::sinc(half * half)))
    }
}

/// A general frame `φ ∈ GL⁺(2)` by its four entries, row by row:
/// `ξ = (φ₁₁, φ₁₂, φ₂₁, φ₂₂)`, `φ = [[ξ₁, ξ₂], [ξ₃, ξ₄]]`. Global on
/// `det φ > 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GlEntries;

impl Fibre<2, 4> for GlEntries {
    const NAME: &'static str = "GL+(2) entries";
    const RIGID: bool = false;

    fn coordinate_names(&self) -> [&'static str; 4] {
        ["phi11", "phi12", "phi21", "phi22"]
    }
    /// `Ok` iff the entries are finite and `det φ > 0`.
    fn check(&self, xi: &SVector<f64, 4>) -> Result<()> {
        check_det_positive(&self.matrix(xi)).map(|_| ())
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 4>) -> SMatrix<D, 2, 2> {
        SMatrix::<D, 2, 2>::new(xi[0], xi[1], xi[2], xi[3])
    }
    /// The entries of `φ`; fails unless `det φ > 0`.
    fn coordinates(&self, phi: &SMatrix<f64, 2, 2>) -> Result<SVector<f64, 4>> {
        check_det_positive(phi)?;
        Ok(SVector::<f64, 4>::new(phi[(0, 0)], phi[(0, 1)], phi[(1, 0)], phi[(1, 1)]))
    }
}

/// The paper's two-polar decomposition (§4, §5.1 after (a84)):
/// `φ = L(α) D(λ, μ) R(β)⁻¹`, `L`, `R` planar rotations,
/// `D = diag(λ, μ)`, `ξ = (α, β, λ, μ)`, `λ, μ > 0`.
///
/// Not a global chart: it is singular where `λ = μ` (there only `α − β` is
/// defined, and the mass matrix of any Lagrangian is singular), and
/// `(α, β, λ, μ)`, `(α + π/2, β + π/2, μ, λ)`, `(α + π, β + π, λ, μ)` give the
/// same `φ`. For doubly isotropic bodies (`J = I·1`) `α`, `β` are cyclic and
/// `p_α` (spin), `p_β` (vorticity) are conserved (SPEC §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TwoPolar;

impl Fibre<2, 4> for TwoPolar {
    const NAME: &'static str = "GL+(2) two-polar";
    const RIGID: bool = false;

    fn coordinate_names(&self) -> [&'static str; 4] {
        ["alpha", "beta", "lambda", "mu"]
    }
    /// `Ok` iff all four are finite and `λ, μ > 0`.
    fn check(&self, xi: &SVector<f64, 4>) -> Result<()> {
        finite("xi = (alpha, beta, lambda, mu)", xi.iter())?;
        for (field, v) in [("lambda", xi[2]), ("mu", xi[3])] {
            if v <= 0.0 {
                return Err(Error::InvalidParameter { field, value: v, allowed: "> 0 (principal stretch)" });
            }
        }
        Ok(())
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 4>) -> SMatrix<D, 2, 2> {
        let z = D::from(0.0);
        rot2(xi[0]) * SMatrix::<D, 2, 2>::new(xi[2], z, z, xi[3]) * rot2(-xi[1])
    }
    /// The branch with `λ > μ`: writing `φ = Q·U(α − β) + P·S(α + β)` with
    /// `U` a rotation and `S(a) = [[cos a, sin a], [sin a, −cos a]]` a
    /// reflection, `λ = Q + P`, `μ = Q − P`. Fails unless `det φ > 0`, and
    /// with [`Error::OutsideChart`] where `λ = μ` (to 1e-12 relative).
    fn coordinates(&self, phi: &SMatrix<f64, 2, 2>) -> Result<SVector<f64, 4>> {
        check_det_positive(phi)?;
        let (a, b, c, d) = (phi[(0, 0)], phi[(0, 1)], phi[(1, 0)], phi[(1, 1)]);
        let (e, f, g, h) = ((a + d) / 2.0, (a - d) / 2.0, (c + b) / 2.0, (c - b) / 2.0);
        let q = e.hypot(h);
        let p = f.hypot(g);
        if p <= 1e-12 * q {
            return Err(Error::OutsideChart {
                manifold: "GL+(2) two-polar",
                reason: "λ = μ: the two-polar angles α and β are not separately defined",
            });
        }
        let (rot, refl) = (h.atan2(e), g.atan2(f));
        Ok(SVector::<f64, 4>::new((refl + rot) / 2.0, (refl - rot) / 2.0, q + p, q - p))
    }
}

/// The polar decomposition `φ = U(ψ) A`, `A = [[ξ, η], [η, ζ]]` symmetric
/// positive definite (§5.1, the affine body after (a109)): `ξ = (ψ, ξ, η, ζ)`.
/// A global chart of GL⁺(2) (for `A` positive definite).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PolarDecomposition;

impl Fibre<2, 4> for PolarDecomposition {
    const NAME: &'static str = "GL+(2) polar";
    const RIGID: bool = false;

    fn coordinate_names(&self) -> [&'static str; 4] {
        ["psi", "xi", "eta", "zeta"]
    }
    /// `Ok` iff all four are finite and `A` is positive definite
    /// (`ξ > 0`, `ξζ − η² > 0`).
    fn check(&self, xi: &SVector<f64, 4>) -> Result<()> {
        finite("xi = (psi, xi, eta, zeta)", xi.iter())?;
        let det = xi[1] * xi[3] - xi[2] * xi[2];
        if xi[1] <= 0.0 || det <= 0.0 {
            return Err(Error::Constraint {
                field: "A = [[xi, eta], [eta, zeta]]",
                constraint: "A positive definite: ξ > 0 and ξζ − η² > 0",
                defect: if xi[1] <= 0.0 { -xi[1] } else { -det },
                tolerance: 0.0,
            });
        }
        Ok(())
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 4>) -> SMatrix<D, 2, 2> {
        rot2(xi[0]) * SMatrix::<D, 2, 2>::new(xi[1], xi[2], xi[2], xi[3])
    }
    /// `A = √(φᵀφ)` (closed form `(G + √det G·1)/√(tr G + 2√det G)`),
    /// `U = φA⁻¹`, `ψ = atan2(U₂₁, U₁₁)`; fails unless `det φ > 0`.
    fn coordinates(&self, phi: &SMatrix<f64, 2, 2>) -> Result<SVector<f64, 4>> {
        let det = check_det_positive(phi)?;
        let g = phi.transpose() * phi;
        let a = (g + SMatrix::<f64, 2, 2>::identity() * det) / (g.trace() + 2.0 * det).sqrt();
        let ai = a.try_inverse().ok_or(Error::Constraint {
            field: "phi",
            constraint: "det φ > 0 (φ ∈ GL⁺(2))",
            defect: 0.0,
            tolerance: 0.0,
        })?;
        let u = phi * ai;
        Ok(SVector::<f64, 4>::new(u[(1, 0)].atan2(u[(0, 0)]), a[(0, 0)], a[(0, 1)], a[(1, 1)]))
    }
}

fn check_stretch(field: &'static str, v: f64) -> Result<()> {
    if v > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter { field, value: v, allowed: "> 0 (principal stretch)" })
    }
}

/// The two-polar decomposition restricted to SL(2), the incompressible body
/// of §4 (`det φ = λμ = 1`): `φ = L(α)·diag(λ, 1/λ)·R(β)⁻¹`,
/// `ξ = (α, β, λ)`, `λ > 0`. The holonomic constraint is imposed on the
/// Lagrangian itself, so [`FrameLagrangian`](super::FrameLagrangian) with
/// this fibre gives the projected equations of the incompressible body
/// independently of the frame-bundle form. Singular where `λ = 1` (the
/// branch of [`TwoPolar`]: `λ > 1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TwoPolarSl;

impl Fibre<2, 3> for TwoPolarSl {
    const NAME: &'static str = "SL(2) two-polar";
    const RIGID: bool = false;

    fn coordinate_names(&self) -> [&'static str; 3] {
        ["alpha", "beta", "lambda"]
    }
    /// `Ok` iff all three are finite and `λ > 0`.
    fn check(&self, xi: &SVector<f64, 3>) -> Result<()> {
        finite("xi = (alpha, beta, lambda)", xi.iter())?;
        check_stretch("lambda", xi[2])
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 3>) -> SMatrix<D, 2, 2> {
        let z = D::from(0.0);
        rot2(xi[0]) * SMatrix::<D, 2, 2>::new(xi[2], z, z, xi[2].recip()) * rot2(-xi[1])
    }
    /// `(α, β, λ)` of [`TwoPolar::coordinates`]; fails as it does, and with
    /// [`Error::Constraint`] (field `"phi"`) unless `det φ = 1` to 1e-9.
    fn coordinates(&self, phi: &SMatrix<f64, 2, 2>) -> Result<SVector<f64, 3>> {
        let c = TwoPolar.coordinates(phi)?;
        let d = (c[2] * c[3] - 1.0).abs();
        if d > ORTHOGONALITY_TOLERANCE {
            return Err(Error::Constraint { field: "phi", constraint: "det φ = 1 (φ ∈ SL(2))", defect: d, tolerance: ORTHOGONALITY_TOLERANCE });
        }
        Ok(SVector::<f64, 3>::new(c[0], c[1], c[2]))
    }
}

/// The two-polar decomposition restricted to CO⁺(2), the Weyl body of §4
/// (rotations and dilatations, `λ = μ`): `φ = λ·U(α)`, `ξ = (α, λ)`,
/// `λ > 0` (`β` drops out). A global chart of CO⁺(2) up to `α mod 2π`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TwoPolarWeyl;

impl Fibre<2, 2> for TwoPolarWeyl {
    const NAME: &'static str = "CO+(2) polar";
    const RIGID: bool = false;

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["alpha", "lambda"]
    }
    /// `Ok` iff both are finite and `λ > 0`.
    fn check(&self, xi: &SVector<f64, 2>) -> Result<()> {
        finite("xi = (alpha, lambda)", xi.iter())?;
        check_stretch("lambda", xi[1])
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        rot2(xi[0]) * xi[1]
    }
    /// `λ = √det φ`, `α = atan2(φ₂₁, φ₁₁)`; fails unless `det φ > 0` and
    /// `φ/λ ∈ SO(2)` to [`ORTHOGONALITY_TOLERANCE`] (field `"phi"`).
    fn coordinates(&self, phi: &SMatrix<f64, 2, 2>) -> Result<SVector<f64, 2>> {
        let l = check_det_positive(phi)?.sqrt();
        check_rotation(&(phi / l))?;
        Ok(SVector::<f64, 2>::new(phi[(1, 0)].atan2(phi[(0, 0)]), l))
    }
}

/// A general frame `φ ∈ GL⁺(3)` by its nine entries, row by row (the affine
/// body on S³, §6): `ξ = (φ₁₁, φ₁₂, φ₁₃, φ₂₁, …, φ₃₃)`. Global on `det φ > 0`.
impl Fibre<3, 9> for GlEntries {
    const NAME: &'static str = "GL+(3) entries";
    const RIGID: bool = false;

    fn coordinate_names(&self) -> [&'static str; 9] {
        ["phi11", "phi12", "phi13", "phi21", "phi22", "phi23", "phi31", "phi32", "phi33"]
    }
    /// `Ok` iff the entries are finite and `det φ > 0`.
    fn check(&self, xi: &SVector<f64, 9>) -> Result<()> {
        check_det3_positive(&self.matrix(xi)).map(|_| ())
    }
    fn matrix<D: Scalar>(&self, xi: &SVector<D, 9>) -> SMatrix<D, 3, 3> {
        SMatrix::<D, 3, 3>::from_fn(|i, j| xi[3 * i + j])
    }
    /// The entries of `φ`; fails unless `det φ > 0`.
    fn coordinates(&self, phi: &SMatrix<f64, 3, 3>) -> Result<SVector<f64, 9>> {
        check_det3_positive(phi)?;
        Ok(SVector::<f64, 9>::from_fn(|k, _| phi[(k / 3, k % 3)]))
    }
}

fn check_det3_positive(phi: &SMatrix<f64, 3, 3>) -> Result<f64> {
    finite("phi", phi.iter())?;
    let det = phi.determinant();
    if det > 0.0 {
        Ok(det)
    } else {
        Err(Error::Constraint { field: "phi", constraint: "det φ > 0 (φ ∈ GL⁺(3))", defect: -det, tolerance: 0.0 })
    }
}
