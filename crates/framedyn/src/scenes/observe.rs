//! What a record holds: the columns each model reports (position, velocity,
//! frame, the paper's coordinates, momenta, energy, momentum maps, defect),
//! in the order and units of the [module docs](super).

use std::fmt;

use nalgebra::{SMatrix, SVector};

use super::sink::Column;
use super::spec::Quantity;
use crate::bundle::FrameBundle;
use crate::dynamics::affine::{AffineBodyModel, InternalConstraint};
use crate::dynamics::gyroscope2::Z_ROTATION;
use crate::dynamics::{Gyroscope2Model, Gyroscope3Model, PointModel, SplitDispatch, System};
use crate::method::GroupNumerics;
use crate::potential::Potential;

/// The selected column groups.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sel([bool; 9]);

impl Sel {
    /// Every quantity.
    pub(crate) const ALL: Sel = Sel([true; 9]);

    pub(crate) fn new(qs: &[Quantity]) -> Self {
        let mut s = [false; 9];
        for q in qs {
            s[Quantity::ALL.iter().position(|a| a == q).unwrap_or(0)] = true;
        }
        Sel(s)
    }
    pub(crate) fn has(&self, q: Quantity) -> bool {
        self.0[Quantity::ALL.iter().position(|a| *a == q).unwrap_or(0)]
    }

    /// `q` alone, if selected (`None` if not).
    pub(crate) fn only(&self, q: Quantity) -> Option<Sel> {
        self.has(q).then(|| Sel::new(&[q]))
    }
}

/// Collects the values of a record and, on request, the column descriptions.
pub(crate) struct Row<'a> {
    cols: Option<&'a mut Vec<Column>>,
    vals: &'a mut Vec<f64>,
    group: Option<Quantity>,
}

impl<'a> Row<'a> {
    /// A row of values only.
    pub(crate) fn values(vals: &'a mut Vec<f64>) -> Self {
        Row { cols: None, vals, group: None }
    }

    /// A row of values with their column descriptions.
    pub(crate) fn described(cols: &'a mut Vec<Column>, vals: &'a mut Vec<f64>) -> Self {
        Row { cols: Some(cols), vals, group: None }
    }

    /// The columns put from now on belong to `q`.
    fn group(&mut self, q: Quantity) {
        self.group = Some(q);
    }

    fn put(&mut self, name: fmt::Arguments<'_>, unit: &'static str, v: f64) {
        if let Some(c) = self.cols.as_mut() {
            c.push(Column { name: name.to_string(), unit, group: self.group });
        }
        self.vals.push(v);
    }
}

/// The unit of the rate of a chart coordinate of unit `unit`.
fn rate_unit(unit: &'static str) -> &'static str {
    match unit {
        "rad" => "rad/T",
        "L" => "L/T",
        _ => "1/T",
    }
}

/// Generators of the ambient isometries recorded as momentum maps.
fn generators<const E: usize>() -> Vec<(String, SMatrix<f64, E, E>)> {
    if E == 3 {
        vec![("p_phi".into(), SMatrix::<f64, E, E>::from_fn(|i, j| Z_ROTATION[(i, j)]))]
    } else {
        let mut out = Vec::new();
        for a in 0..E {
            for b in a + 1..E {
                let m = SMatrix::<f64, E, E>::from_fn(|i, j| {
                    if i == a && j == b {
                        -1.0
                    } else if i == b && j == a {
                        1.0
                    } else {
                        0.0
                    }
                });
                out.push((format!("J_{a}{b}"), m));
            }
        }
        out
    }
}

/// What a model reports in a record, in the column order of the module
/// docs. Every model of a scene implements it (generic over the bundle, so
/// a new manifold needs nothing here).
pub(crate) trait Observe: SplitDispatch<State: GroupNumerics + Send> + Clone + Send + 'static {
    /// Puts the selected columns of the state `y` at `t` into `row`.
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>);
}

