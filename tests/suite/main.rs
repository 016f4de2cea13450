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
mod torus;

lie_law_suite!(rn3, framedyn::lie::Rn<3>, radius = 5.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 5.0);
