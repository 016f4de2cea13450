//! The serde description of a scene (TOML or JSON). Every table denies
//! unknown fields; ranges and combinations are checked by
//! [`Scene::validate`](super::Scene::validate).

use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;
use std::fmt;

use super::potential::Series;

/// One number or an array of numbers (`spin = 0.5` or `spin = [0.1, 0, 0.3]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Numbers(pub Vec<f64>);

impl Serialize for Numbers {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.0.len() == 1 {
            s.serialize_f64(self.0[0])
        } else {
            self.0.serialize(s)
        }
    }
}

impl<'de> Deserialize<'de> for Numbers {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Numbers;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Numbers, E> {
                Ok(Numbers(vec![v]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Numbers, E> {
                Ok(Numbers(vec![v as f64]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Numbers, E> {
                Ok(Numbers(vec![v as f64]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Numbers, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    out.push(v);
                }
                Ok(Numbers(out))
            }
        }
        d.deserialize_any(V)
    }
}

/// Optional integer fields (`method.max_steps`, `method.newton_max_iter`,
/// `output.every`, `output.samples`): serde's own messages say `expected
/// u64`; these say the range the field takes. Values within the type's range
/// are accepted here and checked against the field's range where the scene
/// is validated (with the field's own error).
mod count {
    use super::*;

    /// One integer up to `max`, described as `expected`.
    #[derive(Clone, Copy)]
    struct Int {
        expected: &'static str,
        max: u64,
    }

    impl<'de> Visitor<'de> for Int {
        type Value = u64;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str(self.expected)
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<u64, E> {
            if v > self.max {
                return Err(E::invalid_value(de::Unexpected::Unsigned(v), &self));
            }
            Ok(v)
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<u64, E> {
            match u64::try_from(v) {
                Ok(u) => self.visit_u64(u),
                Err(_) => Err(E::invalid_value(de::Unexpected::Signed(v), &self)),
            }
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<u64, E> {
            // JSON integers beyond 64 bits arrive as floats.
            if v.fract() == 0.0 && v.abs() >= 18_446_744_073_709_551_616.0 {
                return Err(E::invalid_value(de::Unexpected::Other(&format!("{v:e} (beyond 64 bits)")), &self));
            }
            Err(E::invalid_type(de::Unexpected::Float(v), &self))
        }
    }

    /// `None` for a JSON `null`, else the integer.
    struct Opt(Int);

    impl<'de> Visitor<'de> for Opt {
        type Value = Option<u64>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            self.0.expecting(f)
        }
        fn visit_none<E: de::Error>(self) -> Result<Option<u64>, E> {
            Ok(None)
        }
        fn visit_unit<E: de::Error>(self) -> Result<Option<u64>, E> {
            Ok(None)
        }
        fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Option<u64>, D::Error> {
            d.deserialize_u64(self.0).map(Some)
        }
    }

    fn opt<'de, D: Deserializer<'de>>(d: D, expected: &'static str, max: u64) -> Result<Option<u64>, D::Error> {
        d.deserialize_option(Opt(Int { expected, max }))
    }

    /// `method.max_steps`, `output.every`.
    pub(super) fn at_least_one<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
        opt(d, "an integer in 1 ..= 2^64 − 1", u64::MAX)
    }

    /// `output.samples`.
    pub(super) fn samples<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
        opt(d, "an integer in 2 ..= 1e8", u64::MAX)
    }

    /// `method.newton_max_iter`.
    pub(super) fn newton_max_iter<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u32>, D::Error> {
        // `opt` refuses values above u32::MAX, so the conversion cannot fail.
        opt(d, "an integer in 1 ..= 1000", u64::from(u32::MAX)).map(|v| v.and_then(|n| u32::try_from(n).ok()))
    }
}

pub use super::manifolds::{ManifoldKind, ManifoldSpec};

/// The body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyKind {
    /// A structureless material point.
    Point,
    /// A gyroscope (orthonormal frame; SO(n) fibre).
    Gyroscope,
    /// An affinely-rigid body (GL⁺(n) fibre).
    Affine,
    /// An incompressible affine body (SL(n) fibre).
    Incompressible,
    /// A Weyl body: rotations and dilatations (CO⁺(n) fibre).
    Weyl,
    /// A purely dilatational body (ℝ⁺ fibre).
    Dilatation,
}

impl BodyKind {
    /// Whether the body has an internal (frame) configuration of GL type.
    pub fn is_affine(self) -> bool {
        matches!(self, BodyKind::Affine | BodyKind::Incompressible | BodyKind::Weyl | BodyKind::Dilatation)
    }
}

/// Sign of the internal kinetic energy of a gyroscope.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SignatureSpec {
    /// `+` (a52).
    #[default]
    Riemannian,
    /// The indefinite Lorentz-type gyroscope of (a138).
    Lorentz,
}

/// `[body]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// `"point"`, `"gyroscope"`, `"affine"`, `"incompressible"`, `"weyl"`, `"dilatation"`.
    pub kind: BodyKind,
    /// Mass `m > 0` (default 1).
    #[serde(default = "one")]
    pub mass: f64,
    /// Isotropic moment `I > 0`: `J = (I/2)δ` for a gyroscope (so `Tr J = I`
    /// in 2-D), `J = I·δ` for affine bodies (§5). Default 1 unless `J` is given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
    /// The full inertia `J^{AB}` (n×n, rows), symmetric positive definite.
    #[serde(default, rename = "J", skip_serializing_if = "Option::is_none")]
    pub j: Option<Vec<Vec<f64>>>,
    /// Gyroscopes only: `"riemannian"` (default) or `"lorentz"` (a138).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub signature: Option<SignatureSpec>,
}

fn one() -> f64 {
    1.0
}

/// The potential family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PotentialKind {
    /// `V = 0`.
    #[default]
    None,
    /// Bertrand oscillator, parameter `kappa` (S², H², S³).
    Oscillator,
    /// Bertrand Kepler potential, parameter `alpha` (S², H², S³).
    Kepler,
    /// `alpha_hat·cos²(r/R) + beta_hat·cos(r/R)` (S², H², S³).
    Cosine,
    /// Central `V(r)` = the series `v` (S², H², S³).
    Central,
    /// The elastic potential (a131), parameter `kappa` (2-D affine bodies).
    Elastic,
    /// Separable `V_r(r) + V_ϱ(ϱ) + V_ε(ε)/ϱ²` (b128), series `v_r`, `v_rho`,
    /// `v_eps` (2-D; `r` is the torus angle ϑ on T²).
    Separable,
    /// Neo-Hookean `W(I₁, I₂, I₃)`, parameters `lambda`, `mu` (S³ affine bodies).
    NeoHookean,
    /// Saint Venant–Kirchhoff, parameters `lambda`, `mu` (S³ affine bodies).
    StVenantKirchhoff,
    /// The sum of `terms` (each with an optional `scale`).
    Sum,
}

