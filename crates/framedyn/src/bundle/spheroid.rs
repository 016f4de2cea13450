//! The orthonormal frame bundle of the spheroid as SO(3), through its Gauss
//! map: see the `FrameBundle` implementation of [`Spheroid`].

use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector2, Vector3};

use super::FrameBundle;
use crate::error::finite;
use crate::lie::{LieGroup, So3};
use crate::manifold::{Manifold, Spheroid};
use crate::{Error, Result};

/// The group that stores a frame of the spheroid: `Q = [n | q₁ | q₂] ∈ SO(3)`
/// (see the `FrameBundle` implementation of [`Spheroid`]).
pub type SpheroidFrame = So3;

/// Tolerance of the checks in [`FrameBundle::from_frame`] and
/// [`FrameBundle::from_chart`] (tangency, orthonormality, orientation).
pub const SPHEROID_FRAME_TOLERANCE: f64 = 1e-9;

fn constraint(field: &'static str, constraint: &'static str, defect: f64) -> Error {
    Error::Constraint { field, constraint, defect, tolerance: SPHEROID_FRAME_TOLERANCE }
}

/// Checks that the 2×2 matrix `u` is a rotation (orthogonal, det = +1).
fn check_rotation2(u: &Matrix2<f64>) -> Result<()> {
    finite("u", u.iter())?;
    let orth = (u.transpose() * u - Matrix2::identity()).amax();
    if orth > SPHEROID_FRAME_TOLERANCE {
        return Err(constraint("u", "u orthogonal, uᵀu = I", orth));
    }
    let det = u.determinant();
    if det <= 0.0 {
        return Err(constraint("u", "det u = +1 (positively oriented frame)", (det - 1.0).abs()));
    }
    Ok(())
}

impl Spheroid {
    /// `W² = n_x² + n_y² + k² n_z²` for the unit normal `n`: `a²W² = nᵀD⁻¹n`.
    #[inline]
    fn w2_of_normal(&self, n: &Vector3<f64>) -> f64 {
        n[0] * n[0] + n[1] * n[1] + self.axis_ratio_squared() * n[2] * n[2]
    }

    /// The shape operator applied to `u`, both in the frame `(q₁, q₂)` of `Q`:
    /// `S u = (W/a)(u + (k⁻² − 1) q_z (q_z·u))`, `q_z = (Q₂₁, Q₂₂)` the `z`
    /// components of the frame vectors.
    #[inline]
    fn shape_operator_times(&self, q: &Matrix3<f64>, u: &Vector2<f64>) -> Vector2<f64> {
        let n = q.column(0).into_owned();
        let scale = self.w2_of_normal(&n).sqrt() / self.equatorial_radius();
        let qz = Vector2::new(q[(2, 1)], q[(2, 2)]);
        (u + qz * (self.inv_k2_minus_one() * qz.dot(u))) * scale
    }
}

