//! Building the model of a scene: the body on the manifold with its
//! potential and initial state, as a type-erased engine. Generic over the
//! frame bundle, so a new manifold reuses all of it (its entry in
//! [`manifolds`](super::manifolds) calls [`Scene::surface_engine`] or
//! [`Scene::space_engine`]).

use nalgebra::SMatrix;

use super::chart::{ChartRunner, ChartTwin};
use super::error::SceneError;
use super::initial::{init_error, Init};
use super::observe::Observe;
use super::potential::{vec_n, Potential2, Potential3};
use super::scene::Scene;
use super::simulation::{boxed, DynEngine};
use super::spec::*;
use crate::body::{Affine, Dilatation, Gyroscope, Incompressible, Point, Signature, Weyl};
use crate::bundle::FrameBundle;
use crate::coords::{AmbientBody, AmbientMap, ChartGeometry, FrameLagrangian, GlEntries, Lagrangian, PlaneRotation, PointLagrangian, RotationVector};
use crate::dynamics::affine::{AffineBodyModel, BodyState, Unconstrained};
use crate::dynamics::constrained::{Conformal, Isochoric, PureDilatation};
use crate::dynamics::{Gyroscope2Model, Gyroscope2State, Gyroscope3Model, Gyroscope3State, PointModel, PointState, System};
use crate::lie::{LieGroup, So2, So3};
use crate::solve::SolveError;

/// What a built model becomes: the simulation's engine ([`Engines`]), or
/// the typed model of the analyses (`super::analysis::Analyses`).
pub(crate) trait Make {
    /// The product.
    type Out;
    /// The product of `system` from `y0` over `span`, with its chart equations.
    fn make<S: Observe>(system: S, y0: S::State, span: (f64, f64), chart: Option<Box<dyn ChartTwin<S>>>) -> Result<Self::Out, SolveError>;
}

/// The engine of a [`Simulation`](super::Simulation).
pub(crate) struct Engines;

impl Make for Engines {
    type Out = Box<dyn DynEngine>;
    fn make<S: Observe>(system: S, y0: S::State, span: (f64, f64), chart: Option<Box<dyn ChartTwin<S>>>) -> Result<Self::Out, SolveError> {
        boxed(system, y0, span, chart)
    }
}

