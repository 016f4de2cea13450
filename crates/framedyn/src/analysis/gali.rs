//! The Generalised Alignment Index GALI_k (Skokos, Bountis & Antonopoulos
//! 2007): the volume spanned by `k` unit deviation vectors carried by the
//! tangent map of each step (see the [module documentation](super)).
//!
//! `GALI_k = |ŵ₁ ∧ … ∧ ŵ_k|`, `ŵᵢ = wᵢ/|wᵢ|`: 1 for orthonormal vectors, 0
//! when they are linearly dependent. On a chaotic orbit all vectors align
//! with the most unstable directions and
//! `GALI_k ∝ exp(−[(λ₁ − λ₂) + … + (λ₁ − λ_k)] t)`; on a regular orbit it
//! stays away from 0 for `k` up to the number of directions in which
//! neighbouring motions drift apart linearly (the torus's dimension, in
//! canonical coordinates) and falls like a power of `t` above it (Skokos,
//! Bountis & Antonopoulos 2008).
//!
//! **The phase space, not the stored state.** The frame-bundle state carries
//! the parallel frame, which is not part of the physical state: turning it in
//! place with the components stored in it turned back changes nothing
//! physical ([`System::gauge`]), and its holonomy angle drifts with the
//! orbit's actions like an angle of the torus. On the stored state a Bertrand
//! orbit and a non-Bertrand central orbit on the sphere both keep two
//! drifting directions. By default ([`GaliOptions::quotient`]) the deviation
//! vectors are therefore taken modulo the gauge directions — after every
//! step their components along them (an orthonormal basis of the directions
//! at the new state) are projected out — so that the index is that of the
//! physical phase space: there the Bertrand orbit's maximal degeneracy
//! leaves one drifting direction and `GALI₂` falls like `1/t`, while a
//! non-degenerate regular orbit keeps `GALI₂` away from 0
//! (docs/integrability.md, "A third indicator: GALI"). The equations are
//! equivariant under the gauge rotations, so a step's tangent map takes
//! gauge directions to gauge directions and the projected map is the
//! tangent map of the quotient.
//!
//! `GALI_2` is SALI's relative: `GALI_2 = S·√(1 − S²/4)` for `S = SALI` of
//! the same two vectors (with `quotient = false`, where both carry the
//! same vectors; SALI measures on the stored state).
//!
//! The vectors are carried as an orthonormal frame `Q` and a `k × k` upper
//! triangular `R` with unit columns: the deviation vectors are `Q·R` up to
//! the length of each, so `GALI_k = |det R| = Π |R_ii|`. A step maps `Q` to
//! `D·Q = Q'·R_s` (modified Gram–Schmidt) and `R` to `R_s·R` (columns then
//! rescaled). The frame stays well conditioned however small the index, so
//! it has no floor set by the error of the finite-difference tangent map
//! (which is relative to each column), and `log GALI_k` is accumulated as a
//! sum, so it does not underflow either.

use std::sync::atomic::AtomicBool;

use nalgebra::DMatrix;

use super::tangent::{tangent_images, Linearisation, Space};
use super::walk::{plan, walk, History, Next};
use super::AnalysisError;
use crate::dynamics::System;
use crate::method::{GroupNumerics, Method};
use crate::solve::StepSize;

/// Settings of [`gali`].
#[derive(Debug, Clone, PartialEq)]
pub struct GaliOptions {
    /// Fixed or error-controlled steps, as
    /// [`LyapunovOptions::step`](super::LyapunovOptions::step).
    pub step: StepSize,
    /// Integration time `T > 0` (the run stops earlier once the index is
    /// below `threshold`).
    pub duration: f64,
    /// The most steps taken (1 … [`MAX_STEPS`](super::MAX_STEPS), the
    /// default; a scene's options take its `method.max_steps`).
    pub max_steps: usize,
    /// The number `k` of deviation vectors, `2 ≤ k ≤` the dimension
    /// (`DOF`, less the gauge directions with [`quotient`](Self::quotient)).
    pub k: usize,
    /// The run stops when `GALI_k` falls below it, `1e-300 ≤ threshold < 1`
    /// (on a chaotic orbit `GALI_k` falls exponentially; on a regular one it
    /// falls like a power of `t` for `k` above the torus's dimension, so
    /// falling below a threshold means chaos only for small `k`: compare
    /// the running values).
    pub threshold: f64,
    /// Seed of the `k` random orthonormal initial vectors (without
    /// [`quotient`](Self::quotient), or for a system without gauge
    /// directions, the same vectors as the first `k` columns of
    /// [`lyapunov_spectrum`](super::lyapunov_spectrum) and, for `k = 2`,
    /// [`sali`](super::sali()) with this seed; with it, their components
    /// outside the gauge directions, orthonormalised).
    pub seed: u64,
    /// The linearisation of the one-step map.
    pub linearisation: Linearisation,
    /// Take the deviation vectors modulo the system's gauge directions
    /// ([`System::gauge`]): the index of the physical phase space (see the
    /// [module documentation](self)). Default `true`; `false` gives the index
    /// of the stored state, the group's `DOF` dimensions. No effect on a
    /// system without gauge directions.
    pub quotient: bool,
}

