//! The diameter of a planar point set (the largest distance between two of its points), in
//! O(p log p) instead of the O(p²) of all pairs, with the value of the all-pairs maximum to the
//! last bit.
//!
//! The largest distance is attained at two vertices of the convex hull (the distance from any
//! point is a convex function, so its maximum over the hull is at a vertex; ref. 1, §4.2). The
//! hull comes from Andrew's monotone chain (ref. 2). Taking the maximum over hull vertices only
//! would give the same value up to round-off, not bit for bit: linkage points come in
//! near-coincident pairs (the two ends of an assembled pin, 1e-13 m apart), and the hull keeps
//! one of each pair where the all-pairs maximum may be attained at the other. So the maximum is
//! taken over a slightly larger candidate set that provably holds every point of a maximal
//! pair:
//!
//! 1. the hull vertices V and, for each, its farthest other vertex (squared distances);
//!    D = the largest of those;
//! 2. the vertices K ⊂ V whose farthest vertex is within 3ε of D, ε = 1e-6 × the diagonal of
//!    the bounding box;
//! 3. the candidates: every point within ε of a vertex of K; the result is the all-pairs
//!    maximum (the same expression as the O(p²) loop) over the candidates.
//!
//! Why nothing is lost: a point a within ε of a vertex v ∉ K is at most D − 3ε + ε from every
//! point (the farthest point from v is a hull vertex), so no pair with it is maximal. A point a
//! at least ε from every vertex lies in the hull as a convex combination Σ λ_i v_i, and for any
//! point x, |a − x|² = Σ λ_i |v_i − x|² − Σ λ_i |v_i − a|² ≤ D² − ε², so |a − x| ≤ D − ε²/(2D),
//! some 1e-13 D below D, far beyond the 1e-16 relative round-off of the distances and of the
//! hull's orientation tests. Every point of a maximal pair is thus a candidate.
//!
//! The cost is O(p log p) for the sort, O(h²) for step 1 (h hull vertices: a handful for a
//! linkage, a few hundred where round-off puts the points of a straight edge, such as a row of
//! ground pivots, slightly off the line), and the all-pairs maximum over the few candidates.
//!
//! # References
//! 1. F. P. Preparata, M. I. Shamos, *Computational Geometry: An Introduction*, Springer, 1985,
//!    §4.2.3 (diameter of a set).
//! 2. A. M. Andrew, Another efficient algorithm for convex hulls in two dimensions,
//!    *Information Processing Letters* 9 (1979) 216–219.

/// The largest distance between two of `points`, equal bit for bit to the maximum of
/// `(a[0] − b[0]).hypot(a[1] − b[1])` over all pairs (0 for fewer than two points; pairs
/// whose distance is NaN are ignored, as `f64::max` ignores them).
pub fn diameter(points: &[[f64; 2]]) -> f64 {
    if points
        .iter()
        .any(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        // Not from an assembled model: the plain loop keeps the NaN and ∞ behaviour.
        return all_pairs(points, (0..points.len()).collect());
    }
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&i, &j| {
        points[i][0]
            .total_cmp(&points[j][0])
            .then(points[i][1].total_cmp(&points[j][1]))
    });
    let hull = hull(points, &order);
    // Step 1: the farthest vertex from each vertex.
    let far: Vec<f64> = hull
        .iter()
        .map(|&i| {
            hull.iter()
                .map(|&j| squared(points[i], points[j]))
                .fold(0.0, f64::max)
                .sqrt()
        })
        .collect();
    let d = far.iter().copied().fold(0.0, f64::max);
    let (lo, hi) = order.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), &i| {
            let p = points[i];
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    let eps = 1e-6 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    // Steps 2 and 3: the points within ε of a vertex whose farthest vertex is within 3ε of D.
    let mut candidate = vec![false; points.len()];
    for (&v, &f) in hull.iter().zip(&far) {
        if f < d - 3.0 * eps {
            continue;
        }
        let p = points[v];
        let start = order.partition_point(|&i| points[i][0] < p[0] - eps);
        for &i in order[start..]
            .iter()
            .take_while(|&&i| points[i][0] <= p[0] + eps)
        {
            if squared(points[i], p) <= eps * eps {
                candidate[i] = true;
            }
        }
    }
    let chosen = (0..points.len()).filter(|&i| candidate[i]).collect();
    all_pairs(points, chosen)
}

