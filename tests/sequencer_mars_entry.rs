//! The thesis's §5.4 THCA execution example, reproduced: the Mars entry program of Figure 3-2
//! (`programs/mars_entry.rmpl`) compiled to the THCA of Figure 3-4 and stepped with the estimate
//! stream the narrative describes. Per cycle, the marking (by location number and source line),
//! the configuration goal and the clock values must match Figures 5-4..5-12 and the text
//! (DESIGN.md §5.3 acceptance).

#[path = "support/rmpl.rs"]
mod rmpl_support;

use kairos::logic::VarTable;
use kairos::sequencer::{AssignmentOracle, Event, Sequencer, StateEstimate};
use rmpl_support::{Figure, load_program, mars_lander_plant, state, updated};

/// One execution cycle of the narrative: the time, how ME's new estimate ŝ(i+1) differs from the
/// previous one, and what the sequencer must show.
struct Cycle {
    name: &'static str,
    time: f64,
    /// Changes ME reports at the end of this cycle (step 6).
    estimate_after: &'static [(&'static str, &'static str)],
    /// m(i) after step 2, as "location@figure-line".
    marked: &'static str,
    /// g(i).
    goal: &'static str,
    /// ω(i), one decimal.
    clocks: &'static str,
    /// m(i+1).
    marked_after: &'static str,
}

const NOTHING: &[(&str, &str)] = &[];