/// The orthonormal frame bundle of the spheroid as SO(3), pole-safe like
/// S²'s: a bundle element is the rotation `Q = [n | q₁ | q₂]` with `n` the
/// outward unit normal at the point and `(q₁, q₂)` a positively oriented
/// orthonormal tangent frame, `q₁ × q₂ = n` (`det Q = +1`, the column order of
/// [`Sphere2`](crate::manifold::Sphere2)'s bundle).
///
/// **Position from the normal.** The spheroid is convex, so its Gauss map
/// `x ↦ n(x)` is a diffeomorphism onto S², with the inverse (derived in
/// [`Spheroid`]) `x(n) = (a²n_x, a²n_y, c²n_z)/√(a²(n_x² + n_y²) + c²n_z²)`
/// ([`Spheroid::point_with_normal`]). The position is therefore stored
/// implicitly in the first column of `Q`: it is on the surface to round-off
/// for every rotation `Q` (`x(n)ᵀD x(n) = 1` identically), and for `a = c = R`
/// it is S²'s `x = R n`.
///
/// **Horizontal lift.** Let the point move with `ẋ = u₁q₁ + u₂q₂` and the
/// frame be parallel-transported. Write `Q̇ = Q h`, `h = QᵀQ̇ ∈ so(3)`.
/// - Normal column: the **Weingarten equation** `ṅ = S ẋ` with the shape
///   operator `S` of the outward normal. For the quadric `F(x) = xᵀDx − 1`,
///   `D = diag(a⁻², a⁻², c⁻²)`, the normal is `n = ∇F/|∇F|`, so
///   `ṅ = (I − nnᵀ) H ẋ / |∇F|` with `H = ∇²F = 2D`, `∇F = 2Dx`. In the frame,
///   `S_ab = q_aᵀ H q_b / |∇F| = q_aᵀ D q_b / |Dx|`, and `|Dx| = 1/√(nᵀD⁻¹n)
///   = 1/(aW)` with `W² = n_x² + n_y² + k² n_z²`, `k = c/a`. Since
///   `D = a⁻²(I + (k⁻² − 1) e_z e_zᵀ)` and `q_aᵀq_b = δ_ab`:
///
///   ```text
///   S = (W/a) (I + (k⁻² − 1) q_z q_zᵀ),      q_z = (q₁·e_z, q₂·e_z),
///   ```
///
///   symmetric and positive definite; `h_{b0} = q_b·ṅ = (S u)_b`.
/// - Frame columns: parallel transport means the tangential part of `q̇_a`
///   vanishes, `q_b·q̇_a = 0` (`h_{ba} = 0`: no rotation in the tangent block),
///   and differentiating `n·q_a = 0` gives `n·q̇_a = −ṅ·q_a = −(S u)_a`.
///
/// Hence, with `w = S u`,
///
/// ```text
/// h(u) = [[0, −w₁, −w₂], [w₁, 0, 0], [w₂, 0, 0]],   the so(3) vector (0, −w₂, w₁),
/// ```
///
/// and `q̇_a = −(S u)_a n = −II(ẋ, q_a) n`. For `a = c = R`, `W = 1` and
/// `S = I/R`: S²'s `h = (1/R)[[0, −u₁, −u₂], [u₁, 0, 0], [u₂, 0, 0]]`. The
/// point follows: `ẋ = (dx/dn) ṅ = S⁻¹ṅ = Σ u_a q_a`, because `dx/dn`
/// restricted to the tangent plane is the inverse of the Weingarten map.
/// Nothing here is singular: `W² ≥ min(1, k²) > 0` for every unit `n`, the
/// poles included.
///
/// **Gaussian curvature.** `K = det S` (Gauss). In the frame
/// `(ê_east, ê_north)` the two vectors have `q_z = (0, cos φ)`, so
/// `S = (W/a) diag(1, 1 + (k⁻² − 1) cos²φ) = diag(W/a, W³/(a k²)) = diag(1/N, 1/M)`
/// and `K = W⁴/(a²k²) = W⁴/c² = 1/(M N)`, as in [`Spheroid`]. In terms of the
/// normal only: `K = (n_x² + n_y² + k² n_z²)²/c²`.
///
/// **Vertical generator.** `q̇ = q w`, `w = [[0, −ω], [ω, 0]]`, is
/// `Q̇ = Q·hat(ω, 0, 0)`, the so(3) vector `(ω, 0, 0)` (as on S²).
///
/// **Velocities of any generator** ([`FrameBundle::frame_velocity`]).
/// `Q̇ = Q hat(ξ)` gives `ṅ` and `q̇` (its columns); the position follows by
/// differentiating `x(n) = a B n/√(nᵀBn)`, `B = diag(1, 1, k²)`:
///
/// ```text
/// ẋ = (a/W) (B ṅ − B n (nᵀ B ṅ)/W²),      W² = nᵀ B n.
/// ```
///
/// **Charts.** `from_chart(x, U)` has `q = E(x)·U` with `E = (ê_east, ê_north)`;
/// `to_chart` reads the latitude and longitude from the normal,
/// `φ = atan2(n_z, √(n_x² + n_y²))`, `λ = atan2(n_y, n_x)`, and fails within
/// [`Spheroid::POLE_TOLERANCE`] of a pole.
impl FrameBundle<2, 3> for Spheroid {
    type Group = So3;

    /// `Q = [n(p) | q₁ | q₂]` with `n(p)` = [`Spheroid::normal_at`], projected
    /// to the nearest rotation. Fails (tolerance 1e-9) unless `p` and `q` are
    /// finite, `p` is on the spheroid ([`Spheroid::POINT_TOLERANCE`]), `q₁, q₂`
    /// are tangent (`|n·q_a| ≤ 1e-9`), orthonormal (`max|qᵀq − I| ≤ 1e-9`) and
    /// positively oriented (`(q₁ × q₂)·n > 0`). Errors name `"p"` or `"q"`.
    fn from_frame(&self, p: &Vector3<f64>, q: &Matrix3x2<f64>) -> Result<So3> {
        self.check_point("p", p)?;
        finite("q", q.iter())?;
        let n = self.normal_at(p);
        let (q1, q2): (Vector3<f64>, Vector3<f64>) = (q.column(0).into(), q.column(1).into());
        let tangent = n.dot(&q1).abs().max(n.dot(&q2).abs());
        if tangent > SPHEROID_FRAME_TOLERANCE {
            return Err(constraint("q", "frame vectors tangent to the spheroid, n·q_a = 0", tangent));
        }
        let orth = (q.transpose() * q - Matrix2::identity()).amax();
        if orth > SPHEROID_FRAME_TOLERANCE {
            return Err(constraint("q", "frame orthonormal, qᵀq = I", orth));
        }
        let det = q1.cross(&q2).dot(&n);
        if det <= 0.0 {
            return Err(constraint("q", "frame positively oriented, q₁ × q₂ = n", (det - 1.0).abs()));
        }
        Ok(So3::new_unchecked(Matrix3::from_columns(&[n, q1, q2])).renormalize())
    }

