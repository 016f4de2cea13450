//! CO⁺(n), the Weyl (conformal) group: dilatations × rotations, the
//! "rotations + dilatations" constraint of the affinely-rigid body (paper §4).

use nalgebra::{DMatrix, SMatrix};

use super::matrix::{commutator, det, dexp_inv_matrix, dexp_matrix, skew_index, skew_part, Basis};
use super::son::{so_defect, so_exp, so_log};
use super::{LieGroup, SoN};
use crate::{Error, Result};

type Mat<const N: usize> = SMatrix<f64, N, N>;

/// The Weyl group CO⁺(n) = ℝ₊ × SO(n): matrices `λR`, `λ > 0`, `R ∈ SO(n)`.
///
/// Stored as `(ln λ, R)`, so that dilatations never overflow and compose
/// exactly additively.
///
/// - **Algebra** co(n) = ℝ·I ⊕ so(n): matrices `κI + ω`, `ω` skew, stored as
///   `SMatrix<f64, N, N>`; `DOF = 1 + n(n−1)/2`. Coordinates: `κ` first, then
///   the so(n) coordinates of `ω` as in [`SoN`] (`ω_ij`, `i < j`
///   lexicographic). Functions taking an algebra element use its projection
///   `κ = tr(a)/n` (the common diagonal value when the diagonal is constant),
///   `ω = (a − aᵀ)/2`; the symmetric traceless part is ignored.
/// - Because `κI` is central: `exp(κI + ω) = e^κ exp(ω)`,
///   `log(λR) = ln λ·I + log R`, `[κI + ω, κ'I + ω'] = [ω, ω']`,
///   `Ad_{λR}(κI + ω) = κI + RωRᵀ`, `dexp_{κI+ω}(κ'I + ω') = κ'I + dexp_ω ω'`,
///   and likewise for `dexp⁻¹`, with the so(n) functions of [`SoN`].
/// - `renormalize`: polar factor of `R`; `constraint_defect` = that of `R`
///   (`+∞` if `ln λ` is not finite).
///
/// Matrix representation: `λR`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Co<const N: usize> {
    ln_lambda: f64,
    rot: SoN<N>,
}

/// CO⁺(2) (≅ ℂ∖{0} as a multiplicative group).
pub type Co2 = Co<2>;
/// CO⁺(3).
pub type Co3 = Co<3>;

const fn co_name(n: usize) -> &'static str {
    match n {
        1 => "CO+(1)",
        2 => "CO+(2)",
        3 => "CO+(3)",
        4 => "CO+(4)",
        5 => "CO+(5)",
        _ => "CO+(n)",
    }
}

/// `(κ, ω)` of an algebra matrix: κ = common diagonal value (exact) or
/// `tr/n`; `ω` its skew part.
fn split<const N: usize>(a: &Mat<N>) -> (f64, Mat<N>) {
    let d0 = a[(0, 0)];
    let kappa = if (1..N).all(|i| a[(i, i)] == d0) {
        d0
    } else {
        a.trace() / N as f64
    };
    (kappa, skew_part(a))
}

/// `κI + ω`.
fn join<const N: usize>(kappa: f64, w: &Mat<N>) -> Mat<N> {
    let mut a = *w;
    for i in 0..N {
        a[(i, i)] += kappa;
    }
    a
}

impl<const N: usize> Co<N> {
    /// `λR` from the dilatation `λ` (finite and > 0, [`Error::InvalidParameter`]
    /// field `"lambda"`) and a rotation matrix validated as by [`SoN::new`].
    pub fn new(lambda: f64, rotation: SMatrix<f64, N, N>) -> Result<Self> {
        let lambda = crate::error::positive("lambda", lambda)?;
        Ok(Co {
            ln_lambda: lambda.ln(),
            rot: SoN::new(rotation)?,
        })
    }

    /// Splits a matrix `m = λR`: `λ = det(m)^{1/n}` (finite, `det m > 0`,
    /// else [`Error::InvalidParameter`] field `"det(matrix)"`), `R = m/λ`
    /// validated as by [`SoN::new`] ([`Error::Constraint`] field `"rotation"`
    /// if `m` is not conformal to within [`SO_TOLERANCE`](super::SO_TOLERANCE)).
    pub fn from_matrix(m: SMatrix<f64, N, N>) -> Result<Self> {
        crate::error::finite("matrix", m.iter())?;
        let d = det(&m);
        if !(d > 0.0 && d.is_finite()) {
            return Err(Error::InvalidParameter {
                field: "det(matrix)",
                value: d,
                allowed: "finite and > 0",
            });
        }
        let ln_lambda = d.ln() / N as f64;
        Ok(Co {
            ln_lambda,
            rot: SoN::new(m * (-ln_lambda).exp())?,
        })
    }

