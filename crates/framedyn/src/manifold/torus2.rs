//! The torus of revolution T²(L, R) of the paper's §5.3: see [`Torus2`].

use nalgebra::{SMatrix, SVector};
use std::f64::consts::{PI, TAU};

use super::{Manifold, Tensor3, Tensor4};
use crate::error::{finite, positive};
use crate::{Error, Result};

/// Largest relative distance from the surface ([`Manifold::point_defect`])
/// accepted by [`Manifold::chart`] and the bundle constructors.
pub const TORUS_POINT_TOLERANCE: f64 = 1e-9;

/// The torus of revolution T²(L, R) of the paper's §5.3 ("Toroidal case",
/// LaTeX source from l.5221), with the induced metric of Euclidean ℝ³.
///
/// - `L` is the distance of the tube centre from the symmetry axis, `R` the tube
///   radius, `L > R > 0` (a ring torus; the paper's `T²(0, L, R)`).
/// - Chart: the global angles `(θ, φ)` of the paper (l.5240–5245): `θ` the
///   "around-tyre" angle measured from the outer equator, `φ` the "along-tyre"
///   angle about the `z` axis. Embedding
///   `x = ((L + R cos θ) cos φ, (L + R cos θ) sin φ, R sin θ)`.
/// - Metric (l.5263): `ds² = R² dθ² + ρ(θ)² dφ²`, `ρ(θ) = L + R cos θ` the
///   distance from the axis; `√|g| = R ρ` (l.5318).
/// - Christoffel symbols (l.5335–5339): `Γ^φ_{θφ} = Γ^φ_{φθ} = −R sin θ/ρ`,
///   `Γ^θ_{φφ} = (L/R + cos θ) sin θ = ρ sin θ / R`; all others vanish.
/// - Gaussian curvature `K = cos θ / (R ρ)`: positive on the outer half
///   `|θ| < π/2`, negative on the inner half, `∫K dA = 0` over the torus.
/// - Frame field (l.5345–5348): `E_θ = R⁻¹ ∂_θ`, `E_φ = ρ⁻¹ ∂_φ`, global and
///   orthonormal. With `Ê_θ = (−sin θ cos φ, −sin θ sin φ, cos θ)`,
///   `Ê_φ = (−sin φ, cos φ, 0)` its embedded vectors and `n = (cos θ cos φ,
///   cos θ sin φ, sin θ)` the outward normal, `Ê_θ × Ê_φ = −n`: the orientation
///   of `(E_θ, E_φ)` is the one whose normal points *into* the tube.
/// - Frame connection: `∇_{E_φ} E_θ = −(sin θ/ρ) E_φ`, `∇_{E_φ} E_φ = (sin θ/ρ) E_θ`,
///   `∇_{E_θ} E_B = 0`, i.e. `Γ^φ_{θφ} = −sin θ/ρ`, `Γ^θ_{φφ} = +sin θ/ρ`. Along a
///   curve the frame turns relative to itself by `Γ(E)(ẋ) = −sin θ φ̇ ε`
///   (`ε` the rotation generator `[[0, −1], [1, 0]]`), so the gyroscope angular
///   velocity relative to `(E_θ, E_φ)` is `ω = ψ̇ − sin θ φ̇`. The paper's
///   `ψ̇ + sin θ φ̇` (l.5362, l.5486) holds for the opposite frame ordering
///   `(E_φ, E_θ)` (SPEC §8); the dynamics are equivalent.
///
/// The geodesic distance has no closed form; [`Torus2::minimal_geodesic`]
/// computes it from Clairaut quadratures and geodesic shooting (see its
/// documentation for the method and accuracy), in the
/// [`geodesic`](super::geodesic) module with the
/// [`GeodesicDistance`](super::GeodesicDistance) implementation.
///
/// All lengths are in the units of `L` and `R`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torus2 {
    big_l: f64,
    small_r: f64,
}

/// Reduces an angle to `(−π, π]`.
pub(super) fn wrap_angle(a: f64) -> f64 {
    let r = (a + PI).rem_euclid(TAU) - PI;
    if r <= -PI {
        r + TAU
    } else {
        r
    }
}

impl Torus2 {
    /// Reduces an angle to `(−π, π]`, the range of the chart angles
    /// (`−π` maps to `π`).
    pub fn reduce_angle(a: f64) -> f64 {
        wrap_angle(a)
    }

