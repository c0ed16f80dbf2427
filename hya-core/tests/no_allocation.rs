//! The hot paths (filter step, estimator update, controller step) never touch the heap: a
//! counting global allocator sees no allocation while they run.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use hya_core::robots::PlanarTwoLink;
use hya_core::{
    ComputedTorque, DisturbanceEstimator, Dynamics, FilterParams, Gains, JointVector, Reference, ThirdOrderFilter,
};

/// Counts allocations made by the current thread (the test harness's own threads do not count).
struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator, with the caller's guarantees.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations_during(work: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    work();
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn hot_paths_do_not_allocate() {
    let arm = PlanarTwoLink::default();
    let params = FilterParams::paper(1e-3).unwrap();
    let q0 = JointVector::from([0.3, -0.2]);
    let mut filter = ThirdOrderFilter::<2>::new(params, q0).unwrap();
    let mut estimator = DisturbanceEstimator::new(&arm, params, q0, arm.gravity(&q0)).unwrap();
    let controller = ComputedTorque::new(&arm, Gains::diagonal([50.0, 50.0], [5.0, 5.0]).unwrap())
        .with_torque_limit(JointVector::from([40.0, 40.0]))
        .unwrap();
    // The counter must see allocations at all, or a zero below would prove nothing.
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);

    let count = allocations_during(|| {
        let mut q = q0;
        for k in 0..2000 {
            q[0] = 0.3 + 0.1 * (k as f64 * 1e-3).sin();
            filter.step(std::hint::black_box(&q)).unwrap();
            let tau = controller
                .command(&q, &filter.state().x2, &Reference::hold(q0), Some(estimator.disturbance()))
                .unwrap()
                .torque;
            estimator.update(&q, &tau).unwrap();
            // The error path must not allocate either.
            assert!(estimator.update(&JointVector::from([f64::NAN, 0.0]), &tau).is_err());
        }
    });
    assert_eq!(count, 0, "the hot paths allocated {count} times");
}
