//! MEGNO, the Mean Exponential Growth factor of Nearby Orbits (Cincotta &
//! Simó 2000): a fast chaos indicator from one tangent vector carried by
//! the tangent map of each step (see the [module documentation](super)).
//!
//! In continuous time `Y(t) = (2/t) ∫₀ᵗ (δ·δ̇/|δ|²) s ds` and its mean
//! `⟨Y⟩(t) = (1/t) ∫₀ᵗ Y(s) ds`. With the discrete tangent map the
//! integrand is the increment of `log |δ|` over a step, and the standard
//! discrete form (Cincotta, Giordano & Simó 2003, for maps) is, with
//! `t_k = k h` after `k` steps from `t₀`,
//!
//! ```text
//! Y(t_N)   = (2/t_N) Σ_{k=1}^{N} t_k log(|δ_k| / |δ_{k−1}|)
//! ⟨Y⟩(t_N) = (1/t_N) Σ_{k=1}^{N} h Y(t_k)
//! ```
//!
//! For a quasi-periodic orbit `|δ|` grows linearly and `⟨Y⟩ → 2`; for a
//! stable, isochronous periodic orbit `|δ|` stays bounded and `⟨Y⟩ → 0`;
//! for a chaotic orbit `log |δ| ≈ λ₁ t`, `Y ≈ λ₁ t` and `⟨Y⟩ ≈ λ₁ t/2`
//! (Cincotta & Simó 2000). [`MegnoEstimate::slope`], the least-squares
//! slope of `⟨Y⟩` over the second half of the run, therefore estimates
//! `λ₁/2` on a chaotic orbit and tends to 0 on a regular one.

use std::sync::atomic::{AtomicBool, Ordering};

use super::tangent::{step_with_tangents, Linearisation};
use super::AnalysisError;
use crate::dynamics::System;
use crate::lie::LieGroup;
use crate::method::{GroupNumerics, Method};

/// Settings of [`megno`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MegnoOptions {
    /// Fixed step `h > 0`.
    pub h: f64,
    /// Integration time `T > 0`; `round(T/h)` steps of equal size (at most 1e9).
    pub duration: f64,
    /// Seed of the random initial tangent vector (the same vector as the
    /// first column of [`lyapunov_spectrum`](super::lyapunov_spectrum) with this seed).
    pub seed: u64,
    /// The linearisation of the one-step map.
    pub linearisation: Linearisation,
}

impl MegnoOptions {
    /// Seed 1 and the default linearisation.
    pub fn new(h: f64, duration: f64) -> Self {
        MegnoOptions { h, duration, seed: 1, linearisation: Linearisation::default() }
    }
}

/// MEGNO along the run.
#[derive(Debug, Clone, PartialEq)]
pub struct MegnoEstimate {
    /// `Y` at the end of the run.
    pub megno: f64,
    /// Its mean `⟨Y⟩` at the end of the run: → 2 on a quasi-periodic orbit,
    /// → 0 on a stable isochronous periodic one, grows like `λ₁t/2` on a
    /// chaotic one.
    pub mean: f64,
    /// Least-squares slope of `⟨Y⟩(t)` over the second half of the run
    /// (every step): `≈ λ₁/2` on a chaotic orbit, → 0 on a regular one.
    pub slope: f64,
    /// The finite-time maximal exponent of the same vector,
    /// `log(|δ(T)|/|δ(0)|)/T`.
    pub lyapunov: f64,
    /// Times of the running values: every step, thinned to at most
    /// [`MAX_HISTORY`](super::lyapunov::MAX_HISTORY) (every `m`-th) and the last.
    pub times: Vec<f64>,
    /// `Y` at `times`.
    pub running_megno: Vec<f64>,
    /// `⟨Y⟩` at `times`.
    pub running_mean: Vec<f64>,
    /// Steps taken.
    pub steps: usize,
    /// Steps of the method per step (1 + the difference steps of one column).
    pub steps_per_step: usize,
}

/// The MEGNO of the trajectory of `method` from `(t0, y0)` with one tangent
/// vector (see the [module documentation](self)). `cancel` is polled every
/// step.
pub fn megno<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, opts: &MegnoOptions, cancel: Option<&AtomicBool>) -> Result<MegnoEstimate, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    super::check_span(opts.h, opts.duration)?;
    opts.linearisation.validate()?;
    super::check_start(t0, y0)?;
    let n = super::step_count(opts.h, opts.duration)?;
    let h = opts.duration / n as f64;
    let mut col = super::lyapunov::random_frame(S::State::DOF, 1, opts.seed);
    let stride = super::lyapunov::history_stride(n, 1);
    let (mut y, mut t) = (*y0, t0);
    // Σ t_k log|δ_k/δ_{k−1}|, Σ h Y(t_k), log|δ_k/δ_0|.
    let (mut weighted, mut integral, mut log_growth) = (0.0, 0.0, 0.0);
    let (mut megno, mut mean) = (f64::NAN, f64::NAN);
    let (mut times, mut running_megno, mut running_mean) = (Vec::new(), Vec::new(), Vec::new());
    // Sums of the least-squares fit of ⟨Y⟩ against t over the second half.
    let half = n / 2;
    let (mut fit_n, mut st, mut stt, mut sy, mut sty) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return Err(AnalysisError::Cancelled { t });
        }
        let k = (i + 1) as f64;
        let t1 = t0 + h * k;
        y = step_with_tangents(system, method, t, &y, t1 - t, &mut col, &opts.linearisation)?;
        t = t1;
        let norm = col.column(0).norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(AnalysisError::Degenerate { column: 0, t, norm });
        }
        col.unscale_mut(norm);
        let growth = norm.ln();
        log_growth += growth;
        // Time since the start, in units of h: k (the map's step count).
        weighted += k * growth;
        megno = 2.0 * weighted / k;
        integral += megno;
        mean = integral / k;
        if i >= half {
            let s = k * h;
            fit_n += 1.0;
            st += s;
            stt += s * s;
            sy += mean;
            sty += s * mean;
        }
        if (i + 1) % stride == 0 || i + 1 == n {
            times.push(t);
            running_megno.push(megno);
            running_mean.push(mean);
        }
    }
    let den = fit_n * stt - st * st;
    let slope = if fit_n >= 2.0 && den > 0.0 { (fit_n * sty - st * sy) / den } else { f64::NAN };
    Ok(MegnoEstimate {
        megno,
        mean,
        slope,
        lyapunov: log_growth / (n as f64 * h),
        times,
        running_megno,
        running_mean,
        steps: n,
        steps_per_step: 1 + opts.linearisation.steps_per_column(),
    })
}
