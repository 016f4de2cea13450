//! The embedded example scenes (`src/scenes/examples/*.toml`).

use super::{Scene, SceneError};

macro_rules! examples {
    ($($name:literal),* $(,)?) => {
        /// The embedded example scenes: `(name, TOML text)`. Every one
        /// parses, validates and runs (tested).
        pub const EXAMPLES: &[(&str, &str)] = &[
            $(($name, include_str!(concat!("examples/", $name, ".toml"))),)*
        ];
    };
}

examples!(
    "s2-gyroscope-pole",
    "h2-affine-separable",
    "h2-dilatation",
    "h2-gyroscope",
    "h2-gyroscope-lorentz",
    "h2-incompressible-elastic",
    "h2-point-bound",
    "h2-point-escape",
    "h2-point-kepler",
    "h2-weyl",
    "s2-affine-elastic",
    "s2-dilatation-separable",
    "s2-gyroscope-cosine",
    "s2-incompressible-elastic",
    "s2-point-central",
    "s2-point-kepler",
    "s2-point-oscillator",
    "s2-point-sum",
    "s2-gyroscope-splitting",
    "s2-weyl-separable",
    "s3-affine-neo-hookean",
    "s3-dilatation",
    "s3-gyroscope",
    "s3-incompressible-svk",
    "s3-point-kepler",
    "s3-point-oscillator",
    "s3-weyl",
    "t2-affine-elastic",
    "t2-dilatation",
    "t2-gyroscope-separable",
    "t2-incompressible",
    "t2-point",
    "t2-weyl",
    "spheroid-point-geodesic",
    "spheroid-gyroscope",
    "spheroid-affine-elastic",
);

/// The scene `framedyn run` uses without arguments: a gyroscope on S² whose
/// path crosses the north pole, where the paper's coordinates are singular.
pub const DEFAULT_SCENE: &str = "s2-gyroscope-pole";

/// The embedded scene `name`, parsed.
pub fn example(name: &str) -> Result<Scene, SceneError> {
    match EXAMPLES.iter().find(|(n, _)| *n == name) {
        Some((_, text)) => Scene::from_toml_str(text),
        None => Err(SceneError::UnknownScene {
            name: name.to_string(),
            available: EXAMPLES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", "),
        }),
    }
}
