//! Cycle times as a log-bucketed histogram: small in a JSON line, and shards merge exactly.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Buckets per doubling: a percentile read from the histogram is the bucket's upper bound, at
/// most 2^(1/4) − 1 ≈ 19 % above the true value — plenty to size a flight computer's cycle.
const PER_DOUBLING: f64 = 4.0;

/// Counts of values (microseconds) per bucket `k`, which holds values in
/// `(2^((k−1)/4), 2^(k/4)]` (bucket 0: up to 1 µs).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Histogram(BTreeMap<u16, u64>);

impl Histogram {
    /// Counts one value, in microseconds.
    pub fn add(&mut self, micros: f64) {
        let k = (PER_DOUBLING * micros.max(1.0).log2()).ceil();
        *self.0.entry(k.min(f64::from(u16::MAX)) as u16).or_default() += 1;
    }

    /// Adds another histogram's counts.
    pub fn merge(&mut self, other: &Histogram) {
        for (&k, &n) in &other.0 {
            *self.0.entry(k).or_default() += n;
        }
    }

    /// How many values were counted.
    pub fn count(&self) -> u64 {
        self.0.values().sum()
    }

    /// The `q` quantile (0 to 1) as its bucket's upper bound, microseconds; `None` when empty.
    pub fn quantile(&self, q: f64) -> Option<f64> {
        let n = self.count();
        let rank = ((q.clamp(0.0, 1.0) * n as f64).ceil() as u64).max(1);
        let mut seen = 0;
        self.0.iter().find_map(|(&k, &count)| {
            seen += count;
            (seen >= rank).then(|| 2f64.powf(f64::from(k) / PER_DOUBLING))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quantiles are bucket upper bounds within 19 % of the value, and merging adds counts.
    #[test]
    fn quantiles_bound_the_values_and_merge_adds() {
        let mut a = Histogram::default();
        for v in [10.0, 20.0, 30.0, 1000.0] {
            a.add(v);
        }
        let median = a.quantile(0.5).expect("counted");
        assert!((20.0..20.0 * 1.19).contains(&median), "{median}");
        let max = a.quantile(1.0).expect("counted");
        assert!((1000.0..1190.0).contains(&max), "{max}");
        let mut b = a.clone();
        b.merge(&a);
        assert_eq!(b.count(), 8);
        assert_eq!(b.quantile(0.5), a.quantile(0.5));
        assert_eq!(Histogram::default().quantile(0.5), None);
    }
}
