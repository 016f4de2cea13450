//! The plan of a run: the `[method]`, `[time]`, `[output]` and `[quality]` tables
//! checked and turned into the driver's [`Settings`], the method from the
//! registry, and the selected columns.

use super::error::SceneError;
use super::events::compile_event;
use super::observe::Sel;
use super::scene::Scene;
use super::sink::Column;
use super::spec::*;
use crate::method::registry::{self, Built, MethodEntry, MethodParams};
use crate::method::MethodError;
use crate::solve::{fixed_step_count, Adaptive, Event, Projection, Save, Settings, SolveError, StepSize, Tol, RTOL_MIN};

/// Default limit on accepted steps of a scene run.
pub const DEFAULT_SCENE_MAX_STEPS: u64 = 1_000_000_000;

/// Everything a run needs besides the model: span, method, the driver's
/// settings, the selected column groups and the events (on the full record).
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    pub t0: f64,
    pub t_end: f64,
    pub entry: &'static MethodEntry,
    pub method: Built,
    pub settings: Settings,
    pub sel: Sel,
    pub events: Vec<Event<[f64]>>,
    /// `(energy_drift, defect)` limits of the quality check.
    pub quality: (f64, f64),
    /// Estimate the global error with a reference run ([`Plan::reference`]).
    pub global_error: bool,
}

impl Plan {
    /// The plan of the reference run of a global-error estimate: a
    /// hundredth of the tolerances (`rtol ≥` [`RTOL_MIN`]) or a quarter of
    /// the fixed step, over `[t0, t_end]`, saving exactly at `times` (the
    /// records of the run) the compared quantities only, without events.
    pub(crate) fn reference(&self, t_end: f64, times: Vec<f64>) -> Plan {
        let mut p = self.clone();
        p.t_end = t_end;
        p.events = Vec::new();
        p.global_error = false;
        p.sel = Sel::new(&MEASURED);
        p.settings.save = Save::At(times);
        p.settings.dense = false;
        p.settings.max_steps = p.settings.max_steps.saturating_mul(4);
        p.settings.step = match &self.settings.step {
            StepSize::Adaptive(a) => {
                let tighter = |t: &Tol, floor: f64| match t {
                    Tol::Scalar(v) => Tol::Scalar((v / 100.0).max(floor)),
                    Tol::PerComponent(v) => Tol::PerComponent(v.iter().map(|x| (x / 100.0).max(floor)).collect()),
                };
                StepSize::Adaptive(Adaptive { rtol: tighter(&a.rtol, RTOL_MIN), atol: tighter(&a.atol, 0.0), ..a.clone() })
            }
            StepSize::Fixed(h) => StepSize::Fixed(h / 4.0),
        };
        p
    }
}

/// The quantities a global-error estimate compares.
pub(crate) const MEASURED: [Quantity; 4] = [Quantity::Position, Quantity::Velocity, Quantity::Frame, Quantity::Momenta];

/// A time span for building a model only (probing which methods apply):
/// the scene's if valid, else `(0, 1)`.
pub(crate) fn probe_span(t: &TimeSpec) -> (f64, f64) {
    if t.t0.is_finite() && t.t_end.is_finite() && t.t_end != t.t0 {
        (t.t0, t.t_end)
    } else {
        (0.0, 1.0)
    }
}

/// A method error as a scene error at `method.<field>`.
fn method_error(e: MethodError, m: &MethodSpec) -> SceneError {
    match e {
        MethodError::InvalidParameter { field, value, allowed } => SceneError::invalid(format!("method.{field}"), value, format!("must be {allowed}")),
        MethodError::Unknown { name, allowed } => SceneError::invalid("method.name", format!("\"{name}\""), format!("one of {allowed}")),
        MethodError::Unsupported { reason, .. } => {
            let f = if m.newton_tol.is_some() { "method.newton_tol" } else { "method.newton_max_iter" };
            SceneError::invalid(f, "(given)", format!("{reason}, not \"{}\"", m.name))
        }
    }
}

