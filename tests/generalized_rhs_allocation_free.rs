//! Claim: after its first evaluation, a right-hand side and an event evaluation of the
//! generalised formulation of a model without clearance joints allocate nothing, with the dense
//! and with the sparse LU of the dependent block (faer's factors only grow, the symbolic analysis is made once per partition,
//! and every buffer is sized when the formulation is built).
//!
//! Counted by a global allocator that counts the allocations of the calling thread (the test
//! harness runs tests on threads of their own).

use linkdyn::formulation::generalized::BlockSolver;
use linkdyn::formulation::{DaeOptions, Formulation, Generalized};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: every call is forwarded to the system allocator unchanged; the counter is a
// thread-local Cell (no allocation, no lock) and is skipped during thread teardown.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded with the caller's layout.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

#[test]
fn rhs_and_events_allocate_nothing_after_the_first_call() {
    // 10 loops: m = 62 dependent coordinates, either LU forced.
    let set = ["parameters.N=10".to_string()];
    let model = linkdyn::model::load("models/nfourbar_chain.toml".as_ref(), &set)
        .unwrap_or_else(|e| panic!("{e}"));
    for solver in [BlockSolver::Dense, BlockSolver::Sparse] {
        let f = Generalized::new(&model, &DaeOptions::default())
            .unwrap_or_else(|e| panic!("{e}"))
            .with_block_solver(solver);
        let y0 = f.initial_state();
        let mut dy = vec![0.0; y0.len()];
        let mut g = vec![0.0; f.n_events()];
        f.rhs(0.0, &y0, &mut dy)
            .unwrap_or_else(|e| panic!("{solver:?}: {e}"));
        // States along the motion (warm starts a step ahead: Newton iterates), as at stages.
        let states: Vec<Vec<f64>> = [1e-4, 1e-3, 1e-2]
            .iter()
            .map(|h| y0.iter().zip(&dy).map(|(y, d)| y + h * d).collect())
            .collect();
        // First calls: faer's factors grow to their size.
        for y in &states {
            f.rhs(0.0, y, &mut dy)
                .unwrap_or_else(|e| panic!("{solver:?}: {e}"));
            f.events(0.0, y, &mut g);
        }
        let before = allocations();
        for _ in 0..3 {
            for (k, y) in states.iter().enumerate() {
                let t = [1e-4, 1e-3, 1e-2][k];
                f.rhs(t, y, &mut dy)
                    .unwrap_or_else(|e| panic!("{solver:?}: {e}"));
                f.events(t, y, &mut g);
            }
        }
        let made = allocations() - before;
        assert_eq!(
            made, 0,
            "{solver:?}: {made} allocations in 9 right-hand sides and 9 event evaluations"
        );
    }
}
