//! Events: zeros of a scalar function `g(t, y)` along a trajectory.
//!
//! After every accepted step the driver evaluates `g` at the new state and
//! compares its sign with the last non-zero sign seen. A change (or an exact
//! zero at the step's end) is a crossing; it is located on the method's
//! continuous extension over the step (its dense output, or a sub-step: see
//! [`driver`](super::driver)) by Brent's method \[Bre73\] to the time
//! tolerance of the options, so the located time is as accurate as the
//! trajectory. Two sign changes within one step cancel and are not seen
//! (limit the step size to resolve closely spaced zeros). A zero at `t₀` is
//! not reported.
//!
//! \[Bre73\] R. P. Brent, *Algorithms for Minimization without Derivatives*,
//! Prentice-Hall 1973, ch. 4 (the algorithm `zeroin`).

use std::fmt;
use std::sync::Arc;

use crate::lie::LieGroup;

/// Which crossings an event reports (scene files: `direction = "rising"`,
/// `"falling"` or `"either"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// `g` goes from negative to non-negative.
    Rising,
    /// `g` goes from positive to non-positive.
    Falling,
    /// Both.
    #[default]
    Either,
}

/// The event function's type: `g(t, x)` of the time and the state `x` (a
/// group element for [`solve`](super::solve), the record — one value per
/// column — for the scene engine).
pub type EventFn<G> = dyn Fn(f64, &G) -> f64 + Send + Sync;

/// An event `g(t, x) = 0`: its name, function, the [`Direction`] of the
/// crossings it reports and whether the first one stops the run. The one
/// event type of the crate: `Event<G>` on the states of a typed problem,
/// `Event<[f64]>` on the records of a scene (the scene file's `[[events]]`,
/// the Python module's `framedyn.Event`); both are located by the same
/// routine ([`driver`](super::driver)).
pub struct Event<G: ?Sized> {
    pub(crate) name: String,
    pub(crate) g: Arc<EventFn<G>>,
    pub(crate) direction: Direction,
    pub(crate) terminal: bool,
}

impl<G: ?Sized> Clone for Event<G> {
    fn clone(&self) -> Self {
        Event { name: self.name.clone(), g: self.g.clone(), direction: self.direction, terminal: self.terminal }
    }
}

impl<G: ?Sized> fmt::Debug for Event<G> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Event")
            .field("name", &self.name)
            .field("direction", &self.direction)
            .field("terminal", &self.terminal)
            .finish_non_exhaustive()
    }
}

impl<G: ?Sized> Event<G> {
    /// The event `g(t, y) = 0`, reporting crossings in both directions,
    /// non-terminal.
    pub fn new(name: impl Into<String>, g: impl Fn(f64, &G) -> f64 + Send + Sync + 'static) -> Self {
        Event { name: name.into(), g: Arc::new(g), direction: Direction::Either, terminal: false }
    }

    /// The event with the function `g` shared with other events.
    pub fn from_arc(name: impl Into<String>, g: Arc<EventFn<G>>) -> Self {
        Event { name: name.into(), g, direction: Direction::Either, terminal: false }
    }

    /// Reports only crossings in `direction`.
    pub fn direction(mut self, direction: Direction) -> Self {
        self.direction = direction;
        self
    }

    /// Stops the integration at the first reported crossing.
    pub fn terminal(mut self) -> Self {
        self.terminal = true;
        self
    }

    /// The name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Which crossings are reported.
    pub fn direction_of(&self) -> Direction {
        self.direction
    }

    /// Whether the first reported crossing stops the run.
    pub fn is_terminal(&self) -> bool {
        self.terminal
    }

    /// `g(t, y)`.
    pub fn value(&self, t: f64, y: &G) -> f64 {
        (self.g)(t, y)
    }
}

/// A located event.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord<G: LieGroup> {
    /// Index of the event in the options.
    pub index: usize,
    /// Located time.
    pub t: f64,
    /// State at `t` (from the dense output).
    pub y: G,
    /// True if `g` was rising through zero.
    pub rising: bool,
    /// True if the event stopped the integration.
    pub terminal: bool,
}

/// Brent's `zeroin` on `[a, b]` with `f(a)·f(b) ≤ 0`: returns a point within
/// `2ε|x| + xtol/2` of a zero of `f` (and the number of evaluations).
pub fn brent(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64, xtol: f64) -> (f64, usize) {
    brent_dyn(&mut f, a, b, fa, fb, xtol)
}

/// [`brent`] on a function called through a trait object: compiled once,
/// not once per caller's closure (the driver's event location runs it for
/// every system × method it is instantiated with; the call through the
/// pointer is nothing beside the dense-output evaluation behind it).
pub(crate) fn brent_dyn(f: &mut dyn FnMut(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64, xtol: f64) -> (f64, usize) {
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    if fa == 0.0 {
        return (a, 0);
    }
    if fb == 0.0 {
        return (b, 0);
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    let mut evals = 0;
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return (b, evals);
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * xm * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * xm * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = xm;
                e = d;
            }
        } else {
            d = xm;
            e = d;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
        evals += 1;
        if !fb.is_finite() {
            return (b, evals);
        }
    }
    (b, evals)
}
