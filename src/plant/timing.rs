//! Probabilities over time (DESIGN.md §6.2; thesis §6.1.3, §6.2.2).
//!
//! Each transition has a *law* saying how likely it is to fire in one step of the executive, a
//! step being the interval `(t(i), t(i+1)]` of length δ during which the component's clock (time
//! since it entered its mode) goes from `c` to `c + δ`:
//! - **per cycle** (`probability: p`): `p` per step whatever δ is, as in the thesis's tables;
//! - **rate** (`rate: R`, per second): an exponential hazard, `1 − e^(−R·δ)`, independent of the
//!   cycle period;
//! - **timed** (`after: Uniform(l, u)` ..., with nominal factor `p`): the conditional form of
//!   §6.2.2, `p · (F(c+δ) − F(c)) / (1 − F(c))`, where `F` is the distribution's CDF on the clock.
//!   Over several steps these compose to `p`-weighted `F`: with `p = 1`, the probability of having
//!   fired by clock `c` is exactly `F(c)` whatever the cycle period. Once the distribution's mass
//!   is spent (`F(c) = 1`, e.g. past a uniform window) the transition is overdue and fires with
//!   probability `p`.
//!
//! A mode's transitions combine into one distribution over next modes ([`mode_distribution`]):
//! rates are *hazards that compete with everything else* — in a step a hazard strikes with
//! probability `1 − e^(−ΣR·δ)`, shared in proportion to the rates — and the per-cycle and timed
//! transitions share the remaining `e^(−ΣR·δ)`; the mode stays with what is left (§6.1.3: "one
//! minus the sum of the probabilities of the outgoing ... transitions"). With per-cycle fault
//! probabilities only (Table 6.1) this is the plain sum of the thesis.

use crate::logic::ValueId;

/// Below this survival the distribution's mass counts as spent: the transition is overdue.
const SPENT: f64 = 1e-12;

/// How close to a window bound (a uniform's `lower` and `upper`, a fixed delay) a clock reading
/// counts as *at* the bound, seconds. Such a reading is taken as this much past the bound (see
/// [`Timing::reading`]).
///
/// Why: a component's clock restarts at the end of the step in which it changed mode (Figure 6-7
/// step 8, `newInit = t_abs`), the latest time it can have entered it, so the clock may read up to
/// one step less than the time actually spent. A departure seen one cycle after a `Uniform(0.1,
/// 0.2)` mode was entered, with a 0.1 s cycle, covers clock `(0, 0.1]`, where the window has no
/// mass: the departure was impossible, and a fault was the only explanation — in exact arithmetic
/// too; floating-point times (`40.3 − 40.2 ≠ 0.1`) only decided between 0 and 1e-14. Taking a
/// reading at a bound as 1 ms past it closes the windows at cycle instants: such a departure gets
/// the window's first millisecond of mass (1 % for the camera), a fixed delay reached up to
/// rounding fires, and readings farther than 1 ms from every bound are unchanged. 1 ms is far
/// below any cycle period (§8 of the thesis: timing conditions below the cycle's resolution are
/// not meaningful).
pub const BOUND_TOLERANCE: f64 = 1e-3;

/// When a timed transition fires, as a distribution of the component clock (seconds since the
/// component entered its mode).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Timing {
    /// Uniform on `[lower, upper]` (Table 6.1's densities, Figure 6-5's windows).
    Uniform {
        /// Earliest time, seconds.
        lower: f64,
        /// Latest time, seconds.
        upper: f64,
    },
    /// Normal, unbounded (the EDL entry trigger, §7.2.4). Mass before the mode was entered is
    /// never taken: the conditional form starts from the clock's first value.
    Gaussian {
        /// Mean, seconds.
        mean: f64,
        /// Standard deviation, seconds.
        sd: f64,
    },
    /// Exponential with this rate per second (memoryless: the clock does not matter).
    Exponential {
        /// Rate, per second.
        rate: f64,
    },
    /// Exactly this long after entering the mode.
    Fixed {
        /// Delay, seconds.
        delay: f64,
    },
}

impl Timing {
    /// `1 − F(clock)`: the probability that the transition has not fired by `clock`, were it
    /// always enabled.
    pub fn survival(&self, clock: f64) -> f64 {
        match *self {
            Timing::Uniform { lower, upper } => {
                if clock <= lower {
                    1.0
                } else if clock >= upper {
                    0.0
                } else {
                    (upper - clock) / (upper - lower)
                }
            }
            Timing::Gaussian { mean, sd } => {
                0.5 * libm::erfc((clock - mean) / (sd * std::f64::consts::SQRT_2))
            }
            Timing::Exponential { rate } => (-rate * clock.max(0.0)).exp(),
            Timing::Fixed { delay } => {
                if clock < delay {
                    1.0
                } else {
                    0.0
                }
            }
        }
    }