    /// From `ln λ` and a rotation, without checks.
    #[inline]
    pub fn from_parts(ln_lambda: f64, rotation: SoN<N>) -> Self {
        Co {
            ln_lambda,
            rot: rotation,
        }
    }

    /// The dilatation factor `λ`.
    #[inline]
    pub fn lambda(&self) -> f64 {
        self.ln_lambda.exp()
    }

    /// `ln λ`.
    #[inline]
    pub fn ln_lambda(&self) -> f64 {
        self.ln_lambda
    }

    /// The rotation `R`.
    #[inline]
    pub fn rotation(&self) -> &SoN<N> {
        &self.rot
    }

    /// The matrix `λR`.
    pub fn matrix(&self) -> SMatrix<f64, N, N> {
        self.rot.matrix() * self.lambda()
    }
}

impl<const N: usize> LieGroup for Co<N> {
    type Algebra = SMatrix<f64, N, N>;
    const DOF: usize = 1 + N * (N - 1) / 2;
    const NAME: &'static str = co_name(N);

    #[inline]
    fn identity() -> Self {
        Co {
            ln_lambda: 0.0,
            rot: SoN::identity(),
        }
    }
    #[inline]
    fn compose(&self, rhs: &Self) -> Self {
        Co {
            ln_lambda: self.ln_lambda + rhs.ln_lambda,
            rot: self.rot.compose(&rhs.rot),
        }
    }
    #[inline]
    fn inverse(&self) -> Self {
        Co {
            ln_lambda: -self.ln_lambda,
            rot: self.rot.inverse(),
        }
    }
    fn exp(a: &Self::Algebra) -> Self {
        let (kappa, w) = split(a);
        Co {
            ln_lambda: kappa,
            rot: SoN::new_unchecked(so_exp(&w)),
        }
    }
    fn log(&self) -> Result<Self::Algebra> {
        if !self.ln_lambda.is_finite() {
            return Err(Error::NotFinite { field: "ln_lambda" });
        }
        Ok(join(self.ln_lambda, &so_log(self.rot.matrix(), Self::NAME)?))
    }
    fn adjoint(&self, a: &Self::Algebra) -> Self::Algebra {
        let (kappa, w) = split(a);
        join(kappa, &self.rot.adjoint(&w))
    }
    #[inline]
    fn bracket(a: &Self::Algebra, b: &Self::Algebra) -> Self::Algebra {
        skew_part(&commutator(&skew_part(a), &skew_part(b)))
    }
    fn dexp(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        let (_, w) = split(a);
        let (kv, wv) = split(v);
        join(kv, &skew_part(&dexp_matrix(&w, &wv, true)))
    }
    fn dexp_inv(a: &Self::Algebra, v: &Self::Algebra) -> Self::Algebra {
        let (_, w) = split(a);
        let (kv, wv) = split(v);
        join(kv, &skew_part(&dexp_inv_matrix(&w, &wv, Basis::Skew, true)))
    }
    /// `(κ, ω coordinates)`; missing coordinates are 0.
    fn algebra_from_coords(c: &[f64]) -> Self::Algebra {
        let at = |k: usize| c.get(k).copied().unwrap_or(0.0);
        let mut a = Mat::<N>::zeros();
        for k in 0..Self::DOF - 1 {
            let (i, j) = skew_index::<N>(k);
            a[(i, j)] = at(k + 1);
            a[(j, i)] = -at(k + 1);
        }
        join(at(0), &a)
    }
    fn algebra_coords(a: &Self::Algebra) -> Vec<f64> {
        let (kappa, w) = split(a);
        let mut c = Vec::with_capacity(Self::DOF);
        c.push(kappa);
        c.extend((0..Self::DOF - 1).map(|k| {
            let (i, j) = skew_index::<N>(k);
            w[(i, j)]
        }));
        c
    }
    fn to_matrix(&self) -> DMatrix<f64> {
        let m = self.matrix();
        DMatrix::from_column_slice(N, N, m.as_slice())
    }
    fn algebra_to_matrix(a: &Self::Algebra) -> DMatrix<f64> {
        let (kappa, w) = split(a);
        let m = join(kappa, &w);
        DMatrix::from_column_slice(N, N, m.as_slice())
    }
    /// The rotation's defect `max(max|RᵀR − I|, |det R − 1|)`; `+∞` if
    /// `ln λ` is not finite.
    fn constraint_defect(&self) -> f64 {
        if self.ln_lambda.is_finite() {
            so_defect(self.rot.matrix())
        } else {
            f64::INFINITY
        }
    }
    fn renormalize(&self) -> Self {
        Co {
            ln_lambda: self.ln_lambda,
            rot: self.rot.renormalize(),
        }
    }
}
