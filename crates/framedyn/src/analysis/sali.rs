//! The Smaller Alignment Index (Skokos 2001): a fast chaos indicator from
//! two tangent vectors carried by the tangent map of each step (see the
//! [module documentation](super)).
//!
//! Both vectors are normalised after every step; `SALI = min(|u₁ + u₂|,
//! |u₁ − u₂|)`. On a chaotic orbit both align with the most unstable
//! direction and SALI falls like `exp(−(λ₁ − λ₂)t)`; on a regular orbit of a
//! system with at least two degrees of freedom the vectors fall into the
//! tangent space of the torus without aligning and SALI stays away from 0.

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::DMatrix;

use super::tangent::{step_with_tangents, Linearisation};
use super::AnalysisError;
use crate::dynamics::System;
use crate::lie::LieGroup;
use crate::method::{GroupNumerics, Method};

/// Settings of [`sali`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaliOptions {
    /// Fixed step `h > 0`.
    pub h: f64,
    /// Integration time `T > 0` (the run stops earlier once SALI is below
    /// `threshold`).
    pub duration: f64,
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
        SaliOptions { h, duration, threshold: 1e-8, seed: 1, linearisation: Linearisation::default() }
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
}

/// The SALI of the trajectory of `method` from `(t0, y0)`. `cancel` is
/// polled every step.
pub fn sali<S, M>(system: &S, method: &M, t0: f64, y0: &S::State, opts: &SaliOptions, cancel: Option<&AtomicBool>) -> Result<SaliEstimate, AnalysisError>
where
    S: System,
    S::State: GroupNumerics,
    M: Method<S>,
{
    if !(opts.h.is_finite() && opts.h > 0.0) {
        return Err(AnalysisError::invalid("h", opts.h, "finite and > 0"));
    }
    if !(opts.duration.is_finite() && opts.duration > 0.0) {
        return Err(AnalysisError::invalid("duration", opts.duration, "finite and > 0"));
    }
    if !(opts.threshold > 0.0 && opts.threshold < 1.0) {
        return Err(AnalysisError::invalid("threshold", opts.threshold, "between 0 and 1 (exclusive)"));
    }
    opts.linearisation.validate()?;
    if !t0.is_finite() {
        return Err(AnalysisError::invalid("t0", t0, "finite"));
    }
    if !crate::solve::state_is_finite(y0) {
        return Err(AnalysisError::Solve(crate::solve::SolveError::InvalidInitialState { defect: y0.constraint_defect() }));
    }
    let dof = S::State::DOF;
    if dof < 2 {
        return Err(AnalysisError::invalid("state", format!("a {dof}-dimensional state group"), "at least 2 dimensions"));
    }
    let n = (opts.duration / opts.h).round().max(1.0);
    if n > 1e9 {
        return Err(AnalysisError::invalid("h", opts.h, "≥ duration/1e9 (at most 1e9 steps)"));
    }
    let n = n as usize;
    let h = opts.duration / n as f64;
    let mut cols = super::lyapunov::random_frame(dof, 2, opts.seed);
    let (mut y, mut t) = (*y0, t0);
    let mut index = f64::NAN;
    let mut min = f64::INFINITY;
    for i in 0..n {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return Err(AnalysisError::Cancelled { t });
        }
        let t1 = t0 + h * (i + 1) as f64;
        y = step_with_tangents(system, method, t, &y, t1 - t, &mut cols, &opts.linearisation)?;
        t = t1;
        normalise(&mut cols, t)?;
        index = (cols.column(0) + cols.column(1)).norm().min((cols.column(0) - cols.column(1)).norm());
        min = min.min(index);
        if index < opts.threshold {
            return Ok(SaliEstimate { sali: index, chaotic_at: Some(t), min, steps: i + 1 });
        }
    }
    Ok(SaliEstimate { sali: index, chaotic_at: None, min, steps: n })
}

fn normalise(m: &mut DMatrix<f64>, t: f64) -> Result<(), AnalysisError> {
    for j in 0..m.ncols() {
        let n = m.column(j).norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(AnalysisError::Degenerate { column: j, t, norm: n });
        }
        m.column_mut(j).unscale_mut(n);
    }
    Ok(())
}
