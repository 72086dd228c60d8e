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
//!   is spent (`F(c) = 1` exactly, e.g. past a uniform window) the transition is overdue and
//!   fires with probability `p`. A Gaussian's mass is never spent: far in its upper tail the
//!   conditional form is evaluated in log space (`1 − e^(ln S(c+δ) − ln S(c))`, with the
//!   asymptotic Mills-ratio series where `erfc` would underflow), so an overdue Gaussian event
//!   keeps the design's hazard rather than jumping to `p`.
//!
//! A mode's transitions combine into one distribution over next modes ([`mode_distribution`]):
//! rates are *hazards that compete with everything else* — in a step a hazard strikes with
//! probability `1 − e^(−ΣR·δ)`, shared in proportion to the rates — and the per-cycle and timed
//! transitions share the remaining `e^(−ΣR·δ)`; the mode stays with what is left (§6.1.3: "one
//! minus the sum of the probabilities of the outgoing ... transitions"). With per-cycle fault
//! probabilities only (Table 6.1) this is the plain sum of the thesis.

use crate::logic::ValueId;

/// Past this many standard deviations above a Gaussian's mean, `ln S` comes from the asymptotic
/// series of the Mills ratio rather than from `erfc` (which underflows near 37.5 σ); at 30 σ the
/// series' first omitted term is below 1e-15.
const GAUSSIAN_SERIES_FROM: f64 = 30.0;

/// How close to a window bound (a uniform's `lower` and `upper`, a fixed delay) a clock reading
/// counts as *at* the bound, seconds. Such a reading is taken as this much past the bound (see
/// `Timing::reading`).
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
        let (from, to) = match *self {
            Timing::Exponential { rate } => return 1.0 - (-rate * step.max(0.0)).exp(),
            Timing::Gaussian { mean, sd } => {
                // 1 − S(to)/S(from), from the log survivals: accurate in both tails.
                let (from, length) = standardised(mean, sd, before, step);
                let ratio = gaussian_log_survival_ratio(from, length);
                return (-ratio.exp_m1()).clamp(0.0, 1.0);
            }
            _ => (self.reading(before), self.reading(before + step.max(0.0))),
        };
        let survived = self.survival(from);
        if survived <= 0.0 {
            return 1.0;
        }
        ((survived - self.survival(to)) / survived).clamp(0.0, 1.0)
    }

    /// Whether the step from clock `before` is on the law's *steady stretch* before it can
    /// fire: [`Timing::conditional`]`(before, step)` is then one and the same value, bit for
    /// bit, for every reading `before` where this holds (with the same `step`). So a
    /// distribution computed at one steady reading is the distribution at every other, and
    /// need not be computed again while the clock runs on a steady stretch (estimation's quiet
    /// cycles: the Mars EDL's entry trigger, `Gaussian(16800, 30)`, is steady for its first
    /// 15,600 s). Why each holds, reading `conditional` (module documentation):
    /// - *exponential*: memoryless, `conditional` does not read `before` at all;
    /// - *uniform, fixed*: both survivals it reads, at the window readings of `before` and
    ///   `before + step`, are exactly 1 (the window has not opened by the step's end), so it
    ///   returns `(1 − 1) / 1`;
    /// - *Gaussian*: both standardised readings (computed by the same expressions as in
    ///   `conditional`) are below the mean, where `ln S(z)` reads `erfc(−z/√2)`, and both
    ///   arguments are at least `ERFC_ZERO_FROM` (28), where `erfc` is exactly 0; so both log
    ///   survivals are `ln_1p(−0.5 · 0)` and the ratio the same.
    ///
    /// No reading where the step's conditional probability is positive is steady, nor any
    /// past a window (the tests check that steady readings agree, and where the stretch ends).
    pub fn steady_at(&self, before: f64, step: f64) -> bool {
        match *self {
            Timing::Exponential { .. } => true,
            Timing::Gaussian { mean, sd } => {
                let (from, length) = standardised(mean, sd, before, step);
                // `gaussian_log_survival_ratio`'s `to` (below the mean it takes the difference of
                // the two logs), and `gaussian_log_survival`'s branch and `erfc` argument.
                let to = from + length;
                let no_mass = |z: f64| z < 0.0 && -z / std::f64::consts::SQRT_2 >= ERFC_ZERO_FROM;
                no_mass(from) && no_mass(to)
            }
            Timing::Uniform { .. } | Timing::Fixed { .. } => {
                let (from, to) = (self.reading(before), self.reading(before + step.max(0.0)));
                self.survival(from) == 1.0 && self.survival(to) == 1.0
            }
        }
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
}

