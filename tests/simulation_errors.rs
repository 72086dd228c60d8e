//! The scenario loader's errors (DESIGN.md §11 scenario files, §13: "every file error points at
//! file:line:column with the offending text and what was expected"). Each file in
//! `tests/bad_scenarios/` says in its first comment what is wrong with it; its snapshot shows the
//! message as `kairos run` prints it.

#[path = "support/bad_files.rs"]
#[macro_use]
mod bad_files;

use kairos::simulation;

macro_rules! bad_scenario {
    ($($case:tt)+) => { bad_file!(simulation::load, "tests/bad_scenarios", $($case)+); };
}

bad_scenario!(syntax_error, "syntax_error.ron:6:5", "Expected comma");
bad_scenario!(unknown_field, "unknown_field.ron:6:5", "`ends`");
bad_scenario!(missing_program, "missing_program.ron:3:15", "cannot read");
bad_scenario!(
    unknown_observable,
    "unknown_observable.ron:8:17",
    "did you mean `engine.temp`?"
);
bad_scenario!(
    unknown_value,
    "unknown_value.ron:8:74",
    "one of: low, nominal"
);
bad_scenario!(
    command_on_a_mode,
    "command_on_a_mode.ron:8:42",
    "a formula over the plant's controls"
);
bad_scenario!(zero_delay, "zero_delay.ron:8:72", "Cycles(1) or more");
bad_scenario!(
    bad_condition,
    "bad_condition.ron:8:57",
    "syntax error in formula"
);
bad_scenario!(
    duplicate_rule,
    "duplicate_rule.ron:8:25",
    "already declared"
);
bad_scenario!(
    unknown_rule,
    "unknown_rule.ron:11:70",
    "did you mean `PDE powers up`?",
    "valve 1 sticks"
);
bad_scenario!(
    unknown_event,
    "unknown_event.ron:8:35",
    "did you mean `GoalFailed`?"
);
bad_scenario!(
    nominal_fault,
    "nominal_fault.ron:8:32",
    "resettable, failed"
);
bad_scenario!(
    goal_not_in_program,
    "goal_not_in_program.ron:8:30",
    "its goals: engine = firing"
);
bad_scenario!(
    window_backwards,
    "window_backwards.ron:8:67",
    "window_backwards.ron:8:88"
);
bad_scenario!(
    time_after_end,
    "time_after_end.ron:8:41",
    "after the run ends at 100 s"
);
// Deadlines a `Duration` cannot hold are located errors, not a panic.
bad_scenario!(
    deadline_too_long,
    "deadline_too_long.ron:8:15",
    "is longer than any duration"
);
bad_scenario!(
    deadline_1e20,
    "deadline_1e20.ron:7:15",
    "is longer than any duration"
);
// Mode estimation's history window: 0 to `estimation::MAX_HISTORY` steps, re-run on `Doubt` or
// `Surprise` (src/estimation/timed_me.rs, "When the window is re-run").
bad_scenario!(
    history_negative,
    "history_negative.ron:7:14",
    "a history window of -3 steps",
    "0 (none) to 10000"
);
bad_scenario!(
    history_too_long,
    "history_too_long.ron:8:14",
    "a history window of 1000000000 steps"
);
bad_scenario!(
    rerun_unknown,
    "rerun_unknown.ron:7:12",
    "`Doubt`",
    "`Surprise`"
);
// A run of more than `simulation::MAX_CYCLES` cycles is refused before it starts.
bad_scenario!(
    too_many_cycles,
    "too_many_cycles.ron:7:10",
    "1.000e9 cycles, more than the 10000000",
    "line 6, column 12"
);
bad_scenario!(
    model_bad_faults,
    "model_bad_faults.ron:11:14",
    "is not a component of the plant",
    "did you mean `stuck-closed`?",
    "`open` is not a fault mode of `valve1`",
    "is not a time in seconds",
    "after the end",
    "is not `component = mode @ time`",
    "noise 1.5 is not a probability"
);
// A scenario runs a program or a mission (DESIGN.md §15.4); the mission's problems and
// the expectations on its network are located like the rest.
bad_scenario!(
    both_program_and_mission,
    "both_program_and_mission.ron:4:15",
    "names both"
);
bad_scenario!(
    no_control_program,
    "no_control_program.ron:2:1",
    "names no control program"
);
bad_scenario!(
    missing_mission,
    "missing_mission.ron:3:15",
    "cannot read missions/no_such_mission.ron"
);
bad_scenario!(
    mission_other_plant,
    "mission_other_plant.ron:3:15",
    "binds to the plant model `models/thermostat.ron`"
);
bad_scenario!(
    mission_unschedulable,
    "mission_unschedulable.ron:3:15",
    "unachievable: [origin, a] Transition switch1 ∈ {stuck-open}"
);
bad_scenario!(
    mission_expectation_in_rmpl,
    "mission_expectation_in_rmpl.ron:7:14",
    "the scenario runs an RMPL program"
);
bad_scenario!(
    unknown_mission_names,
    "unknown_mission_names.ron:8:23",
    "did you mean `TP_E`?",
    "unknown_mission_names.ron:9:23",
    "unknown_mission_names.ron:10:26",
    "did you mean `stay-warm`?"
);

// `believed` (the executive's initial certainty, the seed's tests 5 and 6).
bad_scenario!(
    believed_unknown,
    "believed_unknown.ron:8:18",
    "no component `switch3`",
    "did you mean `switch2`?",
    "believed_unknown.ron:8:54",
    "one of switch1's modes: open, closed, stuck-open, stuck-closed"
);

// `Optional` rules, `choose` and `AnyOf` (the formats of `kairos explore`).
bad_scenario!(
    optional_window,
    "optional_window.ron:9:57",
    "a time at or after `from`",
    "1 or more cycles"
);
// `Between` intervals, their `choose` delays, `deliver` orders.
bad_scenario!(
    between_interval,
    "before it opens at 60 s",
    "is not the start of an interval",
    "an optional rule's effect cannot land in an interval",
    "outside the rule's interval",
    "2.5 s is not the time of a cycle",
    "did you mean `fine`?"
);
bad_scenario!(
    choose_unknown,
    "no optional rule `PDE powers up`",
    "outside the rule's window",
    "cannot be one of `AnyOf`"
);

// A rule's `submit:` is resolved by the mission loader (DESIGN.md §15.4): every
// problem of its points, constraints and goals is located in the scenario, as in a mission file.
bad_scenario!(
    submit_bad_goals,
    "submit_bad_goals.ron:11:23",
    "did you mean `TP_E`?",
    "submit_bad_goals.ron:14:70",
    "unknown time point `TP_G`",
    "did you mean `temperature`?",
    "a goal on `switch1` may only constrain `switch1`",
    "a Maintain goal needs a constraint",
    "unknown goal type `StayWarm`"
);
bad_scenario!(
    submit_in_rmpl,
    "submit_in_rmpl.ron:8:56",
    "the scenario runs an RMPL program"
);
