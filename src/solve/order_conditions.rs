//! Test helper: Butcher's order conditions checked numerically on rooted trees.
//!
//! A Runge–Kutta method (A, b) has order p iff Σ_i b_i Φ_i(τ) = 1/γ(τ) for every rooted tree τ
//! with at most p nodes, where Φ(•) = 1 and Φ([τ₁, …, τ_m])_i = Π_k (A Φ(τ_k))_i, and the
//! density is γ(•) = 1, γ(τ) = |τ| Π_k γ(τ_k). A continuous extension b(θ) has order p* iff
//! Σ_i b_i(θ) Φ_i(τ) = θ^|τ| / γ(τ) for |τ| ≤ p* [Hairer–Nørsett–Wanner, Sec. II.2 and II.6].
//! Trees are generated up to order 8: 1, 1, 2, 4, 9, 20, 48, 115 of each order.

/// Largest tree order generated.
const MAX_ORDER: usize = 8;

/// All rooted trees up to [`MAX_ORDER`] nodes, children as indices into the same list.
struct Trees {
    order: Vec<usize>,
    children: Vec<Vec<usize>>,
    gamma: Vec<f64>,
}

impl Trees {
    fn generate() -> Self {
        let mut trees = Trees {
            order: vec![1],
            children: vec![Vec::new()],
            gamma: vec![1.0],
        };
        for n in 2..=MAX_ORDER {
            let known = trees.order.len();
            let mut found = Vec::new();
            let mut current = Vec::new();
            multisets(
                &trees.order[..known],
                n - 1,
                known,
                &mut current,
                &mut found,
            );
            for children in found {
                let gamma = n as f64 * children.iter().map(|&c| trees.gamma[c]).product::<f64>();
                trees.order.push(n);
                trees.children.push(children);
                trees.gamma.push(gamma);
            }
        }
        trees
    }
}

/// Appends every multiset of tree indices (non-increasing, each below `below`) whose orders sum
/// to `remaining`.
fn multisets(
    order: &[usize],
    remaining: usize,
    below: usize,
    current: &mut Vec<usize>,
    out: &mut Vec<Vec<usize>>,
) {
    if remaining == 0 {
        out.push(current.clone());
        return;
    }
    for idx in (0..below).rev() {
        if order[idx] <= remaining {
            current.push(idx);
            multisets(order, remaining - order[idx], idx + 1, current, out);
            current.pop();
        }
    }
}

/// An explicit tableau with its elementary weights Φ(τ) for every tree.
pub(crate) struct Tableau {
    trees: Trees,
    phi: Vec<Vec<f64>>,
}

impl Tableau {
    /// `a[i]` holds a_i0 .. a_i(i−1) of an s-stage explicit method.
    pub(crate) fn new(a: &[&[f64]], s: usize) -> Self {
        let trees = Trees::generate();
        let mut a_phi: Vec<Vec<f64>> = Vec::new();
        let mut phi: Vec<Vec<f64>> = Vec::new();
        for children in &trees.children {
            let mut p = vec![1.0; s];
            for &c in children {
                for (pi, api) in p.iter_mut().zip(&a_phi[c]) {
                    *pi *= api;
                }
            }
            let ap: Vec<f64> = (0..s)
                .map(|i| a[i].iter().zip(&p).map(|(aij, pj)| aij * pj).sum())
                .collect();
            phi.push(p);
            a_phi.push(ap);
        }
        Tableau { trees, phi }
    }

    /// max over trees with |τ| ≤ order of |Σ w_i Φ_i(τ) − θ^|τ|/γ(τ)|.
    pub(crate) fn max_continuous_defect(&self, w: &[f64], theta: f64, order: usize) -> f64 {
        let mut worst: f64 = 0.0;
        for (idx, p) in self.phi.iter().enumerate() {
            let n = self.trees.order[idx];
            if n > order {
                continue;
            }
            let lhs: f64 = w.iter().zip(p).map(|(wi, pi)| wi * pi).sum();
            let rhs = theta.powi(n as i32) / self.trees.gamma[idx];
            worst = worst.max((lhs - rhs).abs());
        }
        worst
    }

    /// Number of trees of each order 1..=8 (checks the generator).
    fn counts(&self) -> Vec<usize> {
        (1..=MAX_ORDER)
            .map(|n| self.trees.order.iter().filter(|&&o| o == n).count())
            .collect()
    }
}

/// max over trees with |τ| ≤ order of the defect of the weights b.
pub(crate) fn max_defect(t: &Tableau, b: &[f64], order: usize) -> f64 {
    t.max_continuous_defect(b, 1.0, order)
}

/// Weights b_j(θ) of a dense output that is linear in the stages: `dense(k, out)` must write
/// the interpolant for h = 1 and y_old = 0 with the stage vectors `k` given; feeding it unit
/// vectors k_j = e_j returns b(θ).
pub(crate) fn continuous_weights(
    s: usize,
    mut dense: impl FnMut(&[Vec<f64>], &mut [f64]),
) -> Vec<f64> {
    let k: Vec<Vec<f64>> = (0..s)
        .map(|j| (0..s).map(|i| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    let mut out = vec![0.0; s];
    dense(&k, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tree_counts_match_oeis_a000081() {
        let t = Tableau::new(&[&[]], 1);
        assert_eq!(t.counts(), vec![1, 1, 2, 4, 9, 20, 48, 115]);
    }

    #[test]
    fn classical_rk4_has_order_4_exactly() {
        let a: [&[f64]; 4] = [&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]];
        let t = Tableau::new(&a, 4);
        let b = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];
        // 1/6 and 1/3 are rounded in f64: defects of an ulp or two.
        assert!(max_defect(&t, &b, 4) < 1e-15);
        assert!(max_defect(&t, &b, 5) > 1e-3);
    }
}
