//! A closed loop's memory does not grow with its duration: the metrics are accumulated tick by
//! tick and the trace keeps at most `MAX_TRACE_SAMPLES` ticks. A global allocator that tracks
//! the live heap measures each run's peak (this binary runs this one test, so no other thread
//! allocates meanwhile).
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use hya_sim::analysis::simulate::simulate_recording;
use hya_sim::run::trace::{bytes_per_sample, Recording, MAX_TRACE_SAMPLES};
use hya_sim::{Method, Robot, Scenario};

/// Tracks the bytes live on the heap and their peak.
struct PeakAllocator;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for PeakAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
        PEAK.fetch_max(live, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator, with the caller's guarantees.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: `ptr` came from `System.alloc` with this `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: PeakAllocator = PeakAllocator;

/// The peak of the live heap above its level at the start, bytes, while `work` runs.
fn peak_during(work: impl FnOnce()) -> usize {
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    work();
    PEAK.load(Ordering::Relaxed) - base
}

#[test]
fn memory_of_a_closed_loop_does_not_grow_with_its_duration() {
    let mut scenario = Scenario::builtin("planar2_goto").unwrap();
    let robot = Robot::<2>::load(&scenario.robot).unwrap();
    let dt = scenario.controller.dt_s;
    let mut peak = |duration_s: f64, recording: Recording| {
        scenario.duration_s = duration_s;
        peak_during(|| drop(simulate_recording(&scenario, Method::Lu, &robot, recording).unwrap()))
    };
    // Metrics alone: the same peak for 20 s as for 80 s, to a few kilobytes (both hold the
    // limit-cycle window's samples, its full 10 s).
    let (short, long) = (peak(20.0, Recording::Off), peak(80.0, Recording::Off));
    assert!(long <= short + 16 * 1024, "metrics only: {short} B for 20 s, {long} B for 80 s");
    // A kept trace: up to its bound, then no more.
    let at_bound = MAX_TRACE_SAMPLES as f64 * dt;
    let trace_bytes = MAX_TRACE_SAMPLES * bytes_per_sample(2);
    let (bounded, beyond) = (peak(at_bound, Recording::Bounded), peak(4.0 * at_bound, Recording::Bounded));
    assert!(bounded >= trace_bytes, "a trace of {MAX_TRACE_SAMPLES} ticks holds {bounded} B");
    assert!(beyond <= bounded + 16 * 1024, "{bounded} B at the bound, {beyond} B at four times it");
}
