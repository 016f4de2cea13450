//! Butcher tableaux of explicit Runge–Kutta methods, stored as cited `const`
//! data with a const-generic number of stages (so the engine keeps its stage
//! arrays on the stack).
//!
//! A tableau `(A, b, c)` with `s` stages applied to `θ̇ = F(t, θ)` reads
//! `Kᵢ = F(t + cᵢh, θ₀ + h Σⱼ aᵢⱼ Kⱼ)`, `θ₁ = θ₀ + h Σᵢ bᵢ Kᵢ`. The RKMK engine
//! ([`Rkmk`](super::Rkmk)) applies it to the algebra coordinate of
//! `y = y₀·exp(θ)`.
//!
//! Every tableau here is checked in the test suite: explicit (`aᵢⱼ = 0` for
//! `j ≥ i`), row sums `cᵢ = Σⱼ aᵢⱼ`, and all order conditions
//! `Σᵢ bᵢ Φᵢ(τ) = 1/γ(τ)` for the rooted trees `τ` up to its order
//! ([`order_residual`](super::trees::order_residual)), likewise for the
//! embedded weights and the continuous extensions.
//!
//! References:
//! - \[Heun1900\] K. Heun, *Neue Methode zur approximativen Integration der
//!   Differentialgleichungen einer unabhängigen Veränderlichen*, Z. Math.
//!   Phys. 45 (1900) 23–38.
//! - \[Kutta1901\] W. Kutta, *Beitrag zur näherungsweisen Integration totaler
//!   Differentialgleichungen*, Z. Math. Phys. 46 (1901) 435–453.
//! - \[DP80\] J. R. Dormand, P. J. Prince, *A family of embedded Runge–Kutta
//!   formulae*, J. Comput. Appl. Math. 6 (1980) 19–26.
//! - \[Sha86\] L. F. Shampine, *Some practical Runge–Kutta formulas*, Math.
//!   Comp. 46 (1986) 135–150 (the dense output of DOPRI5).
//! - \[HNW93\] E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary
//!   Differential Equations I*, 2nd ed., Springer 1993: Table II.1.1 (RK4),
//!   Table II.5.2 (DOPRI5), §II.6 and the code DOPRI5 (dense output
//!   coefficients `d`), §II.4 (step-size control).
//! - \[But64\] J. C. Butcher, *On Runge–Kutta processes of high order*, J.
//!   Austral. Math. Soc. 4 (1964) 179–194; tableau as in J. C. Butcher,
//!   *Numerical Methods for Ordinary Differential Equations*, Wiley 2008, §324.
//! - \[MK99\] H. Munthe-Kaas, *High order Runge–Kutta methods on manifolds*,
//!   Appl. Numer. Math. 29 (1999) 115–127.
//! - \[IMNZ00\] A. Iserles, H. Z. Munthe-Kaas, S. P. Nørsett, A. Zanna,
//!   *Lie-group methods*, Acta Numerica 9 (2000) 215–365.

/// Highest power of `σ` in a continuous extension `bᵢ(σ)` (and in the
/// polynomial of a [`DensePoly`](super::DensePoly)).
pub const DENSE_DEGREE: usize = 5;

/// An explicit Runge–Kutta method with `S` stages.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tableau<const S: usize> {
    /// Short name, e.g. `"RK4"`.
    pub name: &'static str,
    /// Where the coefficients come from.
    pub source: &'static str,
    /// The strictly lower-triangular matrix `A` (row `i`: stage `i`).
    pub a: [[f64; S]; S],
    /// Weights `b` of the propagated solution.
    pub b: [f64; S],
    /// Nodes `c` (`cᵢ = Σⱼ aᵢⱼ`).
    pub c: [f64; S],
    /// Classical order `p` of `(A, b, c)`.
    pub order: u32,
    /// Embedded weights `b̂` for error estimation, if any.
    pub embedded: Option<Embedded<S>>,
    /// A continuous extension `bᵢ(σ)` using the same stages, if any.
    pub dense: Option<DenseWeights<S>>,
    /// A commutator-economised Lie-group form of the method, if any (used by
    /// default by [`Rkmk`](super::Rkmk), see [`BracketForm`]).
    pub brackets: Option<BracketForm>,
}

/// Embedded weights `b̂` of a second solution of order `order`; the
/// difference of the two solutions estimates the local error of the lower.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Embedded<const S: usize> {
    /// The weights `b̂`.
    pub b_hat: [f64; S],
    /// Order `p̂` of `(A, b̂, c)`.
    pub order: u32,
}

/// A continuous extension `θ(t₀ + σh) = θ₀ + h Σᵢ bᵢ(σ) Kᵢ`, `σ ∈ [0, 1]`,
/// with `bᵢ(σ) = Σ_{m=1}^{DENSE_DEGREE} coeffs[m−1][i] σᵐ` (so `bᵢ(0) = 0`;
/// `bᵢ(1) = bᵢ` for a consistent extension).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseWeights<const S: usize> {
    /// Power-basis coefficients, row `m − 1` multiplies `σᵐ`.
    pub coeffs: [[f64; S]; DENSE_DEGREE],
    /// Order `q` of the extension: its local error is `O(h^{q+1})` for every `σ`.
    pub order: u32,
}