/// `[potential]` (also each entry of `terms`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PotentialSpec {
    /// The family (default `"none"`).
    #[serde(default)]
    pub kind: PotentialKind,
    /// A factor multiplying the potential (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Oscillator and elastic constant κ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kappa: Option<f64>,
    /// Kepler constant α.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// α̂ of the cosine family.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_hat: Option<f64>,
    /// β̂ of the cosine family.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta_hat: Option<f64>,
    /// Lamé constant λ (S³ invariant potentials).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lambda: Option<f64>,
    /// Shear modulus μ (S³ invariant potentials).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Centre of a central potential, embedding coordinates (default: the
    /// pole of the paper's chart).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<Vec<f64>>,
    /// `V(r)` of a central potential.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v: Option<Series>,
    /// `V_r` of a separable potential.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_r: Option<Series>,
    /// `V_ϱ` of a separable potential.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_rho: Option<Series>,
    /// `V_ε` of a separable potential.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_eps: Option<Series>,
    /// The terms of a sum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub terms: Option<Vec<PotentialSpec>>,
}

/// `[initial]`: either the chart coordinates of the manifold, named as the
/// manifold names them ([`Manifold::coordinate_names`](crate::manifold::Manifold::coordinate_names):
/// `r, phi` on S² and H², `theta, phi` on T², `r1, r2, r3` on S³, `lat, lon`
/// on the spheroid), with their rates `*_dot`; or the embedding
/// (`position`, `velocity`, optionally `frame`); plus the internal state of
/// the body. Every key that is not one of the fixed fields below is read as
/// a chart coordinate (a number) and checked against the manifold when the
/// scene is built.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct InitialSpec {
    /// Chart coordinates and rates by name (`r`, `phi_dot`, …).
    pub coordinates: BTreeMap<String, f64>,
    /// Embedding position (3 or 4 numbers).
    pub position: Option<Vec<f64>>,
    /// Embedding velocity (tangent at `position`).
    pub velocity: Option<Vec<f64>>,
    /// Gyroscope body frame as a list of its vectors `e_A` (embedding
    /// components; orthonormal, tangent, positively oriented).
    pub frame: Option<Vec<Vec<f64>>>,
    /// 2-D gyroscope: angle `α` of the body frame from the reference frame
    /// (the manifold's frame field `E(x)`, or a Gram–Schmidt frame at a chart
    /// pole).
    pub alpha: Option<f64>,
    /// S³ gyroscope: rotation vector of the body frame from the reference frame.
    pub orientation: Option<Vec<f64>>,
    /// Gyroscope spin (2-D: a number; S³: three body components).
    pub spin: Option<Numbers>,
    /// Gyroscope angular velocity instead of `spin` (2-D: `α̇` relative to
    /// the parallel frame; S³: body components).
    pub omega: Option<Numbers>,
    /// Affine bodies: internal configuration `ρ` (n×n rows), `e = q·ρ` with
    /// `q` the reference frame (default identity).
    pub rho: Option<Vec<Vec<f64>>>,
    /// Affine bodies: internal velocity `ρ̇` (n×n rows, default 0).
    pub rho_dot: Option<Vec<Vec<f64>>>,
}