impl Scene {
    /// Checks `[time]`, `[method]` and `[output]` and builds the plan (events
    /// are compiled later, against the model's columns).
    pub(crate) fn plan(&self) -> Result<Plan, SceneError> {
        let t = &self.time;
        if !t.t0.is_finite() {
            return Err(SceneError::invalid("time.t0", t.t0, "must be finite"));
        }
        if !t.t_end.is_finite() || t.t_end == t.t0 {
            return Err(SceneError::invalid("time.t_end", t.t_end, "must be finite and ≠ t0"));
        }
        let span = t.t_end - t.t0;
        let m = &self.method;
        let entry = registry::lookup(&m.name).map_err(|e| method_error(e, m))?;
        let method = entry.build(&MethodParams { newton_tol: m.newton_tol, newton_max_iter: m.newton_max_iter }).map_err(|e| method_error(e, m))?;
        let adaptive = m.rtol.is_some() || m.atol.is_some() || (m.h.is_none() && entry.adaptive);
        let step = if adaptive {
            if m.h.is_some() {
                return Err(SceneError::invalid("method.h", m.h.unwrap_or(f64::NAN), "give either h (fixed steps) or rtol/atol (adaptive), not both"));
            }
            if !entry.adaptive {
                let adaptive: Vec<&str> = registry::METHODS.iter().filter(|e| e.adaptive).map(|e| e.name).collect();
                return Err(SceneError::invalid(
                    "method.rtol",
                    m.rtol.or(m.atol).unwrap_or(f64::NAN),
                    format!("adaptive stepping (rtol/atol) needs a method with an embedded pair: name = {}", adaptive.join(", ")),
                ));
            }
            let rtol = m.rtol.unwrap_or(1e-8);
            let atol = m.atol.unwrap_or(1e-10);
            if !(rtol.is_finite() && rtol >= crate::solve::RTOL_MIN) {
                return Err(SceneError::invalid(
                    "method.rtol",
                    rtol,
                    "must be finite and ≥ 1e-14 (below it the local error estimate is round-off and the step underflows)",
                ));
            }
            if !(atol.is_finite() && atol > 0.0) {
                return Err(SceneError::invalid("method.atol", atol, "must be finite and > 0"));
            }
            StepSize::Adaptive(Adaptive::new(rtol, atol))
        } else {
            let h = m.h.unwrap_or(span.abs() / 1000.0);
            if !(h.is_finite() && h > 0.0) {
                return Err(SceneError::invalid("method.h", h, "must be finite and > 0"));
            }
            StepSize::Fixed(h)
        };
        let max_steps = m.max_steps.unwrap_or(DEFAULT_SCENE_MAX_STEPS);
        if max_steps == 0 {
            return Err(SceneError::invalid("method.max_steps", 0, "must be ≥ 1"));
        }
        if let StepSize::Fixed(h) = &step {
            let n = fixed_step_count(t.t0, t.t_end, *h)
                .map_err(|e| {
                    let allowed = match e {
                        SolveError::InvalidParameter { allowed, .. } => format!("must be {allowed}"),
                        other => other.to_string(),
                    };
                    SceneError::invalid("method.h", h, allowed).with_note(&format!("time.t0 = {:?}, time.t_end = {:?}", t.t0, t.t_end))
                })?;
            if n as u64 > max_steps {
                return Err(SceneError::invalid(
                    "method.h",
                    h,
                    format!("the span needs {n} steps of at most h, more than method.max_steps = {max_steps}; raise h or max_steps"),
                ));
            }
        }
        let o = &self.output;
        let given = o.every.is_some() as u8 + o.times.is_some() as u8 + o.samples.is_some() as u8;
        if given > 1 {
            let path = if o.times.is_some() { "output.times" } else { "output.samples" };
            return Err(SceneError::invalid(path, "(given together with another sampling)", "give only one of every, times, samples"));
        }
        let (lo, hi) = (t.t0.min(t.t_end), t.t0.max(t.t_end));
        let save = if let Some(ts) = &o.times {
            if ts.is_empty() {
                return Err(SceneError::invalid("output.times", "[]", "must list at least one time"));
            }
            for (i, &x) in ts.iter().enumerate() {
                if !(x >= lo && x <= hi) {
                    return Err(SceneError::invalid(format!("output.times[{i}]"), x, format!("must lie in the time span [{lo}, {hi}]")));
                }
            }
            Save::At(ts.clone())
        } else if let Some(n) = o.samples {
            if !(2..=100_000_000).contains(&n) {
                return Err(SceneError::invalid("output.samples", n, "must be in 2 ..= 1e8"));
            }
            Save::At((0..n).map(|i| if i + 1 == n { t.t_end } else { t.t0 + span * (i as f64 / (n - 1) as f64) }).collect())
        } else {
            let every = o.every.unwrap_or(1);
            if every == 0 {
                return Err(SceneError::invalid("output.every", 0, "must be ≥ 1"));
            }
            Save::Every(every)
        };
        let quantities = o.quantities.clone().unwrap_or_else(|| Quantity::ALL.to_vec());
        if let Some(p) = &o.path {
            if p.is_empty() {
                return Err(SceneError::invalid("output.path", "\"\"", "must be a non-empty path"));
            }
        }
        for (field, v) in [("quality.energy_drift", self.quality.energy_drift), ("quality.defect", self.quality.defect)] {
            if let Some(v) = v {
                if !(v > 0.0) {
                    return Err(SceneError::invalid(field, v, "must be > 0 (inf switches the check off)"));
                }
            }
        }
        let projection = match &m.project {
            None => Projection::None,
            Some(name) => Projection::from_name(name).ok_or_else(|| SceneError::invalid("method.project", format!("{name:?}"), format!("must be {}", Projection::NAMES)))?,
        };
        let settings = Settings { step, save, dense: false, max_steps: usize::try_from(max_steps).unwrap_or(usize::MAX), event_xtol: 0.0, projection };
        Ok(Plan { t0: t.t0, t_end: t.t_end, entry, method, settings, sel: Sel::new(&quantities), events: Vec::new(), quality: self.quality.limits(), global_error: m.global_error.unwrap_or(false) })
    }

    /// The scene's `[[events]]` as events on the full record `columns`.
    pub(crate) fn compile_events(&self, columns: &[Column]) -> Result<Vec<Event<[f64]>>, SceneError> {
        self.events.iter().enumerate().map(|(i, e)| compile_event(e, i, columns)).collect()
    }
}