impl Scene {
    /// The engine of a body on the surface `m` (two frame vectors in ℝ³)
    /// with the potential `pot`: every body kind, generic over the bundle.
    ///
    /// `chart`: the manifold's chart geometry ([`coords`](crate::coords)),
    /// if it has one, for the coordinate methods (points, gyroscopes and
    /// affine bodies get their chart equations from it).
    pub(crate) fn surface_engine<K: Make, B, C>(&self, m: B, pot: Potential2, span: (f64, f64), chart: Option<C>) -> Result<K::Out, SceneError>
    where
        B: FrameBundle<2, 3> + Clone + Send + 'static,
        C: ChartGeometry<2, 3> + 'static,
        PointModel<B, Potential2, 2, 3>: Observe + System<State = PointState<B::Group, 2>>,
        Gyroscope2Model<B, Potential2>: Observe + System<State = Gyroscope2State<B::Group>>,
        AffineBodyModel<B, Potential2, Unconstrained, 2, 3>: Observe + System<State = BodyState<B, Unconstrained, 2, 3>>,
        AffineBodyModel<B, Potential2, Isochoric, 2, 3>: Observe + System<State = BodyState<B, Isochoric, 2, 3>>,
        AffineBodyModel<B, Potential2, Conformal, 2, 3>: Observe + System<State = BodyState<B, Conformal, 2, 3>>,
        AffineBodyModel<B, Potential2, PureDilatation<2>, 2, 3>: Observe + System<State = BodyState<B, PureDilatation<2>, 2, 3>>,
    {
        let init = Init::<B, 2, 3>::new(&m, &self.initial).map_err(|e| e.with_note(&self.manifold_note()))?;
        let b = &self.body;
        let run = |e: SolveError| SceneError::invalid("initial", "(state)", e.to_string());
        match b.kind {
            BodyKind::Point => {
                self.no_internal(&["alpha", "orientation", "spin", "omega", "frame", "rho", "rho_dot"])?;
                let body = Point::new(b.mass).map_err(|e| SceneError::from_core("body.mass", e))?;
                self.no_inertia()?;
                let twin = chart.map(|c| twin::<_, _, 2, 2, 3>(PointLagrangian::new(c, &body, pot.clone())));
                let model = PointModel::new(m.clone(), body, pot).map_err(|e| SceneError::from_core("potential", e))?;
                let y = model.state_from_parts(&init.g, &init.u).map_err(|e| self.state_error(e))?;
                K::make(model, y, span, twin).map_err(run)
            }
            BodyKind::Gyroscope => {
                self.no_internal(&["orientation", "rho", "rho_dot"])?;
                self.one_inertia()?;
                let mut body = match &b.j {
                    Some(j) => Gyroscope::<2>::new(b.mass, mat::<2>(j, "body.J")?),
                    None => Gyroscope::<2>::isotropic(b.mass, b.inertia.unwrap_or(1.0)),
                }
                .map_err(|e| self.body_error(e))?;
                if b.signature == Some(SignatureSpec::Lorentz) {
                    body = body.with_signature(Signature::Lorentz);
                }
                let twin = chart.map(|c| twin::<_, _, 3, 2, 3>(FrameLagrangian::<C, PlaneRotation, Potential2, 2, 3, 1, 3>::gyroscope(c, PlaneRotation, &body, pot.clone())));
                let model = Gyroscope2Model::new(m.clone(), body, pot).map_err(|e| self.body_error(e))?;
                let i = &self.initial;
                let spin = match (&i.spin, &i.omega) {
                    (Some(_), Some(_)) => return Err(SceneError::invalid("initial.omega", "(given with spin)", "give spin or omega, not both")),
                    (Some(s), None) => scalar(s, "initial.spin")?,
                    (None, Some(w)) => model.spin_for_angular_velocity(scalar(w, "initial.omega")?),
                    (None, None) => 0.0,
                };
                let y = if let Some(fr) = &i.frame {
                    if i.alpha.is_some() {
                        return Err(SceneError::invalid("initial.alpha", i.alpha.unwrap_or(0.0), "give frame or alpha, not both"));
                    }
                    let e = frame_matrix::<2, 3>(fr)?;
                    model.state(&init.p, &init.v, &e, spin).map_err(|e| self.state_error(e))?
                } else {
                    let alpha = i.alpha.unwrap_or(0.0);
                    if !alpha.is_finite() {
                        return Err(SceneError::invalid("initial.alpha", alpha, "must be finite"));
                    }
                    model.state_from_parts(&init.g, &So2::exp(&nalgebra::Vector1::new(alpha)), &init.u, spin).map_err(|e| self.state_error(e))?
                };
                K::make(model, y, span, twin).map_err(run)
            }
            _ => {
                let affine_chart = chart.map(|c| move |mass: f64, j: SMatrix<f64, 2, 2>, pot: Potential2| -> crate::Result<Box<dyn ChartTwin<AffineBodyModel<B, Potential2, Unconstrained, 2, 3>>>> {
                    Ok(twin::<_, _, 6, 2, 3>(FrameLagrangian::<C, GlEntries, Potential2, 2, 3, 4, 6>::new(c, GlEntries, mass, j, Signature::Riemannian, pot)?))
                });
                self.affine_engine::<K, B, 2, 3>(m, pot, &init, span, affine_chart)
            }
        }
    }

