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