    /// `F(clock)`, the CDF.
    pub fn cdf(&self, clock: f64) -> f64 {
        1.0 - self.survival(clock)
    }

    /// True when the firing probability depends on how long the component has been in its mode
    /// (all but the memoryless exponential). Estimation forgets clocks that do not matter.
    pub fn needs_clock(&self) -> bool {
        !matches!(self, Timing::Exponential { .. })
    }

    /// The conditional probability of firing in a step from clock `before` to `before + step`,
    /// given it had not fired by `before` (§6.2.2); 1 when overdue.
    pub fn conditional(&self, before: f64, step: f64) -> f64 {
        if let Timing::Exponential { rate } = *self {
            return 1.0 - (-rate * step.max(0.0)).exp();
        }
        let (from, to) = (self.reading(before), self.reading(before + step.max(0.0)));
        let survived = self.survival(from);
        if survived <= SPENT {
            return 1.0;
        }
        (self.mass_between(from, to) / survived).clamp(0.0, 1.0)
    }

    /// The clock reading the window is evaluated at: a positive reading within
    /// [`BOUND_TOLERANCE`] of a bound counts as that far past the bound, any other reading is
    /// itself. Monotone, so the conditional probabilities of successive steps still compose to
    /// `F` of the (adjusted) reading. A reading of 0 (the step in which the mode was entered
    /// starts there) is never moved, so a window opening at 0 keeps its exact first step.
    fn reading(&self, clock: f64) -> f64 {
        let near = |bound: f64| clock > 0.0 && (clock - bound).abs() <= BOUND_TOLERANCE;
        match *self {
            Timing::Uniform { lower, upper } => [lower, upper]
                .into_iter()
                .find(|&bound| near(bound))
                .map_or(clock, |bound| bound + BOUND_TOLERANCE),
            Timing::Fixed { delay } if near(delay) => delay + BOUND_TOLERANCE,
            _ => clock,
        }
    }

    /// `F(to) − F(from)` for `from <= to`, from the tail where it is accurate: long before a
    /// Gaussian's mean `1 − F` rounds to 1, and the difference of two survivals to 0, so the
    /// probability of an early event (an atmospheric entry minutes before the predicted time)
    /// would come out as exactly 0; the lower tail's CDF keeps it.
    fn mass_between(&self, from: f64, to: f64) -> f64 {
        match *self {
            Timing::Gaussian { mean, sd } if to <= mean => {
                let cdf = |x: f64| 0.5 * libm::erfc((mean - x) / (sd * std::f64::consts::SQRT_2));
                cdf(to) - cdf(from)
            }
            _ => self.survival(from) - self.survival(to),
        }
    }
}

/// How likely a transition is to fire in one step when enabled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TransitionLaw {
    /// This probability in every step, whatever its length (the thesis's tables).
    PerCycle {
        /// Probability per step.
        probability: f64,
    },
    /// An exponential hazard: `1 − e^(−rate·δ)` for a step of length δ.
    Rate {
        /// Rate, per second.
        per_second: f64,
    },
    /// A timed transition: nominal factor times the conditional probability of the timing.
    Timed {
        /// The nominal factor `p` (Table 6.1's 0.989).
        probability: f64,
        /// When it fires, on the component clock.
        timing: Timing,
    },
}

impl TransitionLaw {
    /// The probability of firing in a step of length `step` starting at component clock `clock`
    /// (`None` when the clock is not known; only timings that [need it](Timing::needs_clock)
    /// use it, and take an unknown clock as zero), were this transition the only one enabled.
    pub fn step_probability(&self, clock: Option<f64>, step: f64) -> f64 {
        match *self {
            TransitionLaw::PerCycle { probability } => probability,
            TransitionLaw::Rate { per_second } => 1.0 - (-per_second * step.max(0.0)).exp(),
            TransitionLaw::Timed {
                probability,
                timing,
            } => probability * timing.conditional(clock.unwrap_or(0.0), step),
        }
    }

    /// The most this law can give in one step, for the "outgoing probabilities exceed 1" check;
    /// `None` for rates, which compete as hazards and always fit.
    pub fn largest_step_probability(&self) -> Option<f64> {
        match *self {
            TransitionLaw::PerCycle { probability } | TransitionLaw::Timed { probability, .. } => {
                Some(probability)
            }
            TransitionLaw::Rate { .. } => None,
        }
    }

    /// The timing, for timed transitions.
    pub fn timing(&self) -> Option<&Timing> {
        match self {
            TransitionLaw::Timed { timing, .. } => Some(timing),
            _ => None,
        }
    }
}

