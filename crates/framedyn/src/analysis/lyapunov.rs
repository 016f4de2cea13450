//! Lyapunov exponents: Benettin's discrete-QR spectrum on the tangent map,
//! and the two-trajectory estimate of the maximal exponent (see the
//! [module documentation](super)).

use std::sync::atomic::AtomicBool;

use nalgebra::DMatrix;

use super::tangent::{tangent_images, Linearisation, Space};
use super::walk::{plan, walk, History, Next};
use super::AnalysisError;
use crate::dynamics::System;
use crate::lie::LieGroup;
use crate::method::{GroupNumerics, Method, StepRequest};
use crate::solve::{fault_error, StepSize};

/// Settings of [`lyapunov_spectrum`].
#[derive(Debug, Clone, PartialEq)]
pub struct LyapunovOptions {
    /// The steps: fixed (`h > 0`: equal steps of size at most `h`, as a run's,
    /// [`fixed_step_count`](crate::solve::fixed_step_count)) or
    /// error-controlled (the trajectory's error alone chooses them; the
    /// tangent map is that of each accepted step at its size).
    pub step: StepSize,
    /// Integration time `T > 0` (including the transient).
    pub duration: f64,
    /// The most steps taken (1 … [`MAX_STEPS`](super::MAX_STEPS), the
    /// default; a scene's options take its `method.max_steps`).
    pub max_steps: usize,
    /// Number `k` of exponents, `1 ≤ k ≤ DOF` (less the gauge directions
    /// with [`quotient`](Self::quotient); the largest `k`: the first `k`
    /// columns of the QR iteration).
    pub exponents: usize,
    /// Steps between re-orthonormalisations (≥ 1).
    pub renormalise_every: usize,
    /// Time at the start, `0 ≤ transient < duration`, over which the frame is
    /// carried and re-orthonormalised but nothing is averaged.
    pub transient: f64,
    /// Number of batches of the batch-means standard error (≥ 2; at least
    /// one re-orthonormalisation per batch).
    pub batches: usize,
    /// Seed of the random initial orthonormal frame.
    pub seed: u64,
    /// The linearisation of the one-step map.
    pub linearisation: Linearisation,
    /// The spectrum of the phase space: the tangent vectors are taken modulo
    /// the system's gauge directions ([`System::gauge`]) after every step,
    /// as GALI's [`quotient`](super::GaliOptions::quotient), so that the
    /// parallel frame's gauge direction contributes no exponent and a
    /// Hamiltonian model's `2n` exponents pair, `λᵢ + λ₂ₙ₊₁₋ᵢ = 0`. Default
    /// `false`: the spectrum of the stored state, the group's `DOF`
    /// exponents, one zero among them per gauge direction (the other
    /// exponents are the same up to the finite-time error).
    pub quotient: bool,
}

impl LyapunovOptions {
    /// All defaults but the step and the duration: the largest exponent,
    /// re-orthonormalised every 10 steps, no transient, 10 batches.
    pub fn new(h: f64, duration: f64) -> Self {
        Self::with_step(StepSize::Fixed(h), duration)
    }

    /// [`new`](Self::new) with fixed or error-controlled steps.
    pub fn with_step(step: StepSize, duration: f64) -> Self {
        LyapunovOptions { step, duration, max_steps: super::MAX_STEPS, exponents: 1, renormalise_every: 10, transient: 0.0, batches: 10, seed: 1, linearisation: Linearisation::default(), quotient: false }
    }

    /// With `k` exponents.
    pub fn exponents(mut self, k: usize) -> Self {
        self.exponents = k;
        self
    }

    /// The number of fixed steps (`None`: error-controlled), all settings checked.
    fn steps(&self, dof: usize) -> Result<Option<usize>, AnalysisError> {
        let n = check_common(&self.step, self.duration, self.max_steps, self.transient, self.renormalise_every, self.batches)?;
        self.linearisation.validate()?;
        if !(1..=dof).contains(&self.exponents) {
            return Err(AnalysisError::invalid("exponents", self.exponents, format!("between 1 and {dof} (the state group's dimension)")));
        }
        Ok(n)
    }
}

