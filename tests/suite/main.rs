//! The core crate's first integration-test binary: the groups, manifolds,
//! frame bundles, coordinates, potentials and models, with the generic law
//! suites run for every implementation, and the tests of the core's
//! internals. The integrators, the driver, the scenes and the analyses are
//! tested by the second binary, `methods` (tests/suite/methods.rs): two
//! binaries compile side by side on two cores (docs/development.md, "The
//! two commands").

mod bundle_laws;
mod distance_laws;
mod lie_laws;
mod manifold_laws;

mod coords;
mod coords_state;
mod crosscheck;
mod crosscheck_affine;
mod dynamics_affine;
mod dynamics_gyro;
mod hyperbolic;
mod internals;
mod matrix_groups;
mod potentials;
mod sphere;
mod sphere3;
mod spheroid;
mod tangent_fields;
mod torus;

lie_law_suite!(rn3, framedyn::lie::Rn<3>, radius = 5.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 5.0);
// The tangent group G ⋉ 𝔤 (dual numbers over G): its laws hold like any
// group's, its closed-form dexp⁻¹ included (checked against dexp).
lie_law_suite!(tangent_so3, framedyn::lie::Tangent<framedyn::lie::So3>, radius = 2.5, tol = 1e-12, fd_tol = 1e-8, product_radius = 1.0);
lie_law_suite!(tangent_so12, framedyn::lie::Tangent<framedyn::lie::So12>, radius = 1.5, tol = 1e-12, fd_tol = 1e-8, product_radius = 2e-3);
lie_law_suite!(tangent_gl2, framedyn::lie::Tangent<framedyn::lie::Gl<2>>, radius = 2.0, tol = 1e-11, fd_tol = 1e-8, product_radius = 1e-5);
lie_law_suite!(tangent_bundle, framedyn::lie::Tangent<framedyn::lie::Product<framedyn::lie::So3, framedyn::lie::Rn<2>>>, radius = 2.5, tol = 1e-12, fd_tol = 1e-8, product_radius = 1.0);
