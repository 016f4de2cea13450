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
//! With error-controlled steps `t_k` is the time since `t₀` at the end of the
//! `k`-th accepted step and `h` in the second sum is that step's size
//! `t_k − t_{k−1}` (the same sums as quadratures of the continuous form).
//!
//! For a quasi-periodic orbit `|δ|` grows linearly and `⟨Y⟩ → 2`; for a
//! stable, isochronous periodic orbit `|δ|` stays bounded and `⟨Y⟩ → 0`;
//! for a chaotic orbit `log |δ| ≈ λ₁ t`, `Y ≈ λ₁ t` and `⟨Y⟩ ≈ λ₁ t/2`
//! (Cincotta & Simó 2000). [`MegnoEstimate::slope`], the least-squares
//! slope of `⟨Y⟩` over the second half of the run, therefore estimates
//! `λ₁/2` on a chaotic orbit and tends to 0 on a regular one.

use std::sync::atomic::AtomicBool;

use super::tangent::{tangent_images, Linearisation};
use super::walk::{plan, walk, History, Next};
use super::AnalysisError;
use crate::dynamics::System;
use crate::lie::LieGroup;
use crate::method::{GroupNumerics, Method};
use crate::solve::StepSize;

/// Settings of [`megno`].
#[derive(Debug, Clone, PartialEq)]
pub struct MegnoOptions {
    /// Fixed or error-controlled steps, as
    /// [`LyapunovOptions::step`](super::LyapunovOptions::step).
    pub step: StepSize,
    /// Integration time `T > 0` (at most 1e9 steps).
    pub duration: f64,
    /// The most steps taken (1 … [`MAX_STEPS`](super::MAX_STEPS), the
    /// default; a scene's options take its `method.max_steps`).
    pub max_steps: usize,
    /// Seed of the random initial tangent vector (the same vector as the
    /// first column of [`lyapunov_spectrum`](super::lyapunov_spectrum) with this seed).
    pub seed: u64,
    /// The linearisation of the one-step map.
    pub linearisation: Linearisation,
}

impl MegnoOptions {
    /// Seed 1 and the default linearisation.
    pub fn new(h: f64, duration: f64) -> Self {
        Self::with_step(StepSize::Fixed(h), duration)
    }

    /// [`new`](Self::new) with fixed or error-controlled steps.
    pub fn with_step(step: StepSize, duration: f64) -> Self {
        MegnoOptions { step, duration, max_steps: super::MAX_STEPS, seed: 1, linearisation: Linearisation::default() }
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
    /// (every step; with error-controlled steps, those ending in the second
    /// half of the time span): `≈ λ₁/2` on a chaotic orbit, → 0 on a regular one.
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
    /// Steps of the method per step (1 + [`Linearisation::steps_per_column`]).
    pub steps_per_step: usize,
    /// The linearisation used, [`resolve`](Linearisation::resolve)d:
    /// `exact` tells whether the tangent maps were exact or differenced.
    pub linearisation: Linearisation,
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
    let n = plan(&opts.step, opts.duration, opts.max_steps)?;
    opts.linearisation.validate()?;
    super::check_start(t0, y0)?;
    let lin = opts.linearisation.resolve(system, method, t0, y0);
    let mut col = super::lyapunov::random_frame(S::State::DOF, 1, opts.seed);
    let mut history = n.map_or_else(History::growing, |n| History::every(super::lyapunov::history_stride(n, 1)));
    // Σ t_k log|δ_k/δ_{k−1}|, Σ h Y(t_k), log|δ_k/δ_0| (t_k from t₀).
    let (mut weighted, mut integral, mut log_growth) = (0.0, 0.0, 0.0);
    let (mut megno, mut mean, mut s_prev) = (f64::NAN, f64::NAN, 0.0);
    // Sums of the least-squares fit of ⟨Y⟩ against t over the second half.
    let in_second_half = |index: usize, s: f64| match n {
        Some(n) => index > n / 2,
        None => s >= 0.5 * opts.duration,
    };
    let (mut fit_n, mut st, mut stt, mut sy, mut sty) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let walked = walk(system, method, t0, y0, &opts.step, opts.duration, opts.max_steps, cancel, |step| {
        tangent_images(system, method, step.t0, step.y0, step.y1, step.h, &mut col, &lin)?;
        let norm = col.column(0).norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(AnalysisError::Degenerate { column: 0, t: step.t1, norm });
        }
        col.unscale_mut(norm);
        let growth = norm.ln();
        log_growth += growth;
        // Time since the start.
        let s = step.t1 - t0;
        weighted += s * growth;
        megno = 2.0 * weighted / s;
        integral += (s - s_prev) * megno;
        s_prev = s;
        mean = integral / s;
        if in_second_half(step.index, s) {
            fit_n += 1.0;
            st += s;
            stt += s * s;
            sy += mean;
            sty += s * mean;
        }
        history.offer(step.t1, || (megno, mean), step.last);
        Ok(Next::Go)
    })?;
    let den = fit_n * stt - st * st;
    let slope = if fit_n >= 2.0 && den > 0.0 { (fit_n * sty - st * sy) / den } else { f64::NAN };
    let (times, running): (Vec<f64>, Vec<(f64, f64)>) = history.into_rows().into_iter().unzip();
    let (running_megno, running_mean) = running.into_iter().unzip();
    Ok(MegnoEstimate {
        megno,
        mean,
        slope,
        lyapunov: log_growth / (walked.t - t0),
        times,
        running_megno,
        running_mean,
        steps: walked.steps,
        steps_per_step: 1 + lin.steps_per_column(),
        linearisation: lin,
    })
}
