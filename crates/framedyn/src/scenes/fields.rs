//! Numeric scene fields by dotted path (`initial.r`, `potential.kappa`,
//! `body.J.0.1`, `potential.terms.1.alpha_hat`, `initial.position.2`): the
//! columns of an ensemble table ([`super::ensemble`]) and
//! [`Scene::set`](super::Scene::set).
//!
//! A path is parsed once into a [`FieldPath`] (unknown names are refused
//! with the list of what can be set), then applied to any number of scenes
//! without string handling. Indices of vector and matrix fields follow the
//! scene format's nesting (`initial.frame.A.K`: component `K` of frame
//! vector `A`; `body.J.I.J`, `initial.rho.I.J`: row `I`, column `J`) and may
//! also be written in brackets (`potential.terms[1].kappa`, the form in which
//! scene errors name fields). A component can only be set in a field the
//! base scene gives (the field's length is the scene's choice, not the
//! table's).

use std::fmt;

use super::error::SceneError;
use super::scene::Scene;
use super::spec::{InitialSpec, Numbers, PotentialSpec};

/// A numeric field of [`PotentialSpec`].
#[derive(Debug, Clone, PartialEq)]
enum PotentialField {
    Scale,
    Kappa,
    Alpha,
    AlphaHat,
    BetaHat,
    Lambda,
    Mu,
    Centre(usize),
    Term(usize, Box<PotentialField>),
}

/// One settable numeric field of a [`Scene`], parsed from its dotted path.
#[derive(Debug, Clone, PartialEq)]
enum Target {
    ManifoldRadius,
    ManifoldMajor,
    ManifoldMinor,
    EquatorialRadius,
    PolarRadius,
    BodyMass,
    BodyInertia,
    BodyJ(usize, usize),
    Potential(PotentialField),
    Coordinate(String),
    Position(usize),
    Velocity(usize),
    Frame(usize, usize),
    Alpha,
    Orientation(usize),
    Spin(Option<usize>),
    Omega(Option<usize>),
    Rho(usize, usize),
    RhoDot(usize, usize),
    MethodH,
    MethodRtol,
    MethodAtol,
    T0,
    TEnd,
}

/// A parsed dotted path to a numeric scene field.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldPath {
    path: String,
    target: Target,
}

/// What can be set, for error messages.
const SETTABLE: &str = "manifold.{radius, L, R, equatorial_radius, polar_radius}, body.{mass, inertia, J.I.J}, \
potential.{scale, kappa, alpha, alpha_hat, beta_hat, lambda, mu, centre.K, terms.K.<field>}, \
initial.<chart coordinate or rate> (e.g. initial.r, initial.phi_dot), initial.{alpha, spin, omega, spin.K, omega.K, \
position.K, velocity.K, orientation.K, frame.A.K, rho.I.J, rho_dot.I.J}, method.{h, rtol, atol}, time.{t0, t_end}";

fn index(path: &str, part: Option<&str>) -> Result<usize, SceneError> {
    part.and_then(|p| p.parse::<usize>().ok())
        .ok_or_else(|| SceneError::invalid(path, "(path)", "an index (0, 1, …) is expected here"))
}

fn unknown(path: &str) -> SceneError {
    SceneError::invalid(path, "(path)", format!("not a numeric scene field that can be set; allowed: {SETTABLE}"))
}

fn potential_field(path: &str, parts: &[&str]) -> Result<PotentialField, SceneError> {
    let one = |f: PotentialField| if parts.len() == 1 { Ok(f) } else { Err(unknown(path)) };
    match parts.first().copied() {
        Some("scale") => one(PotentialField::Scale),
        Some("kappa") => one(PotentialField::Kappa),
        Some("alpha") => one(PotentialField::Alpha),
        Some("alpha_hat") => one(PotentialField::AlphaHat),
        Some("beta_hat") => one(PotentialField::BetaHat),
        Some("lambda") => one(PotentialField::Lambda),
        Some("mu") => one(PotentialField::Mu),
        Some("centre") if parts.len() == 2 => Ok(PotentialField::Centre(index(path, parts.get(1).copied())?)),
        Some("terms") if parts.len() >= 3 => {
            let k = index(path, parts.get(1).copied())?;
            Ok(PotentialField::Term(k, Box::new(potential_field(path, &parts[2..])?)))
        }
        _ => Err(unknown(path)),
    }
}