impl InitialSpec {
    /// The fixed (non-coordinate) fields of `[initial]`.
    pub const FIELDS: [&'static str; 9] = ["position", "velocity", "frame", "alpha", "orientation", "spin", "omega", "rho", "rho_dot"];

    /// The chart coordinate or rate `name`, if given.
    pub fn coordinate(&self, name: &str) -> Option<f64> {
        self.coordinates.get(name).copied()
    }

    /// Sets the chart coordinate or rate `name`.
    pub fn with_coordinate(mut self, name: &str, value: f64) -> Self {
        self.coordinates.insert(name.to_string(), value);
        self
    }
}

impl Serialize for InitialSpec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        for (k, v) in &self.coordinates {
            m.serialize_entry(k, v)?;
        }
        macro_rules! opt {
            ($($f:ident),*) => {$(
                if let Some(v) = &self.$f {
                    m.serialize_entry(stringify!($f), v)?;
                }
            )*};
        }
        opt!(position, velocity, frame, alpha, orientation, spin, omega, rho, rho_dot);
        m.end()
    }
}

impl<'de> Deserialize<'de> for InitialSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = InitialSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table of chart coordinates (numbers) and the fields position, velocity, frame, alpha, orientation, spin, omega, rho, rho_dot")
            }
            fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<InitialSpec, A::Error> {
                let mut out = InitialSpec::default();
                while let Some(key) = map.next_key::<String>()? {
                    macro_rules! field {
                        ($f:ident) => {{
                            if out.$f.is_some() {
                                return Err(de::Error::duplicate_field(stringify!($f)));
                            }
                            out.$f = map.next_value()?;
                        }};
                    }
                    match key.as_str() {
                        "position" => field!(position),
                        "velocity" => field!(velocity),
                        "frame" => field!(frame),
                        "alpha" => field!(alpha),
                        "orientation" => field!(orientation),
                        "spin" => field!(spin),
                        "omega" => field!(omega),
                        "rho" => field!(rho),
                        "rho_dot" => field!(rho_dot),
                        _ => {
                            if out.coordinates.contains_key(&key) {
                                return Err(de::Error::custom(format_args!("duplicate coordinate `{key}`")));
                            }
                            let v: f64 = map.next_value().map_err(|e: A::Error| {
                                de::Error::custom(format_args!(
                                    "`{key}` is read as a chart coordinate and must be a number ({e}); the other fields of [initial] are {}",
                                    InitialSpec::FIELDS.join(", ")
                                ))
                            })?;
                            out.coordinates.insert(key, v);
                        }
                    }
                }
                Ok(out)
            }
        }
        d.deserialize_map(V)
    }
}