    /// `Q = [n(x) | E(x)·u]`; fails outside the chart (see
    /// [`Manifold::check_chart`]) or unless `u` is a rotation (tolerance 1e-9,
    /// field `"u"`).
    fn from_chart(&self, x: &Vector2<f64>, u: &Matrix2<f64>) -> Result<So3> {
        self.check_chart(x)?;
        check_rotation2(u)?;
        let n = self.normal(x);
        let q = self.ambient_frame(x) * u;
        Ok(So3::new_unchecked(Matrix3::from_columns(&[n, q.column(0).into(), q.column(1).into()])).renormalize())
    }

    /// `x(n)` = [`Spheroid::point_with_normal`] of the first column.
    #[inline]
    fn position(&self, g: &So3) -> Vector3<f64> {
        self.point_with_normal(&g.matrix().column(0).into_owned())
    }

    /// Columns 2 and 3 of `Q`.
    #[inline]
    fn frame_vectors(&self, g: &So3) -> Matrix3x2<f64> {
        g.matrix().fixed_columns::<2>(1).into()
    }

    /// `x = (atan2(n_z, √(n_x² + n_y²)), atan2(n_y, n_x))`, `u = E(x)ᵀ q`.
    /// Fails with [`Error::OutsideChart`] where `√(n_x² + n_y²) ≤`
    /// [`Spheroid::POLE_TOLERANCE`] (and as [`Manifold::check_chart`]), with
    /// [`Error::NotFinite`] for a non-finite `Q`.
    fn to_chart(&self, g: &So3) -> Result<(Vector2<f64>, Matrix2<f64>)> {
        finite("g", g.matrix().iter())?;
        let n: Vector3<f64> = g.matrix().column(0).into();
        let rho = n[0].hypot(n[1]);
        if rho <= Spheroid::POLE_TOLERANCE * n.norm() {
            return Err(Error::OutsideChart {
                manifold: <Spheroid as Manifold<2, 3>>::NAME,
                reason: "normal within POLE_TOLERANCE of the polar axis, where the longitude is undefined",
            });
        }
        let x = Vector2::new(n[2].atan2(rho), n[1].atan2(n[0]));
        self.check_chart(&x)?;
        let u = self.ambient_frame(&x).transpose() * self.frame_vectors(g);
        Ok((x, u))
    }

    /// The so(3) vector `(0, −(Su)₂, (Su)₁)`, `S = (W/a)(I + (k⁻² − 1) q_z q_zᵀ)`.
    #[inline]
    fn horizontal_lift(&self, g: &So3, u: &Vector2<f64>) -> Vector3<f64> {
        let w = self.shape_operator_times(g.matrix(), u);
        Vector3::new(0.0, -w[1], w[0])
    }

    /// The so(3) vector `(ω, 0, 0)`, `ω = (w₂₁ − w₁₂)/2` (the skew part of `w`).
    #[inline]
    fn vertical(&self, _g: &So3, w: &Matrix2<f64>) -> Vector3<f64> {
        Vector3::new(0.5 * (w[(1, 0)] - w[(0, 1)]), 0.0, 0.0)
    }

    /// [`So3`]'s `constraint_defect` (orthonormality and determinant of `Q`).
    #[inline]
    fn bundle_defect(&self, g: &So3) -> f64 {
        g.constraint_defect()
    }

    /// `Q̇ = Q·hat(ξ)`: `q̇` its columns 2, 3; `ẋ = (a/W)(Bṅ − Bn(nᵀBṅ)/W²)` from
    /// its first column `ṅ` (see the type docs).
    #[inline]
    fn frame_velocity(&self, g: &So3, xi: &Vector3<f64>) -> (Vector3<f64>, Matrix3x2<f64>) {
        let q = g.matrix();
        let qdot = q * So3::hat(xi);
        let n: Vector3<f64> = q.column(0).into();
        let ndot: Vector3<f64> = qdot.column(0).into();
        let k2 = self.axis_ratio_squared();
        let bn = Vector3::new(n[0], n[1], k2 * n[2]);
        let bndot = Vector3::new(ndot[0], ndot[1], k2 * ndot[2]);
        let w2 = self.w2_of_normal(&n);
        let xdot = (bndot - bn * (bn.dot(&ndot) / w2)) * (self.equatorial_radius() / w2.sqrt());
        (xdot, qdot.fixed_columns::<2>(1).into_owned())
    }