    /// The engine of a body on the three-manifold `m` (three frame vectors in
    /// ℝ⁴) with the potential `pot`: every body kind, generic over the bundle.
    pub(crate) fn space_engine<K: Make, B, C>(&self, m: B, pot: Potential3, span: (f64, f64), chart: Option<C>) -> Result<K::Out, SceneError>
    where
        B: FrameBundle<3, 4> + Clone + Send + 'static,
        C: ChartGeometry<3, 4> + 'static,
        PointModel<B, Potential3, 3, 4>: Observe + System<State = PointState<B::Group, 3>>,
        Gyroscope3Model<B, Potential3>: Observe + System<State = Gyroscope3State<B::Group>>,
        AffineBodyModel<B, Potential3, Unconstrained, 3, 4>: Observe + System<State = BodyState<B, Unconstrained, 3, 4>>,
        AffineBodyModel<B, Potential3, Isochoric, 3, 4>: Observe + System<State = BodyState<B, Isochoric, 3, 4>>,
        AffineBodyModel<B, Potential3, Conformal, 3, 4>: Observe + System<State = BodyState<B, Conformal, 3, 4>>,
        AffineBodyModel<B, Potential3, PureDilatation<3>, 3, 4>: Observe + System<State = BodyState<B, PureDilatation<3>, 3, 4>>,
    {
        let init = Init::<B, 3, 4>::new(&m, &self.initial).map_err(|e| e.with_note(&self.manifold_note()))?;
        let b = &self.body;
        let run = |e: SolveError| SceneError::invalid("initial", "(state)", e.to_string());
        match b.kind {
            BodyKind::Point => {
                self.no_internal(&["alpha", "orientation", "spin", "omega", "frame", "rho", "rho_dot"])?;
                self.no_inertia()?;
                let body = Point::new(b.mass).map_err(|e| SceneError::from_core("body.mass", e))?;
                let twin = chart.map(|c| twin::<_, _, 3, 3, 4>(PointLagrangian::new(c, &body, pot.clone())));
                let model = PointModel::new(m, body, pot).map_err(|e| SceneError::from_core("potential", e))?;
                let y = model.state_from_parts(&init.g, &init.u).map_err(|e| self.state_error(e))?;
                K::make(model, y, span, twin).map_err(run)
            }
            BodyKind::Gyroscope => {
                self.no_internal(&["alpha", "rho", "rho_dot"])?;
                self.one_inertia()?;
                if b.signature == Some(SignatureSpec::Lorentz) {
                    return Err(SceneError::invalid("body.signature", "\"lorentz\"", "the Lorentz-type gyroscope (a138) is defined on H2 and S2 surfaces; on S3 use riemannian"));
                }
                let body = match &b.j {
                    Some(j) => Gyroscope::<3>::new(b.mass, mat::<3>(j, "body.J")?),
                    None => Gyroscope::<3>::isotropic(b.mass, b.inertia.unwrap_or(1.0)),
                }
                .map_err(|e| self.body_error(e))?;
                let twin = chart.map(|c| twin::<_, _, 6, 3, 4>(FrameLagrangian::<C, RotationVector, Potential3, 3, 4, 3, 6>::gyroscope(c, RotationVector, &body, pot.clone())));
                let model = Gyroscope3Model::new(m, body, pot).map_err(|e| self.body_error(e))?;
                let i = &self.initial;
                let spin_e = match (&i.spin, &i.omega) {
                    (Some(_), Some(_)) => return Err(SceneError::invalid("initial.omega", "(given with spin)", "give spin or omega, not both")),
                    (Some(s), None) => vec3(&s.0, "initial.spin")?,
                    (None, Some(w)) => model.spin_for_angular_velocity(&vec3(&w.0, "initial.omega")?),
                    (None, None) => nalgebra::Vector3::zeros(),
                };
                let y = if let Some(fr) = &i.frame {
                    if i.orientation.is_some() {
                        return Err(SceneError::invalid("initial.orientation", "(given with frame)", "give frame or orientation, not both"));
                    }
                    let e = frame_matrix::<3, 4>(fr)?;
                    model.state(&init.p, &init.v, &e, &spin_e).map_err(|e| self.state_error(e))?
                } else {
                    let rv = match &i.orientation {
                        Some(o) => vec3(o, "initial.orientation")?,
                        None => nalgebra::Vector3::zeros(),
                    };
                    let rho = So3::exp(&rv);
                    model.state_from_parts(&init.g, &rho, &init.u, &(rho.matrix() * spin_e)).map_err(|e| self.state_error(e))?
                };
                K::make(model, y, span, twin).map_err(run)
            }
            _ => {
                let affine_chart = chart.map(|c| move |mass: f64, j: SMatrix<f64, 3, 3>, pot: Potential3| -> crate::Result<Box<dyn ChartTwin<AffineBodyModel<B, Potential3, Unconstrained, 3, 4>>>> {
                    Ok(twin::<_, _, 12, 3, 4>(FrameLagrangian::<C, GlEntries, Potential3, 3, 4, 9, 12>::new(c, GlEntries, mass, j, Signature::Riemannian, pot)?))
                });
                self.affine_engine::<K, B, 3, 4>(m, pot, &init, span, affine_chart)
            }
        }
    }

