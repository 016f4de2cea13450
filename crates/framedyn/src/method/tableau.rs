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
//! - \[PD81\] P. J. Prince, J. R. Dormand, *High order embedded Runge–Kutta
//!   formulae*, J. Comput. Appl. Math. 7 (1981) 67–75.
//! - \[MK99\] H. Munthe-Kaas, *High order Runge–Kutta methods on manifolds*,
//!   Appl. Numer. Math. 29 (1999) 115–127.
//! - \[IMNZ00\] A. Iserles, H. Z. Munthe-Kaas, S. P. Nørsett, A. Zanna,
//!   *Lie-group methods*, Acta Numerica 9 (2000) 215–365.

/// Highest power of `σ` in a continuous extension `bᵢ(σ)` (and in the
/// polynomial of a [`DensePoly`](super::DensePoly)).
pub const DENSE_DEGREE: usize = 7;

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
    /// A continuous extension that needs stages of its own (evaluated only
    /// when dense output is requested), if any; see [`DenseStages`].
    pub dense_stages: Option<&'static DenseStages>,
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
    /// A second, lower-order embedded solution whose difference corrects the
    /// estimate as in DOP853 (see [`Secondary`]), if any.
    pub secondary: Option<Secondary<S>>,
}

impl<const S: usize> Embedded<S> {
    /// The order `r` of the error *estimate* as the controller sees it: the
    /// estimate is `O(h^{r+1})`. Without a secondary solution `r = p̂`
    /// (`Θ − Θ̂ = O(h^{p̂+1})`); with one of order `p̃` the combined estimate
    /// `‖e₁‖²/√(‖e₁‖² + w‖e₂‖²) = O(h^{2(p̂+1) − (p̃+1)})`, so
    /// `r = 2p̂ − p̃` (DOP853: `p̂ = 5`, `p̃ = 3`, `r = 7`, i.e. the step-size
    /// exponent `1/8` of \[HNW93\] §II.5 and the code DOP853).
    pub const fn estimate_order(&self) -> u32 {
        match &self.secondary {
            Some(sec) => 2 * self.order - sec.order,
            None => self.order,
        }
    }
}

/// The secondary embedded solution of a combined error estimator
/// \[HNW93\] §II.5 (the code DOP853): with `e₁ = Θ − Θ̂` (order `p̂`),
/// `e₂ = Θ − Θ̃` (order `p̃ < p̂`) and a norm `‖·‖`, the estimate is
/// `err = ‖e₁‖²/√(‖e₁‖² + w‖e₂‖²)`, which behaves like `‖e₁‖` for large
/// steps and like `‖e₁‖·(‖e₁‖/√w‖e₂‖) = O(h^{2p̂ − p̃ + 1})` for small ones,
/// so it is closer to the error of the propagated higher-order solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Secondary<const S: usize> {
    /// The weights `b̃`.
    pub b_hat: [f64; S],
    /// Order `p̃` of `(A, b̃, c)`.
    pub order: u32,
    /// The weight `w` (DOP853: 0.01).
    pub weight: f64,
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
    dense_stages: None,
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
    dense_stages: None,
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
    dense_stages: None,
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
    dense_stages: None,
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
        secondary: None,
    }),
    dense: Some(DenseWeights { coeffs: dopri5_dense(), order: 4 }),
    dense_stages: None,
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
    dense_stages: None,
    brackets: None,
};

/// Largest number of stages of a tableau together with the extra stages of
/// its [`DenseStages`] (16 for DOP853).
pub const EXTENDED_STAGES: usize = 16;

/// A continuous extension with stages of its own (DOP853 \[HNW93\] §II.6,
/// code DOP853): after the `S` stages of the step come
/// - stage `S` (0-based), the step's end: `θ = Θ`, `c = 1`,
///   `K = dexp⁻¹_{−Θ} f(t₁, y₁)` (row `S` of [`a`](Self::a) is `b`);
/// - stages `S + 1 … stages − 1`: `θᵢ = h Σ_{j<i} aᵢⱼ Kⱼ`,
///   `Kᵢ = dexp⁻¹_{−θᵢ} f(t₀ + cᵢh, y₀·exp(θᵢ))`;
///
/// and `θ(σ) = h Σᵢ bᵢ(σ) Kᵢ` over all `stages`, with the power-basis
/// weights [`dense`](Self::dense). They are evaluated only when dense output
/// is requested (DOP853: 3 evaluations of `f` beyond the step's 12).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseStages {
    /// Total number of stages, `≤ EXTENDED_STAGES`.
    pub stages: usize,
    /// The extended matrix: rows `0 … S−1` are the tableau's `A`, row `S` its
    /// `b`, the rest the extra stages (zero-padded to `EXTENDED_STAGES`).
    pub a: [[f64; EXTENDED_STAGES]; EXTENDED_STAGES],
    /// The nodes of all stages.
    pub c: [f64; EXTENDED_STAGES],
    /// The continuous extension over all stages, and its order.
    pub dense: DenseWeights<EXTENDED_STAGES>,
}