/// Checks the settings common to both estimates; the number of fixed steps
/// (`None`: error-controlled), checked to leave at least one
/// re-orthonormalisation per batch after the transient.
fn check_common(step: &StepSize, duration: f64, max_steps: usize, transient: f64, every: usize, batches: usize) -> Result<Option<usize>, AnalysisError> {
    let n = plan(step, duration, max_steps)?;
    if !(transient.is_finite() && transient >= 0.0 && transient < duration) {
        return Err(AnalysisError::invalid("transient", transient, format!("finite, ≥ 0 and < duration = {duration}")));
    }
    if every == 0 {
        return Err(AnalysisError::invalid("renormalise_every", every, "≥ 1 step"));
    }
    if !(2..=MAX_HISTORY).contains(&batches) {
        return Err(AnalysisError::invalid("batches", batches, format!("between 2 and {MAX_HISTORY}")));
    }
    if let (StepSize::Fixed(h), Some(n)) = (step, n) {
        // After a transient, the first re-orthonormalisation past it starts the averages.
        let h_run = duration / n as f64;
        let averaged = (((duration - transient) / h_run).floor() as usize / every).saturating_sub(usize::from(transient > 0.0));
        if averaged < batches {
            return Err(AnalysisError::invalid(
                "duration",
                duration,
                format!("long enough for {batches} batches of re-orthonormalisations after the transient (now {averaged} of every {every} steps of h = {h})"),
            ));
        }
    }
    Ok(n)
}

/// After the run (an error-controlled run's steps are not known in
/// advance): enough running estimates after the transient for the batches.
fn check_batches(acc: &Accumulator, duration: f64, batches: usize, every: usize) -> Result<(), AnalysisError> {
    let (made, kept) = (acc.added, acc.recorded());
    if kept < batches {
        return Err(AnalysisError::invalid(
            "duration",
            duration,
            format!("long enough for {batches} batches of re-orthonormalisations after the transient (this run made {made}, one every {every} steps, and kept {kept} running estimates)"),
        ));
    }
    Ok(())
}

/// Exponents and their diagnostics.
#[derive(Debug, Clone, PartialEq)]
pub struct LyapunovEstimate {
    /// The exponents (1/time units of the scene), in the order of the QR
    /// columns: the largest first once converged (a short run's finite-time
    /// estimates need not be ordered yet).
    pub exponents: Vec<f64>,
    /// Standard error of each by batch means: the standard deviation of the
    /// batches' exponents over √batches.
    pub stderr: Vec<f64>,
    /// Spread of each running estimate over the second half of the averaging
    /// (max − min): how far from converged.
    pub spread: Vec<f64>,
    /// Times of the running estimates: every re-orthonormalisation after the
    /// transient, thinned to at most [`MAX_HISTORY`] (every `m`-th) and
    /// the last.
    pub times: Vec<f64>,
    /// The running estimates at `times`, one row of `k` exponents per time.
    pub running: Vec<Vec<f64>>,
    /// Steps taken.
    pub steps: usize,
    /// Steps of the method per step (1 + tangent columns × steps per column,
    /// [`Linearisation::steps_per_column`]).
    pub steps_per_step: usize,
    /// The linearisation used, [`resolve`](Linearisation::resolve)d:
    /// `exact` tells whether the tangent maps were exact or differenced.
    pub linearisation: Linearisation,
    /// The dimension of the space the tangent vectors live in: the state
    /// group's `DOF`, less the gauge directions taken out
    /// ([`LyapunovOptions::quotient`]).
    pub dimension: usize,
}

/// A deterministic pseudo-random orthonormal `rows × k` frame (xorshift64*).
pub(crate) fn random_frame(rows: usize, k: usize, seed: u64) -> DMatrix<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        (s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut m = DMatrix::from_fn(rows, k, |_, _| next());
    // A random matrix has full column rank; Gram–Schmidt cannot fail here.
    let _ = orthonormalise(&mut m, 0.0);
    m
}

