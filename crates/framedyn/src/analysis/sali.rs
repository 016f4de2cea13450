//! The Smaller Alignment Index (Skokos 2001): a fast chaos indicator from
//! two tangent vectors carried by the tangent map of each step (see the
//! [module documentation](super)).
//!
//! Both vectors are normalised after every step; `SALI = min(|u₁ + u₂|,
//! |u₁ − u₂|)`. On a chaotic orbit both align with the most unstable
//! direction and SALI falls like `exp(−(λ₁ − λ₂)t)`; on a regular orbit of a
//! system with at least two degrees of freedom the vectors fall into the
//! tangent space of the torus without aligning and SALI stays away from 0.
//!
//! The vectors are carried as `u₁` and the difference `d = u₁ − u₂` (with
//! the sign of `u₂` chosen so that `SALI = |d|`), not as `u₁` and `u₂`: then
//! SALI has no floor set by the error of the finite-difference tangent map
//! (see `Pair`).

use std::sync::atomic::AtomicBool;

use nalgebra::DMatrix;

use super::tangent::{tangent_images, Linearisation};
use super::walk::{plan, walk, Next};
use super::AnalysisError;
use crate::dynamics::System;
use crate::lie::LieGroup;
use crate::method::{GroupNumerics, Method};
use crate::solve::StepSize;

/// Settings of [`sali`].
#[derive(Debug, Clone, PartialEq)]
pub struct SaliOptions {
    /// Fixed or error-controlled steps, as
    /// [`LyapunovOptions::step`](super::LyapunovOptions::step).
    pub step: StepSize,
    /// Integration time `T > 0` (the run stops earlier once SALI is below
    /// `threshold`).
    pub duration: f64,
    /// The most steps taken (1 … [`MAX_STEPS`](super::MAX_STEPS), the
    /// default; a scene's options take its `method.max_steps`).
    pub max_steps: usize,
    /// The value below which the orbit is called chaotic, `0 < threshold < 1`.
    pub threshold: f64,
    /// Seed of the two random initial tangent vectors.
    pub seed: u64,
    /// The linearisation of the one-step map.
    pub linearisation: Linearisation,
}

impl SaliOptions {
    /// Threshold 1e-8, seed 1, the default linearisation.
    pub fn new(h: f64, duration: f64) -> Self {
        Self::with_step(StepSize::Fixed(h), duration)
    }

    /// [`new`](Self::new) with fixed or error-controlled steps.
    pub fn with_step(step: StepSize, duration: f64) -> Self {
        SaliOptions { step, duration, max_steps: super::MAX_STEPS, threshold: 1e-8, seed: 1, linearisation: Linearisation::default() }
    }
}

/// The index along the run.
#[derive(Debug, Clone, PartialEq)]
pub struct SaliEstimate {
    /// SALI at the end of the run.
    pub sali: f64,
    /// The first time SALI fell below the threshold (the run stops there),
    /// or `None`.
    pub chaotic_at: Option<f64>,
    /// The smallest SALI of the run.
    pub min: f64,
    /// Steps taken.
    pub steps: usize,
    /// The linearisation used, [`resolve`](Linearisation::resolve)d:
    /// `exact` tells whether the tangent maps were exact or differenced.
    pub linearisation: Linearisation,
}

/// The SALI of the trajectory of `method` from `(t0, y0)`. `cancel` is
/// polled every step.
pub fn sali<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, opts: &SaliOptions, cancel: Option<&AtomicBool>) -> Result<SaliEstimate, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    plan(&opts.step, opts.duration, opts.max_steps)?;
    if !(opts.threshold > 0.0 && opts.threshold < 1.0) {
        return Err(AnalysisError::invalid("threshold", opts.threshold, "between 0 and 1 (exclusive)"));
    }
    opts.linearisation.validate()?;
    super::check_start(t0, y0)?;
    let lin = opts.linearisation.resolve(system, method, t0, y0);
    let dof = S::State::DOF;
    if dof < 2 {
        return Err(AnalysisError::invalid("state", format!("a {dof}-dimensional state group"), "at least 2 dimensions"));
    }
    // Column 0: u₁; column 1: the direction of d = u₁ − u₂, |d| = `index`
    // (see `Pair`). Two random orthonormal vectors: |d| = √2.
    let mut cols = super::lyapunov::random_frame(dof, 2, opts.seed);
    let mut pair = Pair::new(&mut cols);
    let mut index = pair.index;
    let mut min = f64::INFINITY;
    let mut chaotic_at = None;
    let walked = walk(system, method, t0, y0, &opts.step, opts.duration, opts.max_steps, cancel, |s| {
        tangent_images(system, method, s.t0, s.y0, s.y1, s.h, &mut cols, &lin)?;
        index = pair.advance(&mut cols, s.t1)?;
        min = min.min(index);
        if index < opts.threshold {
            chaotic_at = Some(s.t1);
            return Ok(Next::Stop);
        }
        Ok(Next::Go)
    })?;
    Ok(SaliEstimate { sali: index, chaotic_at, min, steps: walked.steps, linearisation: lin })
}