// The coefficients of the code DOP853 of Hairer & Wanner [HNW93] (dop853.f,
// as in SciPy's `dop853_coefficients.py`), rounded from their 30 printed
// digits to the nearest f64. Row 12 of `D8_A` is `b`, rows 13–15 are the
// extra stages of the dense output.
#[allow(clippy::excessive_precision)]
const D8_A: [[f64; 16]; 16] = [
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.05260015195876773, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0197250569845379, 0.0591751709536137, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.02958758547680685, 0.0, 0.08876275643042054, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402, 0.008273789163814023, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894, -43.48988418106996, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423, -33.28821096898486, -0.020331201708508627, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259, 0.0, 0.0, 0.0, 0.0],
    [0.056167502283047954, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25350021021662483, -0.2462390374708025, -0.12419142326381637, 0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298, 0.0, 0.0, 0.0],
    [0.03183464816350214, 0.0, 0.0, 0.0, 0.0, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099, 0.0, 0.0, -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456, 0.1413124436746325, 0.0, 0.0],
    [-0.42889630158379194, 0.0, 0.0, 0.0, 0.0, -4.697621415361164, 7.683421196062599, 4.06898981839711, 0.3567271874552811, 0.0, 0.0, 0.0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987, 0.0],
];
#[allow(clippy::excessive_precision)]
const D8_C: [f64; 16] = [0.0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726, 0.3333333333333333, 0.25, 0.3076923076923077, 0.6512820512820513, 0.6, 0.8571428571428571, 1.0, 1.0, 0.1, 0.2, 0.7777777777777778];
#[allow(clippy::excessive_precision)]
const D8_E5: [f64; 12] = [0.01312004499419488, 0.0, 0.0, 0.0, 0.0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864, -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294];
#[allow(clippy::excessive_precision)]
const D8_E3: [f64; 12] = [-0.18980075407240762, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, -0.4226823213237919, -0.1521609496625161, 0.20136540080403034, 0.02265179219836082];
#[allow(clippy::excessive_precision)]
const D8_D: [[f64; 16]; 4] = [
    [-8.428938276109013, 0.0, 0.0, 0.0, 0.0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207, 2.117034582445028, -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727, -9.194632392478356, -4.436036387594894],
    [10.427508642579134, 0.0, 0.0, 0.0, 0.0, 242.28349177525817, 165.20045171727028, -374.5467547226902, -22.113666853125306, 7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178, -9.35292435884448, 35.81684148639408],
    [19.985053242002433, 0.0, 0.0, 0.0, 0.0, -387.0373087493518, -189.17813819516758, 527.8081592054236, -11.57390253995963, 6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412, 84.32040550667716, 11.99229113618279],
    [-25.69393346270375, 0.0, 0.0, 0.0, 0.0, -154.18974869023643, -231.5293791760455, 357.6391179106141, 93.40532418362432, -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828, -39.17726167561544, -149.72683625798564],
];

const fn d8_sub_a() -> [[f64; 12]; 12] {
    let mut a = [[0.0; 12]; 12];
    let mut i = 0;
    while i < 12 {
        let mut j = 0;
        while j < 12 {
            a[i][j] = D8_A[i][j];
            j += 1;
        }
        i += 1;
    }
    a
}

const fn d8_b() -> [f64; 12] {
    let mut b = [0.0; 12];
    let mut j = 0;
    while j < 12 {
        b[j] = D8_A[12][j];
        j += 1;
    }
    b
}

const fn d8_c() -> [f64; 12] {
    let mut c = [0.0; 12];
    let mut j = 0;
    while j < 12 {
        c[j] = D8_C[j];
        j += 1;
    }
    c
}

/// `b − e` for the error coefficients `e` of the code (`e = b − b̂`).
const fn d8_minus(e: &[f64; 12]) -> [f64; 12] {
    let b = d8_b();
    let mut w = [0.0; 12];
    let mut j = 0;
    while j < 12 {
        w[j] = b[j] - e[j];
        j += 1;
    }
    w
}

