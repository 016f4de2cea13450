//! Adaptive 15-point Gauss–Kronrod quadrature of a 2-vector integrand (the
//! Clairaut integrals of the torus geodesics): see [`gauss_kronrod`].

use crate::{Error, Result};

/// Kronrod nodes of the 15-point Gauss–Kronrod rule on [−1, 1] (non-negative half).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights.
pub const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
/// Weights of the embedded 7-point Gauss rule (nodes `XGK[1]`, `XGK[3]`, `XGK[5]`, `XGK[7]`).
pub const WG: [f64; 4] = [0.129_484_966_168_869_7, 0.279_705_391_489_276_7, 0.381_830_050_505_118_9, 0.417_959_183_673_469_4];

/// Adaptive 15-point Gauss–Kronrod quadrature of a 2-vector integrand on
/// `[a, b]`: panels are bisected until, in each component, the Kronrod–Gauss
/// difference is below `1e-9` of the panel value or below `1e-16` of `∫|f|`
/// over `[a, b]` (for analytic integrands the Kronrod error is then at
/// round-off level).
pub fn gauss_kronrod<F: Fn(f64) -> [f64; 2]>(f: &F, a: f64, b: f64) -> Result<[f64; 2]> {
    // Kronrod value, Gauss value and Kronrod value of |f| on a panel.
    let panel = |a: f64, b: f64| -> ([f64; 2], [f64; 2], [f64; 2]) {
        let c = 0.5 * (a + b);
        let hw = 0.5 * (b - a);
        let (mut k, mut g, mut ka) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        for i in 0..8 {
            let pts: &[f64] = if i == 7 { &[0.0] } else { &[-1.0, 1.0] };
            for &sg in pts {
                let v = f(c + sg * hw * XGK[i]);
                for m in 0..2 {
                    k[m] += WGK[i] * v[m];
                    ka[m] += WGK[i] * v[m].abs();
                    if i % 2 == 1 {
                        g[m] += WG[i / 2] * v[m];
                    }
                }
            }
        }
        (k.map(|v| v * hw), g.map(|v| v * hw), ka.map(|v| v * hw.abs()))
    };
    let fail = |panels: usize, residual: f64| Error::NoConvergence { what: "torus Clairaut quadrature", iterations: panels, residual };
    let (_, _, scale) = panel(a, b);
    let mut total = [0.0; 2];
    let mut stack = vec![(a, b, 0usize)];
    let mut panels = 0usize;
    while let Some((a, b, depth)) = stack.pop() {
        panels += 1;
        let (k, g, _) = panel(a, b);
        if !(k[0].is_finite() && k[1].is_finite()) {
            return Err(fail(panels, f64::NAN));
        }
        let ok = (0..2).all(|m| (k[m] - g[m]).abs() <= (1e-9 * k[m].abs()).max(1e-16 * scale[m]));
        if ok {
            total[0] += k[0];
            total[1] += k[1];
        } else if depth >= 50 {
            return Err(fail(panels, (k[0] - g[0]).abs().max((k[1] - g[1]).abs())));
        } else {
            let m = 0.5 * (a + b);
            stack.push((m, b, depth + 1));
            stack.push((a, m, depth + 1));
        }
    }
    Ok(total)
}