    /// The torus with tube-centre distance `big_l` (`L`) and tube radius
    /// `small_r` (`R`). Errors: [`Error::InvalidParameter`] for `R` unless finite
    /// and `> 0`, for `L` unless finite and `> R`.
    ///
    /// ```
    /// use framedyn::manifold::Torus2;
    ///
    /// let t2 = Torus2::new(2.0, 0.7)?;
    /// assert_eq!((t2.big_l(), t2.small_r()), (2.0, 0.7));
    /// // L ≤ R would self-intersect: a typed error naming L.
    /// assert!(matches!(Torus2::new(0.5, 0.7), Err(framedyn::Error::InvalidParameter { field: "L", .. })));
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(big_l: f64, small_r: f64) -> Result<Self> {
        let small_r = positive("R", small_r)?;
        if !(big_l.is_finite() && big_l > small_r) {
            return Err(Error::InvalidParameter {
                field: "L",
                value: big_l,
                allowed: "finite and > R (the tube radius)",
            });
        }
        Ok(Torus2 { big_l, small_r })
    }

    /// `L`, the distance of the tube centre from the axis.
    pub fn big_l(&self) -> f64 {
        self.big_l
    }

    /// `R`, the tube radius.
    pub fn small_r(&self) -> f64 {
        self.small_r
    }

    /// `ρ(θ) = L + R cos θ`, the distance from the symmetry axis.
    #[inline]
    pub fn rho(&self, theta: f64) -> f64 {
        self.big_l + self.small_r * theta.cos()
    }

    /// Gaussian curvature `K(θ) = cos θ / (R (L + R cos θ))`.
    #[inline]
    pub fn gaussian_curvature(&self, theta: f64) -> f64 {
        theta.cos() / (self.small_r * self.rho(theta))
    }

    /// Unit vectors `(Ê_θ, Ê_φ, n)` in ℝ³ at the chart point: the embedded frame
    /// field and the outward normal.
    fn unit_vectors(theta: f64, phi: f64) -> (SVector<f64, 3>, SVector<f64, 3>, SVector<f64, 3>) {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        (
            SVector::<f64, 3>::new(-st * cp, -st * sp, ct),
            SVector::<f64, 3>::new(-sp, cp, 0.0),
            SVector::<f64, 3>::new(ct * cp, ct * sp, st),
        )
    }

    /// Outward unit normal of the torus at the point of the torus nearest to
    /// `p`, with the nearest point of the tube-centre circle (defaults where
    /// these are not unique: on the axis, or on the centre circle).
    fn normal_at(&self, p: &SVector<f64, 3>) -> (SVector<f64, 3>, SVector<f64, 3>) {
        let rxy = p[0].hypot(p[1]);
        let (ux, uy) = if rxy > 0.0 { (p[0] / rxy, p[1] / rxy) } else { (1.0, 0.0) };
        let c = SVector::<f64, 3>::new(self.big_l * ux, self.big_l * uy, 0.0);
        let d = p - c;
        let dn = d.norm();
        let n = if dn > 0.0 { d / dn } else { SVector::<f64, 3>::new(ux, uy, 0.0) };
        (n, c)
    }
}

impl Manifold<2, 3> for Torus2 {
    const NAME: &'static str = "T2";

    fn coordinate_names(&self) -> [&'static str; 2] {
        ["theta", "phi"]
    }

    fn coordinate_units(&self) -> [&'static str; 2] {
        ["rad", "rad"]
    }

