//! The manifolds a scene can name: the `[manifold]` table (`kind` and its
//! fields) and, for each kind, how the manifold is built and what it offers
//! the potential families. This is the one place of the scene layer that
//! knows the manifolds: everything else (initial state, models, records,
//! methods) is generic over the frame bundle. Adding a manifold to scenes
//! is a variant of [`ManifoldKind`], its fields in [`ManifoldSpec`] and its
//! arm in [`Scene::build_engine`].

use serde::{Deserialize, Serialize};

use super::chart::NoChart;
use super::error::SceneError;
use super::potential::{build_potential2, build_potential3, Potential2, Potential3, SpacePotentials, SurfacePotentials, UserFunctions, UserPotential};
use super::scene::Scene;
use super::build::Make;
use super::spec::BodyKind;
use crate::coords::{HyperbolicChart, Sphere3Chart, SphereChart, TorusChart};
use crate::manifold::{Hyperbolic2, Sphere2, Sphere3, Spheroid, Torus2};
use crate::potential::{Centre, TorusAngle};

/// The manifold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ManifoldKind {
    /// The sphere S²(R) ⊂ ℝ³.
    S2,
    /// The hyperbolic plane H²(R) ⊂ ℝ^{2,1} (upper sheet).
    H2,
    /// The torus T²(L, R) ⊂ ℝ³.
    T2,
    /// The three-sphere S³(R) ⊂ ℝ⁴.
    S3,
    /// The spheroid (ellipsoid of revolution) with equatorial radius `a` and
    /// polar radius `c` ⊂ ℝ³ (oblate `c < a`, prolate `c > a`).
    #[serde(rename = "spheroid")]
    Spheroid,
}

impl ManifoldKind {
    /// Every kind, in the order of listings.
    pub const ALL: [ManifoldKind; 5] = [ManifoldKind::S2, ManifoldKind::H2, ManifoldKind::T2, ManifoldKind::S3, ManifoldKind::Spheroid];

    /// The name in scene files (`kind = "S2"`).
    pub fn name(self) -> &'static str {
        match self {
            ManifoldKind::S2 => "S2",
            ManifoldKind::H2 => "H2",
            ManifoldKind::T2 => "T2",
            ManifoldKind::S3 => "S3",
            ManifoldKind::Spheroid => "spheroid",
        }
    }

    /// The fields of `[manifold]` this kind takes (besides `kind`).
    pub fn fields(self) -> &'static [&'static str] {
        match self {
            ManifoldKind::S2 | ManifoldKind::H2 | ManifoldKind::S3 => &["radius"],
            ManifoldKind::T2 => &["L", "R"],
            ManifoldKind::Spheroid => &["equatorial_radius", "polar_radius"],
        }
    }

    /// The names of its chart coordinates (the keys of `[initial]`, each
    /// also with its rate `*_dot`), as the manifold names them
    /// ([`Manifold::coordinate_names`](crate::manifold::Manifold::coordinate_names)).
    pub fn coordinate_names(self) -> Vec<&'static str> {
        use crate::manifold::Manifold;
        match self {
            ManifoldKind::S2 => Sphere2::new(1.0).map(|m| m.coordinate_names().to_vec()).unwrap_or_default(),
            ManifoldKind::H2 => Hyperbolic2::new(1.0).map(|m| m.coordinate_names().to_vec()).unwrap_or_default(),
            ManifoldKind::T2 => Torus2::new(2.0, 1.0).map(|m| m.coordinate_names().to_vec()).unwrap_or_default(),
            ManifoldKind::S3 => Sphere3::new(1.0).map(|m| m.coordinate_names().to_vec()).unwrap_or_default(),
            ManifoldKind::Spheroid => Spheroid::new(1.0, 1.0).map(|m| m.coordinate_names().to_vec()).unwrap_or_default(),
        }
    }
}

/// `[manifold]`: `kind` and its size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ManifoldSpec {
    /// `"S2"`, `"H2"`, `"T2"`, `"S3"` or `"spheroid"`.
    pub kind: ManifoldKind,
    /// `R` of S², H², S³ (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// `L`, the major radius of T² (default 2).
    #[serde(default, alias = "L", skip_serializing_if = "Option::is_none")]
    pub major: Option<f64>,
    /// `R`, the minor radius of T² (default 1).
    #[serde(default, alias = "R", skip_serializing_if = "Option::is_none")]
    pub minor: Option<f64>,
    /// The spheroid's equatorial radius `a` (required).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equatorial_radius: Option<f64>,
    /// The spheroid's polar radius `c` (required).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polar_radius: Option<f64>,
}

impl ManifoldSpec {
    /// Refuses the fields this kind does not take.
    fn only(&self, takes: &[&str]) -> Result<(), SceneError> {
        let given = [
            ("radius", self.radius),
            ("L", self.major),
            ("R", self.minor),
            ("equatorial_radius", self.equatorial_radius),
            ("polar_radius", self.polar_radius),
        ];
        for (field, value) in given {
            if let Some(v) = value {
                if !takes.contains(&field) {
                    return Err(SceneError::invalid(
                        format!("manifold.{field}"),
                        v,
                        format!("kind = \"{}\" takes {}", self.kind.name(), takes.join(", ")),
                    ));
                }
            }
        }
        Ok(())
    }
}