impl GaliOptions {
    /// Fixed steps `h`, `k` vectors, threshold 1e-12, seed 1, the default
    /// linearisation, modulo the gauge directions.
    pub fn new(h: f64, duration: f64, k: usize) -> Self {
        Self::with_step(StepSize::Fixed(h), duration, k)
    }

    /// [`new`](Self::new) with fixed or error-controlled steps.
    pub fn with_step(step: StepSize, duration: f64, k: usize) -> Self {
        GaliOptions { step, duration, max_steps: super::MAX_STEPS, k, threshold: 1e-12, seed: 1, linearisation: Linearisation::default(), quotient: true }
    }
}

/// The index along the run.
#[derive(Debug, Clone, PartialEq)]
pub struct GaliEstimate {
    /// `GALI_k` at the end of the run (0 if below the smallest `f64`; see
    /// `log10`).
    pub gali: f64,
    /// `log₁₀ GALI_k` at the end of the run.
    pub log10: f64,
    /// The first time `GALI_k` fell below the threshold (the run stops
    /// there), or `None`.
    pub below_at: Option<f64>,
    /// Times of the running values: every step, thinned to at most
    /// [`MAX_HISTORY`](super::lyapunov::MAX_HISTORY) and the last.
    pub times: Vec<f64>,
    /// `log₁₀ GALI_k` at `times`.
    pub running_log10: Vec<f64>,
    /// Steps taken.
    pub steps: usize,
    /// Steps of the method per step (1 + `k` × [`Linearisation::steps_per_column`]).
    pub steps_per_step: usize,
    /// The linearisation used, [`resolve`](Linearisation::resolve)d:
    /// `exact` tells whether the tangent maps were exact or differenced.
    pub linearisation: Linearisation,
    /// The dimension of the space the vectors live in: the state group's
    /// `DOF`, less the gauge directions taken out
    /// ([`GaliOptions::quotient`]).
    pub dimension: usize,
}

/// `GALI_k` of the trajectory of `method` from `(t0, y0)` (see the [module
/// documentation](self)). `cancel` is looked at every step.
pub fn gali<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, opts: &GaliOptions, cancel: Option<&AtomicBool>) -> Result<GaliEstimate, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let n = plan(&opts.step, opts.duration, opts.max_steps)?;
    super::check_start(t0, y0)?;
    let space = Space::at_start(system, y0, t0, opts.quotient)?;
    let dimension = space.dimension;
    if !(2..=dimension).contains(&opts.k) {
        return Err(AnalysisError::invalid("k", opts.k, format!("between 2 and {dimension} ({})", space.describe())));
    }
    // Above 1e-300 the run stops before a diagonal entry of R can underflow.
    if !(opts.threshold >= 1e-300 && opts.threshold < 1.0) {
        return Err(AnalysisError::invalid("threshold", opts.threshold, "≥ 1e-300 and < 1"));
    }
    opts.linearisation.validate()?;
    let lin = opts.linearisation.resolve(system, method, t0, y0);
    let k = opts.k;
    let mut q = space.random_frame(k, opts.seed, t0)?;
    let mut r = DMatrix::<f64>::identity(k, k);
    let mut history = n.map_or_else(History::growing, |n| History::every(super::lyapunov::history_stride(n, 1)));
    let log_threshold = opts.threshold.log10();
    let mut log10 = 0.0;
    let mut below_at = None;
    let walked = walk(system, method, t0, y0, &opts.step, opts.duration, opts.max_steps, cancel, |s| {
        tangent_images(system, method, s.t0, s.y0, s.y1, s.h, &mut q, &lin)?;
        space.project(system, s.y1, s.t1, &mut q)?;
        let rs = super::lyapunov::orthonormalise(&mut q, s.t1)?;
        r = rs * &r;
        log10 = 0.0;
        for j in 0..k {
            let norm = r.column(j).norm();
            if !(norm.is_finite() && norm > 0.0) {
                return Err(AnalysisError::Degenerate { column: j, t: s.t1, norm });
            }
            r.column_mut(j).unscale_mut(norm);
            log10 += r[(j, j)].abs().log10();
        }
        let below = log10 < log_threshold;
        history.offer(s.t1, || log10, s.last || below);
        if below {
            below_at = Some(s.t1);
            return Ok(Next::Stop);
        }
        Ok(Next::Go)
    })?;
    let (times, running_log10) = history.into_rows().into_iter().unzip();
    Ok(GaliEstimate {
        gali: 10f64.powf(log10),
        log10,
        below_at,
        times,
        running_log10,
        steps: walked.steps,
        steps_per_step: 1 + k * lin.steps_per_column(),
        linearisation: lin,
        dimension,
    })
}