    /// The angles are global: every finite chart point is regular.
    fn check_chart(&self, x: &SVector<f64, 2>) -> Result<()> {
        if x.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Error::OutsideChart { manifold: "T2", reason: "the angles (theta, phi) must be finite" })
        }
    }

    /// `diag(R², (L + R cos θ)²)`.
    fn metric(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        let rho = self.rho(x[0]);
        SMatrix::<f64, 2, 2>::new(self.small_r * self.small_r, 0.0, 0.0, rho * rho)
    }

    /// `Γ^θ_{φφ} = ρ sin θ / R`, `Γ^φ_{θφ} = Γ^φ_{φθ} = −R sin θ / ρ` (paper l.5335).
    fn christoffel(&self, x: &SVector<f64, 2>) -> Tensor3<2> {
        let s = x[0].sin();
        let rho = self.rho(x[0]);
        let r = self.small_r;
        let mut g = [[[0.0; 2]; 2]; 2];
        g[0][1][1] = rho * s / r;
        g[1][0][1] = -r * s / rho;
        g[1][1][0] = -r * s / rho;
        g
    }

    /// `R^θ_{φθφ} = −R^θ_{φφθ} = K ρ² = ρ cos θ / R`,
    /// `R^φ_{θφθ} = −R^φ_{θθφ} = K R² = R cos θ / ρ`, all others zero.
    fn riemann(&self, x: &SVector<f64, 2>) -> Tensor4<2> {
        let c = x[0].cos();
        let rho = self.rho(x[0]);
        let r = self.small_r;
        let mut t = [[[[0.0; 2]; 2]; 2]; 2];
        t[0][1][0][1] = rho * c / r;
        t[0][1][1][0] = -rho * c / r;
        t[1][0][1][0] = r * c / rho;
        t[1][0][0][1] = -r * c / rho;
        t
    }

    /// Columns `E_θ = (1/R, 0)`, `E_φ = (0, 1/ρ)` (paper l.5345).
    fn frame(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(1.0 / self.small_r, 0.0, 0.0, 1.0 / self.rho(x[0]))
    }

    /// `Γ^θ_{φφ} = sin θ/ρ`, `Γ^φ_{θφ} = −sin θ/ρ` (index order `[A][B][C]`,
    /// `∇_{E_C} E_B = Γ^A_{BC} E_A`); all others zero.
    fn frame_connection(&self, x: &SVector<f64, 2>) -> Tensor3<2> {
        let k = x[0].sin() / self.rho(x[0]);
        let mut g = [[[0.0; 2]; 2]; 2];
        g[0][1][1] = k;
        g[1][0][1] = -k;
        g
    }

    fn ambient_metric(&self) -> SMatrix<f64, 3, 3> {
        SMatrix::identity()
    }

    /// `((L + R cos θ) cos φ, (L + R cos θ) sin φ, R sin θ)` (paper l.5240).
    fn embed(&self, x: &SVector<f64, 2>) -> SVector<f64, 3> {
        let (st, ct) = x[0].sin_cos();
        let (sp, cp) = x[1].sin_cos();
        let rho = self.big_l + self.small_r * ct;
        SVector::<f64, 3>::new(rho * cp, rho * sp, self.small_r * st)
    }

    /// `v^θ ∂_θ + v^φ ∂_φ = R v^θ Ê_θ + ρ v^φ Ê_φ`.
    fn embed_tangent(&self, x: &SVector<f64, 2>, v: &SVector<f64, 2>) -> SVector<f64, 3> {
        let (et, ep, _) = Self::unit_vectors(x[0], x[1]);
        et * (self.small_r * v[0]) + ep * (self.rho(x[0]) * v[1])
    }

    /// `θ = atan2(z, √(x² + y²) − L)`, `φ = atan2(y, x)`, both in `(−π, π]`.
    /// Errors: [`Error::NotFinite`], or [`Error::Constraint`] if the point is
    /// farther than [`TORUS_POINT_TOLERANCE`] (relative to `R`) from the torus.
    fn chart(&self, p: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        finite("p", p.iter())?;
        let defect = self.point_defect(p);
        if defect > TORUS_POINT_TOLERANCE {
            return Err(Error::Constraint {
                field: "p",
                constraint: "on the torus: (sqrt(x^2 + y^2) - L)^2 + z^2 = R^2",
                defect,
                tolerance: TORUS_POINT_TOLERANCE,
            });
        }
        let rxy = p[0].hypot(p[1]);
        let theta = wrap_angle(p[2].atan2(rxy - self.big_l));
        let phi = wrap_angle(p[1].atan2(p[0]));
        Ok(SVector::<f64, 2>::new(theta, phi))
    }

    /// `(w·Ê_θ / R, w·Ê_φ / ρ)`: the chart components of the tangential part of
    /// `w` (a normal component is ignored). Errors as for [`Manifold::chart`].
    fn chart_tangent(&self, p: &SVector<f64, 3>, w: &SVector<f64, 3>) -> Result<SVector<f64, 2>> {
        let x = self.chart(p)?;
        finite("w", w.iter())?;
        let (et, ep, _) = Self::unit_vectors(x[0], x[1]);
        Ok(SVector::<f64, 2>::new(w.dot(&et) / self.small_r, w.dot(&ep) / self.rho(x[0])))
    }

    /// `|dist(p, C) − R| / R`, `C` the tube-centre circle: the Euclidean
    /// distance of `p` from the torus relative to the tube radius.
    fn point_defect(&self, p: &SVector<f64, 3>) -> f64 {
        let dc = (p[0].hypot(p[1]) - self.big_l).hypot(p[2]);
        (dc - self.small_r).abs() / self.small_r
    }

    /// `c + R (p − c)/|p − c|`, `c` the nearest point of the tube-centre circle.
    fn project_point(&self, p: &SVector<f64, 3>) -> SVector<f64, 3> {
        let (n, c) = self.normal_at(p);
        c + n * self.small_r
    }

    /// `w − (n·w) n`, `n` the outward normal at the nearest point of the torus.
    fn project_tangent(&self, p: &SVector<f64, 3>, w: &SVector<f64, 3>) -> SVector<f64, 3> {
        let (n, _) = self.normal_at(p);
        w - n * n.dot(w)
    }
}
