//! Numerical geodesics, for manifolds whose geodesic distance has no closed
//! form. The torus T² is the one: its minimal geodesics and the
//! [`GeodesicDistance`](super::GeodesicDistance) implementation of
//! [`Torus2`](super::Torus2) are in the private module `torus2` (public items:
//! [`TorusGeodesic`] and the inherent methods
//! [`Torus2::minimal_geodesic`](super::Torus2::minimal_geodesic),
//! [`Torus2::chart_distance`](super::Torus2::chart_distance) and
//! [`Torus2::geodesic_endpoint`](super::Torus2::geodesic_endpoint)); its
//! Clairaut quadratures use the adaptive Gauss–Kronrod rule of `gauss_kronrod`.

pub(crate) mod gauss_kronrod;
pub(crate) mod torus2;

pub use torus2::TorusGeodesic;
