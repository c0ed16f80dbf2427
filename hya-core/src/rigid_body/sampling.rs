//! Deterministic, varied joint states for benchmarks: no allocation, no random-number crate.

use crate::JointVector;

/// `M` states `[q, q̇, q̈]` with entries spread uniformly over ±π rad, ±2 rad/s and ±5 rad/s²,
/// from a xorshift64 stream with a fixed seed: the same on every machine and every run.
pub fn varied_states<const N: usize, const M: usize>() -> [[JointVector<N>; 3]; M] {
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move |scale: f64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        scale * ((seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
    };
    core::array::from_fn(|_| [core::f64::consts::PI, 2.0, 5.0].map(|s| JointVector::from_fn(|_, _| next(s))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_are_spread_and_repeatable() {
        let a: [[JointVector<3>; 3]; 16] = varied_states();
        assert_eq!(a, varied_states::<3, 16>());
        assert!(a
            .iter()
            .all(|[q, qd, qdd]| q.amax() <= core::f64::consts::PI && qd.amax() <= 2.0 && qdd.amax() <= 5.0));
        assert!(a[0] != a[1]);
    }
}