/// `[method]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// The method's name, one of the registry's
    /// ([`METHODS`](crate::method::METHODS)); default RKMK4.
    #[serde(default = "default_method")]
    pub name: String,
    /// Fixed step size (upper bound; the span is split into equal steps).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub h: Option<f64>,
    /// Relative tolerance (adaptive methods; default 1e-8), finite and
    /// `≥ 1e-14`. A bound on each step's local error, not on the run's
    /// global error: see [`Adaptive`](crate::solve::Adaptive) and
    /// `docs/performance.md`, "Tolerance proportionality".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rtol: Option<f64>,
    /// Absolute tolerance (adaptive methods; default 1e-10), finite and `> 0`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atol: Option<f64>,
    /// Limit on the number of accepted steps (default 10⁹).
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "count::at_least_one")]
    pub max_steps: Option<u64>,
    /// Estimate the run's global error (default false): the run is repeated
    /// with a hundredth of the tolerances (a quarter of the fixed step) and
    /// compared at every record; see
    /// [`GlobalError`](super::GlobalError). Costs the reference run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub global_error: Option<bool>,
    /// Project the end of every accepted step back onto the initial energy:
    /// `"energy"`, or `"none"` (default). For flows that turn energy errors
    /// into growing phase errors (Kepler-type pericentre passages); see
    /// [`projection`](crate::solve::projection) and `docs/performance.md`,
    /// "Tolerance proportionality", for what it gains and costs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub project: Option<String>,
    /// `implicit_midpoint` only: Newton tolerance (relative, max norm) in
    /// `[1e-16, 1e-2]` (default 1e-14).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub newton_tol: Option<f64>,
    /// `implicit_midpoint` only: Newton iterations per step, `1 ..= 1000`
    /// (default 30).
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "count::newton_max_iter")]
    pub newton_max_iter: Option<u32>,
}

fn default_method() -> String {
    crate::method::registry::RK4.name.into()
}

impl Default for MethodSpec {
    fn default() -> Self {
        MethodSpec { name: default_method(), h: None, rtol: None, atol: None, max_steps: None, global_error: None, project: None, newton_tol: None, newton_max_iter: None }
    }
}

/// `[time]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// Start `t₀` (default 0).
    #[serde(default)]
    pub t0: f64,
    /// End `t_end` (≠ t₀; may be earlier: backwards integration).
    pub t_end: f64,
}

/// Output quantities (column groups).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Embedding position `x0 …`.
    Position,
    /// Embedding velocity `v0 …`.
    Velocity,
    /// Body frame vectors `e1_0 …` (embedding components).
    Frame,
    /// The paper's coordinates and their rates (NaN where the chart is singular).
    Coordinates,
    /// Momenta of the internal motion (spin, hypermomentum).
    Momenta,
    /// Affine bodies: the covariant rate `De/Dt` of the body frame vectors
    /// (embedding components, `de1_0 …`).
    FrameRate,
    /// Total energy.
    Energy,
    /// Momentum maps (p_φ; on S³ the six so(4) charges).
    MomentumMap,
    /// Constraint defect.
    Defect,
}

impl Quantity {
    /// The name in scene files and listings (`"position"`, `"momentum_map"`, …).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Position => "position",
            Quantity::Velocity => "velocity",
            Quantity::Frame => "frame",
            Quantity::Coordinates => "coordinates",
            Quantity::Momenta => "momenta",
            Quantity::FrameRate => "frame_rate",
            Quantity::Energy => "energy",
            Quantity::MomentumMap => "momentum_map",
            Quantity::Defect => "defect",
        }
    }

    /// All quantities, in column order.
    pub const ALL: [Quantity; 9] = [
        Quantity::Position,
        Quantity::Velocity,
        Quantity::Frame,
        Quantity::Coordinates,
        Quantity::Momenta,
        Quantity::FrameRate,
        Quantity::Energy,
        Quantity::MomentumMap,
        Quantity::Defect,
    ];
}

