//! What the continuation tests read from a branch: its special points.

use linkdyn::analysis::orbit::{Branch, BranchEnd, SpecialKind};

/// The located special points of `b`, (kind, parameter), in order along the branch.
pub fn specials(b: &Branch) -> Vec<(SpecialKind, f64)> {
    b.points
        .iter()
        .filter_map(|p| p.special.map(|k| (k, p.parameter)))
        .collect()
}

/// The parameter of the one special point of `b`, which must be of `kind`, on a branch that
/// reached its end with every change it detected located.
pub fn the_one_special_point(b: &Branch, kind: SpecialKind) -> f64 {
    assert_eq!(b.end, BranchEnd::Reached);
    assert!(b.unlocated.is_empty(), "{:?}", b.unlocated);
    let found = specials(b);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, kind, "{found:?}");
    found[0].1
}