/// One commutator term `coeff·h²·[K_left, K_right]` (0-based stage indices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BracketTerm {
    /// Index of the left stage slope.
    pub left: usize,
    /// Index of the right stage slope.
    pub right: usize,
    /// Coefficient multiplying `h²·[K_left, K_right]`.
    pub coeff: f64,
}

/// The commutator form of an RKMK method \[MK99\], \[IMNZ00\]: the stages use
/// the raw vector field, `Kᵢ = f(t + cᵢh, y₀·exp(θᵢ))` without `dexp⁻¹`, and
/// the corrections `dexp⁻¹` would make are replaced, to the order of the
/// method, by a few commutators of the `Kⱼ`:
/// `θᵢ = h Σⱼ aᵢⱼ Kⱼ + Σ (terms of stage i)`,
/// `Θ = h Σᵢ bᵢ Kᵢ + Σ (output terms)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BracketForm {
    /// `(i, term)`: `term` is added to the argument `θᵢ` of stage `i`.
    pub stages: &'static [(usize, BracketTerm)],
    /// Terms added to the step's increment `Θ`.
    pub output: &'static [BracketTerm],
    /// Where the form comes from, and in which convention.
    pub source: &'static str,
}

impl<const S: usize> Tableau<S> {
    /// Number of stages `S`.
    pub const STAGES: usize = S;

    /// First-same-as-last: the last stage is evaluated at the new solution
    /// (`a_{S,j} = bⱼ`, `c_S = 1`), so it is the first stage of the next step.
    pub const fn is_fsal(&self) -> bool {
        if S < 2 || self.c[S - 1] != 1.0 {
            return false;
        }
        let mut j = 0;
        while j < S {
            if self.a[S - 1][j] != self.b[j] {
                return false;
            }
            j += 1;
        }
        true
    }

    /// Number of leading stages needed for the propagated solution alone
    /// (one past the last non-zero `bᵢ`, and every stage it depends on).
    pub const fn solution_stages(&self) -> usize {
        let mut n = S;
        while n > 1 && self.b[n - 1] == 0.0 {
            n -= 1;
        }
        n
    }

    /// `maxᵢ |cᵢ − Σⱼ aᵢⱼ|`.
    pub fn row_sum_defect(&self) -> f64 {
        (0..S)
            .map(|i| (self.c[i] - self.a[i].iter().sum::<f64>()).abs())
            .fold(0.0, f64::max)
    }

    /// True if `aᵢⱼ = 0` for every `j ≥ i`.
    pub fn is_explicit(&self) -> bool {
        (0..S).all(|i| (i..S).all(|j| self.a[i][j] == 0.0))
    }
}

/// Lie–Euler, order 1: `y₁ = y₀·exp(h f(t₀, y₀))`.
pub const LIE_EULER: Tableau<1> = Tableau {
    name: "Lie-Euler",
    source: "explicit Euler; Lie-group form IMNZ00",
    a: [[0.0]],
    b: [1.0],
    c: [0.0],
    order: 1,
    embedded: None,
    dense: None,
    brackets: None,
};

/// Heun's second-order method (explicit trapezoidal rule) \[Heun1900\],
/// `c = (0, 1)`, `a₂₁ = 1`, `b = (½, ½)`.
pub const HEUN: Tableau<2> = Tableau {
    name: "Heun",
    source: "Heun (1900); HNW93 Table II.1.1 (order 2, c2 = 1)",
    a: [[0.0, 0.0], [1.0, 0.0]],
    b: [0.5, 0.5],
    c: [0.0, 1.0],
    order: 2,
    embedded: None,
    dense: None,
    brackets: None,
};