/// The two deviation vectors as `u₁` and their difference `d = u₁ − u₂`
/// (unit vectors `u₁`, `u₂`, with `u₁·u₂ ≥ 0`, so `SALI = |d|`).
///
/// Carrying `u₂` itself, `|u₁ − u₂|` is a difference of two numbers of size 1
/// each with the error of the finite-difference tangent map (round-off
/// `~u/ε` relative per step, uncorrelated between the columns): SALI stops
/// falling at a floor proportional to `1/ε` (3.2e-9 at `ε = 1e-5` on the
/// atlas's tilted gyroscope, 3.2e-13 at `ε = 0.1`; docs/integrability.md).
/// Carrying `d` as a column of its own, its image `D d` is linearised along
/// `d`'s own direction, with an error relative to `|d|`, and the
/// normalisation of both vectors is applied to it in closed form, without
/// the cancellation: SALI falls like `exp(−(λ₁ − λ₂)t)` without a floor.
struct Pair {
    /// `|d|`: the index.
    index: f64,
}

impl Pair {
    /// From two orthonormal columns `u₁`, `u₂`: column 1 becomes the
    /// direction of `u₁ − u₂`.
    fn new(cols: &mut DMatrix<f64>) -> Self {
        let d = cols.column(0) - cols.column(1);
        let index = d.norm();
        cols.set_column(1, &(d / index));
        Pair { index }
    }

    /// After a step of the tangent map (column 0: `v₁ = D u₁`, column 1:
    /// `w = D d̂`, so that `D d = a w`, `a = |d|`): `u₁' = v₁/n₁` and
    /// `d' = v₁/n₁ − (v₁ − a w)/n₂` with `n₂ = |v₁ − a w|`, written as
    /// `d'/a = w/n₂ + v₁ (a|w|² − 2 v₁·w)/(n₁ n₂ (n₁ + n₂))` (from
    /// `n₂ − n₁ = (n₂² − n₁²)/(n₁ + n₂)`), which has no cancellation when
    /// `a` is small. If then `u₁'·u₂' < 0` (`|d'| > √2`), `u₂` is replaced by
    /// `−u₂` (SALI does not change, the tangent map is linear): `d' ← 2u₁' − d'`.
    fn advance(&mut self, cols: &mut DMatrix<f64>, t: f64) -> Result<f64, AnalysisError> {
        let a = self.index;
        let v1 = cols.column(0).clone_owned();
        let w = cols.column(1).clone_owned();
        let n1 = v1.norm();
        if !(n1.is_finite() && n1 > 0.0) {
            return Err(AnalysisError::Degenerate { column: 0, t, norm: n1 });
        }
        let v2 = &v1 - &w * a;
        let n2 = v2.norm();
        if !(n2.is_finite() && n2 > 0.0) {
            return Err(AnalysisError::Degenerate { column: 1, t, norm: n2 });
        }
        let g = &w / n2 + &v1 * ((a * w.norm_squared() - 2.0 * v1.dot(&w)) / (n1 * n2 * (n1 + n2)));
        let u1 = v1 / n1;
        let gn = g.norm();
        if !(gn.is_finite() && gn > 0.0) {
            return Err(AnalysisError::Degenerate { column: 1, t, norm: gn });
        }
        // |d'| = a·|g| and its direction g/|g|, without forming a·g (which
        // would underflow before a does).
        let (mut norm, mut dir) = (a * gn, g / gn);
        if norm > std::f64::consts::SQRT_2 {
            let d = &u1 * 2.0 - &dir * norm;
            norm = d.norm();
            dir = d / norm;
        }
        cols.set_column(0, &u1);
        cols.set_column(1, &dir);
        self.index = norm;
        Ok(norm)
    }
}
