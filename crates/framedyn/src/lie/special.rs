//! Coefficient functions of the closed-form exponentials, as functions of a
//! *signed* squared angle `s`.
//!
//! For a generator `X` with `X³ = −s·X` (so(3): `s = θ²`; so(1,2): `s` is the
//! Casimir `ω² − b₁² − b₂²`, positive for elliptic, zero for parabolic and
//! negative for hyperbolic generators) the exponential and its derivatives are
//! polynomials in `X` whose coefficients are the entire functions below. Writing
//! them in `s` instead of `θ` makes them continuous (indeed analytic) across
//! `s = 0`: for `s < 0` the trigonometric closed forms turn hyperbolic.
//!
//! Each function switches from its closed form to its Taylor series at a
//! threshold chosen for that coefficient: where the closed form cancels
//! catastrophically (`sinc3`, `dexpinv`) the series is used up to `|s| = 1`
//! with enough terms for full double precision; where the closed form is well
//! conditioned (`sinc`, `cosc`) only a tiny neighbourhood of 0 uses the series.

/// Largest `|s|` at which `sinc`/`cosc` use their Taylor series.
pub const SERIES_SMALL: f64 = 1e-6;
/// Largest `|s|` at which `sinc3`/`dexpinv` use their Taylor series.
pub const SERIES_WIDE: f64 = 1.0;

const fn alternating_inverse_factorials<const N: usize>(offset: usize) -> [f64; N] {
    // c_k = (−1)^k / (2k + offset)!
    let mut out = [0.0; N];
    let mut k = 0;
    while k < N {
        let n = 2 * k + offset;
        let mut f = 1.0;
        let mut i = 2;
        while i <= n {
            f *= i as f64;
            i += 1;
        }
        out[k] = if k % 2 == 0 { 1.0 / f } else { -1.0 / f };
        k += 1;
    }
    out
}

const SINC: [f64; 4] = alternating_inverse_factorials::<4>(1);
const COSC: [f64; 4] = alternating_inverse_factorials::<4>(2);
const SINC3: [f64; 11] = alternating_inverse_factorials::<11>(3);
/// `|B_{2k}|/(2k)!`, k = 1..=12: Taylor coefficients of `dexpinv` in `s`.
const DEXPINV: [f64; 12] = [
    1.0 / 12.0,
    1.0 / 720.0,
    1.0 / 30240.0,
    1.0 / 1209600.0,
    1.0 / 47900160.0,
    691.0 / 1307674368000.0,
    1.0 / 74724249600.0,
    3617.0 / 10670622842880000.0,
    43867.0 / 5109094217170944000.0,
    174611.0 / 802857662698291200000.0,
    854513.0 / 155112100433309859840000.0,
    236364091.0 / 1693824136731743669452800000.0,
];

#[inline]
fn horner(c: &[f64], s: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ck| acc * s + ck)
}

/// `sin(√s)/√s` (`sinh(√−s)/√−s` for `s < 0`); entire, `= Σ (−s)^k/(2k+1)!`.
#[inline]
pub fn sinc(s: f64) -> f64 {
    if s.abs() < SERIES_SMALL {
        horner(&SINC, s)
    } else if s > 0.0 {
        let x = s.sqrt();
        x.sin() / x
    } else {
        let y = (-s).sqrt();
        y.sinh() / y
    }
}

/// `(1 − cos√s)/s` (`(cosh√−s − 1)/(−s)` for `s < 0`); `= Σ (−s)^k/(2k+2)!`.
#[inline]
pub fn cosc(s: f64) -> f64 {
    if s.abs() < SERIES_SMALL {
        horner(&COSC, s)
    } else if s > 0.0 {
        let h = 0.5 * s.sqrt();
        let sh = h.sin();
        2.0 * sh * sh / s
    } else {
        let h = 0.5 * (-s).sqrt();
        let sh = h.sinh();
        -2.0 * sh * sh / s
    }
}

/// `(sinc(s), cosc(s))` together, with one `sin_cos` of the half angle
/// instead of two sines: `sin θ = 2 sin(θ/2) cos(θ/2)`,
/// `1 − cos θ = 2 sin²(θ/2)` (the same closed forms, equal to round-off;
/// the Taylor series below [`SERIES_SMALL`]). For the exponentials of
/// so(3) and so(1,2) in the integrators' inner loop.
#[inline(always)]
pub fn sinc_cosc(s: f64) -> (f64, f64) {
    if s.abs() < SERIES_SMALL {
        (horner(&SINC, s), horner(&COSC, s))
    } else if s > 0.0 {
        let x = s.sqrt();
        let (sh, ch) = (0.5 * x).sin_cos();
        (2.0 * sh * ch / x, 2.0 * sh * sh / s)
    } else {
        let y = (-s).sqrt();
        let e = (0.5 * y).exp_m1();
        // sinh(y/2) = (e + e/(e+1))/2, cosh(y/2) = (e + 1 + 1/(e+1))/2
        let inv = 1.0 / (e + 1.0);
        let (sh, ch) = (0.5 * (e + e * inv), 0.5 * (e + 1.0 + inv));
        (2.0 * sh * ch / y, -2.0 * sh * sh / s)
    }
}

/// `(1 − sinc(s))/s = (√s − sin√s)/s^{3/2}` (hyperbolic for `s < 0`);
/// `= Σ (−s)^k/(2k+3)!`.
#[inline]
pub fn sinc3(s: f64) -> f64 {
    if s.abs() < SERIES_WIDE {
        horner(&SINC3, s)
    } else if s > 0.0 {
        let x = s.sqrt();
        (x - x.sin()) / (s * x)
    } else {
        let y = (-s).sqrt();
        (y.sinh() - y) / (-s * y)
    }
}

/// `(1 − (√s/2)·cot(√s/2))/s` (`((y/2)coth(y/2) − 1)/y²`, `y = √−s`, for
/// `s < 0`); `= Σ_{k≥1} |B_{2k}|/(2k)! s^{k−1}`, singular at `s = (2π)²`.
/// The coefficient of `ad²` in the closed-form `dexp⁻¹` of so(3), su(2), so(1,2).
#[inline]
pub fn dexpinv(s: f64) -> f64 {
    if s.abs() < SERIES_WIDE {
        horner(&DEXPINV, s)
    } else if s > 0.0 {
        let h = 0.5 * s.sqrt();
        (1.0 - h / h.tan()) / s
    } else {
        let h = 0.5 * (-s).sqrt();
        (h / h.tanh() - 1.0) / (-s)
    }
}

/// `dexp_a(v) = v + cosc(s)·a × v + sinc3(s)·a × (a × v)`, `s = |a|²`: the
/// closed-form `dexp` of a Lie algebra whose bracket is the cross product
/// (so(3), su(2) in the paper's basis), where `ad_a³ = −s·ad_a`.
#[inline]
pub fn dexp_cross(a: &nalgebra::Vector3<f64>, v: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
    let s = a.norm_squared();
    let av = a.cross(v);
    v + av * cosc(s) + a.cross(&av) * sinc3(s)
}

/// `dexp_a⁻¹(v) = v − ½·a × v + dexpinv(s)·a × (a × v)`, `s = |a|²`, valid for
/// `|a| < 2π`: the inverse of [`dexp_cross`].
#[inline]
pub fn dexp_inv_cross(a: &nalgebra::Vector3<f64>, v: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
    let s = a.norm_squared();
    let av = a.cross(v);
    v - av * 0.5 + a.cross(&av) * dexpinv(s)
}
