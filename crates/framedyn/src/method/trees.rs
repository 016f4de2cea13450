//! Rooted trees and the Runge–Kutta order conditions, for checking tableaux
//! numerically (\[HNW93\] §II.2, Butcher's theory).
//!
//! A method `(A, b, c)` has order `p` iff `Σᵢ bᵢ Φᵢ(τ) = 1/γ(τ)` for every
//! rooted tree `τ` with at most `p` vertices, where the stage weights are
//! `Φᵢ(•) = 1` and `Φᵢ([τ₁, …, τₘ]) = Πₖ Σⱼ aᵢⱼ Φⱼ(τₖ)`, and the density is
//! `γ(•) = 1`, `γ([τ₁, …, τₘ]) = |τ| Πₖ γ(τₖ)`. A continuous extension
//! `bᵢ(σ)` has order `q` iff `Σᵢ bᵢ(σ) Φᵢ(τ) = σ^{|τ|}/γ(τ)` for `|τ| ≤ q`.
//!
//! \[HNW93\] E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary
//! Differential Equations I*, 2nd ed., Springer 1993, §II.2, §II.6.

use std::collections::BTreeSet;

use super::tableau::{DenseWeights, DENSE_DEGREE};

/// A rooted tree, stored canonically as the sorted list of the subtrees of
/// its root (so equal trees compare equal).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RootedTree(Vec<RootedTree>);

impl RootedTree {
    /// The tree with one vertex, `•`.
    pub fn leaf() -> Self {
        RootedTree(Vec::new())
    }

    /// The tree `[τ₁, …, τₘ]`: a root with the given subtrees.
    pub fn graft(mut children: Vec<RootedTree>) -> Self {
        children.sort();
        RootedTree(children)
    }

    /// The subtrees of the root.
    pub fn children(&self) -> &[RootedTree] {
        &self.0
    }

    /// Number of vertices `|τ|`.
    pub fn order(&self) -> usize {
        1 + self.0.iter().map(RootedTree::order).sum::<usize>()
    }

    /// The density `γ(τ) = |τ| Πₖ γ(τₖ)`.
    pub fn density(&self) -> f64 {
        self.order() as f64 * self.0.iter().map(RootedTree::density).product::<f64>()
    }

    /// Stage weights `Φᵢ(τ)`, `i = 1…S`, of the matrix `a`.
    pub fn stage_weights<const S: usize>(&self, a: &[[f64; S]; S]) -> [f64; S] {
        let mut phi = [1.0; S];
        for child in &self.0 {
            let w = child.stage_weights(a);
            for (i, p) in phi.iter_mut().enumerate() {
                *p *= (0..S).map(|j| a[i][j] * w[j]).sum::<f64>();
            }
        }
        phi
    }

    /// Every tree obtained by attaching one new leaf to one vertex of `self`.
    fn extensions(&self) -> Vec<RootedTree> {
        let mut out = Vec::new();
        let mut with_leaf = self.0.clone();
        with_leaf.push(RootedTree::leaf());
        out.push(RootedTree::graft(with_leaf));
        for (k, child) in self.0.iter().enumerate() {
            for ext in child.extensions() {
                let mut ch = self.0.clone();
                ch[k] = ext;
                out.push(RootedTree::graft(ch));
            }
        }
        out
    }
}

/// All rooted trees with exactly `n ≥ 1` vertices (none for `n = 0`):
/// 1, 1, 2, 4, 9, 20, 48, 115 trees for `n = 1…8`. Every tree of order `n`
/// arises from one of order `n − 1` by attaching a leaf.
pub fn trees_of_order(n: usize) -> Vec<RootedTree> {
    if n == 0 {
        return Vec::new();
    }
    let mut level: BTreeSet<RootedTree> = BTreeSet::new();
    level.insert(RootedTree::leaf());
    for _ in 1..n {
        let next: BTreeSet<RootedTree> = level.iter().flat_map(RootedTree::extensions).collect();
        level = next;
    }
    level.into_iter().collect()
}

/// `max |Σᵢ wᵢ Φᵢ(τ) − 1/γ(τ)|` over all trees with `1 ≤ |τ| ≤ p`: zero (to
/// round-off) iff the weights `w` (the `b` or `b̂` of a tableau) give order `p`.
pub fn order_residual<const S: usize>(a: &[[f64; S]; S], w: &[f64; S], p: usize) -> f64 {
    (1..=p)
        .flat_map(trees_of_order)
        .map(|t| {
            let phi = t.stage_weights(a);
            let lhs: f64 = w.iter().zip(phi.iter()).map(|(wi, pi)| wi * pi).sum();
            (lhs - 1.0 / t.density()).abs()
        })
        .fold(0.0, f64::max)
}

/// The weights `bᵢ(σ)` of a continuous extension at `σ`.
pub fn dense_weights_at<const S: usize>(d: &DenseWeights<S>, sigma: f64) -> [f64; S] {
    let mut w = [0.0; S];
    for (i, wi) in w.iter_mut().enumerate() {
        let mut s = 0.0;
        for m in (0..DENSE_DEGREE).rev() {
            s = (s + d.coeffs[m][i]) * sigma;
        }
        *wi = s;
    }
    w
}

/// `max |Σᵢ bᵢ(σ) Φᵢ(τ) − σ^{|τ|}/γ(τ)|` over the trees with `1 ≤ |τ| ≤ q`
/// and the given `σ`: zero iff the continuous extension has order `q` there.
pub fn dense_order_residual<const S: usize>(a: &[[f64; S]; S], d: &DenseWeights<S>, q: usize, sigmas: &[f64]) -> f64 {
    let trees: Vec<RootedTree> = (1..=q).flat_map(trees_of_order).collect();
    let mut worst: f64 = 0.0;
    for &s in sigmas {
        let w = dense_weights_at(d, s);
        for t in &trees {
            let phi = t.stage_weights(a);
            let lhs: f64 = w.iter().zip(phi.iter()).map(|(wi, pi)| wi * pi).sum();
            worst = worst.max((lhs - s.powi(t.order() as i32) / t.density()).abs());
        }
    }
    worst
}