/// §5.4, cycle by cycle. Location numbers are Figure 3-4's; the line after `@` is the line of
/// Figure 3-2 the location comes from.
const NARRATIVE: &[Cycle] = &[
    Cycle {
        name: "Cycle 1: engine=standby asserted; ME reports heating",
        time: 0.0,
        estimate_after: &[("engine", "heating")],
        marked: "1@1 2@2",
        goal: "engine = standby",
        clocks: "",
        marked_after: "1@1 2@2",
    },
    Cycle {
        name: "Cycle 2: goal still asserted, not achieved",
        time: 0.5,
        estimate_after: NOTHING,
        marked: "1@1 2@2",
        goal: "engine = standby",
        clocks: "",
        marked_after: "1@1 2@2",
    },
    Cycle {
        name: "Cycles 3..N1-1: unchanged while the engine heats",
        time: 30.0,
        estimate_after: NOTHING,
        marked: "1@1 2@2",
        goal: "engine = standby",
        clocks: "",
        marked_after: "1@1 2@2",
    },
    Cycle {
        name: "Cycle N1 (43.2 s): ME confirms standby; 2 -> 3 (Figure 5-5)",
        time: 43.2,
        estimate_after: &[("engine", "standby")],
        marked: "1@1 2@2",
        goal: "engine = standby",
        clocks: "",
        marked_after: "1@1 3@3",
    },
    Cycle {
        name: "Cycle N1+1 (43.8 s): location 3 starts t1; 3 -> 4 (Figure 5-6)",
        time: 43.8,
        estimate_after: NOTHING,
        marked: "1@1 3@3",
        goal: "true",
        clocks: "",
        marked_after: "1@1 4@4",
    },
    Cycle {
        name: "Cycle N1+2 (44.2 s): t1 = 0.4; 4 -> 4",
        time: 44.2,
        estimate_after: NOTHING,
        marked: "1@1 4@4",
        goal: "true",
        clocks: "t1=0.4",
        marked_after: "1@1 4@4",
    },
    Cycle {
        name: "Cycles N1+3..N2-1: waiting for 270 min",
        time: 8000.0,
        estimate_after: NOTHING,
        marked: "1@1 4@4",
        goal: "true",
        clocks: "t1=7956.2",
        marked_after: "1@1 4@4",
    },
    Cycle {
        name: "Cycle N2 (16244.0 s): t1 = 16200.2 >= 270 min; 4 -> 5 (Figure 5-7)",
        time: 16244.0,
        estimate_after: NOTHING,
        marked: "1@1 4@4",
        goal: "true",
        clocks: "t1=16200.2",
        marked_after: "1@1 5@5",
    },
    Cycle {
        name: "Cycle N2+1 (16244.5 s): nav=inertial asserted and confirmed; 5 -> 6 (Figure 5-8)",
        time: 16244.5,
        estimate_after: &[("nav", "inertial")],
        marked: "1@1 5@5",
        goal: "nav = inertial",
        clocks: "t1=16200.7",
        marked_after: "1@1 6@6",
    },
    Cycle {
        name: "Cycle N2+2 (16245.1 s): location 6 starts t2; 6 -> 7 (Figure 5-9)",
        time: 16245.1,
        estimate_after: NOTHING,
        marked: "1@1 6@6",
        goal: "true",
        clocks: "t1=16201.3",
        marked_after: "1@1 7@7",
    },
    Cycle {
        name: "Cycle N2+3 (16245.6 s): t2 = 0.5 < 4 min; 7 -> 7",
        time: 16245.6,
        estimate_after: NOTHING,
        marked: "1@1 7@7",
        goal: "true",
        clocks: "t1=16201.8 t2=0.5",
        marked_after: "1@1 7@7",
    },
    Cycle {
        name: "Cycle N3 (16485.5 s): t2 = 240.4 >= 4 min; 7 -> composite 8 (Figure 5-10)",
        time: 16485.5,
        estimate_after: NOTHING,
        marked: "1@1 7@7",
        goal: "true",
        clocks: "t1=16441.7 t2=240.4",
        marked_after: "1@1 8@8 9@9 10@9 11@10",
    },
    Cycle {
        name: "Cycle N3+1 (16486.0 s): att=entry-orient asserted; ME reports the slew",
        time: 16486.0,
        estimate_after: &[("att", "slew-to-entry")],
        marked: "1@1 8@8 9@9 10@9 11@10",
        goal: "att = entry-orient",
        clocks: "t1=16442.2 t2=240.9",
        marked_after: "1@1 8@8 9@9 10@9 11@10",
    },
    Cycle {
        name: "Cycles N3+2..N4-1: slewing",
        time: 16492.0,
        estimate_after: NOTHING,
        marked: "1@1 8@8 9@9 10@9 11@10",
        goal: "att = entry-orient",
        clocks: "t1=16448.2 t2=246.9",
        marked_after: "1@1 8@8 9@9 10@9 11@10",
    },
    Cycle {
        name: "Cycle N4 (16498.2 s): entry orientation confirmed; 11 -> 12, 10 stays marked \
               despite achievement (re-marked by 9) (Figure 5-11)",
        time: 16498.2,
        estimate_after: &[("att", "entry-orient")],
        marked: "1@1 8@8 9@9 10@9 11@10",
        goal: "att = entry-orient",
        clocks: "t1=16454.4 t2=253.1",
        marked_after: "1@1 8@8 9@9 10@9 12@10",
    },
    Cycle {
        name: "Cycle N4+1 (16498.8 s): both goals asserted and achieved; 12's thread dies \
               (Figure 5-12)",
        time: 16498.8,
        estimate_after: &[("lander", "separated")],
        marked: "1@1 8@8 9@9 10@9 12@10",
        goal: "att = entry-orient and lander = separated",
        clocks: "t1=16455.0 t2=253.7",
        marked_after: "1@1 8@8 9@9 10@9",
    },
    Cycle {
        name: "Remaining cycles: holding the entry orientation; ME reports entry initiated",
        time: 16600.0,
        estimate_after: &[("entry", "initiated")],
        marked: "1@1 8@8 9@9 10@9",
        goal: "att = entry-orient",
        clocks: "t1=16556.2 t2=354.9",
        marked_after: "1@1 8@8 9@9 10@9",
    },
    Cycle {
        name: "Entry initiated: 8's maintenance is violated, its contents unmarked, 1 and 8 die",
        time: 16600.5,
        estimate_after: NOTHING,
        marked: "1@1 8@8",
        goal: "true",
        clocks: "t1=16556.7 t2=355.4",
        marked_after: "",
    },
];

/// §5.4 "Initial State": {Engine=Off, Nav=Earth-relative, Att=Cruise-orient, Lander=Connected,
/// Entry=Not-initiated}.
fn initial_state(table: &VarTable) -> StateEstimate {
    state(
        table,
        &[
            ("engine", "off"),
            ("nav", "earth-relative"),
            ("att", "cruise-orient"),
            ("lander", "connected"),
            ("entry", "not-initiated"),
        ],
    )
}