#[allow(clippy::too_many_arguments)]
fn observe_common<B: FrameBundle<N, E>, const N: usize, const E: usize>(
    bundle: &B,
    sel: Sel,
    t: f64,
    x: &SVector<f64, E>,
    v: &SVector<f64, E>,
    frame: Option<&SMatrix<f64, E, N>>,
    row: &mut Row<'_>,
    extra_coords: impl FnOnce(&mut Row<'_>),
) {
    row.put(format_args!("t"), "T", t);
    if sel.has(Quantity::Position) {
        row.group(Quantity::Position);
        for i in 0..E {
            row.put(format_args!("x{i}"), "L", x[i]);
        }
    }
    if sel.has(Quantity::Velocity) {
        row.group(Quantity::Velocity);
        for i in 0..E {
            row.put(format_args!("v{i}"), "L/T", v[i]);
        }
    }
    if sel.has(Quantity::Frame) {
        row.group(Quantity::Frame);
        if let Some(e) = frame {
            for a in 0..N {
                for i in 0..E {
                    row.put(format_args!("e{}_{i}", a + 1), "1", e[(i, a)]);
                }
            }
        }
    }
    if sel.has(Quantity::Coordinates) {
        row.group(Quantity::Coordinates);
        let names = bundle.coordinate_names();
        let units = bundle.coordinate_units();
        let (c, cd) = match bundle.chart(x) {
            Ok(c) => {
                let cd = bundle.chart_tangent(x, v).unwrap_or(SVector::from_element(f64::NAN));
                (c, cd)
            }
            Err(_) => (SVector::from_element(f64::NAN), SVector::from_element(f64::NAN)),
        };
        for i in 0..N {
            row.put(format_args!("{}", names[i]), units[i], c[i]);
        }
        for i in 0..N {
            row.put(format_args!("{}_dot", names[i]), rate_unit(units[i]), cd[i]);
        }
        extra_coords(row);
    }
}

fn observe_tail<S: System, const E: usize>(
    sys: &S,
    sel: Sel,
    y: &S::State,
    row: &mut Row<'_>,
    momentum_map: impl Fn(&SMatrix<f64, E, E>) -> f64,
) {
    if sel.has(Quantity::Energy) {
        row.group(Quantity::Energy);
        row.put(format_args!("energy"), "M L^2/T^2", sys.energy(y));
    }
    if sel.has(Quantity::MomentumMap) {
        row.group(Quantity::MomentumMap);
        for (name, g) in generators::<E>() {
            row.put(format_args!("{name}"), "M L^2/T", momentum_map(&g));
        }
    }
    if sel.has(Quantity::Defect) {
        row.group(Quantity::Defect);
        row.put(format_args!("defect"), "1", sys.defect(y));
    }
}

impl<B, P, const N: usize, const E: usize> Observe for PointModel<B, P, N, E>
where
    B: FrameBundle<N, E> + 'static,
    P: Potential<N, E> + Clone + 'static,
    PointModel<B, P, N, E>: System<State = crate::dynamics::PointState<B::Group, N>>,
    crate::dynamics::PointState<B::Group, N>: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v) = (self.position(y), self.velocity(y));
        observe_common::<B, N, E>(self.bundle(), sel, t, &x, &v, None, row, |_| {});
        observe_tail::<Self, E>(self, sel, y, row, |g| self.momentum_map(y, g).unwrap_or(f64::NAN));
    }
}

impl<B, P> Observe for Gyroscope2Model<B, P>
where
    B: FrameBundle<2, 3> + 'static,
    P: Potential<2, 3> + Clone + 'static,
    <Gyroscope2Model<B, P> as System>::State: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v, e) = (self.position(y), self.velocity(y), self.body_frame(y));
        observe_common::<B, 2, 3>(self.bundle(), sel, t, &x, &v, Some(&e), row, |row| {
            let alpha = match self.bundle().to_chart(&y.0 .0) {
                Ok((_, u)) => u[(1, 0)].atan2(u[(0, 0)]) + self.internal_angle(y),
                Err(_) => f64::NAN,
            };
            row.put(format_args!("alpha"), "rad", alpha);
        });
        if sel.has(Quantity::Momenta) {
            row.group(Quantity::Momenta);
            row.put(format_args!("spin"), "M L^2/T", self.spin(y));
        }
        observe_tail::<Self, 3>(self, sel, y, row, |g| self.momentum_map(y, g).unwrap_or(f64::NAN));
    }
}

impl<B, P> Observe for Gyroscope3Model<B, P>
where
    B: FrameBundle<3, 4> + 'static,
    P: Potential<3, 4> + Clone + 'static,
    <Gyroscope3Model<B, P> as System>::State: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v, e) = (self.position(y), self.velocity(y), self.body_frame(y));
        observe_common::<B, 3, 4>(self.bundle(), sel, t, &x, &v, Some(&e), row, |_| {});
        if sel.has(Quantity::Momenta) {
            row.group(Quantity::Momenta);
            let s = self.spin_body(y);
            for a in 0..3 {
                row.put(format_args!("spin_{}", a + 1), "M L^2/T", s[a]);
            }
        }
        observe_tail::<Self, 4>(self, sel, y, row, |g| self.momentum_map(y, g).unwrap_or(f64::NAN));
    }
}

impl<B, V, C, const N: usize, const E: usize> Observe for AffineBodyModel<B, V, C, N, E>
where
    B: FrameBundle<N, E> + 'static,
    V: Potential<N, E> + Clone + 'static,
    C: InternalConstraint<N>,
    C::Body: Clone,
    AffineBodyModel<B, V, C, N, E>: System<State = crate::dynamics::affine::BodyState<B, C, N, E>> + Clone,
    crate::dynamics::affine::BodyState<B, C, N, E>: GroupNumerics + Send,
{
    fn observe(&self, sel: Sel, t: f64, y: &Self::State, row: &mut Row<'_>) {
        let (x, v, e) = (self.position(y), self.velocity(y), self.body_frame(y));
        observe_common::<B, N, E>(self.bundle(), sel, t, &x, &v, Some(&e), row, |row| {
            let s = self.stretches(y);
            for a in 0..N {
                row.put(format_args!("stretch_{}", a + 1), "1", s[a]);
            }
        });
        if sel.has(Quantity::Momenta) {
            row.group(Quantity::Momenta);
            let k = self.hypermomentum(y);
            for a in 0..N {
                for b in 0..N {
                    row.put(format_args!("k_{}{}", a + 1, b + 1), "M L^2/T", k[(a, b)]);
                }
            }
        }
        if sel.has(Quantity::FrameRate) {
            row.group(Quantity::FrameRate);
            let de = self.frame_rate(y);
            for a in 0..N {
                for i in 0..E {
                    row.put(format_args!("de{}_{i}", a + 1), "1/T", de[(i, a)]);
                }
            }
        }
        observe_tail::<Self, E>(self, sel, y, row, |g| self.noether_charge(y, g).unwrap_or(f64::NAN));
    }
}