impl Scene {
    /// The engine of this scene's body on its manifold, with the scene's
    /// potential plus the user potential, if any, over `span`.
    pub(crate) fn build_engine<K: Make>(&self, user: Option<UserFunctions>, span: &(f64, f64)) -> Result<K::Out, SceneError> {
        let ms = &self.manifold;
        let span = *span;
        let user2 = |pot: Potential2, length: f64| -> Result<Potential2, SceneError> {
            Ok(match user.clone() {
                None => pot,
                Some(u) => {
                    let u = UserPotential::new(u, self.body.kind != BodyKind::Point, length).map_err(|e| SceneError::from_core("potential", e))?;
                    Potential2::Sum(vec![(1.0, pot), (1.0, Potential2::User(u))])
                }
            })
        };
        match ms.kind {
            ManifoldKind::S2 => {
                ms.only(ms.kind.fields())?;
                let m = Sphere2::new(ms.radius.unwrap_or(1.0)).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                let centre = |c: Option<&nalgebra::Vector3<f64>>| match c {
                    None => Ok(Centre::sphere2(&m)),
                    Some(c) => Centre::sphere2_at(&m, c),
                };
                let ctx = SurfacePotentials { name: "S2", centre: Some(&centre), torus: None, cosine: None, length: m.radius() };
                let pot = user2(build_potential2(&self.potential, "potential", &ctx)?, ctx.length)?;
                let chart = SphereChart::new(m.radius()).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                self.surface_engine::<K, _, _>(m, pot, span, Some(chart))
            }
            ManifoldKind::H2 => {
                ms.only(ms.kind.fields())?;
                let m = Hyperbolic2::new(ms.radius.unwrap_or(1.0)).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                let centre = |c: Option<&nalgebra::Vector3<f64>>| match c {
                    None => Ok(Centre::hyperbolic2(&m)),
                    Some(c) => Centre::hyperbolic2_at(&m, c),
                };
                let ctx = SurfacePotentials { name: "H2", centre: Some(&centre), torus: None, cosine: None, length: m.radius() };
                let pot = user2(build_potential2(&self.potential, "potential", &ctx)?, ctx.length)?;
                let chart = HyperbolicChart::new(m.radius()).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                self.surface_engine::<K, _, _>(m, pot, span, Some(chart))
            }
            ManifoldKind::T2 => {
                ms.only(ms.kind.fields())?;
                let (l, r) = (ms.major.unwrap_or(2.0), ms.minor.unwrap_or(1.0));
                let note = format!("manifold.L = {l:?}, manifold.R = {r:?}");
                let m = Torus2::new(l, r).map_err(|e| SceneError::from_core("manifold", e).with_note(&note))?;
                let angle = TorusAngle::new(l, r).map_err(|e| SceneError::from_core("manifold", e))?;
                let ctx = SurfacePotentials { name: "T2", centre: None, torus: Some(angle), cosine: None, length: r };
                let pot = user2(build_potential2(&self.potential, "potential", &ctx)?, ctx.length)?;
                let chart = TorusChart::new(l, r).map_err(|e| SceneError::from_core("manifold", e))?;
                self.surface_engine::<K, _, _>(m, pot, span, Some(chart))
            }
            ManifoldKind::S3 => {
                ms.only(ms.kind.fields())?;
                let m = Sphere3::new(ms.radius.unwrap_or(1.0)).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                let centre = |c: Option<&nalgebra::Vector4<f64>>| match c {
                    None => Ok(Centre::sphere3(&m)),
                    Some(c) => Centre::sphere3_at(&m, c),
                };
                let ctx = SpacePotentials { name: "S3", centre: Some(&centre), length: m.radius() };
                let pot = build_potential3(&self.potential, "potential", &ctx)?;
                let pot = match user {
                    None => pot,
                    Some(u) => Potential3::Sum(vec![
                        (1.0, pot),
                        (1.0, Potential3::User(UserPotential::new(u, true, ctx.length).map_err(|e| SceneError::from_core("potential", e))?)),
                    ]),
                };
                let chart = Sphere3Chart::new(m.radius()).map_err(|e| SceneError::from_core("manifold.radius", e))?;
                self.space_engine::<K, _, _>(m, pot, span, Some(chart))
            }
            ManifoldKind::Spheroid => {
                ms.only(ms.kind.fields())?;
                let req = |v: Option<f64>, f: &str| v.ok_or_else(|| SceneError::invalid(format!("manifold.{f}"), "(missing)", "required for kind = \"spheroid\""));
                let (a, c) = (req(ms.equatorial_radius, "equatorial_radius")?, req(ms.polar_radius, "polar_radius")?);
                let note = format!("manifold.equatorial_radius = {a:?}, manifold.polar_radius = {c:?}");
                let m = Spheroid::new(a, c).map_err(|e| SceneError::from_core("manifold", e).with_note(&note))?;
                // The cosine family in the height along the axis, z/c: the
                // axial component of the pole of the sphere of radius c.
                let axis = Centre::sphere2(&Sphere2::new(c).map_err(|e| SceneError::from_core("manifold.polar_radius", e))?);
                let ctx = SurfacePotentials { name: "spheroid", centre: None, torus: None, cosine: Some(axis), length: a.min(c) };
                let pot = user2(build_potential2(&self.potential, "potential", &ctx)?, ctx.length)?;
                self.surface_engine::<K, _, _>(m, pot, span, None::<NoChart>)
            }
        }
    }
}