#[test]
fn compiled_locations_are_figure_3_4s_with_their_source_lines() {
    // §3.3: locations 1 and 8 are composites, 2-7 and 9-12 primitives; each maps to the text of
    // Figure 3-2 it was compiled from.
    let figure = Figure::new(load_program(
        "programs/mars_entry.rmpl",
        Some(&mars_lander_plant()),
    ));
    let expected = [
        (1, 1, "EntrySequence() :: {"),
        (2, 2, "engine = standby"),
        (3, 3, "t1 = 0"),
        (4, 4, "when (t1 ≥ 270.0 min) donext {"),
        (5, 5, "nav = inertial"),
        (6, 6, "t2 = 0"),
        (7, 7, "when (t2 ≥ 4.0 min) donext {"),
        (8, 8, "do {"),
        (9, 9, "always (att = entry-orient)"),
        (10, 9, "att = entry-orient"),
        (
            11,
            10,
            "when (att = entry-orient) donext (lander = separated)",
        ),
        (12, 10, "lander = separated"),
    ];
    assert_eq!(figure.thca.locations().len(), expected.len());
    for (number, line, text) in expected {
        let (actual_line, actual_text) = figure.origin(number);
        assert_eq!(
            (actual_line, actual_text.as_str()),
            (line, text),
            "location {number}"
        );
    }
    let composites: Vec<u32> = figure
        .thca
        .locations()
        .iter()
        .filter(|l| l.is_composite())
        .map(|l| l.id.number())
        .collect();
    assert_eq!(composites, [1, 8]);
}

#[test]
fn section_5_4_walk_through() {
    let plant = mars_lander_plant();
    let figure = Figure::new(load_program("programs/mars_entry.rmpl", Some(&plant)));
    let table = figure.thca.table().clone();
    let mut oracle = AssignmentOracle::new(&table);
    let mut sequencer = Sequencer::new(figure.thca.clone());
    let mut estimate = initial_state(&table);
    for cycle in NARRATIVE {
        let start = sequencer
            .begin_cycle(cycle.time, &estimate, &mut oracle)
            .unwrap_or_else(|e| panic!("{}: {e}", cycle.name));
        assert_eq!(
            figure.marking(&sequencer),
            cycle.marked,
            "{}: m(i)",
            cycle.name
        );
        let goal = start.goal.formula.display(&table).to_string();
        assert_eq!(goal, cycle.goal, "{}: g(i)", cycle.name);
        let clocks: Vec<String> = start
            .clocks
            .iter()
            .map(|(clock, value)| format!("{}={value:.1}", table.clock_name(*clock)))
            .collect();
        assert_eq!(clocks.join(" "), cycle.clocks, "{}: ω(i)", cycle.name);

        let next = updated(&table, &estimate, cycle.estimate_after);
        let end = sequencer
            .end_cycle(&next, &mut oracle)
            .unwrap_or_else(|e| panic!("{}: {e}", cycle.name));
        assert_eq!(
            figure.marking(&sequencer),
            cycle.marked_after,
            "{}: m(i+1)",
            cycle.name
        );
        assert_eq!(
            end.completed,
            cycle.marked_after.is_empty(),
            "{}",
            cycle.name
        );
        estimate = next;
    }
    assert!(sequencer.is_complete(), "§5.4: execution terminates");
}

#[test]
fn walk_through_events_name_their_source() {
    // Figure 5-3 step 3 at Cycle N1+1 ("the current system time of 43.8 sec is stored as the
    // initialization time for t1"), step 7 at Cycle N4, step 2 when entry is initiated.
    let plant = mars_lander_plant();
    let figure = Figure::new(load_program("programs/mars_entry.rmpl", Some(&plant)));
    let table = figure.thca.table().clone();
    let mut oracle = AssignmentOracle::new(&table);
    let mut sequencer = Sequencer::new(figure.thca.clone());
    let mut estimate = initial_state(&table);
    let mut events = Vec::new();
    for cycle in NARRATIVE {
        let next = updated(&table, &estimate, cycle.estimate_after);
        let step = sequencer
            .step(cycle.time, &estimate, &next, &mut oracle)
            .unwrap();
        events.extend(step.start.events.into_iter().chain(step.end.events));
        estimate = next;
    }
    let described: Vec<String> = events
        .iter()
        .filter_map(|event| figure.describe(event))
        .collect();
    let text = described.join("\n");
    for expected in [
        "clock t1 started at 43.8 by location 3 (`t1 = 0`)",
        "clock t2 started at 16245.1 by location 6 (`t2 = 0`)",
        "goal of location 2 achieved (`engine = standby`)",
        "goal of location 10 achieved (`att = entry-orient`)",
        "goal of location 12 achieved (`lander = separated`)",
        "location 8 preempted (`do {`)",
        "completed",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in\n{text}");
    }
    assert_eq!(
        events
            .iter()
            .filter(|e| matches!(e, Event::Completed))
            .count(),
        1
    );
}
