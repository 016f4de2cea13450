//! The geodesic-distance law suite, for the manifolds that implement
//! [`GeodesicDistance`]: [`check_distance_at`] (agreement with the metric at a
//! chart point) and [`check_distance_laws`] (metric-space laws at three
//! points), called by each such manifold's tests.

use framedyn::manifold::GeodesicDistance;
use nalgebra::SVector;

/// Checks, at the chart point `x`: the distance vanishes on the diagonal,
/// `d(p, p) = 0`, and agrees to first order with the metric,
/// `d(p, q) ≈ √(g_{ij} dx^i dx^j)` for `q` the embedding of `x + dx`,
/// `|dx| ~ 10⁻⁴` (relative error `O(|dx|)`, bounded by 10⁻³).
pub fn check_distance_at<M: GeodesicDistance<N, E>, const N: usize, const E: usize>(
    m: &M,
    x: &SVector<f64, N>,
) -> Result<(), String> {
    let check = |name: &str, err: f64, bound: f64| -> Result<(), String> {
        if err <= bound && err.is_finite() {
            Ok(())
        } else {
            Err(format!("{} at {x:?}: law `{name}` violated, error {err:e} > {bound:e}", M::NAME))
        }
    };
    m.check_chart(x).map_err(|e| format!("{} at {x:?}: check_chart failed: {e}", M::NAME))?;
    let g = m.metric(x);
    let p = m.embed(x);
    let v: SVector<f64, N> = SVector::from_fn(|i, _| 0.3 + 0.7 * i as f64);
    check("d(p, p) = 0", m.distance(&p, &p).map_err(|e| e.to_string())?, 1e-7)?;
    let dx = v * 1e-4;
    let q = m.embed(&(x + dx));
    let d = m.distance(&p, &q).map_err(|e| e.to_string())?;
    let ds = dx.dot(&(g * dx)).sqrt();
    check("d ≈ √(g dx dx) for nearby points", (d - ds).abs() / ds, 1e-3)?;
    Ok(())
}

/// Metric-space laws of `distance` at three embedded points: symmetry,
/// positivity and the triangle inequality.
pub fn check_distance_laws<M: GeodesicDistance<N, E>, const N: usize, const E: usize>(
    m: &M,
    p: &SVector<f64, E>,
    q: &SVector<f64, E>,
    r: &SVector<f64, E>,
) -> Result<(), String> {
    let d = |a: &SVector<f64, E>, b: &SVector<f64, E>| m.distance(a, b).map_err(|e| e.to_string());
    let (pq, qp, qr, pr) = (d(p, q)?, d(q, p)?, d(q, r)?, d(p, r)?);
    if (pq - qp).abs() > 1e-9 * (1.0 + pq) {
        return Err(format!("{}: distance not symmetric: {pq} vs {qp}", M::NAME));
    }
    if pq < 0.0 || !pq.is_finite() {
        return Err(format!("{}: distance {pq} invalid", M::NAME));
    }
    if pr > pq + qr + 1e-9 * (1.0 + pr) {
        return Err(format!("{}: triangle inequality violated: {pr} > {pq} + {qr}", M::NAME));
    }
    Ok(())
}