    /// `K = (n_x² + n_y² + k² n_z²)²/c² = W⁴/c² = 1/(M N)`.
    #[inline]
    fn curvature_at(&self, g: &So3) -> f64 {
        let w2 = self.w2_of_normal(&g.matrix().column(0).into_owned());
        let kc = w2 / self.polar_radius();
        kc * kc
    }

    /// The derivative of `(0, −w₂, w₁)`, `w = (W/a)(u + (k⁻² − 1) q_z (q_z·u))`,
    /// along `δQ = Q·hat(η)`: `δ(W/a) = δW²/(2aW)`,
    /// `δW² = 2(n_x δn_x + n_y δn_y + k² n_z δn_z)`.
    fn lift_derivative(&self, g: &So3, u: &Vector2<f64>, eta: &Vector3<f64>) -> Vector3<f64> {
        let q = g.matrix();
        let dq = q * So3::hat(eta);
        let n: Vector3<f64> = q.column(0).into();
        let dn: Vector3<f64> = dq.column(0).into();
        let w2 = self.w2_of_normal(&n);
        let w = w2.sqrt();
        let dw2 = 2.0 * (n[0] * dn[0] + n[1] * dn[1] + self.axis_ratio_squared() * n[2] * dn[2]);
        let a = self.equatorial_radius();
        let (scale, dscale) = (w / a, dw2 / (2.0 * a * w));
        let kappa = self.inv_k2_minus_one();
        let qz = Vector2::new(q[(2, 1)], q[(2, 2)]);
        let dqz = Vector2::new(dq[(2, 1)], dq[(2, 2)]);
        let base = u + qz * (kappa * qz.dot(u));
        let dw = base * dscale + (dqz * qz.dot(u) + qz * dqz.dot(u)) * (kappa * scale);
        Vector3::new(0.0, -dw[1], dw[0])
    }

    /// `δK = 2W² δW²/c²` along `δQ = Q·hat(η)`.
    fn curvature_derivative(&self, g: &So3, eta: &Vector3<f64>) -> f64 {
        let q = g.matrix();
        let n: Vector3<f64> = q.column(0).into();
        let dn: Vector3<f64> = (q * So3::hat(eta)).column(0).into();
        let w2 = self.w2_of_normal(&n);
        let dw2 = 2.0 * (n[0] * dn[0] + n[1] * dn[1] + self.axis_ratio_squared() * n[2] * dn[2]);
        let c = self.polar_radius();
        2.0 * w2 * dw2 / (c * c)
    }

    /// The derivative of [`frame_velocity`](FrameBundle::frame_velocity)
    /// along `δQ = Q·hat(η)`: `δQ̇ = Q·hat(η)·hat(ξ)`, and the derivative of
    /// `ẋ = (a/W)(Bṅ − Bn (nᵀBṅ)/W²)` in `n` and `ṅ`.
    fn frame_velocity_derivative(&self, g: &So3, xi: &Vector3<f64>, eta: &Vector3<f64>) -> (Vector3<f64>, Matrix3x2<f64>) {
        let q = g.matrix();
        let qdot = q * So3::hat(xi);
        let dq = q * So3::hat(eta);
        let dqdot = dq * So3::hat(xi);
        let k2 = self.axis_ratio_squared();
        let b = |v: Vector3<f64>| Vector3::new(v[0], v[1], k2 * v[2]);
        let n: Vector3<f64> = q.column(0).into();
        let ndot: Vector3<f64> = qdot.column(0).into();
        let dn: Vector3<f64> = dq.column(0).into();
        let dndot: Vector3<f64> = dqdot.column(0).into();
        let (bn, bndot) = (b(n), b(ndot));
        let w2 = self.w2_of_normal(&n);
        let dw2 = 2.0 * bn.dot(&dn);
        let p = bn.dot(&ndot);
        let dp = b(dn).dot(&ndot) + bn.dot(&dndot);
        let v = bndot - bn * (p / w2);
        let dv = b(dndot) - b(dn) * (p / w2) - bn * (dp / w2 - p * dw2 / (w2 * w2));
        let a = self.equatorial_radius();
        let c0 = a / w2.sqrt();
        let dc0 = -c0 * dw2 / (2.0 * w2);
        (v * dc0 + dv * c0, dqdot.fixed_columns::<2>(1).into_owned())
    }
}
