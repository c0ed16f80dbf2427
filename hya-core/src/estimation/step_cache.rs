//! The filter's discretisation for each step length of a log, computed once per length.
//!
//! A log with timestamps steps by `T_k = t_{k+1} − t_k`, and the exact first-order-hold step over
//! `T_k` needs `Φ = e^{A T_k}` and `Γa`, `Γb` from a 5×5 matrix exponential (see
//! [`crate::estimation::filter`]): about as costly as the whole estimator update. Real logs repeat a few
//! lengths (a regular grid's `dt`, the two or three values its printed timestamps round to, a
//! controller's 10 and 12 ms): [`DiscretisationCache`] keeps the last [`CACHE_SLOTS`] lengths,
//! keyed by the bits of `T_k`, so a regular log costs one lookup per row and a jittered log one
//! exponential per new length. Least recently used lengths make room for new ones. The slots are
//! a fixed array: nothing is allocated, ever.

use crate::estimation::filter::{Discretisation, FilterParams};
use crate::Error;

/// How many step lengths a [`DiscretisationCache`] remembers.
pub const CACHE_SLOTS: usize = 8;

/// The discretisations of one filter for the last [`CACHE_SLOTS`] step lengths used.
#[derive(Debug, Clone)]
pub struct DiscretisationCache {
    params: FilterParams,
    /// `T.to_bits()` of each slot in use.
    keys: [u64; CACHE_SLOTS],
    /// When each slot was last used, in lookups.
    used_at: [u64; CACHE_SLOTS],
    steps: [Discretisation; CACHE_SLOTS],
    filled: usize,
    clock: u64,
    misses: u64,
}

impl DiscretisationCache {
    /// A cache for the filter `params`, holding its own sample time's discretisation already.
    pub fn new(params: FilterParams) -> Self {
        let own = Discretisation::new(&params);
        Self {
            keys: [params.dt_s().to_bits(); CACHE_SLOTS],
            used_at: [0; CACHE_SLOTS],
            steps: [own; CACHE_SLOTS],
            filled: 1,
            clock: 0,
            misses: 0,
            params,
        }
    }

    /// The discretisation over `dt_s`, computed on its first use (or when its slot was reused).
    ///
    /// `dt_s` is checked as a sample time by [`FilterParams::with_dt`]: finite, positive and with
    /// `ω · dt_s` at most [`MAX_RATE_TIMES_DT`](crate::MAX_RATE_TIMES_DT), or an
    /// [`Error::InvalidParameter`] naming the bound.
    pub fn get(&mut self, dt_s: f64) -> Result<&Discretisation, Error> {
        self.clock += 1;
        let key = dt_s.to_bits();
        let slot = match self.keys[..self.filled].iter().position(|&k| k == key) {
            Some(slot) => slot,
            None => {
                let step = Discretisation::new(&self.params.with_dt(dt_s)?);
                let slot = if self.filled < CACHE_SLOTS {
                    self.filled += 1;
                    self.filled - 1
                } else {
                    (0..CACHE_SLOTS).min_by_key(|&s| self.used_at[s]).unwrap_or(0)
                };
                self.misses += 1;
                self.keys[slot] = key;
                self.steps[slot] = step;
                slot
            }
        };
        self.used_at[slot] = self.clock;
        Ok(&self.steps[slot])
    }

    /// How many discretisations [`get`](Self::get) has computed (lookups that missed).
    pub fn misses(&self) -> u64 {
        self.misses
    }

    /// The filter parameters, at their own sample time.
    pub fn params(&self) -> &FilterParams {
        &self.params
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_own_sample_time_is_cached_from_the_start_and_lengths_are_reused() {
        let params = FilterParams::paper(1e-3).unwrap();
        let mut cache = DiscretisationCache::new(params);
        assert_eq!(cache.get(1e-3).unwrap(), &Discretisation::new(&params));
        assert_eq!(cache.misses(), 0);
        let long = *cache.get(0.03).unwrap();
        assert_eq!(long, Discretisation::new(&params.with_dt(0.03).unwrap()));
        assert_eq!(cache.get(0.03).unwrap(), &long);
        assert_eq!(cache.misses(), 1);
    }

    #[test]
    fn the_least_recently_used_length_makes_room() {
        let mut cache = DiscretisationCache::new(FilterParams::paper(1e-3).unwrap());
        // Seven more lengths fill the slots; 1 ms is used again, so 2 ms is the oldest.
        for k in 2..=8 {
            cache.get(k as f64 * 1e-3).unwrap();
        }
        cache.get(1e-3).unwrap();
        cache.get(9e-3).unwrap();
        assert_eq!(cache.misses(), 8);
        cache.get(1e-3).unwrap();
        cache.get(3e-3).unwrap();
        assert_eq!(cache.misses(), 8, "1 and 3 ms still cached");
        cache.get(2e-3).unwrap();
        assert_eq!(cache.misses(), 9, "2 ms was evicted");
    }

    #[test]
    fn a_step_the_filter_cannot_discretise_is_refused() {
        let mut cache = DiscretisationCache::new(FilterParams::paper(1e-3).unwrap());
        for bad in [0.0, -1e-3, f64::NAN, 3.0] {
            assert!(matches!(cache.get(bad), Err(Error::InvalidParameter { .. })), "{bad}");
        }
        assert_eq!(cache.misses(), 0);
    }
}