/// Modified Gram–Schmidt with one re-orthogonalisation pass: `m = Q·R` with
/// `Q` written over `m` and the upper triangular `R` returned (its diagonal:
/// the norms `|R_ii|` of Benettin's method). Fails at time `t` on a column
/// that vanishes or is not finite.
pub(crate) fn orthonormalise(m: &mut DMatrix<f64>, t: f64) -> Result<DMatrix<f64>, AnalysisError> {
    let k = m.ncols();
    let mut r = DMatrix::zeros(k, k);
    for j in 0..k {
        for _pass in 0..2 {
            for i in 0..j {
                let p = m.column(i).dot(&m.column(j));
                r[(i, j)] += p;
                let ci = m.column(i).clone_owned();
                m.column_mut(j).axpy(-p, &ci, 1.0);
            }
        }
        let n = m.column(j).norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(AnalysisError::Degenerate { column: j, t, norm: n });
        }
        m.column_mut(j).unscale_mut(n);
        r[(j, j)] = n;
    }
    Ok(r)
}

/// Largest number of recorded running estimates (and of batches), besides
/// the last estimate, which is always recorded.
pub const MAX_HISTORY: usize = 10_000;

/// Every how many re-orthonormalisations a running estimate is recorded,
/// for `n` steps re-orthonormalised every `every`.
pub(crate) fn history_stride(n: usize, every: usize) -> usize {
    (n / every).div_ceil(MAX_HISTORY).max(1)
}

/// The running sums of `log |R_ii|` at the re-orthonormalisations after the
/// transient, turned into estimates and diagnostics.
struct Accumulator {
    t_start: f64,
    sums: Vec<f64>,
    /// Re-orthonormalisations added.
    added: usize,
    history: History<Vec<f64>>,
}

impl Accumulator {
    /// Recording every `stride`-th re-orthonormalisation (`None`: as many as
    /// [`History::growing`] keeps).
    fn new(k: usize, t_start: f64, stride: Option<usize>) -> Self {
        let history = stride.map_or_else(History::growing, History::every);
        Accumulator { t_start, sums: vec![0.0; k], added: 0, history }
    }

    /// Adds one re-orthonormalisation's logarithms and offers the running
    /// sums to the history (thinned to at most [`MAX_HISTORY`] rows and the
    /// `last`, so that its memory does not grow with the run).
    fn add(&mut self, t: f64, logs: impl Iterator<Item = f64>, last: bool) {
        for (s, l) in self.sums.iter_mut().zip(logs) {
            *s += l;
        }
        self.added += 1;
        let sums = &self.sums;
        self.history.offer(t, || sums.clone(), last);
    }

    /// The running sums recorded.
    fn recorded(&self) -> usize {
        self.history.rows().len()
    }

    /// `(estimates, stderr, spread, times, running)`.
    #[allow(clippy::type_complexity)]
    fn finish(self, batches: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<Vec<f64>>) {
        let k = self.sums.len();
        let (times, cumulative): (Vec<f64>, Vec<Vec<f64>>) = self.history.into_rows().into_iter().unzip();
        let n = times.len();
        let running: Vec<Vec<f64>> = times.iter().zip(&cumulative).map(|(t, s)| s.iter().map(|x| x / (t - self.t_start)).collect()).collect();
        let estimates = running.last().cloned().unwrap_or_else(|| vec![f64::NAN; k]);
        let mut stderr = vec![0.0; k];
        let mut spread = vec![0.0; k];
        // Batch b spans the re-orthonormalisations (b·n/B, (b+1)·n/B].
        let at = |i: Option<usize>| -> (f64, Vec<f64>) {
            match i {
                None => (self.t_start, vec![0.0; k]),
                Some(i) => (times[i], cumulative[i].clone()),
            }
        };
        for c in 0..k {
            let mut values = Vec::with_capacity(batches);
            for b in 0..batches {
                let lo = (b * n / batches).checked_sub(1);
                let hi = ((b + 1) * n / batches).checked_sub(1);
                let (t0, s0) = at(lo);
                let (t1, s1) = at(hi);
                values.push((s1[c] - s0[c]) / (t1 - t0));
            }
            let mean = values.iter().sum::<f64>() / batches as f64;
            let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (batches - 1) as f64;
            stderr[c] = (var / batches as f64).sqrt();
            let half = &running[n / 2..];
            let (lo, hi) = half.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| (lo.min(r[c]), hi.max(r[c])));
            spread[c] = hi - lo;
        }
        (estimates, stderr, spread, times, running)
    }
}

