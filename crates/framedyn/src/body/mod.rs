//! Bodies: the parameters of the structured particles (paper §4, SPEC §1).
//!
//! | body | frame `e` | fibre | degrees of freedom |
//! |---|---|---|---|
//! | [`Point`] | none | — | `n` |
//! | [`Gyroscope`] | orthonormal, positively oriented | SO(n) | `n + n(n−1)/2` |
//! | [`Affine`] | any positively oriented frame | GL⁺(n) | `n + n²` |
//! | [`Incompressible`] | `det` fixed | SL(n) | `n + n² − 1` |
//! | [`Weyl`] | rotations and dilatations | CO⁺(n) | `n + n(n−1)/2 + 1` |
//! | [`Dilatation`] | pure dilatations of a fixed frame | ℝ⁺ | `n + 1` |
//!
//! Kinetic energy (a52): `T = (m/2) g(ẋ, ẋ) + ½ g(De_A/Dt, De_B/Dt) J^{AB}`
//! with `m > 0` and `J` the symmetric positive-definite micromaterial inertia.
//! For a two-dimensional gyroscope only `I = Tr J` enters; the paper's n = 3
//! gyroscope of §6 has `J = (I/2)δ` (SPEC §7). The indefinite "Lorentz-type"
//! gyroscope of (a138) has the internal term with a minus sign
//! ([`Signature::Lorentz`]).

use nalgebra::SMatrix;

use crate::error::{finite, positive};
use crate::{Error, Result};

/// Relative tolerance of the symmetry check of `J`.
pub const INERTIA_SYMMETRY_TOL: f64 = 1e-12;

/// Checks that `j` is finite, symmetric (relative 1e-12) and positive definite.
pub fn check_inertia<const N: usize>(j: &SMatrix<f64, N, N>) -> Result<SMatrix<f64, N, N>> {
    finite("J", j.iter())?;
    let scale = j.amax().max(f64::MIN_POSITIVE);
    let asym = (j - j.transpose()).amax() / scale;
    if asym > INERTIA_SYMMETRY_TOL {
        return Err(Error::Constraint {
            field: "J",
            constraint: "J symmetric",
            defect: asym,
            tolerance: INERTIA_SYMMETRY_TOL,
        });
    }
    let sym = (j + j.transpose()) * 0.5;
    if sym.cholesky().is_none() {
        let min_eig = nalgebra::DMatrix::from_column_slice(N, N, sym.as_slice()).symmetric_eigenvalues().min();
        return Err(Error::Constraint {
            field: "J",
            constraint: "J positive definite (all eigenvalues > 0)",
            defect: -min_eig,
            tolerance: 0.0,
        });
    }
    Ok(sym)
}

/// A structureless material point of mass `m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    mass: f64,
}

impl Point {
    /// A point of mass `mass` (finite, > 0).
    ///
    /// ```
    /// use framedyn::body::Point;
    ///
    /// assert_eq!(Point::new(2.0)?.mass(), 2.0);
    /// assert!(matches!(Point::new(0.0), Err(framedyn::Error::InvalidParameter { field: "mass", .. })));
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(mass: f64) -> Result<Self> {
        Ok(Self { mass: positive("mass", mass)? })
    }
    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }
}

/// Sign of the internal kinetic energy of a gyroscope.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Signature {
    /// `T_int = +½ g(De_A/Dt, De_B/Dt) J^{AB}` (a52).
    #[default]
    Riemannian,
    /// The indefinite "Lorentz-type" energy of (a138): the internal term with
    /// a minus sign.
    Lorentz,
}

/// An infinitesimal gyroscope: mass `m`, inertia `J` (n×n, symmetric positive
/// definite), orthonormal frame (fibre SO(n)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gyroscope<const N: usize> {
    mass: f64,
    inertia: SMatrix<f64, N, N>,
    signature: Signature,
}

