//! [`Scene`]: the whole description of a simulation, read from TOML or JSON
//! (or built in code), validated, and built into a [`Simulation`].

use std::sync::Arc;

use super::error::{Location, SceneError};
use super::locate;
use super::potential::{UserFunctions, UserPotentialFn};
use super::observe::Sel;
use super::simulation::Simulation;
use super::spec::*;

/// Text a scene was read from (for locating errors).
#[derive(Debug, Clone, PartialEq)]
enum Source {
    Toml(Arc<str>),
    Json(Arc<str>),
}

/// A scene: the whole description of a simulation (see the [module docs](crate::scenes)).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// `format`: the version of the scene format the text is written in.
    /// Absent means [`Scene::FORMAT`], the version this build reads and
    /// writes; any other version is refused (an invalid `format` error), even
    /// when the rest of the scene does not parse, so that a scene written
    /// for a newer framedyn says so instead of failing on a field it does
    /// not know.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<u32>,
    /// A short name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// What the scene shows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// `[manifold]`.
    pub manifold: ManifoldSpec,
    /// `[body]`.
    pub body: BodySpec,
    /// `[potential]` (default none).
    #[serde(default)]
    pub potential: PotentialSpec,
    /// `[initial]`.
    pub initial: InitialSpec,
    /// `[method]` (default RK4 with `h = (t_end − t₀)/1000`).
    #[serde(default)]
    pub method: MethodSpec,
    /// `[time]`.
    pub time: TimeSpec,
    /// `[output]`.
    #[serde(default)]
    pub output: OutputSpec,
    /// `[quality]`: the limits the run's summary is judged against (see
    /// [`QualitySpec`]).
    #[serde(default, skip_serializing_if = "QualitySpec::is_default")]
    pub quality: QualitySpec,
    /// `[[events]]`: crossings located and reported during the run (see
    /// [`EventSpec`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<EventSpec>,
    #[serde(skip)]
    source: Option<Source>,
}

impl Scene {
    /// The scene format version this build reads (the `format` field):
    /// raised, with an entry in the changelog, when a scene that parsed
    /// before would parse differently or not at all.
    pub const FORMAT: u32 = 1;

    /// A scene from its parts, with no potential, the default method and
    /// output (fill in the public fields to change them).
    pub fn new(manifold: ManifoldSpec, body: BodySpec, initial: InitialSpec, time: TimeSpec) -> Scene {
        Scene {
            format: None,
            name: None,
            description: None,
            manifold,
            body,
            potential: PotentialSpec::default(),
            initial,
            method: MethodSpec::default(),
            time,
            output: OutputSpec::default(),
            quality: QualitySpec::default(),
            events: Vec::new(),
            source: None,
        }
    }