/// The `k` largest Lyapunov exponents of the trajectory of `method` from
/// `(t0, y0)` (Benettin's discrete QR on the tangent map of the one-step
/// map; see the [module documentation](super)). `cancel` is polled every step.
pub fn lyapunov_spectrum<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, opts: &LyapunovOptions, cancel: Option<&AtomicBool>) -> Result<LyapunovEstimate, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let n = opts.steps(S::State::DOF)?;
    super::check_start(t0, y0)?;
    let space = Space::at_start(system, y0, t0, opts.quotient)?;
    let lin = opts.linearisation.resolve(system, method, t0, y0);
    let dimension = space.dimension;
    if opts.exponents > dimension {
        return Err(AnalysisError::invalid("exponents", opts.exponents, format!("between 1 and {dimension} ({})", space.describe())));
    }
    let mut cols = space.random_frame(opts.exponents, opts.seed, t0)?;
    let t_avg = t0 + opts.transient;
    let stride = n.map(|n| history_stride(n, opts.renormalise_every));
    let mut acc = (opts.transient == 0.0).then(|| Accumulator::new(opts.exponents, t0, stride));
    let walked = walk(system, method, t0, y0, &opts.step, opts.duration, opts.max_steps, cancel, |s| {
        tangent_images(system, method, s.t0, s.y0, s.y1, s.h, &mut cols, &lin)?;
        space.project(system, s.y1, s.t1, &mut cols)?;
        if s.index % opts.renormalise_every == 0 || s.last {
            let r = orthonormalise(&mut cols, s.t1)?.diagonal();
            match &mut acc {
                Some(a) => a.add(s.t1, r.iter().map(|x| x.ln()), s.last),
                None if s.t1 >= t_avg - 0.5 * s.h => acc = Some(Accumulator::new(opts.exponents, s.t1, stride)),
                None => {}
            }
        }
        Ok(Next::Go)
    })?;
    let acc = acc.ok_or_else(|| AnalysisError::invalid("transient", opts.transient, "shorter than the run"))?;
    check_batches(&acc, opts.duration, opts.batches, opts.renormalise_every)?;
    let (exponents, stderr, spread, times, running) = acc.finish(opts.batches);
    Ok(LyapunovEstimate { exponents, stderr, spread, times, running, steps: walked.steps, steps_per_step: 1 + opts.exponents * lin.steps_per_column(), linearisation: lin, dimension })
}

/// Settings of [`two_trajectory`].
#[derive(Debug, Clone, PartialEq)]
pub struct TwoTrajectoryOptions {
    /// Fixed or error-controlled steps, as [`LyapunovOptions::step`] (the
    /// companion takes the trajectory's steps).
    pub step: StepSize,
    /// Integration time `T > 0` (including the transient).
    pub duration: f64,
    /// The most steps taken (1 … [`MAX_STEPS`](super::MAX_STEPS), the
    /// default; a scene's options take its `method.max_steps`).
    pub max_steps: usize,
    /// The separation `d₀` the companion is renormalised to (algebra
    /// units), `0 < d₀ ≤ 1e-3`.
    pub separation: f64,
    /// Steps between renormalisations (≥ 1).
    pub renormalise_every: usize,
    /// Time at the start over which nothing is averaged.
    pub transient: f64,
    /// Batches of the batch-means standard error (≥ 2).
    pub batches: usize,
    /// Seed of the random initial direction.
    pub seed: u64,
}

impl TwoTrajectoryOptions {
    /// `d₀ = 1e-8`, renormalised every 10 steps, no transient, 10 batches.
    pub fn new(h: f64, duration: f64) -> Self {
        Self::with_step(StepSize::Fixed(h), duration)
    }