impl<const N: usize> Gyroscope<N> {
    /// A gyroscope of mass `mass` (finite, > 0) and inertia `inertia`
    /// (symmetric positive definite).
    ///
    /// ```
    /// use framedyn::body::Gyroscope;
    /// use nalgebra::Matrix3;
    ///
    /// // An anisotropic top for S³ (n = 3).
    /// let top = Gyroscope::<3>::new(1.0, Matrix3::from_diagonal(&[0.2, 0.35, 0.5].into()))?;
    /// assert_eq!(top.inertia()[(2, 2)], 0.5);
    /// // Not positive definite: a typed error naming J and the constraint.
    /// let err = Gyroscope::<3>::new(1.0, Matrix3::from_diagonal(&[0.2, -0.1, 0.5].into())).unwrap_err();
    /// assert!(matches!(err, framedyn::Error::Constraint { field: "J", .. }));
    /// # Ok::<(), framedyn::Error>(())
    /// ```
    pub fn new(mass: f64, inertia: SMatrix<f64, N, N>) -> Result<Self> {
        Ok(Self { mass: positive("mass", mass)?, inertia: check_inertia(&inertia)?, signature: Signature::Riemannian })
    }
    /// An isotropic gyroscope with `J = (I/2)δ`: for n = 2 its moment of
    /// inertia `Tr J` is `I`; for n = 3 `I` is the ordinary moment of inertia
    /// of §6 (SPEC §7).
    pub fn isotropic(mass: f64, moment: f64) -> Result<Self> {
        let i = positive("I", moment)?;
        Self::new(mass, SMatrix::identity() * (0.5 * i))
    }
    /// The same body with the indefinite internal energy of (a138).
    pub fn with_signature(mut self, signature: Signature) -> Self {
        self.signature = signature;
        self
    }
    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// The inertia `J^{AB}`.
    pub fn inertia(&self) -> &SMatrix<f64, N, N> {
        &self.inertia
    }
    /// `I = Tr J`, the moment of inertia of a two-dimensional gyroscope.
    pub fn trace_inertia(&self) -> f64 {
        self.inertia.trace()
    }
    /// The sign of the internal kinetic energy.
    pub fn signature(&self) -> Signature {
        self.signature
    }
}

macro_rules! affine_kind {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name<const N: usize> {
            mass: f64,
            inertia: SMatrix<f64, N, N>,
        }

        impl<const N: usize> $name<N> {
            /// A body of mass `mass` (finite, > 0) and inertia `inertia`
            /// (symmetric positive definite).
            pub fn new(mass: f64, inertia: SMatrix<f64, N, N>) -> Result<Self> {
                Ok(Self { mass: positive("mass", mass)?, inertia: check_inertia(&inertia)? })
            }
            /// A body with isotropic inertia `J = I·δ` (the §5 convention for
            /// affine bodies; its rigid limit has moment `2I` in 2-D, SPEC §7).
            pub fn isotropic(mass: f64, moment: f64) -> Result<Self> {
                let i = positive("I", moment)?;
                Self::new(mass, SMatrix::identity() * i)
            }
            /// The mass `m`.
            pub fn mass(&self) -> f64 {
                self.mass
            }
            /// The inertia `J^{AB}`.
            pub fn inertia(&self) -> &SMatrix<f64, N, N> {
                &self.inertia
            }
        }
    };
}

affine_kind!(
    /// An infinitesimal affinely-rigid body: any positively oriented frame
    /// (fibre GL⁺(n)).
    Affine
);
affine_kind!(
    /// An incompressible affine body: `det` of the frame (relative to an
    /// orthonormal one) fixed (fibre SL(n)), §4.
    Incompressible
);
affine_kind!(
    /// A Weyl body: rotations and dilatations only (fibre CO⁺(n)), §4.
    Weyl
);
affine_kind!(
    /// A purely dilatational body: the frame is `λ` times a frame parallel-
    /// transported along the path (fibre ℝ⁺), §4.
    Dilatation
);