/// From this argument on `erfc` is exactly 0: erfc(28) ≈ 7e-343 is far below the least
/// subnormal double (5e-324), so a faithful `erfc` rounds it and everything past it to 0 (libm's
/// returns 0 for every argument of at least 28 by a branch of its own).
const ERFC_ZERO_FROM: f64 = 28.0;

/// A Gaussian step from clock `before`, `step` long, in standard deviations: where it starts
/// relative to the mean, and its length (negative lengths taken as 0). One function for
/// [`Timing::conditional`] and [`Timing::steady_at`], so that both read the same numbers.
fn standardised(mean: f64, sd: f64, before: f64, step: f64) -> (f64, f64) {
    ((before - mean) / sd, step.max(0.0) / sd)
}

/// `ln S(z)` of the standard normal, `S = 1 − Φ`, accurate everywhere: below the mean from the
/// lower tail (`ln(1 − Φ(z))` with `Φ(z)` tiny long before the mean — an atmospheric entry
/// minutes early keeps its small probability), above it from `erfc`, and past
/// [`GAUSSIAN_SERIES_FROM`] from the asymptotic series.
fn gaussian_log_survival(z: f64) -> f64 {
    if z < 0.0 {
        (-0.5 * libm::erfc(-z / std::f64::consts::SQRT_2)).ln_1p()
    } else if z < GAUSSIAN_SERIES_FROM {
        (0.5 * libm::erfc(z / std::f64::consts::SQRT_2)).ln()
    } else {
        -0.5 * z * z - z.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln() + mills_series(z).ln()
    }
}

/// `z·S(z)/φ(z)` for large `z`: `1 − 1/z² + 3/z⁴ − 15/z⁶ + …` (Abramowitz & Stegun 26.2.12),
/// to the 1/z¹² term.
fn mills_series(z: f64) -> f64 {
    let w = 1.0 / (z * z);
    [1.0, -1.0, 3.0, -15.0, 105.0, -945.0, 10395.0]
        .iter()
        .rev()
        .fold(0.0, |acc, c| acc * w + c)
}