/// The power-basis weights of the DOP853 continuous extension. The code
/// evaluates `θ(σ) = σ(r₁ + (1−σ)(r₂ + σ(r₃ + (1−σ)(r₄ + σ(r₅ + (1−σ)(r₆ + σr₇))))))`
/// with `r₁ = Θ`, `r₂ = hK₁ − Θ`, `r₃ = 2Θ − hK₁ − hK₁₃`, `rₘ = hΣᵢ dₘ₋₄,ᵢKᵢ`
/// (`m = 4 … 7`, over the 16 stages); this multiplies the nested form out.
const fn dop853_dense() -> [[f64; EXTENDED_STAGES]; DENSE_DEGREE] {
    const N: usize = EXTENDED_STAGES;
    let b = d8_b();
    // r[m] for m = 0 … 6 (r₁ … r₇) as weights over the stages.
    let mut r = [[0.0; N]; 7];
    let mut i = 0;
    while i < 12 {
        r[0][i] = b[i];
        r[1][i] = -b[i];
        r[2][i] = 2.0 * b[i];
        i += 1;
    }
    r[1][0] += 1.0;
    r[2][0] -= 1.0;
    r[2][12] -= 1.0;
    let mut m = 0;
    while m < 4 {
        let mut i = 0;
        while i < N {
            r[3 + m][i] = D8_D[m][i];
            i += 1;
        }
        m += 1;
    }
    // Horner from the inside out: p ← (p + r_m)·σ for even m (from the end),
    // p ← (p + r_m)·(1 − σ) for odd; p[k] multiplies σᵏ.
    let mut p = [[0.0; N]; DENSE_DEGREE + 1];
    let mut step = 0;
    while step < 7 {
        let m = 6 - step;
        let mut i = 0;
        while i < N {
            p[0][i] += r[m][i];
            i += 1;
        }
        let mut q = [[0.0; N]; DENSE_DEGREE + 1];
        let mut k = 0;
        while k < DENSE_DEGREE {
            let mut i = 0;
            while i < N {
                if step % 2 == 0 {
                    // ·σ
                    q[k + 1][i] = p[k][i];
                } else {
                    // ·(1 − σ)
                    q[k][i] += p[k][i];
                    q[k + 1][i] -= p[k][i];
                }
                i += 1;
            }
            k += 1;
        }
        p = q;
        step += 1;
    }
    let mut w = [[0.0; N]; DENSE_DEGREE];
    let mut k = 0;
    while k < DENSE_DEGREE {
        w[k] = p[k + 1];
        k += 1;
    }
    w
}

/// The extra stages and the order-7 continuous extension of DOP853.
pub const DOP853_DENSE: DenseStages = DenseStages {
    stages: 16,
    a: D8_A,
    c: D8_C,
    dense: DenseWeights { coeffs: dop853_dense(), order: 7 },
};

/// DOP853 \[HNW93\] §II.5 (Dormand & Prince's 8(5,3) pair \[PD81\] as
/// modified by Hairer & Wanner in the code DOP853): 12 stages, order 8
/// propagated; the error estimate combines the embedded solutions of order 5
/// (`e₁`) and 3 (`e₂`) as `‖e₁‖²/√(‖e₁‖² + 0.01‖e₂‖²)` ([`Secondary`]); the
/// continuous extension of order 7 needs the value at the new point and 3
/// more stages ([`DOP853_DENSE`]). As a 12-stage tableau it is not FSAL in
/// the sense of [`Tableau::is_fsal`], but `f(t₁, y₁)` — evaluated for the
/// next step — is the first stage of the next step, so a step costs 12
/// evaluations (15 with dense output).
pub const DOP853: Tableau<12> = Tableau {
    name: "DOP853",
    source: "Prince & Dormand (1981); Hairer & Wanner, code DOP853 (HNW93 §II.5), coefficients of dop853.f",
    a: d8_sub_a(),
    b: d8_b(),
    c: d8_c(),
    order: 8,
    embedded: Some(Embedded {
        b_hat: d8_minus(&D8_E5),
        order: 5,
        secondary: Some(Secondary { b_hat: d8_minus(&D8_E3), order: 3, weight: 0.01 }),
    }),
    dense: None,
    dense_stages: Some(&DOP853_DENSE),
    brackets: None,
};