    /// The engine of an affine body (any constraint); `chart` builds the
    /// chart equations of the unconstrained body from its mass, inertia and
    /// potential (the constrained bodies have none here).
    fn affine_engine<K: Make, B, const N: usize, const E: usize>(
        &self,
        m: B,
        pot: <Self as PotFor<N, E>>::Pot,
        init: &Init<B, N, E>,
        span: (f64, f64),
        chart: Option<impl FnOnce(f64, SMatrix<f64, N, N>, <Self as PotFor<N, E>>::Pot) -> crate::Result<Box<dyn ChartTwin<AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Unconstrained, N, E>>>>>,
    ) -> Result<K::Out, SceneError>
    where
        Self: PotFor<N, E>,
        B: FrameBundle<N, E> + Clone + Send + 'static,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Unconstrained, N, E>: Observe + System<State = BodyState<B, Unconstrained, N, E>>,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Isochoric, N, E>: Observe + System<State = BodyState<B, Isochoric, N, E>>,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, Conformal, N, E>: Observe + System<State = BodyState<B, Conformal, N, E>>,
        AffineBodyModel<B, <Self as PotFor<N, E>>::Pot, PureDilatation<N>, N, E>: Observe + System<State = BodyState<B, PureDilatation<N>, N, E>>,
    {
        self.no_internal(&["alpha", "orientation", "spin", "omega", "frame"])?;
        self.one_inertia()?;
        let b = &self.body;
        if b.signature.is_some() {
            return Err(SceneError::invalid("body.signature", "(given)", "signature is for gyroscopes only"));
        }
        let j = match &b.j {
            Some(j) => mat::<N>(j, "body.J")?,
            None => {
                let i = b.inertia.unwrap_or(1.0);
                if !(i.is_finite() && i > 0.0) {
                    return Err(SceneError::invalid("body.inertia", i, "must be finite and > 0"));
                }
                SMatrix::<f64, N, N>::identity() * i
            }
        };
        let i = &self.initial;
        let rho = match &i.rho {
            Some(r) => mat::<N>(r, "initial.rho")?,
            None => SMatrix::identity(),
        };
        let rho_dot = match &i.rho_dot {
            Some(r) => mat::<N>(r, "initial.rho_dot")?,
            None => SMatrix::zeros(),
        };
        let run = |e: SolveError| SceneError::invalid("initial", "(state)", e.to_string());
        macro_rules! go {
            ($body:ty, $c:ty) => {{
                let body = <$body>::new(b.mass, j).map_err(|e| self.body_error(e))?;
                let model = AffineBodyModel::<B, _, $c, N, E>::new(m, body, pot).map_err(|e| self.body_error(e))?;
                let y = model.state(&init.g, &rho, &init.u, &rho_dot).map_err(|e| self.state_error(e))?;
                K::make(model, y, span, None).map_err(run)
            }};
        }
        match b.kind {
            BodyKind::Affine => {
                let body = Affine::<N>::new(b.mass, j).map_err(|e| self.body_error(e))?;
                let twin = match chart {
                    Some(make) => Some(make(b.mass, j, pot.clone()).map_err(|e| self.body_error(e))?),
                    None => None,
                };
                let model = AffineBodyModel::<B, _, Unconstrained, N, E>::new(m, body, pot).map_err(|e| self.body_error(e))?;
                let y = model.state(&init.g, &rho, &init.u, &rho_dot).map_err(|e| self.state_error(e))?;
                K::make(model, y, span, twin).map_err(run)
            }
            BodyKind::Incompressible => go!(Incompressible<N>, Isochoric),
            BodyKind::Weyl => go!(Weyl<N>, Conformal),
            _ => go!(Dilatation<N>, PureDilatation<N>),
        }
    }