/// Kutta's third-order method \[Kutta1901\],
/// `c = (0, ½, 1)`, `a₂₁ = ½`, `a₃₁ = −1`, `a₃₂ = 2`, `b = (1/6, 2/3, 1/6)`.
pub const KUTTA3: Tableau<3> = Tableau {
    name: "Kutta3",
    source: "Kutta (1901); HNW93 Table II.1.1 (order 3)",
    a: [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [-1.0, 2.0, 0.0]],
    b: [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    c: [0.0, 0.5, 1.0],
    order: 3,
    embedded: None,
    dense: None,
    brackets: None,
};

/// The commutator form of classical RK4 with two commutators \[MK99\],
/// \[IMNZ00\], written for `ẏ = y·f`, `y = y₀·exp(θ)` (left
/// trivialisation, in which `dexp⁻¹_{−θ} = I + ½ad_θ + …`, so the signs of the
/// commutators are opposite to the right-trivialised form `ẏ = A(y)·y`
/// printed in \[IMNZ00\]):
/// `θ₃ = (h/2)K₂ + (h²/8)[K₁, K₂]`, `Θ = (h/6)(K₁ + 2K₂ + 2K₃ + K₄) + (h²/12)[K₁, K₄]`.
pub const RK4_BRACKETS: BracketForm = BracketForm {
    stages: &[(2, BracketTerm { left: 0, right: 1, coeff: 1.0 / 8.0 })],
    output: &[BracketTerm { left: 0, right: 3, coeff: 1.0 / 12.0 }],
    source: "Munthe-Kaas (1999); IMNZ00 (RKMK methods), signs for the left-trivialised equation",
};

/// The classical fourth-order method of Kutta \[Kutta1901\], HNW93 Table II.1.1,
/// with the two-commutator Lie-group form [`RK4_BRACKETS`].
pub const RK4: Tableau<4> = Tableau {
    name: "RK4",
    source: "Kutta (1901), classical RK4; HNW93 Table II.1.1",
    a: [[0.0, 0.0, 0.0, 0.0], [0.5, 0.0, 0.0, 0.0], [0.0, 0.5, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]],
    b: [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    c: [0.0, 0.5, 0.5, 1.0],
    order: 4,
    embedded: None,
    dense: None,
    brackets: Some(RK4_BRACKETS),
};

const DP_B: [f64; 7] = [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0];

/// The coefficients `d` of Shampine's dense output of DOPRI5 \[Sha86\], as in
/// the code DOPRI5 of \[HNW93\].
const DP_D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// The power-basis weights of the DOPRI5 continuous extension. The code
/// DOPRI5 evaluates `θ(σ) = θ₀ + σ(Δ + (1−σ)(r₃ + σ(r₄ + (1−σ)r₅)))` with
/// `Δ = hΣbᵢKᵢ`, `r₃ = hK₁ − Δ`, `r₄ = Δ − hK₇ − r₃`, `r₅ = hΣdᵢKᵢ`; expanding
/// in powers of `σ`:
/// `bᵢ(σ) = δᵢ₁σ + (3bᵢ − 2δᵢ₁ − δᵢ₇ + dᵢ)σ² + (−2bᵢ + δᵢ₁ + δᵢ₇ − 2dᵢ)σ³ + dᵢσ⁴`.
const fn dopri5_dense() -> [[f64; 7]; DENSE_DEGREE] {
    let mut w = [[0.0; 7]; DENSE_DEGREE];
    let mut i = 0;
    while i < 7 {
        let d1 = if i == 0 { 1.0 } else { 0.0 };
        let d7 = if i == 6 { 1.0 } else { 0.0 };
        w[0][i] = d1;
        w[1][i] = 3.0 * DP_B[i] - 2.0 * d1 - d7 + DP_D[i];
        w[2][i] = -2.0 * DP_B[i] + d1 + d7 - 2.0 * DP_D[i];
        w[3][i] = DP_D[i];
        i += 1;
    }
    w
}

/// Dormand–Prince 5(4) \[DP80\], HNW93 Table II.5.2: 7 stages, FSAL, order 5
/// propagated (local extrapolation), embedded order 4, and Shampine's
/// continuous extension of order 4 \[Sha86\].
pub const DOPRI5: Tableau<7> = Tableau {
    name: "DOPRI5",
    source: "Dormand & Prince (1980); HNW93 Table II.5.2; dense output: Shampine (1986), code DOPRI5",
    a: [
        [0.0; 7],
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0],
        [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0, 0.0],
        [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0, 0.0],
        DP_B,
    ],
    b: DP_B,
    c: [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    order: 5,
    embedded: Some(Embedded {
        b_hat: [
            5179.0 / 57600.0,
            0.0,
            7571.0 / 16695.0,
            393.0 / 640.0,
            -92097.0 / 339200.0,
            187.0 / 2100.0,
            1.0 / 40.0,
        ],
        order: 4,
    }),
    dense: Some(DenseWeights { coeffs: dopri5_dense(), order: 4 }),
    brackets: None,
};

/// Butcher's seven-stage method of order 6 \[But64\],
/// `c = (0, ⅓, ⅔, ⅓, ½, ½, 1)`, `b = (11/120, 0, 27/40, 27/40, −4/15, −4/15, 11/120)`.
pub const BUTCHER6: Tableau<7> = Tableau {
    name: "Butcher6",
    source: "Butcher (1964); Butcher, Numerical Methods for ODEs (2008) §324",
    a: [
        [0.0; 7],
        [1.0 / 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 2.0 / 3.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1.0 / 12.0, 1.0 / 3.0, -1.0 / 12.0, 0.0, 0.0, 0.0, 0.0],
        [-1.0 / 16.0, 9.0 / 8.0, -3.0 / 16.0, -3.0 / 8.0, 0.0, 0.0, 0.0],
        [0.0, 9.0 / 8.0, -3.0 / 8.0, -3.0 / 4.0, 1.0 / 2.0, 0.0, 0.0],
        [9.0 / 44.0, -9.0 / 11.0, 63.0 / 44.0, 18.0 / 11.0, 0.0, -16.0 / 11.0, 0.0],
    ],
    b: [11.0 / 120.0, 0.0, 27.0 / 40.0, 27.0 / 40.0, -4.0 / 15.0, -4.0 / 15.0, 11.0 / 120.0],
    c: [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0, 1.0 / 2.0, 1.0 / 2.0, 1.0],
    order: 6,
    embedded: None,
    dense: None,
    brackets: None,
};
