//! The tangent lift of a system: the trajectory and one tangent vector,
//! integrated together on the tangent group.

use super::split::{NoSplit, SplitDispatch};
use super::System;
use crate::lie::{AlgebraVector, LieGroup, ProductAlgebra, Tangent, TangentAlgebra};

/// The tangent lift of `S`: states `(y, ξ)` of the [`Tangent`] group (a
/// perturbation `δy = y·ξ`), moving by
///
/// ```text
/// ẏ = y·f(t, y),      ξ̇ = Df(t, y)[ξ] + [ξ, f(t, y)]
/// ```
///
/// — the variational equation in the left trivialisation (from
/// `d/dt (y·exp(sξ)) = y·exp(sξ)·f(t, y·exp(sξ))` at first order in `s`),
/// which is `ẏ = y·f` over dual numbers: the tangent group's vector field is
/// `(f, Df[ξ])`. A Lie-group method stepping this system returns the exact
/// derivative of its own one-step map along `ξ₀` (see [`crate::lie::tangent`]).
///
/// Built only for a system whose [`System::tangent_field`] exists
/// ([`Linearised::new`]); energy and defect are those of `y`.
#[derive(Debug, Clone, Copy)]
pub struct Linearised<'a, S> {
    system: &'a S,
}

impl<'a, S: System> Linearised<'a, S> {
    /// The tangent lift of `system`, if it has an exact derivative
    /// ([`System::tangent_field`] answers at `(t, y)`).
    pub fn new(system: &'a S, t: f64, y: &S::State) -> Option<Self> {
        system.tangent_field(t, y, &<S::State as LieGroup>::Algebra::zero()).map(|_| Linearised { system })
    }

    /// The tangent lift of `system` without asking whether it has an exact
    /// derivative (a system without one makes every step fail as non-finite).
    pub fn unchecked(system: &'a S) -> Self {
        Linearised { system }
    }

    /// The system.
    pub fn system(&self) -> &'a S {
        self.system
    }
}

impl<S: System> System for Linearised<'_, S> {
    type State = Tangent<S::State>;

    /// `(f, Df[ξ])`; every component NaN if the system stops answering (a
    /// step then fails as non-finite rather than returning a wrong tangent).
    #[inline]
    fn vector_field(&self, t: f64, y: &Self::State) -> TangentAlgebra<<S::State as LieGroup>::Algebra> {
        match self.system.tangent_field(t, &y.0, &y.1) {
            Some((f, df)) => ProductAlgebra(f, df),
            None => {
                let mut a = <TangentAlgebra<<S::State as LieGroup>::Algebra> as AlgebraVector>::zero();
                for i in 0..<TangentAlgebra<<S::State as LieGroup>::Algebra> as AlgebraVector>::LEN {
                    a.set(i, f64::NAN);
                }
                a
            }
        }
    }

    fn energy(&self, y: &Self::State) -> f64 {
        self.system.energy(&y.0)
    }

    fn defect(&self, y: &Self::State) -> f64 {
        if y.1.is_finite() {
            self.system.defect(&y.0)
        } else {
            f64::NAN
        }
    }
}

/// No splitting: the splittings' exact free flows are not lifted (their
/// tangent maps are differenced).
impl<S: System> SplitDispatch for Linearised<'_, S> {
    type Split = NoSplit<Tangent<S::State>>;
    fn as_splittable(&self) -> Option<&Self::Split> {
        None
    }
}
