//! Infinitesimal gyroscopes in the parallel-frame form: the derivation shared
//! by [`Gyroscope2Model`](super::gyroscope2::Gyroscope2Model) (n = 2: S², H²,
//! T²) and [`Gyroscope3Model`](super::gyroscope3::Gyroscope3Model) (n = 3: S³).
//!
//! # Variables
//! The body frame is `e = q·ρ`: `q` the frame of the bundle element `g`,
//! parallel-transported along the path, and `ρ ∈ SO(n)` the internal rotation
//! relative to it. The velocity is `ẋ = q·u`. Because `q` is parallel,
//! `De/Dt = q·ρ̇` (no drive term), and (a52) becomes
//! ```text
//! T = (m/2)|u|² + σ·½ tr(ρ̇ J ρ̇ᵀ),        σ = +1 (a52), −1 (Lorentz-type, a138)
//! ```
//! With the body angular velocity `Ŵ = ρᵀρ̇` this is `½ W·𝕀W`, `𝕀 = (tr J)·1 − J`
//! (the matrix form of the inertia operator `Ŵ ↦ JŴ + ŴJ`); for n = 2 it is
//! `½ I α̇²` with `I = Tr J` and `ρ = U(α)`.
//!
//! # Spin
//! The paper's kinematical spin (after (a59), (b62)) in `q`-components is
//! `S = K − Kᵀ`, `K = ρ J ρ̇ᵀ`, i.e. `S = −ρ (JŴ + ŴJ) ρᵀ = −[ρ 𝕀 W]×`. The
//! models carry the **canonical** internal momentum instead, which differs only
//! by the signature: `S_σ = σ S`, the momentum conjugate to the internal
//! rotation. For n = 3 the state holds its vector `π = −vee(S_σ) = σ ρ 𝕀 W`
//! (the spin as an axial vector, in `q`-components); for n = 2 the scalar
//! `s = (S_σ)¹² = σ I α̇` (the paper's `p_ψ` of (a143), (a144)).
//!
//! Why the canonical momentum: (i) without torque it is constant — `q` is
//! parallel, so `DS/Dt = Ṡ` in `q`-components and (b61) reads `ṡ = 0`,
//! `π̇ = 0` exactly, which every Runge–Kutta/RKMK method preserves; (ii) the
//! spin–curvature force is `K s ε u` (n = 2), `K π × u` (n = 3) for **both**
//! signatures: in the Riemannian equations the force depends on `J` only
//! through the spin, and the Lorentz-type kinetic energy is the Riemannian one
//! with `J → −J`, which maps `S ↦ −S = S_σ`; (iii) the momentum maps and the
//! energy are then `σ`-free except for `T_int = σ s²/(2I)` (n = 2),
//! `½ π·(σ ρ𝕀ρᵀ)⁻¹π` (n = 3), and `p_ψ` of (a143)/(a144) is `s` itself.
//!
//! # Equations (a59), (b61)/(b62) in the parallel frame
//! ```text
//! ġ = g·horizontal_lift(g, u)
//! m u̇ = −K S_σ u + F̂                  (spin–curvature force, SPEC §7)
//! ρ̇ = ρ·Ŵ,  W = (σ𝕀)⁻¹ ρᵀ π   (n = 3);   α̇ = σ s / I   (n = 2)
//! π̇ = τ = −vee(Gρᵀ − ρGᵀ)  (n = 3);    ṡ = −∂V/∂α = −⟨G, ρε⟩   (n = 2)
//! ```
//! Here `K` is the sectional curvature ([`FrameBundle::curvature_at`](crate::bundle::FrameBundle::curvature_at)):
//! with `R̂_{abcd} = K(δ_ac δ_bd − δ_ad δ_bc)` the force of (a59) is
//! `½ S^k_l R̂^l_k{}^a{}_j u^j = ½K((Sᵀu)_a − (Su)_a) = −K(Su)_a`.
//! For n = 2, `S_σ = [[0, s], [−s, 0]] = −s ε` gives `m u̇ = K s ε u + F̂`,
//! `ε = [[0, −1], [1, 0]]`; for n = 3, `S_σ = −[π]×` gives `K π × u`. The
//! force is orthogonal to `u` and does no work. `F̂_a = −H_a V` is the
//! horizontal force (frame transported parallel, [`horizontal_force`](super::horizontal_force));
//! `G = qᵀ ∂V/∂e` is [`internal_gradient`](super::internal_gradient) (`G_{cb} = ∂V/∂ρ_{cb}`).
//! The internal equation is (b61) `DS/Dt = N − Nᵀ` with
//! `N^{ab} = −e^a_K ∂V/∂e_{bK}`, i.e. `N = −ρGᵀ` and `Ṡ = Gρᵀ − ρGᵀ`; for
//! n = 2 its `(1, 2)` entry equals `−∂V/∂α` (`∂ρ/∂α = ρε`).
//!
//! # Momentum maps
//! A one-parameter group of ambient isometries `exp(tA)` (`Aᵀη + ηA = 0`)
//! that maps the manifold to itself acts on the configuration `(x, e)` by
//! `x ↦ exp(tA)x`, `e ↦ exp(tA)e`. Its Noether charge is the pairing of the
//! velocity with the generator in the kinetic metric of (a52):
//! ```text
//! J_A = m⟨A x, ẋ⟩_η + σ J^{AB} g(De_A/Dt, P_T(A e_B))  = m⟨A x, ẋ⟩_η + ½ tr(W_A S_σ)
//! ```
//! with `P_T` the tangential projection (`∇_v ξ = P_T(A v)` for the Killing
//! field `ξ = A x`) and `W_A = qᵀηAq` (skew). For n = 2, `½ tr(W_A S_σ) =
//! s·⟨A q₁, q₂⟩_η`; for n = 3 it is `vee(W_A)·π`. The paper's `p_φ` on S², H²,
//! T² is `A = e_y e_xᵀ − e_x e_yᵀ` (rotations about the z axis), e.g. on S²
//! `p_φ = mR² sin²ϑ φ̇ + s cos ϑ`.
//!
//! # Signature
//! `σ = −1` ([`Signature::Lorentz`]) is the indefinite kinetic energy of
//! (a138). What changes (derivation above):
//! the canonical spin `s = −I α̇` is opposite to the kinematical `S¹² = I α̇`;
//! with it the spin–curvature force keeps its form `K s ε u`; `α̇ = −s/I`; the
//! energy is `(m/2)|u|² − s²/(2I) + V`. In the radial Hamilton–Jacobi equation
//! (a143) the term is therefore `+ (m/I)s²` for (a138) and `− (m/I)s²` for
//! (a135) — the printed signs are swapped (SPEC §8). The tests compare both
//! signatures with the SO(3) and SO(1,2) tops of (d94), (a142)/(b142) whose
//! third moment is `±I`.

use crate::body::Signature;

/// `σ = +1` for [`Signature::Riemannian`], `−1` for [`Signature::Lorentz`].
pub fn signature_sign(signature: Signature) -> f64 {
    match signature {
        Signature::Riemannian => 1.0,
        Signature::Lorentz => -1.0,
    }
}