    /// Parses a TOML scene. Errors ([`SceneError::Parse`]) name the field,
    /// the parser's message (value and expected type/variants) and the line
    /// and column.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let de = toml::Deserializer::new(text);
        let mut scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let location = inner.span().map(|s| locate::offset_to_location(text, s.start));
            // Errors of the TOML syntax itself come before any field is
            // deserialised: the key is read from the line.
            let path = if path == "." { inner.span().and_then(|s| locate::toml_key_at(text, s.start)).unwrap_or_default() } else { path };
            let error = SceneError::Parse {
                format: "TOML",
                path,
                message: inner.message().trim().to_string(),
                location,
            };
            // A scene of another format version fails on that, not on a field it may add.
            match toml::from_str::<FormatProbe>(text) {
                Ok(FormatProbe { format: Some(v) }) if v != Self::FORMAT => locate_format(Self::format_error(v), locate::toml_path(text, "format")),
                _ => error,
            }
        })?;
        scene.source = Some(Source::Toml(text.into()));
        scene.check_format().map_err(|e| scene.locate(e))?;
        Ok(scene)
    }

    /// Parses a JSON scene (same fields as TOML). Errors as [`Self::from_toml_str`].
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        let mut de = serde_json::Deserializer::from_str(text);
        let mut scene: Scene = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let location = if inner.line() > 0 { Some(Location { line: inner.line(), column: inner.column() }) } else { None };
            let mut message = inner.to_string();
            if let Some(i) = message.find(" at line ") {
                message.truncate(i);
            }
            let error = SceneError::Parse { format: "JSON", path: if path == "." { String::new() } else { path }, message, location };
            match serde_json::from_str::<FormatProbe>(text) {
                Ok(FormatProbe { format: Some(v) }) if v != Self::FORMAT => locate_format(Self::format_error(v), locate::json_path(text, "format")),
                _ => error,
            }
        })?;
        de.end().map_err(|e| SceneError::Parse {
            format: "JSON",
            path: String::new(),
            message: "trailing characters after the scene".into(),
            location: Some(Location { line: e.line(), column: e.column() }),
        })?;
        scene.source = Some(Source::Json(text.into()));
        scene.check_format().map_err(|e| scene.locate(e))?;
        Ok(scene)
    }

    /// Parses TOML, or JSON when the text starts with `{`.
    pub fn from_str_auto(text: &str) -> Result<Scene, SceneError> {
        if text.trim_start().starts_with('{') {
            Self::from_json_str(text)
        } else {
            Self::from_toml_str(text)
        }
    }

    /// The scene as TOML.
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# cannot serialise: {e}\n"))
    }

    /// The scene as JSON.
    pub fn to_json_string(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// The names of the registry's methods ([`METHODS`](crate::method::METHODS))
    /// that can integrate this scene's manifold × body: those that need
    /// nothing, the splittings where the model has exact free flows, the
    /// coordinate methods where the paper's chart equations of the
    /// manifold × body exist. Fails as [`Self::build`] does for a scene that
    /// cannot be built.
    pub fn allowed_methods(&self) -> Result<Vec<&'static str>, SceneError> {
        let mut probe = self.clone();
        probe.method = MethodSpec::default();
        probe.events.clear();
        let engine = probe.build_engine::<super::build::Engines>(None, &super::plan::probe_span(&self.time)).map_err(|e| self.locate(e))?;
        Ok(crate::method::METHODS.iter().filter(|m| engine.supports(m.needs)).map(|m| m.name).collect())
    }

    /// Checks everything [`Self::build`] checks, without running.
    pub fn validate(&self) -> Result<(), SceneError> {
        self.build().map(|_| ())
    }

    /// Builds the simulation. Errors name the field (`body.mass`,
    /// `initial.r`, `potential.terms[0].kappa`, …), the value and what is
    /// allowed, with the line and column when the scene came from text.
    pub fn build(&self) -> Result<Simulation, SceneError> {
        self.build_inner(None).map_err(|e| self.locate(e))
    }

    /// Builds the simulation with a user potential `f(x, e)` added to the
    /// scene's potential (`x`: embedding position, `e`: the body frame
    /// vectors column-major, for points the reference frame). Its gradient
    /// is taken by extrapolated finite differences
    /// ([`FnPotential`](crate::potential::FnPotential)): slower than the
    /// built-ins.
    pub fn build_with_user_potential(&self, f: UserPotentialFn) -> Result<Simulation, SceneError> {
        self.build_with_user(UserFunctions { value: f, gradient: None })
    }

    /// [`Self::build_with_user_potential`], with the user's own gradient if
    /// [`UserFunctions::gradient`] is given ([`UserGradientFn`](crate::scenes::UserGradientFn): `∂V/∂x` and
    /// `∂V/∂e` in the same layouts as `x` and `e`) instead of finite
    /// differences: one call of each function per evaluation. The gradient
    /// is trusted as it is.
    pub fn build_with_user(&self, user: UserFunctions) -> Result<Simulation, SceneError> {
        self.build_inner(Some(user)).map_err(|e| self.locate(e))
    }

    /// The output path (default `trajectory.csv`, or `.npz` for `format = "npz"`).
    pub fn output_path(&self) -> String {
        match (&self.output.path, self.output.format) {
            (Some(p), _) => p.clone(),
            (None, Some(Format::Npz)) => "trajectory.npz".into(),
            (None, _) => "trajectory.csv".into(),
        }
    }

    /// The output format: `format`, else from the extension of the path.
    pub fn output_format(&self) -> Format {
        self.output.format.unwrap_or_else(|| {
            if self.output_path().to_ascii_lowercase().ends_with(".npz") {
                Format::Npz
            } else {
                Format::Csv
            }
        })
    }

    /// `format` absent or [`Self::FORMAT`].
    fn check_format(&self) -> Result<(), SceneError> {
        match self.format {
            Some(v) if v != Self::FORMAT => Err(Self::format_error(v)),
            _ => Ok(()),
        }
    }

    fn format_error(v: u32) -> SceneError {
        SceneError::invalid(
            "format",
            v,
            format!(
                "this framedyn ({}) reads scene format {} (omit `format` or write `format = {}`); a scene of another format needs the framedyn version that writes it (CHANGELOG.md)",
                env!("CARGO_PKG_VERSION"),
                Self::FORMAT,
                Self::FORMAT
            ),
        )
    }

    pub(crate) fn locate(&self, e: SceneError) -> SceneError {
        match e {
            SceneError::Invalid { path, value, allowed, location: None } => {
                let location = match &self.source {
                    Some(Source::Toml(s)) => locate::toml_path(s, &path),
                    Some(Source::Json(s)) => locate::json_path(s, &path),
                    None => None,
                };
                SceneError::Invalid { path, value, allowed, location }
            }
            other => other,
        }
    }

    /// Plans, builds the engine of the manifold × body, checks that the
    /// method can integrate it, and compiles the events.
    fn build_inner(&self, user: Option<UserFunctions>) -> Result<Simulation, SceneError> {
        self.check_format()?;
        let mut plan = self.plan()?;
        let engine = self.planned_engine(user, &plan)?;
        let columns = engine.columns(plan.sel);
        let event_columns = engine.columns(Sel::ALL);
        plan.events = self.compile_events(&event_columns)?;
        Ok(Simulation { engine, plan, columns, event_columns, name: self.name.clone().unwrap_or_default(), stepping: None })
    }

    /// The engine of the manifold × body over the plan's span, checked to be
    /// one the plan's method can integrate.
    pub(crate) fn planned_engine(&self, user: Option<UserFunctions>, plan: &super::plan::Plan) -> Result<Box<dyn super::simulation::DynEngine>, SceneError> {
        let engine = self.build_engine::<super::build::Engines>(user, &(plan.t0, plan.t_end))?;
        if !engine.supports(plan.entry.needs) {
            let allowed: Vec<&str> = crate::method::METHODS.iter().filter(|m| engine.supports(m.needs)).map(|m| m.name).collect();
            return Err(SceneError::invalid(
                "method.name",
                format!("\"{}\"", plan.entry.name),
                format!(
                    "not available for a {} on {} (it needs {}); allowed here: {}",
                    super::build::kind_body(self.body.kind),
                    self.manifold.kind.name(),
                    plan.entry.needs.describe(),
                    allowed.join(", ")
                ),
            ));
        }
        Ok(engine)
    }
}

/// The `format` field alone, read leniently when a scene does not parse.
#[derive(serde::Deserialize)]
struct FormatProbe {
    #[serde(default)]
    format: Option<u32>,
}

fn locate_format(e: SceneError, location: Option<Location>) -> SceneError {
    match e {
        SceneError::Invalid { path, value, allowed, .. } => SceneError::Invalid { path, value, allowed, location },
        other => other,
    }
}
