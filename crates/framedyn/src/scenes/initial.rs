//! The initial state of `[initial]`: the chart coordinates of the manifold
//! (named as [`Manifold::coordinate_names`](crate::manifold::Manifold::coordinate_names)
//! names them) or the embedding, turned into a bundle element and velocity.

use nalgebra::{SMatrix, SVector};

use super::error::SceneError;
use super::potential::vec_n;
use super::spec::InitialSpec;
use crate::bundle::FrameBundle;
use crate::dynamics::point::{bundle_element_at, tangent_components};

/// A core error while building the initial state, at the `[initial]` field
/// it concerns.
pub(crate) fn init_error(e: crate::Error) -> SceneError {
    let field = match &e {
        crate::Error::InvalidParameter { field, .. } | crate::Error::NotFinite { field } | crate::Error::Constraint { field, .. } => *field,
        _ => "",
    };
    let path = match field {
        "p" => "initial.position",
        "v" | "u" => "initial.velocity",
        "e" | "q" => "initial.frame",
        "spin" => "initial.spin",
        "rho" | "det(rho)" => "initial.rho",
        "rho_dot" => "initial.rho_dot",
        "alpha" => "initial.alpha",
        _ => "initial",
    };
    SceneError::from_core(path, e)
}

/// The initial point: position, velocity, reference bundle element and
/// velocity components in its frame.
pub(crate) struct Init<B: FrameBundle<N, E>, const N: usize, const E: usize> {
    pub p: SVector<f64, E>,
    pub v: SVector<f64, E>,
    pub g: B::Group,
    pub u: SVector<f64, N>,
}

impl<B: FrameBundle<N, E>, const N: usize, const E: usize> Init<B, N, E> {
    /// From the chart coordinates named as the manifold names them, or from
    /// `position`/`velocity` in the embedding.
    pub(crate) fn new(b: &B, i: &InitialSpec) -> Result<Self, SceneError> {
        let names = b.coordinate_names();
        let get = |name: &str| i.coordinate(name);
        // The rate `NAME_dot` of a coordinate, found without building the key.
        let rate = |name: &str| i.coordinates.iter().find(|(k, _)| k.strip_suffix("_dot") == Some(name)).map(|(_, v)| *v);
        // Keys that are neither a coordinate of this manifold nor its rate.
        for (key, value) in &i.coordinates {
            let own = names.iter().any(|n| key == n || key.strip_suffix("_dot") == Some(n));
            if !own {
                let rates: Vec<String> = names.iter().map(|n| format!("{n}_dot")).collect();
                return Err(SceneError::invalid(
                    format!("initial.{key}"),
                    value,
                    format!(
                        "not a coordinate of this manifold; its coordinates are {} (rates {}); other fields of [initial]: {}",
                        names.join(", "),
                        rates.join(", "),
                        InitialSpec::FIELDS.join(", ")
                    ),
                ));
            }
        }
        let any_chart = names.iter().any(|n| get(n).is_some() || rate(n).is_some());
        if any_chart && (i.position.is_some() || i.velocity.is_some()) {
            return Err(SceneError::invalid("initial.position", "(given with paper coordinates)", "give either the paper's coordinates or position/velocity, not both"));
        }
        if any_chart {
            let mut x = SVector::<f64, N>::zeros();
            let mut xd = SVector::<f64, N>::zeros();
            for (k, n) in names.iter().enumerate() {
                x[k] = get(n).ok_or_else(|| SceneError::invalid(format!("initial.{n}"), "(missing)", format!("all of {} are needed", names.join(", "))))?;
                xd[k] = rate(n).unwrap_or(0.0);
                if !x[k].is_finite() {
                    return Err(SceneError::invalid(format!("initial.{n}"), x[k], "must be finite"));
                }
                if !xd[k].is_finite() {
                    return Err(SceneError::invalid(format!("initial.{n}_dot"), xd[k], "must be finite"));
                }
            }
            b.check_chart(&x).map_err(|e| {
                let point = if names.len() == 1 {
                    String::new()
                } else {
                    let given: Vec<String> = names.iter().zip(x.iter()).map(|(n, v)| format!("initial.{n} = {v:?}")).collect();
                    format!(" at the point {}", given.join(", "))
                };
                SceneError::invalid(format!("initial.{}", names[0]), x[0], format!("{e}{point}; at a chart pole give position/velocity instead"))
            })?;
            let g = b.from_chart(&x, &SMatrix::identity()).map_err(|e| SceneError::from_core(&format!("initial.{}", names[0]), e))?;
            let p = b.embed(&x);
            let v = b.embed_tangent(&x, &xd);
            // Far out on H² the embedding overflows (cosh(r/R) beyond
            // r/R ≈ 710): the coordinates given are at fault, not the
            // velocity computed from them.
            if !(p.iter().all(|c| c.is_finite()) && g_is_finite::<B, N, E>(b, &g)) {
                return Err(SceneError::invalid(
                    format!("initial.{}", names[0]),
                    x[0],
                    "gives a point whose embedding coordinates overflow double precision (on H², r/R must stay below about 710)",
                ));
            }
            if !v.iter().all(|c| c.is_finite()) {
                // The largest rate is at fault; the message gives them all.
                let k = (0..N).max_by(|&a, &b| xd[a].abs().total_cmp(&xd[b].abs())).unwrap_or(0);
                let rates: Vec<String> = names.iter().zip(xd.iter()).map(|(n, r)| format!("initial.{n}_dot = {r:?}")).collect();
                return Err(SceneError::invalid(
                    format!("initial.{}_dot", names[k]),
                    xd[k],
                    format!("gives a velocity whose embedding components overflow double precision (rates {})", rates.join(", ")),
                ));
            }
            let u = tangent_components(b, &g, &v, "v").map_err(init_error)?;
            Ok(Init { p, v, g, u })
        } else {
            let p = i.position.as_ref().ok_or_else(|| {
                SceneError::invalid("initial.position", "(missing)", format!("give the paper's coordinates ({}) or position = [...]", names.join(", ")))
            })?;
            let p = vec_n::<E>(p, "initial.position")?;
            let v = match &i.velocity {
                Some(v) => vec_n::<E>(v, "initial.velocity")?,
                None => SVector::zeros(),
            };
            let g = bundle_element_at(b, &p).map_err(init_error)?;
            let u = tangent_components(b, &g, &v, "v").map_err(init_error)?;
            Ok(Init { p, v, g, u })
        }
    }
}

/// Whether the bundle element's position and frame are finite.
fn g_is_finite<B: FrameBundle<N, E>, const N: usize, const E: usize>(b: &B, g: &B::Group) -> bool {
    b.position(g).iter().all(|c| c.is_finite()) && b.frame_vectors(g).iter().all(|c| c.is_finite())
}