/// Output file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// Comma-separated values with a header line.
    Csv,
    /// A numpy `.npz` archive (`data`, `columns`, `units`).
    Npz,
}

/// `[output]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Record every N-th accepted step (and the first and last state).
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "count::at_least_one")]
    pub every: Option<u64>,
    /// Record exactly at these times (within the span).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub times: Option<Vec<f64>>,
    /// Record at this many equally spaced times including both ends (≥ 2).
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "count::samples")]
    pub samples: Option<u64>,
    /// Column groups to record (default: all).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quantities: Option<Vec<Quantity>>,
    /// File format (default from the extension of `path`, else CSV).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub format: Option<Format>,
    /// Output path (default `trajectory.csv`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
}

/// `[quality]`: the limits a finished run is judged against
/// ([`RunSummary::warnings`](super::RunSummary::warnings)). A run over a
/// limit, or with a non-finite energy or defect in any record, still
/// writes its records, but its summary carries the warning (the command
/// line exits with code 6, Python warns).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QualitySpec {
    /// Largest accepted energy drift `max |E − E₀|`, relative to `|E₀|`
    /// (absolute when `|E₀| < 1e-12`); default [`QualitySpec::ENERGY_DRIFT`];
    /// `inf` switches the check off (for runs whose energy is not meant to
    /// be conserved to any accuracy).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_drift: Option<f64>,
    /// Largest accepted constraint defect of the states (distance of the
    /// frame from its group); default [`QualitySpec::DEFECT`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub defect: Option<f64>,
}

impl QualitySpec {
    /// Default limit of the relative energy drift: 1e-3 (every embedded
    /// scene stays below 3e-7).
    pub const ENERGY_DRIFT: f64 = 1e-3;
    /// Default limit of the constraint defect: 1e-9 (every method keeps the
    /// state on its group to round-off, ~1e-15).
    pub const DEFECT: f64 = 1e-9;

    /// Whether nothing is set (the table is then left out when saving).
    pub fn is_default(&self) -> bool {
        self.energy_drift.is_none() && self.defect.is_none()
    }

    /// The limits with the defaults filled in.
    pub fn limits(&self) -> (f64, f64) {
        (self.energy_drift.unwrap_or(Self::ENERGY_DRIFT), self.defect.unwrap_or(Self::DEFECT))
    }
}

/// The built-in event functions `g` of `[[events]]` (a crossing is a zero of
/// `g` along the trajectory).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// `g = normal·x − offset` with `x` the embedding position (a plane of
    /// the ambient space: Poincaré sections; `normal = [0, 0, 1]` is the
    /// equator plane of S²).
    Plane,
    /// `g = |x − point| − distance`, the Euclidean distance in the embedding
    /// coordinates (pole passage: `point` = the pole, small `distance`).
    Distance,
    /// `g = column − value` for any record column (all quantities are
    /// available whatever `output.quantities` says): the paper's coordinates
    /// `r`, `phi`, `theta`, `r1`…, `energy`, `spin`, `x2`, …
    Column,
}

/// Which sign changes of `g` an event reports: `"rising"` (from negative to
/// non-negative), `"falling"` (from positive to non-positive) or `"either"`
/// (default) — the driver's [`Direction`](crate::solve::Direction).
pub use crate::solve::Direction as EventDirection;

/// One `[[events]]` entry: a built-in event function, the direction of the
/// crossings reported and whether the first one stops the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventSpec {
    /// `"plane"`, `"distance"` or `"column"`.
    pub kind: EventKind,
    /// Name in the output (default `event{i}`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// `plane`: the normal `n` (embedding components, non-zero).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<Vec<f64>>,
    /// `plane`: the offset `c` of `n·x = c` (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
    /// `distance`: the point `p` (embedding components).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<Vec<f64>>,
    /// `distance`: the distance `d ≥ 0`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<f64>,
    /// `column`: the column's name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column: Option<String>,
    /// `column`: the value crossed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// `"rising"`, `"falling"` or `"either"` (default).
    #[serde(default)]
    pub direction: EventDirection,
    /// Stop the run at the first reported crossing (default false).
    #[serde(default)]
    pub terminal: bool,
}
