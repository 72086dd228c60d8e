//! Embedding the executive in a flight loop (DESIGN.md §10; thesis §7.1.1, Figure 7-1).
//!
//! The plant is reached through two adapters — a [`ControlAdapter`] turns commands into actuator
//! commands, a [`MonitorAdapter`] turns measurements into qualitative observations — and time
//! comes from a [`Clock`]. [`run`] drives an executive with them until a stop condition holds.
//! The loop is separate from [`Executive::step`](super::Executive::step): embedders with their own
//! scheduler call `step` directly.

use std::time::{Duration, Instant};

use super::{Executive, NamedValue, Step, StepError};

/// Sends commands to the plant.
pub trait ControlAdapter {
    /// Issues the command of the cycle at `time` (empty: idle). An error stops the loop.
    fn send(&mut self, time: f64, command: &[NamedValue]) -> Result<(), String>;
}

/// Reads the plant's observables.
pub trait MonitorAdapter {
    /// The observation at `time`: every observable, or as many as are available (missing ones
    /// are unknown for the cycle).
    fn observe(&mut self, time: f64) -> Vec<NamedValue>;
}

/// Where cycle times come from.
pub trait Clock {
    /// The time of the first cycle.
    fn start(&mut self) -> f64;
    /// Waits for the next cycle and returns its time.
    fn next_cycle(&mut self) -> f64;
}

/// A clock that does not wait: cycle `i` is at `start + i · period`. For simulation and tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulatedClock {
    start: f64,
    period: f64,
    cycle: u64,
}

impl SimulatedClock {
    /// Cycles every `period` seconds from `start`.
    pub fn new(start: f64, period: f64) -> Self {
        SimulatedClock {
            start,
            period,
            cycle: 0,
        }
    }
}

impl Clock for SimulatedClock {
    fn start(&mut self) -> f64 {
        self.cycle = 0;
        self.start
    }

    fn next_cycle(&mut self) -> f64 {
        self.cycle += 1;
        // Multiplying rather than adding keeps long runs free of accumulated rounding.
        self.start + self.cycle as f64 * self.period
    }
}

/// Wall-clock time in seconds since the clock started, one cycle every `period`: waits (sleeps)
/// until the next cycle is due; a late cycle starts at once.
#[derive(Debug, Clone, Copy)]
pub struct WallClock {
    origin: Instant,
    period: Duration,
    cycle: u32,
}

impl WallClock {
    /// A clock ticking every `period`, starting now.
    pub fn new(period: Duration) -> Self {
        WallClock {
            origin: Instant::now(),
            period,
            cycle: 0,
        }
    }
}

impl Clock for WallClock {
    fn start(&mut self) -> f64 {
        self.origin = Instant::now();
        self.cycle = 0;
        0.0
    }

    fn next_cycle(&mut self) -> f64 {
        self.cycle = self.cycle.saturating_add(1);
        let due = self.origin + self.period * self.cycle;
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        }
        self.origin.elapsed().as_secs_f64()
    }
}

/// Why the loop stopped early.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The executive refused a cycle.
    #[error(transparent)]
    Step(#[from] StepError),
    /// The control adapter failed to send a command.
    #[error("the control adapter failed at {time} s: {message}")]
    Control {
        /// The cycle's time.
        time: f64,
        /// What the adapter said.
        message: String,
    },
}

/// Runs cycles — observe, step, send — until `stop` says so after a cycle (it sees every
/// [`Step`], so it can also log or check them). Returns the number of cycles run.
pub fn run(
    executive: &mut Executive,
    clock: &mut impl Clock,
    monitor: &mut impl MonitorAdapter,
    control: &mut impl ControlAdapter,
    mut stop: impl FnMut(&Step) -> bool,
) -> Result<u64, RunError> {
    let mut time = clock.start();
    let mut cycles = 0;
    loop {
        let observation = monitor.observe(time);
        let step = executive.step(time, &observation)?;
        cycles += 1;
        let command: Vec<NamedValue> = step
            .command
            .iter()
            .map(|&(x, v)| NamedValue::of(executive.plant(), x, v))
            .collect();
        control
            .send(time, &command)
            .map_err(|message| RunError::Control { time, message })?;
        if stop(&step) {
            return Ok(cycles);
        }
        time = clock.next_cycle();
    }
}