/// `ln S(from + step) − ln S(from)` of the standard normal (in standard deviations, `step >=
/// 0`). Far in the upper tail both logs are large and nearly equal, so the difference is taken
/// term by term there: `−step·(2·from + step)/2 − ln(to/from) + ln(M(to)/M(from))`.
fn gaussian_log_survival_ratio(from: f64, step: f64) -> f64 {
    let to = from + step;
    if from >= GAUSSIAN_SERIES_FROM {
        -0.5 * step * (2.0 * from + step) - (step / from).ln_1p()
            + (mills_series(to) / mills_series(from)).ln()
    } else {
        gaussian_log_survival(to) - gaussian_log_survival(from)
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

    /// Whether [`TransitionLaw::step_probability`]`(clock, step)` is on a steady stretch: the
    /// same value for every clock where this holds (same `step`). Per-cycle and rate laws do
    /// not read the clock; a timed one reads it through its timing's conditional
    /// ([`Timing::steady_at`], an unknown clock taken as zero as there).
    pub fn steady_at(&self, clock: Option<f64>, step: f64) -> bool {
        match *self {
            TransitionLaw::PerCycle { .. } | TransitionLaw::Rate { .. } => true,
            TransitionLaw::Timed { timing, .. } => timing.steady_at(clock.unwrap_or(0.0), step),
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
    fn far_in_a_gaussians_upper_tail_the_conditional_form_still_holds() {
        // DESIGN.md §6.2: p·(F(t) − F(t_prev))/(1 − F(t_prev)) however small
        // the survival. It once fired with the nominal p as soon as the survival was ≤ 1e-12
        // (from 7 σ on). The reference is the formula itself on `erfc`, whose ratio is accurate
        // to ~1e-15 relative wherever it does not underflow (below ~37 σ); the log-space form
        // switches to the asymptotic series at 30 σ, so 30–36 σ checks the series too.
        let unit = Timing::Gaussian { mean: 0.0, sd: 1.0 };
        let exact = |from: f64, step: f64| {
            let s = |z: f64| libm::erfc(z / std::f64::consts::SQRT_2);
            1.0 - s(from + step) / s(from)
        };
        for from in [
            -3.0, 0.0, 5.0, 7.0, 8.0, 10.0, 20.0, 29.99, 30.0, 31.0, 33.5, 36.0,
        ] {
            for step in [0.001, 0.05, 0.5] {
                let p = unit.conditional(from, step);
                let q = exact(from, step);
                assert!(
                    (p - q).abs() <= 1e-12 + 1e-9 * q,
                    "{from} σ + {step}: {p} vs {q}"
                );
            }
        }
        // At 8 σ, 0.1 s on a 1 s deviation: about 0.55, not the nominal 1.
        let law = TransitionLaw::Timed {
            probability: 0.989,
            timing: Timing::Gaussian {
                mean: 100.0,
                sd: 1.0,
            },
        };
        let p = law.step_probability(Some(108.0), 0.1);
        assert!((p - 0.989 * exact(8.0, 0.1)).abs() < 1e-12, "{p}");
        assert!(p < 0.6, "{p}");
        // Beyond erfc's range the hazard keeps growing with the clock, never past 1.
        let far: Vec<f64> = [40.0, 100.0, 1e4]
            .iter()
            .map(|z| unit.conditional(*z, 0.001))
            .collect();
        assert!(
            far.windows(2).all(|w| w[0] < w[1] && w[1] <= 1.0),
            "{far:?}"
        );
        // At 40 σ for 1e-3 σ: S(z+δ)/S(z) ≈ e^(−δ(2z+δ)/2)·z/(z+δ) (the series' ratio is
        // 1 + O(δ/z³)), so the hazard is ≈ 0.0392.
        let (z, d) = (40.0f64, 1e-3);
        let approx = 1.0 - (-0.5 * d * (2.0 * z + d) - (d / z).ln_1p()).exp();
        assert!((far[0] - approx).abs() < 1e-7, "{} vs {approx}", far[0]);
    }

    /// A timing of each kind from its parameters (`kind` modulo 4), with readings around
    /// where its mass lies.
    fn timing_of(kind: u8, a: f64, b: f64) -> Timing {
        match kind % 4 {
            0 => Timing::Uniform {
                lower: a,
                upper: a + b,
            },
            1 => Timing::Gaussian {
                mean: a * 100.0,
                sd: b / 10.0 + 1e-3,
            },
            2 => Timing::Exponential { rate: b },
            _ => Timing::Fixed { delay: a },
        }
    }

    proptest::proptest! {
        #![proptest_config(crate::seeded::config(512))]

        /// `Timing::steady_at` (DESIGN.md §6.2's conditional form, as `conditional` computes
        /// it): every two readings on a steady stretch give the same conditional probability,
        /// bit for bit, whatever the kind; the oracle is `conditional` itself at both.
        #[test]
        fn steady_readings_give_one_conditional(
            kind in 0u8..4,
            a in 0.0f64..100.0,
            b in 0.0f64..100.0,
            // Readings in standard deviations (Gaussian) or seconds around the window.
            x in -60.0f64..5.0,
            y in -60.0f64..5.0,
            step in proptest::prop_oneof![0.0f64..2.0, proptest::strategy::Just(0.1)],
        ) {
            let timing = timing_of(kind, a, b);
            let reading = |x: f64| match timing {
                Timing::Gaussian { mean, sd } => mean + x * sd,
                _ => a + x,
            };
            let (x, y) = (reading(x), reading(y));
            if timing.steady_at(x, step) && timing.steady_at(y, step) {
                let (p, q) = (timing.conditional(x, step), timing.conditional(y, step));
                proptest::prop_assert_eq!(p.to_bits(), q.to_bits(), "{:?} at {} and {}", timing, x, y);
            }
        }
    }

    /// The steady stretches end before mass shows: on a 0.1 s grid through each window no
    /// reading with a positive conditional probability is steady, and the stretch covers what
    /// it is for (the EDL entry trigger, `Gaussian(16800, 30)`, from its mode's entry to 40 σ
    /// before the mean; a uniform or fixed window up to its opening).
    #[test]
    fn a_steady_stretch_ends_before_mass_shows() {
        let entry = Timing::Gaussian {
            mean: 16800.0,
            sd: 30.0,
        };
        let heating = Timing::Uniform {
            lower: 30.0,
            upper: 60.0,
        };
        let fixed = Timing::Fixed { delay: 7.0 };
        for (timing, until) in [(entry, 15_600.0), (heating, 29.9), (fixed, 6.9)] {
            let mut steady = 0;
            for i in 0..=180_000 {
                let clock = f64::from(i) * 0.1;
                let p = timing.conditional(clock, 0.1);
                if timing.steady_at(clock, 0.1) {
                    assert!(p <= 0.0, "{timing:?} at {clock}: steady with {p}");
                    steady += 1;
                } else {
                    assert!(clock > until - 0.1, "{timing:?} at {clock}: not steady");
                }
            }
            assert!(steady > 0);
        }
        // Exponentials are memoryless: steady everywhere.
        let memoryless = Timing::Exponential { rate: 0.1 };
        assert!(
            [0.0, 1e3, 1e9]
                .iter()
                .all(|&c| memoryless.steady_at(c, 0.1))
        );
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