    fn no_internal(&self, fields: &[&str]) -> Result<(), SceneError> {
        let i = &self.initial;
        for f in fields {
            let given = match *f {
                "alpha" => i.alpha.is_some(),
                "orientation" => i.orientation.is_some(),
                "spin" => i.spin.is_some(),
                "omega" => i.omega.is_some(),
                "frame" => i.frame.is_some(),
                "rho" => i.rho.is_some(),
                "rho_dot" => i.rho_dot.is_some(),
                _ => false,
            };
            if given {
                return Err(SceneError::invalid(
                    format!("initial.{f}"),
                    "(given)",
                    format!("not used by a {} on {}", kind_body(self.body.kind), self.manifold.kind.name()),
                ));
            }
        }
        Ok(())
    }

    /// The manifold's parameters as `manifold.radius = 1.0` (for notes on
    /// errors that involve them).
    fn manifold_note(&self) -> String {
        let m = &self.manifold;
        let fields = [("radius", m.radius), ("L", m.major), ("R", m.minor), ("equatorial_radius", m.equatorial_radius), ("polar_radius", m.polar_radius)];
        let given: Vec<String> = fields.iter().filter_map(|(n, v)| v.map(|v| format!("manifold.{n} = {v:?}"))).collect();
        if given.is_empty() {
            "manifold radius 1 (the default)".to_string()
        } else {
            given.join(", ")
        }
    }

    /// An error of the initial state from the core ([`init_error`]), with
    /// the body's parameters, which scale the state (`body.mass = 1.0,
    /// body.inertia = 0.2`).
    fn state_error(&self, e: crate::Error) -> SceneError {
        let b = &self.body;
        let mut note = format!("body.mass = {:?}", b.mass);
        if let Some(i) = b.inertia {
            note.push_str(&format!(", body.inertia = {i:?}"));
        }
        init_error(e).with_note(&note)
    }

    /// An error of a body whose J may have been built from `inertia`: then
    /// it is reported at `body.inertia` (J = inertia·1).
    fn body_error(&self, e: crate::Error) -> SceneError {
        let about_j = matches!(&e, crate::Error::Constraint { field: "J", .. } | crate::Error::InvalidParameter { field: "J", .. } | crate::Error::NotFinite { field: "J" });
        match self.body.inertia {
            Some(i) if about_j && self.body.j.is_none() => SceneError::invalid("body.inertia", format!("{i:?}"), format!("gives J = inertia·1 that the body refuses: {e}")),
            _ => SceneError::from_core("body", e),
        }
    }

    /// A body's inertia is `inertia` (isotropic) or the matrix `J`, never
    /// both (one would be silently ignored).
    fn one_inertia(&self) -> Result<(), SceneError> {
        if let (Some(i), Some(_)) = (self.body.inertia, &self.body.j) {
            return Err(SceneError::invalid("body.inertia", format!("{i:?}"), "is given together with body.J; give one of them (inertia: isotropic, J: the full matrix)"));
        }
        Ok(())
    }

