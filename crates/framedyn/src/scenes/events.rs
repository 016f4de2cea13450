//! The built-in event functions of `[[events]]` (`plane`, `distance`,
//! `column`) as [`Event`]s on the full record: the one event type of the
//! crate ([`solve::event`](crate::solve::event)), located by the driver.

use std::sync::Arc;

use super::error::SceneError;
use super::sink::Column;
use super::spec::{EventKind, EventSpec};
use crate::solve::event::{Event, EventFn};

/// The event function of `[[events]]` entry `i` over the full record.
pub(crate) fn compile_event(e: &EventSpec, i: usize, cols: &[Column]) -> Result<Event<[f64]>, SceneError> {
    let path = |f: &str| format!("events[{i}].{f}");
    let kind = match e.kind {
        EventKind::Plane => "plane",
        EventKind::Distance => "distance",
        EventKind::Column => "column",
    };
    let used: &[&str] = match e.kind {
        EventKind::Plane => &["normal", "offset"],
        EventKind::Distance => &["point", "distance"],
        EventKind::Column => &["column", "value"],
    };
    for (f, given) in [
        ("normal", e.normal.is_some()),
        ("offset", e.offset.is_some()),
        ("point", e.point.is_some()),
        ("distance", e.distance.is_some()),
        ("column", e.column.is_some()),
        ("value", e.value.is_some()),
    ] {
        if given && !used.contains(&f) {
            return Err(SceneError::invalid(path(f), "(given)", format!("kind = \"{kind}\" takes only: {}", used.join(", "))));
        }
    }
    let xs: Vec<usize> = cols.iter().enumerate().filter(|(_, c)| c.name.len() == 2 && c.name.starts_with('x')).map(|(j, _)| j).collect();
    let dim = xs.len();
    let vector = |v: &Option<Vec<f64>>, f: &str| -> Result<Vec<f64>, SceneError> {
        let v = v.as_ref().ok_or_else(|| SceneError::invalid(path(f), "(missing)", format!("required for kind = \"{kind}\": {dim} embedding components")))?;
        if v.len() != dim {
            return Err(SceneError::invalid(path(f), format!("an array of {} numbers", v.len()), format!("must have exactly {dim} numbers (embedding components)")));
        }
        if let Some(j) = v.iter().position(|x| !x.is_finite()) {
            return Err(SceneError::invalid(format!("{}[{j}]", path(f)), v[j], "must be finite"));
        }
        Ok(v.clone())
    };
    let number = |v: Option<f64>, f: &str, default: Option<f64>| -> Result<f64, SceneError> {
        let x = v.or(default).ok_or_else(|| SceneError::invalid(path(f), "(missing)", format!("required for kind = \"{kind}\"")))?;
        if !x.is_finite() {
            return Err(SceneError::invalid(path(f), x, "must be finite"));
        }
        Ok(x)
    };
    let g: Arc<EventFn<[f64]>> = match e.kind {
        EventKind::Plane => {
            let n = vector(&e.normal, "normal")?;
            if n.iter().all(|x| *x == 0.0) {
                return Err(SceneError::invalid(path("normal"), "[0, …]", "must be a non-zero vector"));
            }
            let c = number(e.offset, "offset", Some(0.0))?;
            Arc::new(move |_t, row: &[f64]| xs.iter().zip(&n).map(|(&j, a)| a * row[j]).sum::<f64>() - c)
        }
        EventKind::Distance => {
            let p = vector(&e.point, "point")?;
            let d = number(e.distance, "distance", None)?;
            if d < 0.0 {
                return Err(SceneError::invalid(path("distance"), d, "must be ≥ 0"));
            }
            Arc::new(move |_t, row: &[f64]| xs.iter().zip(&p).map(|(&j, a)| (row[j] - a).powi(2)).sum::<f64>().sqrt() - d)
        }
        EventKind::Column => {
            let name = e.column.as_deref().ok_or_else(|| SceneError::invalid(path("column"), "(missing)", "required for kind = \"column\": a record column"))?;
            let j = cols.iter().position(|c| c.name == name).ok_or_else(|| {
                SceneError::invalid(path("column"), format!("\"{name}\""), format!("not a column of this scene; allowed: {}", cols.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")))
            })?;
            let v = number(e.value, "value", None)?;
            Arc::new(move |_t, row: &[f64]| row[j] - v)
        }
    };
    if let Some(n) = &e.name {
        if n.is_empty() || n.contains([',', '\n', '"']) {
            return Err(SceneError::invalid(path("name"), format!("{n:?}"), "must be non-empty, without commas, quotes or newlines"));
        }
    }
    let event = Event::from_arc(e.name.clone().unwrap_or_else(|| format!("event{i}")), g).direction(e.direction);
    Ok(if e.terminal { event.terminal() } else { event })
}
