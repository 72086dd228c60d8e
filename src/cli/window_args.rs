//! `--history N` and `--rerun doubt|surprise`, shared by `kairos estimate`, `kairos bench` and
//! `kairos run`: mode estimation's history window and which occasions re-run it
//! (`TimedMeOptions::history`, `TimedMeOptions::rerun`). Given, they replace a scenario's
//! `history` and `rerun`; not given, the scenario's (or the defaults) hold.

use kairos::estimation::{DEFAULT_HISTORY, MAX_HISTORY, Rerun, TimedMeOptions};
use kairos::simulation::Scenario;

/// The history window's options.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct WindowArgs {
    /// How many recent steps mode estimation keeps to estimate again tracking 8κ states when
    /// truncating to κ may have cost it the truth (default 16; 0: none, a step costs one step
    /// at κ).
    #[arg(long, value_name = "STEPS", value_parser = parse_history)]
    pub history: Option<usize>,
    /// Which occasions re-run the window: `doubt` (default; also when the two most likely
    /// plant states are too close to call, the more accurate) or `surprise` (only when an
    /// observation contradicts or surprises the belief, the cheaper).
    #[arg(long, value_name = "doubt|surprise", value_parser = parse_rerun)]
    pub rerun: Option<Rerun>,
}

impl WindowArgs {
    /// TimedME's options at κ with these set.
    pub fn options(&self, kappa: usize) -> TimedMeOptions {
        let mut options = TimedMeOptions::kappa(kappa);
        if let Some(history) = self.history {
            options.history = history;
        }
        if let Some(rerun) = self.rerun {
            options.rerun = rerun;
        }
        options
    }

    /// Replaces the scenario's settings with those given.
    pub fn apply(&self, scenario: &mut Scenario) {
        if let Some(history) = self.history {
            scenario.history = history;
        }
        if let Some(rerun) = self.rerun {
            scenario.rerun = rerun;
        }
    }

    /// Whether any was given.
    pub fn given(&self) -> bool {
        self.history.is_some() || self.rerun.is_some()
    }
}

/// TimedME's settings as a title names them: κ, and the history window where it is not the
/// default's (`κ = 10`, `κ = 10, history 0`, `κ = 10, re-run on surprise`).
pub fn describe(options: &TimedMeOptions) -> String {
    let mut text = format!("κ = {}", options.kappa);
    if options.history != DEFAULT_HISTORY {
        text += &format!(", history {}", options.history);
    }
    if options.rerun != Rerun::default() && options.history > 0 {
        text += &format!(", re-run on {}", options.rerun.name());
    }
    text
}

/// `--history`: 0 to [`MAX_HISTORY`] steps.
fn parse_history(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n <= MAX_HISTORY => Ok(n),
        _ => Err(format!(
            "`{text}` is not a number of steps from 0 (no history window) to {MAX_HISTORY}"
        )),
    }
}

/// `--rerun`: a policy's name.
fn parse_rerun(text: &str) -> Result<Rerun, String> {
    Rerun::named(text.trim()).ok_or_else(|| {
        let names: Vec<&str> = Rerun::ALL.iter().map(|r| r.name()).collect();
        format!(
            "`{text}` is not a re-run policy: one of {}",
            names.join(", ")
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn policies_are_read_by_name() {
        assert_eq!(parse_rerun("surprise"), Ok(Rerun::Surprise));
        assert_eq!(parse_rerun("doubt"), Ok(Rerun::Doubt));
        assert!(parse_rerun("never").is_err());
    }

    #[test]
    fn history_windows_are_bounded() {
        assert_eq!(parse_history("0"), Ok(0));
        assert_eq!(parse_history(&MAX_HISTORY.to_string()), Ok(MAX_HISTORY));
        assert!(parse_history(&(MAX_HISTORY + 1).to_string()).is_err());
        assert!(parse_history("-1").is_err());
    }
}
