//! The core crate's integration-test binary: generic law suites, run for every
//! implementation (one binary, so the crate is linked once).

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
mod adaptive;
mod ensemble;
mod hyperbolic;
mod integrators;
mod internals;
mod lyapunov;
mod matrix_groups;
mod megno;
mod potentials;
mod registry;
mod scenes;
mod scenes_golden;
mod sections;
mod sphere;
mod sphere3;
mod spheroid;
mod splitting;
mod testing;
mod stability;
mod implicit;
mod baselines;
mod torus;
mod validation;

lie_law_suite!(rn3, framedyn::lie::Rn<3>, radius = 5.0, tol = 1e-14, fd_tol = 1e-9, product_radius = 5.0);