    /// [`new`](Self::new) with fixed or error-controlled steps.
    pub fn with_step(step: StepSize, duration: f64) -> Self {
        TwoTrajectoryOptions { step, duration, max_steps: super::MAX_STEPS, separation: 1e-8, renormalise_every: 10, transient: 0.0, batches: 10, seed: 1 }
    }
}

/// The maximal exponent from two nearby trajectories.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoTrajectoryEstimate {
    /// The estimate.
    pub exponent: f64,
    /// Its standard error by batch means.
    pub stderr: f64,
    /// Spread of the running estimate over the second half (max − min).
    pub spread: f64,
    /// Times of the running estimates.
    pub times: Vec<f64>,
    /// The running estimates.
    pub running: Vec<f64>,
    /// Steps taken (of each trajectory).
    pub steps: usize,
}

/// The maximal Lyapunov exponent from the separation of the trajectory of
/// `(t0, y0)` and a companion `y·exp(d₀ ξ)` (left-trivialised separation
/// `|log(y⁻¹ z)|` in algebra coordinates), both stepped by `method`, the
/// companion pulled back to distance `d₀` along the current separation
/// every `renormalise_every` steps (Benettin, Galgani, Strelcyn 1976). It
/// does not use the tangent map: an independent check of
/// [`lyapunov_spectrum`].
pub fn two_trajectory<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, opts: &TwoTrajectoryOptions, cancel: Option<&AtomicBool>) -> Result<TwoTrajectoryEstimate, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    let n = check_common(&opts.step, opts.duration, opts.max_steps, opts.transient, opts.renormalise_every, opts.batches)?;
    if !(opts.separation.is_finite() && opts.separation > 0.0 && opts.separation <= 1e-3) {
        return Err(AnalysisError::invalid("separation", opts.separation, "finite, > 0 and ≤ 1e-3"));
    }
    super::check_start(t0, y0)?;
    let dof = S::State::DOF;
    let d0 = opts.separation;
    let dir = random_frame(dof, 1, opts.seed);
    let along = |y: &S::State, d: &[f64]| y.compose(&S::State::exp(&S::State::algebra_from_coords(d)));
    let scaled: Vec<f64> = dir.iter().map(|x| x * d0).collect();
    let mut z = along(y0, &scaled);
    let t_avg = t0 + opts.transient;
    let stride = n.map(|n| history_stride(n, opts.renormalise_every));
    let mut acc = (opts.transient == 0.0).then(|| Accumulator::new(1, t0, stride));
    let walked = walk(system, method, t0, y0, &opts.step, opts.duration, opts.max_steps, cancel, |s| {
        // The companion takes the trajectory's step.
        z = method.step(system, s.t0, &z, s.h, StepRequest::plain()).map(|o| o.y).map_err(|f| AnalysisError::Solve(fault_error(f, s.t0, s.h)))?;
        if s.index % opts.renormalise_every == 0 || s.last {
            let y = s.y1;
            let sep = S::State::algebra_coords(&y.inverse().compose(&z).log()?);
            let d = sep.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !(d.is_finite() && d > 0.0) {
                return Err(AnalysisError::Degenerate { column: 0, t: s.t1, norm: d });
            }
            let back: Vec<f64> = sep.iter().map(|x| x * (d0 / d)).collect();
            z = along(y, &back);
            match &mut acc {
                Some(a) => a.add(s.t1, std::iter::once((d / d0).ln()), s.last),
                None if s.t1 >= t_avg - 0.5 * s.h => acc = Some(Accumulator::new(1, s.t1, stride)),
                None => {}
            }
        }
        Ok(Next::Go)
    })?;
    let acc = acc.ok_or_else(|| AnalysisError::invalid("transient", opts.transient, "shorter than the run"))?;
    check_batches(&acc, opts.duration, opts.batches, opts.renormalise_every)?;
    let (e, se, sp, times, running) = acc.finish(opts.batches);
    Ok(TwoTrajectoryEstimate { exponent: e[0], stderr: se[0], spread: sp[0], times, running: running.into_iter().map(|r| r[0]).collect(), steps: walked.steps })
}
