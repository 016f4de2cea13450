//! The core crate's second integration-test binary: the integrators and the
//! method registry, the driver (fixed and adaptive steps, events, stop
//! reasons), the scene engine and its ensembles, the analyses (Lyapunov
//! exponents, SALI, MEGNO, sections) and the validation against the paper.
//! Its files live beside those of `suite` (tests/suite/main.rs).

mod adaptive;
mod ensemble;
mod gali;
mod gauge;
mod integrators;
mod lyapunov;
mod megno;
mod registry;
mod scenes;
mod scenes_golden;
mod sections;
mod splitting;
mod testing;
mod stability;
mod implicit;
mod baselines;
mod validation;