impl std::fmt::Display for Timing {
    /// The spelling of the model file: `Uniform(30, 60)`, `Gaussian(120, 10)`, ...
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Timing::Uniform { lower, upper } => write!(f, "Uniform({lower}, {upper})"),
            Timing::Gaussian { mean, sd } => write!(f, "Gaussian({mean}, {sd})"),
            Timing::Exponential { rate } => write!(f, "Exponential({rate})"),
            Timing::Fixed { delay } => write!(f, "Fixed({delay})"),
        }
    }
}

impl std::fmt::Display for TransitionLaw {
    /// `p 0.989`, `rate 0.0001/s`, `after Uniform(30, 60) s, p 0.989`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TransitionLaw::PerCycle { probability } => write!(f, "p {probability}"),
            TransitionLaw::Rate { per_second } => write!(f, "rate {per_second}/s"),
            TransitionLaw::Timed {
                probability,
                timing,
            } if *probability == 1.0 => write!(f, "after {timing} s"),
            TransitionLaw::Timed {
                probability,
                timing,
            } => write!(f, "after {timing} s, p {probability}"),
        }
    }
}

/// The distribution over a component's next mode in one step (§6.1.3, §6.2.2): `enabled` are the
/// enabled transitions' targets and laws; the component stays in `current` with the remainder.
/// Parallel transitions to one target add up (§6.2.2, footnote 1); targets with probability 0 are
/// left out. Should the per-cycle and timed probabilities add up to more than 1 (a model that
/// validation would refuse), they are scaled down to fit.
pub fn mode_distribution<I>(
    current: ValueId,
    enabled: I,
    clock: Option<f64>,
    step: f64,
) -> Vec<(ValueId, f64)>
where
    I: IntoIterator<Item = (ValueId, TransitionLaw)>,
    I::IntoIter: Clone,
{
    let enabled = enabled.into_iter();
    let total_rate: f64 = enabled
        .clone()
        .filter_map(|(_, law)| match law {
            TransitionLaw::Rate { per_second } => Some(per_second),
            _ => None,
        })
        .sum();
    let no_hazard = (-total_rate * step.max(0.0)).exp();
    let hazard = 1.0 - no_hazard;
    let ordinary: f64 = enabled
        .clone()
        .filter(|(_, law)| !matches!(law, TransitionLaw::Rate { .. }))
        .map(|(_, law)| law.step_probability(clock, step))
        .sum();
    let scale = if ordinary > 1.0 { 1.0 / ordinary } else { 1.0 };
    let mut out: Vec<(ValueId, f64)> = Vec::with_capacity(4);
    let mut add = |target: ValueId, p: f64| {
        if p <= 0.0 {
            return;
        }
        match out.iter_mut().find(|(t, _)| *t == target) {
            Some((_, q)) => *q += p,
            None => out.push((target, p)),
        }
    };
    for (target, law) in enabled {
        let p = match law {
            TransitionLaw::Rate { per_second } if total_rate > 0.0 => {
                hazard * per_second / total_rate
            }
            TransitionLaw::Rate { .. } => 0.0,
            law => no_hazard * scale * law.step_probability(clock, step),
        };
        add(target, p);
    }
    add(current, no_hazard * (1.0 - ordinary * scale).max(0.0));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEATING: ValueId = ValueId(1);
    const STANDBY: ValueId = ValueId(2);
    const FAILED: ValueId = ValueId(4);

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn table_6_1_tau_6_fires_with_0_989_once_the_window_is_spanned() {
        let tau6 = TransitionLaw::Timed {
            probability: 0.989,
            timing: Timing::Uniform {
                lower: 0.0,
                upper: 0.1,
            },
        };
        assert!(close(tau6.step_probability(Some(0.0), 0.1), 0.989));
        assert!(close(tau6.step_probability(Some(0.0), 0.05), 0.989 * 0.5));
        // Overdue: still the nominal factor.
        assert!(close(tau6.step_probability(Some(0.3), 0.1), 0.989));
    }

    #[test]
    fn the_conditional_form_composes_to_the_cdf_for_any_cycle_period() {
        let timings = [
            Timing::Uniform {
                lower: 30.0,
                upper: 60.0,
            },
            Timing::Gaussian {
                mean: 20.0,
                sd: 4.0,
            },
            Timing::Exponential { rate: 0.1 },
            Timing::Fixed { delay: 7.0 },
        ];
        for timing in timings {
            for period in [0.1, 0.7, 1.0, 3.3, 13.0] {
                let mut not_yet = 1.0;
                let mut clock: f64 = 0.0;
                while clock < 70.0 {
                    not_yet *= 1.0 - timing.conditional(clock, period);
                    clock += period;
                    // Gaussian mass before clock 0 is never taken: compare with the truncation.
                    // Readings within the bound tolerance are evaluated past the bound.
                    let expected = timing.survival(timing.reading(clock)) / timing.survival(0.0);
                    assert!(
                        (not_yet - expected).abs() < 1e-9,
                        "{timing:?} period {period} clock {clock}: {not_yet} vs {expected}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_departure_seen_at_a_windows_bound_is_possible_and_nothing_else_changes() {
        // The camera of Figure 6-5 leaves taking-picture after Uniform(0.1, 0.2) s; with a 0.1 s
        // cycle the departure is seen one cycle after the entry, at clock 40.3 − 40.2, which is
        // not quite 0.1 in f64 (and would have no mass if it were).
        let picture = Timing::Uniform {
            lower: 0.1,
            upper: 0.2,
        };
        let step = 40.300000000000004 - 40.2;
        let p = picture.conditional(0.0, step);
        assert!(close(p, BOUND_TOLERANCE / 0.1), "{p}");
        assert!(close(picture.conditional(0.0, 0.1), p));
        // The next step takes the rest: the window is spent at its upper bound.
        assert!(close(picture.conditional(step, step), 1.0));
        // Just short of the upper bound counts as reaching it.
        assert!(close(picture.conditional(0.15, 0.0499999999), 1.0));
        // A fixed delay reached up to rounding fires.
        let fixed = Timing::Fixed { delay: 0.3 };
        assert_eq!(fixed.conditional(0.0, 0.7 - 0.4), 1.0);
        // Away from the bounds, and at an opening bound of 0, the exact form.
        assert!(close(picture.conditional(0.0, 0.15), 0.5));
        assert!(close(picture.conditional(0.12, 0.04), 0.5));
        let tau6 = Timing::Uniform {
            lower: 0.0,
            upper: 0.1,
        };
        assert!(close(tau6.conditional(0.0, 0.05), 0.5));
    }

    #[test]
    fn an_event_long_before_a_gaussians_mean_keeps_its_small_probability() {
        // The EDL entry trigger (§7.2.4): drag sensed 10 standard deviations before the
        // predicted entry time is unlikely, not impossible: the mass of the step is about the
        // density at its middle times the step, ≈ 2.6e-25.
        let entry = Timing::Gaussian {
            mean: 16800.0,
            sd: 30.0,
        };
        let p = entry.conditional(16500.0, 0.1);
        let z: f64 = (16500.05 - 16800.0) / 30.0;
        let density = (-z * z / 2.0).exp() / (2.0 * std::f64::consts::PI).sqrt() / 30.0;
        assert!((p / (density * 0.1) - 1.0).abs() < 1e-3, "{p}");
        // Near and after the mean nothing changes.
        let near = entry.conditional(16790.0, 0.1);
        assert!((near - (1.0 - entry.survival(16790.1) / entry.survival(16790.0))).abs() < 1e-12);
    }

    #[test]
    fn rates_are_hazards_that_leave_the_rest_their_share() {
        // §7.1.2's engine heating: timed to standby (p = 1) and a failure rate.
        let timed = TransitionLaw::Timed {
            probability: 1.0,
            timing: Timing::Uniform {
                lower: 30.0,
                upper: 60.0,
            },
        };
        let fail = TransitionLaw::Rate { per_second: 0.01 };
        let d = mode_distribution(HEATING, [(STANDBY, timed), (FAILED, fail)], Some(44.0), 1.0);
        let p = |m| d.iter().find(|(t, _)| *t == m).map_or(0.0, |(_, p)| *p);
        let survive = (-0.01f64).exp();
        assert!(close(p(FAILED), 1.0 - survive));
        assert!(close(p(STANDBY), survive / 16.0));
        assert!(close(p(HEATING), survive * 15.0 / 16.0));
        assert!(close(d.iter().map(|(_, p)| p).sum::<f64>(), 1.0));
    }

    #[test]
    fn stay_is_the_remainder_and_parallel_transitions_add() {
        let p = |x| TransitionLaw::PerCycle { probability: x };
        let d = mode_distribution(
            ValueId(0),
            [(ValueId(1), p(0.2)), (ValueId(1), p(0.3))],
            None,
            1.0,
        );
        assert_eq!(d, vec![(ValueId(1), 0.5), (ValueId(0), 0.5)]);
        // Spent: staying is impossible, so it is left out.
        let d = mode_distribution(
            ValueId(0),
            [(ValueId(1), p(0.989)), (ValueId(2), p(0.011))],
            None,
            1.0,
        );
        assert_eq!(d.len(), 2);
        // Over-full (refused by validation): scaled, never negative.
        let d = mode_distribution(
            ValueId(0),
            [(ValueId(1), p(0.8)), (ValueId(2), p(0.8))],
            None,
            1.0,
        );
        assert!(close(d.iter().map(|(_, p)| p).sum::<f64>(), 1.0));
    }
}