impl FieldPath {
    /// Parses `path` (`initial.r`, `body.J.0.1`, `potential.terms[1].kappa`, …).
    pub fn parse(path: &str) -> Result<FieldPath, SceneError> {
        let normal = path.replace('[', ".").replace(']', "");
        let parts: Vec<&str> = normal.split('.').collect();
        if parts.iter().any(|p| p.is_empty()) {
            return Err(unknown(path));
        }
        let two = |i: usize| -> Result<(usize, usize), SceneError> {
            if parts.len() != i + 2 {
                return Err(SceneError::invalid(path, "(path)", "two indices (row, column) are expected"));
            }
            Ok((index(path, Some(parts[i]))?, index(path, Some(parts[i + 1]))?))
        };
        let one = |i: usize| -> Result<usize, SceneError> {
            if parts.len() != i + 1 {
                return Err(SceneError::invalid(path, "(path)", "one index (0, 1, …) is expected"));
            }
            index(path, Some(parts[i]))
        };
        let exact = |t: Target| if parts.len() == 2 { Ok(t) } else { Err(unknown(path)) };
        let target = match (parts[0], parts.get(1).copied()) {
            ("manifold", Some("radius")) => exact(Target::ManifoldRadius)?,
            ("manifold", Some("L" | "major")) => exact(Target::ManifoldMajor)?,
            ("manifold", Some("R" | "minor")) => exact(Target::ManifoldMinor)?,
            ("manifold", Some("equatorial_radius")) => exact(Target::EquatorialRadius)?,
            ("manifold", Some("polar_radius")) => exact(Target::PolarRadius)?,
            ("body", Some("mass")) => exact(Target::BodyMass)?,
            ("body", Some("inertia")) => exact(Target::BodyInertia)?,
            ("body", Some("J")) => {
                let (i, j) = two(2)?;
                Target::BodyJ(i, j)
            }
            ("potential", Some(_)) => Target::Potential(potential_field(path, &parts[1..])?),
            ("initial", Some("position")) => Target::Position(one(2)?),
            ("initial", Some("velocity")) => Target::Velocity(one(2)?),
            ("initial", Some("orientation")) => Target::Orientation(one(2)?),
            ("initial", Some("frame")) => {
                let (a, k) = two(2)?;
                Target::Frame(a, k)
            }
            ("initial", Some("rho")) => {
                let (i, j) = two(2)?;
                Target::Rho(i, j)
            }
            ("initial", Some("rho_dot")) => {
                let (i, j) = two(2)?;
                Target::RhoDot(i, j)
            }
            ("initial", Some("alpha")) => exact(Target::Alpha)?,
            ("initial", Some("spin")) => Target::Spin(if parts.len() == 2 { None } else { Some(one(2)?) }),
            ("initial", Some("omega")) => Target::Omega(if parts.len() == 2 { None } else { Some(one(2)?) }),
            ("initial", Some(name)) if !InitialSpec::FIELDS.contains(&name) => exact(Target::Coordinate(name.to_string()))?,
            ("method", Some("h")) => exact(Target::MethodH)?,
            ("method", Some("rtol")) => exact(Target::MethodRtol)?,
            ("method", Some("atol")) => exact(Target::MethodAtol)?,
            ("time", Some("t0")) => exact(Target::T0)?,
            ("time", Some("t_end")) => exact(Target::TEnd)?,
            _ => return Err(unknown(path)),
        };
        Ok(FieldPath { path: path.to_string(), target })
    }

    /// The path as given.
    pub fn as_str(&self) -> &str {
        &self.path
    }

    /// Whether the field belongs to the run's plan (`method.*`, `time.*`:
    /// span, step size, tolerances) rather than to the model or its
    /// initial state.
    pub(crate) fn is_plan(&self) -> bool {
        matches!(self.target, Target::MethodH | Target::MethodRtol | Target::MethodAtol | Target::T0 | Target::TEnd)
    }

