//! Entire coefficient functions of `s = θ²`, generic over the scalar type.
//!
//! The S³ chart and the SO(3) rotation vector need `sin θ/θ`, `1 − θ cot θ`,
//! … at and near `θ = 0`, where the closed forms divide by zero or cancel,
//! and for dual numbers, whose derivative parts through `√s` blow up at
//! `s = 0`. Each function is written in `s` and evaluated by its Taylor series
//! for `s <` [`SERIES_MAX`] (terms until they drop below 1e-19, so the series
//! is exact to double precision there) and by its closed form beyond, where
//! none of them cancels by more than a factor of about 3. Coefficients are the
//! exact rationals rounded once (generated with sympy).

use crate::potential::Scalar;

/// `s = θ²` below which the Taylor series are used.
pub(crate) const SERIES_MAX: f64 = 1.0;

/// `(−1)^k/(2k+1)!`: `sin θ/θ`.
pub const SINC: [f64; 11] = [
    1.0, -0.16666666666666666, 0.008333333333333333, -0.0001984126984126984, 2.7557319223985893e-06,
    -2.505210838544172e-08, 1.6059043836821613e-10, -7.647163731819816e-13, 2.8114572543455206e-15,
    -8.22063524662433e-18, 1.9572941063391263e-20,
];
/// `(−1)^k/(2k)!`: `cos θ`.
pub const COS: [f64; 12] = [
    1.0, -0.5, 0.041666666666666664, -0.001388888888888889, 2.48015873015873e-05, -2.755731922398589e-07,
    2.08767569878681e-09, -1.1470745597729725e-11, 4.779477332387385e-14, -1.5619206968586225e-16,
    4.110317623312165e-19, -8.896791392450574e-22,
];
/// `(cos θ − sin θ/θ)/θ²`.
pub const DSINC: [f64; 11] = [
    -0.3333333333333333, 0.03333333333333333, -0.0011904761904761906, 2.2045855379188714e-05,
    -2.505210838544172e-07, 1.9270852604185937e-09, -1.0706029224547743e-11, 4.498331606952833e-14,
    -1.4797143443923793e-16, 3.9145882126782523e-19, -8.509974375387505e-22,
];
/// `(1 − cos θ·sin θ/θ)/θ²`.
pub const SINCCOS_DEFECT: [f64; 13] = [
    0.6666666666666666, -0.13333333333333333, 0.012698412698412698, -0.0007054673721340388,
    2.565335898669232e-05, -6.577784355562133e-07, 1.2529113058213587e-08, -1.8425166262078804e-10,
    2.1549902060910882e-12, -2.0523716248486557e-14, 1.622428161935696e-16, -1.0816187746237974e-18,
    6.163069940876338e-21,
];
/// `(1 − (sin θ/θ)²)/θ²`.
pub const SINC2_DEFECT: [f64; 12] = [
    0.3333333333333333, -0.044444444444444446, 0.0031746031746031746, -0.00014109347442680775,
    4.275559831115387e-06, -9.39683479366019e-08, 1.5661391322766984e-09, -2.0472406957865337e-11,
    2.1549902060910883e-13, -1.8657923862260506e-15, 1.3520234682797467e-17, -8.320144420183057e-20,
];
/// `(1 − θ cot θ)/θ²` = `Σ 2^{2k}|B_{2k}|/(2k)! θ^{2k−2}` (radius of convergence π²).
pub const COT_DEFECT: [f64; 20] = [
    0.3333333333333333, 0.022222222222222223, 0.0021164021164021165, 0.00021164021164021165,
    2.1377799155576935e-05, 2.1644042808063972e-06, 2.1925947851873778e-07, 2.2214608789979678e-08,
    2.2507846516808994e-09, 2.2805151204592183e-10, 2.3106432599002624e-11, 2.3411706819824882e-12,
    2.3721017400233653e-13, 2.4034415333307705e-14, 2.4351954029183367e-15, 2.4673688045172075e-16,
    2.499967277122081e-17, 2.532996435740635e-18, 2.566461970282629e-19, 2.6003696460137274e-20,
];
/// `(1 − cos θ)/θ²`.
pub const VERSC: [f64; 11] = [
    0.5, -0.041666666666666664, 0.001388888888888889, -2.48015873015873e-05, 2.755731922398589e-07,
    -2.08767569878681e-09, 1.1470745597729725e-11, -4.779477332387385e-14, 1.5619206968586225e-16,
    -4.110317623312165e-19, 8.896791392450574e-22,
];

/// `Σ c_k s^k`, keeping terms up to the first one below 1e-20 of `|c₀|` for
/// this `|s|` (the coefficients decrease and `|s| < 1`). The dropped terms
/// change the first and second derivatives along `s = θ²` by at most
/// `≈ 4k²|c_{k+1}/c_k|·1e-20 < 1e-17` relative (one more factor `s` than the
/// last kept term), so dual numbers up to second order stay exact.
#[inline]
pub fn horner<D: Scalar>(c: &[f64], s: D) -> D {
    let a = s.re().abs();
    let mut n = c.len();
    let mut pow = 1.0;
    for (k, ck) in c.iter().enumerate() {
        if k > 0 && (ck * pow).abs() < 1e-20 * c[0].abs() {
            n = k + 1;
            break;
        }
        pow *= a;
    }
    c[..n].iter().rev().fold(D::from(0.0), |acc, &ck| acc * s + ck)
}

/// `θ` and `(sin θ, cos θ)` for the closed forms (`s ≥ SERIES_MAX`).
#[inline]
fn theta_sc<D: Scalar>(s: D) -> (D, D, D) {
    let t = s.sqrt();
    let (sn, cs) = t.sin_cos();
    (t, sn, cs)
}

/// `sin θ/θ`, `θ = √s`.
pub fn sinc<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&SINC, s)
    } else {
        let (t, sn, _) = theta_sc(s);
        sn / t
    }
}

/// `cos θ`, `θ = √s`.
pub fn cos<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&COS, s)
    } else {
        s.sqrt().cos()
    }
}

/// `(cos θ − sin θ/θ)/θ²` (`= 2·d(sinc)/ds`).
pub fn dsinc<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&DSINC, s)
    } else {
        let (t, sn, cs) = theta_sc(s);
        (cs - sn / t) / s
    }
}

/// `(1 − cos θ·sin θ/θ)/θ²`.
pub fn sinccos_defect<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&SINCCOS_DEFECT, s)
    } else {
        let (t, sn, cs) = theta_sc(s);
        (D::from(1.0) - cs * sn / t) / s
    }
}

/// `(1 − (sin θ/θ)²)/θ²`.
pub fn sinc2_defect<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&SINC2_DEFECT, s)
    } else {
        let (t, sn, _) = theta_sc(s);
        let sc = sn / t;
        (D::from(1.0) - sc * sc) / s
    }
}

/// `(1 − θ cot θ)/θ²` (pole at `θ = π`).
pub fn cot_defect<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&COT_DEFECT, s)
    } else {
        let (t, sn, cs) = theta_sc(s);
        (D::from(1.0) - t * cs / sn) / s
    }
}

/// `(1 − cos θ)/θ²`.
pub fn versc<D: Scalar>(s: D) -> D {
    if s.re() < SERIES_MAX {
        horner(&VERSC, s)
    } else {
        (D::from(1.0) - s.sqrt().cos()) / s
    }
}