    fn no_inertia(&self) -> Result<(), SceneError> {
        if self.body.inertia.is_some() || self.body.j.is_some() || self.body.signature.is_some() {
            return Err(SceneError::invalid("body.inertia", "(given)", "a point has a mass only"));
        }
        Ok(())
    }
}

/// The chart equations of the Lagrangian `lag` as the chart twin of a model.
fn twin<S, L, const Q: usize, const N: usize, const E: usize>(lag: L) -> Box<dyn ChartTwin<S>>
where
    S: Observe + AmbientBody<N, E>,
    L: Lagrangian<Q> + AmbientMap<Q, N, E> + Send + Sync + 'static,
{
    Box::new(ChartRunner::<L, Q, N, E>::new(lag))
}

/// Selects the potential type of bodies with `N` frame vectors in `E` dimensions.
pub(crate) trait PotFor<const N: usize, const E: usize> {
    /// The potential enum.
    type Pot: crate::potential::Potential<N, E> + Clone + 'static;
}
impl PotFor<2, 3> for Scene {
    type Pot = Potential2;
}
impl PotFor<3, 4> for Scene {
    type Pot = Potential3;
}

pub(crate) fn kind_body(k: BodyKind) -> &'static str {
    match k {
        BodyKind::Point => "point",
        BodyKind::Gyroscope => "gyroscope",
        BodyKind::Affine => "affine body",
        BodyKind::Incompressible => "incompressible body",
        BodyKind::Weyl => "Weyl body",
        BodyKind::Dilatation => "dilatational body",
    }
}

// -- arrays ------------------------------------------------------------------

fn vec3(v: &[f64], path: &str) -> Result<nalgebra::Vector3<f64>, SceneError> {
    vec_n::<3>(v, path)
}

fn scalar(v: &Numbers, path: &str) -> Result<f64, SceneError> {
    if v.0.len() != 1 {
        return Err(SceneError::invalid(path, format!("an array of {} numbers", v.0.len()), "must be a single number here (2-D gyroscope)"));
    }
    if !v.0[0].is_finite() {
        return Err(SceneError::invalid(path, v.0[0], "must be finite"));
    }
    Ok(v.0[0])
}

/// An `N×N` matrix from rows.
fn mat<const N: usize>(rows: &[Vec<f64>], path: &str) -> Result<SMatrix<f64, N, N>, SceneError> {
    if rows.len() != N || rows.iter().any(|r| r.len() != N) {
        return Err(SceneError::invalid(path, format!("{} rows", rows.len()), format!("must be a {N}×{N} matrix given as {N} rows of {N} numbers")));
    }
    let m = SMatrix::<f64, N, N>::from_fn(|i, j| rows[i][j]);
    if m.iter().any(|x| !x.is_finite()) {
        return Err(SceneError::invalid(path, "(non-finite entry)", "entries must be finite"));
    }
    Ok(m)
}

/// The frame matrix (columns `e_A`) from a list of `N` vectors of `E` numbers.
fn frame_matrix<const N: usize, const E: usize>(vs: &[Vec<f64>]) -> Result<SMatrix<f64, E, N>, SceneError> {
    if vs.len() != N || vs.iter().any(|r| r.len() != E) {
        return Err(SceneError::invalid("initial.frame", format!("{} vectors", vs.len()), format!("must list {N} frame vectors of {E} numbers each")));
    }
    let m = SMatrix::<f64, E, N>::from_fn(|i, a| vs[a][i]);
    if m.iter().any(|x| !x.is_finite()) {
        return Err(SceneError::invalid("initial.frame", "(non-finite entry)", "entries must be finite"));
    }
    Ok(m)
}