/// The all-pairs maximum over the points `chosen` (increasing indices), as the O(p²) loop
/// computes it.
fn all_pairs(points: &[[f64; 2]], chosen: Vec<usize>) -> f64 {
    let mut diameter = 0.0_f64;
    for (k, &i) in chosen.iter().enumerate() {
        let a = points[i];
        for &j in &chosen[k + 1..] {
            let b = points[j];
            diameter = diameter.max((a[0] - b[0]).hypot(a[1] - b[1]));
        }
    }
    diameter
}

fn squared(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// z-component of (b − a) × (c − a): positive for a left turn a → b → c.
fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Vertices of the convex hull (indices into `points`), by Andrew's monotone chain over
/// `order` (the points sorted by x, then y); collinear points are left out.
fn hull(points: &[[f64; 2]], order: &[usize]) -> Vec<usize> {
    if order.len() < 3 {
        return order.to_vec();
    }
    let mut lower: Vec<usize> = Vec::new();
    for &i in order {
        while let [.., a, b] = lower[..] {
            if cross(points[a], points[b], points[i]) > 0.0 {
                break;
            }
            lower.pop();
        }
        lower.push(i);
    }
    let mut upper: Vec<usize> = Vec::new();
    for &i in order.iter().rev() {
        while let [.., a, b] = upper[..] {
            if cross(points[a], points[b], points[i]) > 0.0 {
                break;
            }
            upper.pop();
        }
        upper.push(i);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::formulation::test_rng::Lcg;

    #[test]
    fn equals_the_all_pairs_maximum_bit_for_bit() {
        // Clouds shaped like linkages: points on a few segments (collinear runs, a row of
        // ground pivots), each with a near-coincident twin 1e-13 away (the two ends of a
        // pin), plus interior points; and plain random clouds and degenerate cases.
        let mut rng = Lcg(7);
        let mut cases: Vec<Vec<[f64; 2]>> = vec![
            vec![],
            vec![[1.0, 2.0]],
            vec![[1.0, 2.0], [1.0, 2.0]],
            vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]],
            vec![[0.0, 0.0]; 5],
        ];
        for case in 0..300 {
            let mut points = Vec::new();
            let segments = 1 + case % 5;
            for _ in 0..segments {
                let (x0, y0) = (rng.next() * 4.0 - 2.0, rng.next() * 4.0 - 2.0);
                let (dx, dy) = (rng.next() - 0.5, rng.next() - 0.5);
                for k in 0..(2 + case % 17) {
                    let t = k as f64 * 0.3;
                    let p = [x0 + t * dx, y0 + t * dy];
                    points.push(p);
                    // Twins from 1e-13 down to a few ulps apart (where the hull's orientation
                    // test is round-off, and may keep either twin), and points off the segment
                    // by round-off.
                    let size = 10f64.powi(-13 - (k % 4));
                    let twin = [size * (rng.next() - 0.5), size * (rng.next() - 0.5)];
                    points.push([p[0] + twin[0], p[1] + twin[1]]);
                }
            }
            for _ in 0..case % 40 {
                points.push([rng.next() * 2.0 - 1.0, rng.next() * 2.0 - 1.0]);
            }
            cases.push(points);
        }
        for (k, points) in cases.iter().enumerate() {
            let all = all_pairs(points, (0..points.len()).collect());
            let fast = diameter(points);
            assert_eq!(
                fast.to_bits(),
                all.to_bits(),
                "case {k} ({} points): {fast} against {all}",
                points.len()
            );
        }
    }

    #[test]
    fn a_nan_point_is_ignored_as_by_the_plain_loop() {
        let points = [[0.0, 0.0], [f64::NAN, 1.0], [3.0, 4.0]];
        assert_eq!(diameter(&points), 5.0);
    }
}