    /// Sets the field in `scene` to `value`. Fails (naming the path) for a
    /// non-finite value, for a component of a field the scene does not give
    /// or outside its length, and for a potential field of a term that does
    /// not exist. Ranges are checked when the scene is built.
    pub fn apply(&self, scene: &mut Scene, value: f64) -> Result<(), SceneError> {
        let path = self.path.as_str();
        if !value.is_finite() {
            return Err(SceneError::invalid(path, value, "must be a finite number"));
        }
        let absent = |field: &str| SceneError::invalid(path, value, format!("the base scene gives no `{field}` to change a component of; give the whole field in the base scene"));
        let range = |len: usize| SceneError::invalid(path, value, format!("index out of range: the base scene's field has {len} entries"));
        let vector = |v: &mut Option<Vec<f64>>, k: usize, field: &str| -> Result<(), SceneError> {
            let v = v.as_mut().ok_or_else(|| absent(field))?;
            let n = v.len();
            *v.get_mut(k).ok_or_else(|| range(n))? = value;
            Ok(())
        };
        let matrix = |m: &mut Option<Vec<Vec<f64>>>, i: usize, j: usize, field: &str| -> Result<(), SceneError> {
            let m = m.as_mut().ok_or_else(|| absent(field))?;
            let n = m.len();
            let row = m.get_mut(i).ok_or_else(|| range(n))?;
            let n = row.len();
            *row.get_mut(j).ok_or_else(|| range(n))? = value;
            Ok(())
        };
        let numbers = |v: &mut Option<Numbers>, k: Option<usize>, field: &str| -> Result<(), SceneError> {
            match k {
                None => {
                    *v = Some(Numbers(vec![value]));
                    Ok(())
                }
                Some(k) => {
                    let v = v.as_mut().ok_or_else(|| absent(field))?;
                    let n = v.0.len();
                    *v.0.get_mut(k).ok_or_else(|| range(n))? = value;
                    Ok(())
                }
            }
        };
        let init = &mut scene.initial;
        match &self.target {
            Target::ManifoldRadius => scene.manifold.radius = Some(value),
            Target::ManifoldMajor => scene.manifold.major = Some(value),
            Target::ManifoldMinor => scene.manifold.minor = Some(value),
            Target::EquatorialRadius => scene.manifold.equatorial_radius = Some(value),
            Target::PolarRadius => scene.manifold.polar_radius = Some(value),
            Target::BodyMass => scene.body.mass = value,
            Target::BodyInertia => scene.body.inertia = Some(value),
            Target::BodyJ(i, j) => matrix(&mut scene.body.j, *i, *j, "body.J")?,
            Target::Potential(f) => set_potential(&mut scene.potential, f, value, path)?,
            Target::Coordinate(name) => match init.coordinates.get_mut(name) {
                Some(v) => *v = value,
                None => {
                    init.coordinates.insert(name.clone(), value);
                }
            },
            Target::Position(k) => vector(&mut init.position, *k, "initial.position")?,
            Target::Velocity(k) => vector(&mut init.velocity, *k, "initial.velocity")?,
            Target::Orientation(k) => vector(&mut init.orientation, *k, "initial.orientation")?,
            Target::Frame(a, k) => matrix(&mut init.frame, *a, *k, "initial.frame")?,
            Target::Rho(i, j) => matrix(&mut init.rho, *i, *j, "initial.rho")?,
            Target::RhoDot(i, j) => matrix(&mut init.rho_dot, *i, *j, "initial.rho_dot")?,
            Target::Alpha => init.alpha = Some(value),
            Target::Spin(k) => numbers(&mut init.spin, *k, "initial.spin")?,
            Target::Omega(k) => numbers(&mut init.omega, *k, "initial.omega")?,
            Target::MethodH => scene.method.h = Some(value),
            Target::MethodRtol => scene.method.rtol = Some(value),
            Target::MethodAtol => scene.method.atol = Some(value),
            Target::T0 => scene.time.t0 = value,
            Target::TEnd => scene.time.t_end = value,
        }
        Ok(())
    }
}

fn set_potential(p: &mut PotentialSpec, f: &PotentialField, value: f64, path: &str) -> Result<(), SceneError> {
    match f {
        PotentialField::Scale => p.scale = Some(value),
        PotentialField::Kappa => p.kappa = Some(value),
        PotentialField::Alpha => p.alpha = Some(value),
        PotentialField::AlphaHat => p.alpha_hat = Some(value),
        PotentialField::BetaHat => p.beta_hat = Some(value),
        PotentialField::Lambda => p.lambda = Some(value),
        PotentialField::Mu => p.mu = Some(value),
        PotentialField::Centre(k) => {
            let c = p.centre.as_mut().ok_or_else(|| {
                SceneError::invalid(path, value, "the base scene gives no `centre` to change a component of; give the whole field in the base scene")
            })?;
            let n = c.len();
            *c.get_mut(*k).ok_or_else(|| SceneError::invalid(path, value, format!("index out of range: the base scene's centre has {n} entries")))? = value;
        }
        PotentialField::Term(k, inner) => {
            let terms = p.terms.as_mut().map(|t| t.as_mut_slice()).unwrap_or(&mut []);
            let n = terms.len();
            let term = terms
                .get_mut(*k)
                .ok_or_else(|| SceneError::invalid(path, value, format!("no term {k}: the base scene's potential has {n} terms")))?;
            set_potential(term, inner, value, path)?;
        }
    }
    Ok(())
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.path)
    }
}

impl Scene {
    /// Sets the numeric field at the dotted `path` (see [`FieldPath`]):
    /// `scene.set("initial.r", 0.3)`, `scene.set("potential.kappa", 2.0)`.
    /// The scene is not validated here; [`Scene::build`] checks ranges and
    /// names the field.
    ///
    /// ```
    /// use framedyn::scenes::{example, DEFAULT_SCENE};
    ///
    /// let mut scene = example(DEFAULT_SCENE)?;
    /// scene.set("initial.r", 0.7)?;
    /// assert_eq!(scene.initial.coordinate("r"), Some(0.7));
    /// let err = scene.set("initial.nonsense.3", 1.0).unwrap_err();
    /// assert!(err.to_string().contains("initial.nonsense.3"));
    /// # Ok::<(), framedyn::scenes::SceneError>(())
    /// ```
    pub fn set(&mut self, path: &str, value: f64) -> Result<(), SceneError> {
        FieldPath::parse(path)?.apply(self, value)
    }
}
