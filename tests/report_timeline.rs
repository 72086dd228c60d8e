//! The SVG timeline of a run: real runs of the executive drawn and read back
//! with an XML parser — one lane per state variable, a mark per command and diagnosis, idle
//! stretches compressed — a snapshot of a small run, and inputs that must not break it.

use kairos::diagnostic::Source;
use kairos::executive::{Event, EventKind, Executive, NamedValue, Retention, Timelines};
use kairos::logic::{ValueId, VarId};
use kairos::plant::Plant;
use kairos::report::timeline::{TimelineInput, TimelineOptions, render, render_with};
use kairos::rmpl::{self, LinkOptions};
use roxmltree::{Document, Node};

fn load_plant(name: &str, text: &str) -> Plant {
    Plant::load(&Source::new(name, text)).expect("a valid model")
}

fn propulsion() -> Plant {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/propulsion.ron");
    load_plant(
        path,
        &std::fs::read_to_string(path).expect("the model exists"),
    )
}

fn executive(plant: Plant, program: &str) -> Executive {
    let options = LinkOptions {
        plant: Some(plant.table()),
        ..LinkOptions::default()
    };
    let thca = rmpl::load(&Source::new("programs/test.rmpl", program), &options)
        .expect("the program links against the plant");
    Executive::builder(plant, thca)
        .kappa(5)
        .build()
        .expect("the executive builds")
}

/// A finished run: the executive, every step's events, the first and last cycle's times.
struct Run {
    executive: Executive,
    events: Vec<Event>,
    start: f64,
    end: f64,
}

impl Run {
    fn svg(&self, title: &str) -> String {
        render(&self.input(title))
    }

    fn input<'a>(&'a self, title: &'a str) -> TimelineInput<'a> {
        TimelineInput {
            plant: self.executive.plant(),
            program: self.executive.program(),
            timelines: self.executive.timelines(),
            events: &self.events,
            injected: &[],
            start: self.start,
            end: self.end,
            title,
        }
    }

    fn count(&self, matches: fn(&EventKind) -> bool) -> usize {
        self.events.iter().filter(|e| matches(&e.kind)).count()
    }
}

/// A plant simulated by hand: it answers the executive's commands with observations.
trait Hardware {
    fn observe(&mut self, time: f64) -> Vec<NamedValue>;
    fn command(&mut self, time: f64, assignment: &NamedValue);
}

/// Runs cycles from t = 0 until the run settles or `until`; `next` gives the next cycle's time.
fn drive(
    mut executive: Executive,
    hardware: &mut dyn Hardware,
    until: f64,
    next: impl Fn(f64, bool) -> f64,
) -> Run {
    let mut events = Vec::new();
    let mut time = 0.0;
    let mut end = 0.0;
    while time <= until {
        let observation = hardware.observe(time);
        let step = executive.step(time, &observation).expect("time increases");
        for &(var, value) in &step.command {
            hardware.command(time, &NamedValue::of(executive.plant(), var, value));
        }
        events.extend(step.events.iter().cloned());
        end = time;
        if step.is_settled() {
            break;
        }
        time = next(time, !step.command.is_empty());
    }
    Run {
        executive,
        events,
        start: 0.0,
        end,
    }
}

/// The propulsion hardware: the PDE relays commands when on; the engine heats for 40 s; the
/// valves pass tank pressure when open. The PDE may drop into its resettable fault at a time.
#[derive(Default)]
struct Propulsion {
    pde_on: bool,
    pde_resettable: bool,
    fault_at: Option<f64>,
    open: [bool; 2],
    engine: &'static str,
    heating_since: f64,
}

impl Propulsion {
    fn new(fault_at: Option<f64>) -> Self {
        Propulsion {
            fault_at,
            engine: "off",
            ..Propulsion::default()
        }
    }

    fn relay(&mut self, time: f64, command: &str) {
        match (command, self.engine) {
            ("open1", _) => self.open[0] = true,
            ("open2", _) => self.open[1] = true,
            ("close1", _) => self.open[0] = false,
            ("close2", _) => self.open[1] = false,
            ("engine-standby", "off") => {
                self.engine = "heating";
                self.heating_since = time;
            }
            ("engine-fire", "standby") => self.engine = "firing",
            ("engine-off", _) => self.engine = "off",
            _ => {}
        }
    }
}

impl Hardware for Propulsion {
    fn observe(&mut self, time: f64) -> Vec<NamedValue> {
        if self.fault_at.is_some_and(|t| time >= t) {
            self.fault_at = None;
            self.pde_resettable = true;
            self.pde_on = false;
        }
        if self.engine == "heating" && time - self.heating_since >= 40.0 {
            self.engine = "standby";
        }
        let level = |high: bool| if high { "high" } else { "low" };
        let (powered, hot) = (
            self.engine != "off",
            matches!(self.engine, "standby" | "firing"),
        );
        let firing = self.engine == "firing";
        vec![
            NamedValue::new("valve1.outlet", level(self.open[0])),
            NamedValue::new("valve2.outlet", level(self.open[1])),
            NamedValue::new("engine.power", if powered { "nominal" } else { "zero" }),
            NamedValue::new("engine.temp", if hot { "nominal" } else { "low" }),
            NamedValue::new("engine.thrust", if firing { "nominal" } else { "zero" }),
        ]
    }

    fn command(&mut self, time: f64, assignment: &NamedValue) {
        match assignment.value.symbol().unwrap_or_default() {
            "on" if !self.pde_resettable => self.pde_on = true,
            "off" => (self.pde_on, self.pde_resettable) = (false, false),
            "reset" if self.pde_resettable => (self.pde_on, self.pde_resettable) = (true, false),
            relayed if self.pde_on => self.relay(time, relayed),
            _ => {}
        }
    }
}

/// `engine = firing` on propulsion with the PDE dropping into its resettable fault at t = 1
/// (§7.2.5): a diagnosis and a repair, every cycle a second.
fn propulsion_with_a_pde_fault() -> Run {
    let executive = executive(propulsion(), "Fire() :: { engine = firing }");
    drive(executive, &mut Propulsion::new(Some(1.0)), 400.0, |t, _| {
        t + 1.0
    })
}

/// The parsed picture.
struct Picture<'a> {
    document: Document<'a>,
}

impl<'a> Picture<'a> {
    fn parse(svg: &'a str) -> Picture<'a> {
        let document = Document::parse(svg).expect("the timeline is well-formed XML");
        let root = document.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert_eq!(
            root.tag_name().namespace(),
            Some("http://www.w3.org/2000/svg")
        );
        Picture { document }
    }

    /// Elements with all these classes.
    fn with_class(&self, element: &str, classes: &[&str]) -> Vec<Node<'_, 'a>> {
        self.document
            .descendants()
            .filter(|n| n.has_tag_name(element))
            .filter(|n| {
                let class: Vec<&str> = n.attribute("class").unwrap_or("").split(' ').collect();
                classes.iter().all(|c| class.contains(c))
            })
            .collect()
    }

    fn lanes(&self) -> Vec<&str> {
        self.with_class("g", &["lane"])
            .iter()
            .map(|g| g.attribute("data-component").unwrap_or(""))
            .collect()
    }

    fn events(&self, class: &str) -> Vec<Node<'_, 'a>> {
        self.with_class("g", &["event", class])
    }
}

/// The text of an element and its descendants.
fn text_of(node: Node) -> String {
    node.descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect::<String>()
        .trim()
        .to_string()
}

/// The texts of an element's `<text>` descendants (labels, not tooltips).
fn labels_of(node: Node) -> Vec<String> {
    node.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(text_of)
        .collect()
}

fn number(node: Node, attribute: &str) -> f64 {
    node.attribute(attribute)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{attribute} is a number"))
}

/// Advance of one character of the picture's monospace font, per pixel of font size (the
/// renderer's own measure, so a label's box is known without font metrics).
const CHAR_WIDTH: f64 = 0.62;

/// The font size of an element of the picture: tick labels and mode names are smaller.
fn font_size(node: Node) -> f64 {
    let class = node.attribute("class").unwrap_or("");
    if class.starts_with("tick") || class.starts_with("mode") {
        10.0
    } else {
        11.0
    }
}

/// Asserts that no two labels on one line overlap: mark labels and goal bars on each level of
/// each row, and tick labels on each line of both axes. Returns how many were checked.
fn assert_no_label_overlaps(picture: &Picture) -> usize {
    let mut boxes: Vec<(i64, f64, f64, String)> = Vec::new();
    for node in picture.document.descendants() {
        let class = node.attribute("class").unwrap_or("");
        let (x, y) = match (node.attribute("x"), node.attribute("y")) {
            (Some(_), Some(_)) => (number(node, "x"), number(node, "y")),
            _ => continue,
        };
        let text = text_of(node);
        let (baseline, width) =
            if node.has_tag_name("text") && (class == "label" || class.starts_with("tick")) {
                (
                    y,
                    text.chars().count() as f64 * font_size(node) * CHAR_WIDTH,
                )
            } else if node.has_tag_name("rect") && class == "goal-bar" {
                // A bar sits 10 px above its level's baseline.
                (y + 10.0, number(node, "width"))
            } else {
                continue;
            };
        boxes.push(((baseline * 10.0).round() as i64, x, x + width, text));
    }
    boxes.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    for pair in boxes.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        // A goal's own label starts inside its bar: only different marks may not overlap.
        let bar_and_its_label = a.3.is_empty() && (b.1 - a.1).abs() < 4.0;
        if a.0 == b.0 && !bar_and_its_label {
            assert!(a.2 <= b.1 + 0.05, "{:?} overlaps {:?}", a, b);
        }
    }
    boxes.len()
}

/// §12, the timeline: one lane per state variable, goals, commands (repairs told apart)
/// and diagnoses, fault modes highlighted.
#[test]
fn a_propulsion_run_draws_one_lane_per_state_variable_and_a_mark_per_command_and_diagnosis() {
    let run = propulsion_with_a_pde_fault();
    let svg = run.svg("propulsion: engine = firing, PDE fault at 1 s");
    let picture = Picture::parse(&svg);

    let names: Vec<&str> = run
        .executive
        .plant()
        .components()
        .iter()
        .map(|c| c.name())
        .collect();
    assert_eq!(picture.lanes(), names, "one lane per component, in order");

    let commands = run.count(|k| matches!(k, EventKind::CommandIssued { .. }));
    let repairs = run.count(|k| matches!(k, EventKind::CommandIssued { repair: true, .. }));
    let diagnoses = run.count(|k| matches!(k, EventKind::Diagnosis { .. }));
    let goals = run.count(|k| matches!(k, EventKind::GoalAsserted { .. }));
    assert!(
        commands >= 8 && repairs >= 1 && diagnoses >= 1,
        "{:?}",
        run.events
    );
    assert_eq!(picture.events("command").len(), commands);
    assert_eq!(picture.events("repair").len(), repairs);
    assert_eq!(picture.events("diagnosis").len(), diagnoses);
    assert_eq!(picture.events("goal").len(), goals);
    assert_eq!(picture.events("completed").len(), 1);

    // The repair is labelled as such, the diagnosis names the component and fault mode, and the
    // goal carries its text and program line. A fault's label starts with the number of its
    // note under the picture, which has the full text.
    let repair = &picture.events("repair")[0];
    assert_eq!(labels_of(*repair), ["repair: PDE.cmd = reset"]);
    let diagnosis = &picture.events("diagnosis")[0];
    assert!(labels_of(*diagnosis)[0].starts_with("[1] PDE: resettable (p "));
    let notes = labels_of(
        picture
            .with_class("g", &[])
            .into_iter()
            .find(|g| g.attribute("id") == Some("footer"))
            .expect("a footer"),
    );
    assert!(
        notes
            .iter()
            .any(|n| n.starts_with("[1] diagnosis at ")
                && n.contains("PDE = resettable, probability")),
        "{notes:?}"
    );
    assert_eq!(
        labels_of(picture.events("goal")[0]),
        ["engine = firing (line 1)"]
    );
    assert!(text_of(picture.events("goal")[0]).contains("test.rmpl:1:"));

    // The PDE's lane shows its fault mode highlighted; the engine's lane names its modes.
    let pde = picture.with_class("g", &["lane"])[0];
    let faults: Vec<&str> = pde
        .descendants()
        .filter(|n| n.attribute("class") == Some("interval fault"))
        .filter_map(|n| n.attribute("data-mode"))
        .collect();
    assert_eq!(faults, ["resettable"]);
    let engine = picture
        .with_class("g", &["lane"])
        .into_iter()
        .find(|g| g.attribute("data-component") == Some("engine"))
        .expect("an engine lane");
    let modes: Vec<&str> = engine
        .descendants()
        .filter_map(|n| n.attribute("data-mode"))
        .collect();
    assert_eq!(modes, ["off", "heating", "standby", "firing"]);
    assert!(labels_of(engine).contains(&"heating".to_string()));

    // Two minutes of cycles a second apart: nothing to compress.
    assert!(picture.with_class("g", &["idle-break"]).is_empty());
    assert!(assert_no_label_overlaps(&picture) > 10);
}

/// "readable at a glance": labels crowded into one instant stack on levels
/// instead of overlapping, and past the level limit are thinned (the mark and its tooltip stay).
#[test]
fn crowded_labels_stack_without_overlapping_and_thin_past_the_limit() {
    let plant = propulsion();
    let timelines = empty_timelines(&plant);
    let events: Vec<Event> = (0..30)
        .map(|i| {
            event(
                10.0 + f64::from(i) * 0.01,
                EventKind::CommandIssued {
                    assignments: vec![format!("PDE.cmd = command-number-{i}")],
                    purpose: "crowding".to_string(),
                    repair: false,
                    serves: Vec::new(),
                },
            )
        })
        .collect();
    let options = TimelineOptions {
        max_label_levels: 6,
        ..TimelineOptions::default()
    };
    let svg = render_with(&input(&plant, &timelines, &events, (0.0, 20.0)), &options);
    let picture = Picture::parse(&svg);
    let commands = picture.events("command");
    assert_eq!(commands.len(), 30, "every command keeps its mark");
    let labelled = commands
        .iter()
        .filter(|c| !labels_of(**c).is_empty())
        .count();
    assert!((6..30).contains(&labelled), "{labelled} labels on 6 levels");
    assert!(
        commands
            .iter()
            .all(|c| text_of(*c).contains("command-number-"))
    );
    assert_no_label_overlaps(&picture);
}

/// §12, "idle stretches compressed": a cruise becomes one fixed-width break labelled with its
/// duration.
#[test]
fn a_long_idle_stretch_is_compressed_to_a_marked_break() {
    // Half an hour, not longer: propulsion.ron's valves stick closed at 1e-4/s, which a closed
    // valve does not show, so after two hours the executive believes them stuck.
    let program =
        "Cruise() :: { engine = standby; t = 0; when (t >= 2000) donext engine = firing }";
    let executive = executive(propulsion(), program);
    // Cycles a second apart while anything happens, then every 500 s through the cruise.
    let run = drive(executive, &mut Propulsion::new(None), 5000.0, |t, _| {
        if (100.0..1500.0).contains(&t) {
            t + 500.0
        } else {
            t + 1.0
        }
    });
    assert!(run.end > 2000.0 && run.end < 2100.0, "settles after firing");
    let svg = run.svg("a long cruise");
    let picture = Picture::parse(&svg);
    let breaks = picture.with_class("g", &["idle-break"]);
    assert_eq!(breaks.len(), 1, "one idle stretch: the cruise");
    let cruise = breaks[0];
    let (from, until) = (number(cruise, "data-from"), number(cruise, "data-until"));
    assert!(from < 100.0 && until >= 2000.0, "{from} .. {until}");
    assert_eq!(labels_of(cruise), ["≈ 33 min idle"]);
    let band = cruise
        .descendants()
        .find(|n| n.attribute("class") == Some("break-band"))
        .expect("a band");
    assert_eq!(
        number(band, "width"),
        28.0,
        "a fixed width, whatever the duration"
    );
    assert_eq!(picture.lanes().len(), 6);
    assert_eq!(
        picture.events("command").len(),
        run.count(|k| matches!(k, EventKind::CommandIssued { .. }))
    );
}

/// §12: the idle threshold decides what is compressed.
#[test]
fn a_larger_threshold_keeps_the_stretch_linear() {
    let program =
        "Cruise() :: { engine = standby; t = 0; when (t >= 1000) donext engine = firing }";
    let executive = executive(propulsion(), program);
    let run = drive(executive, &mut Propulsion::new(None), 3000.0, |t, _| {
        t + 5.0
    });
    let options = TimelineOptions {
        idle_threshold: 3600.0,
        ..TimelineOptions::default()
    };
    let svg = render_with(&run.input("no compression"), &options);
    assert!(
        Picture::parse(&svg)
            .with_class("g", &["idle-break"])
            .is_empty()
    );
    let svg = run.svg("compressed");
    assert_eq!(
        Picture::parse(&svg).with_class("g", &["idle-break"]).len(),
        1
    );
}

/// A lamp that can break (it then stays dark) and a fan.
const ROOM: &str = r#"Plant(
    name: "room",
    components: [
        Component(
            name: "lamp",
            attributes: { "cmd": ["none", "on", "off"], "light": ["dark", "lit"] },
            modes: [
                Mode(name: "off", constraint: "lamp.light = dark", reward: 0),
                Mode(name: "on", constraint: "lamp.light = lit", reward: 0),
                Mode(name: "broken", kind: Fault, constraint: "lamp.light = dark", reward: -10),
            ],
            initial: { "off": 1.0 },
            transitions: [
                (from: "off", to: "on", guard: "lamp.cmd = on", probability: 0.999),
                (from: "on", to: "off", guard: "lamp.cmd = off", probability: 0.999),
                (from: "*", to: "broken", rate: 0.001),
            ],
        ),
        Component(
            name: "fan",
            attributes: { "cmd": ["none", "on", "off"], "air": ["still", "moving"] },
            modes: [
                Mode(name: "off", constraint: "fan.air = still", reward: 0),
                Mode(name: "on", constraint: "fan.air = moving", reward: 0),
            ],
            initial: { "off": 1.0 },
            transitions: [
                (from: "off", to: "on", guard: "fan.cmd = on", probability: 0.999),
                (from: "on", to: "off", guard: "fan.cmd = off", probability: 0.999),
            ],
        ),
    ],
    controls: { "lamp.cmd": "none", "fan.cmd": "none" },
    observables: ["lamp.light", "fan.air"],
)"#;

/// The room: the fan on at once, the lamp on at 5 s; the lamp goes dark at 10 s.
fn room_run() -> Run {
    struct Room {
        lamp: bool,
        fan: bool,
    }
    impl Hardware for Room {
        fn observe(&mut self, time: f64) -> Vec<NamedValue> {
            let lit = self.lamp && time < 10.0;
            vec![
                NamedValue::new("lamp.light", if lit { "lit" } else { "dark" }),
                NamedValue::new("fan.air", if self.fan { "moving" } else { "still" }),
            ]
        }
        fn command(&mut self, _: f64, assignment: &NamedValue) {
            let on = assignment.value.symbol() == Some("on");
            match assignment.variable.as_str() {
                "lamp.cmd" => self.lamp = on,
                _ => self.fan = on,
            }
        }
    }
    // The fan is turned off at 14 s so that the program is still running when the lamp fails.
    let program = "Room() :: { fan = on; t = 0; { when (t >= 5) donext lamp = on, when (t >= 14) donext fan = off } }";
    let executive = executive(load_plant("room.ron", ROOM), program);
    let mut room = Room {
        lamp: false,
        fan: false,
    };
    drive(executive, &mut room, 20.0, |t, _| t + 1.0)
}

/// §12, the timeline: a lamp failing shows as its fault mode in its lane and a diagnosis;
/// the same run draws the same picture.
#[test]
fn a_small_run_is_drawn_the_same_every_time() {
    let run = room_run();
    let svg = run.svg("room: fan, then lamp; the lamp breaks at 10 s");
    let picture = Picture::parse(&svg);
    assert_eq!(picture.lanes(), ["lamp", "fan"]);
    assert_eq!(picture.events("diagnosis").len(), 1);
    let lamp = picture.with_class("g", &["lane"])[0];
    assert!(
        lamp.descendants().any(|n| n.has_tag_name("rect")
            && n.attribute("data-mode") == Some("broken")
            && n.attribute("class").is_some_and(|c| c.contains("fault"))),
        "the broken lamp is drawn as a fault"
    );
    assert_no_label_overlaps(&picture);
    assert_eq!(
        svg,
        run.svg("room: fan, then lamp; the lamp breaks at 10 s")
    );
}

fn empty_timelines(plant: &Plant) -> Timelines {
    Timelines::new(
        plant.components().len(),
        plant.observables(),
        Retention::default(),
    )
}

fn input<'a>(
    plant: &'a Plant,
    timelines: &'a Timelines,
    events: &'a [Event],
    (start, end): (f64, f64),
) -> TimelineInput<'a> {
    TimelineInput {
        plant,
        program: None,
        timelines,
        events,
        injected: &[],
        start,
        end,
        title: "edge case",
    }
}

/// "nothing panics on odd input": an empty run.
#[test]
fn a_run_with_no_cycles_draws_empty_lanes() {
    let plant = propulsion();
    let timelines = empty_timelines(&plant);
    let svg = render(&input(&plant, &timelines, &[], (0.0, 0.0)));
    let picture = Picture::parse(&svg);
    assert_eq!(picture.lanes().len(), 6);
    let empty = picture
        .with_class("text", &["none"])
        .iter()
        .filter(|n| text_of(**n) == "no estimate")
        .count();
    assert_eq!(empty, 6);
}

/// Odd input: a single cycle, and modes held for one cycle.
#[test]
fn a_single_cycle_and_zero_length_intervals_draw() {
    let plant = propulsion();
    let mut timelines = empty_timelines(&plant);
    for lane in 0..6 {
        timelines.record_state(lane, 3.0, ValueId(0), 1.0);
    }
    let svg = render(&input(&plant, &timelines, &[], (3.0, 3.0)));
    let picture = Picture::parse(&svg);
    let widths: Vec<f64> = picture
        .with_class("rect", &["interval"])
        .iter()
        .map(|r| number(*r, "width"))
        .collect();
    assert_eq!(widths.len(), 6);
    assert!(widths.iter().all(|&w| w > 1000.0), "{widths:?}");

    // Modes that held for a single cycle, back to back, each get a visible sliver.
    let mut timelines = empty_timelines(&plant);
    for (i, t) in [0.0, 0.1, 0.2, 0.3, 100.0].into_iter().enumerate() {
        timelines.record_state(4, t, ValueId(i as u32 % 4), 0.9);
    }
    let svg = render(&input(&plant, &timelines, &[], (0.0, 100.0)));
    let picture = Picture::parse(&svg);
    let widths: Vec<f64> = picture
        .with_class("rect", &["interval"])
        .iter()
        .map(|r| number(*r, "width"))
        .collect();
    assert_eq!(widths.len(), 5);
    assert!(widths.iter().all(|&w| w >= 1.0), "{widths:?}");
}

/// Odd input: events outside the window are left out and counted; a drawn
/// window cuts the lanes' intervals at its edges.
#[test]
fn events_outside_the_window_are_counted_not_drawn() {
    let run = propulsion_with_a_pde_fault();
    let commands = run.count(|k| matches!(k, EventKind::CommandIssued { .. }));
    let inside = run
        .events
        .iter()
        .filter(|e| matches!(e.kind, EventKind::CommandIssued { .. }) && e.time <= 20.0)
        .count();
    assert!(
        inside > 0 && inside < commands,
        "the window cuts the commands"
    );
    let window = TimelineInput {
        start: 0.0,
        end: 20.0,
        ..run.input("the first 20 s")
    };
    let picture_svg = render(&window);
    let picture = Picture::parse(&picture_svg);
    assert_eq!(picture.events("command").len(), inside);
    assert!(text_of(picture.document.root_element()).contains("events outside the drawn window"));
    let right_edge = picture
        .with_class("rect", &["interval"])
        .iter()
        .map(|r| number(*r, "x") + number(*r, "width"))
        .fold(0.0, f64::max);
    assert!(right_edge <= 1600.0, "{right_edge}");

    // A window wholly before the run draws its lanes empty of marks.
    let before = TimelineInput {
        start: -100.0,
        end: -50.0,
        ..run.input("before the run")
    };
    let picture_svg = render(&before);
    let picture = Picture::parse(&picture_svg);
    assert_eq!(picture.lanes().len(), 6);
    assert!(picture.events("command").is_empty());
}

/// The timeline and §13, odd input: hostile text, huge and non-finite times, reversed
/// windows, unknown components and values, silly options.
#[test]
fn hostile_text_huge_times_and_nonsense_windows_still_make_valid_svg() {
    let plant = propulsion();
    let mut timelines = empty_timelines(&plant);
    timelines.record_state(0, 0.0, ValueId(0), f64::NAN);
    timelines.record_state(0, 1e14, ValueId(99), 0.2);
    timelines.record_state(7, 5.0, ValueId(0), 1.0);
    timelines.record_command(2e14, vec![(VarId(9999), ValueId(3))]);
    let hostile = "<script>alert(\"x\")</script> & \u{1}\u{7}'\u{FFFF}";
    let events = [
        event(
            1e14,
            EventKind::GoalFailed {
                goal: hostile.to_string(),
                reason: hostile.to_string(),
            },
        ),
        event(
            5e13,
            EventKind::CommandIssued {
                assignments: vec![hostile.to_string()],
                purpose: hostile.to_string(),
                repair: true,
                serves: Vec::new(),
            },
        ),
        event(
            -4.0,
            EventKind::Diagnosis {
                component: kairos::plant::ComponentId(42),
                mode: hostile.to_string(),
                probability: f64::INFINITY,
                next: vec![(hostile.to_string(), f64::NAN)],
                evidence: vec![hostile.to_string()],
            },
        ),
        event(f64::NAN, EventKind::ProgramCompleted),
        event(
            3.0,
            EventKind::ObservationRejected {
                variable: hostile.to_string(),
                value: String::new(),
                reason: String::new(),
            },
        ),
    ];
    for window in [
        (0.0, 2e14),
        (f64::NAN, f64::NAN),
        (f64::INFINITY, f64::NEG_INFINITY),
        (1e300, -1e300),
        (50.0, 10.0),
    ] {
        let svg = render(&input(&plant, &timelines, &events, window));
        let picture = Picture::parse(&svg);
        assert_eq!(picture.lanes().len(), 6, "{window:?}");
        assert!(!svg.contains("<script>"));
    }
    let svg = render(&input(&plant, &timelines, &events, (-10.0, 2e14)));
    let picture = Picture::parse(&svg);
    assert_eq!(
        picture.events("command").len(),
        2,
        "the event and the history's"
    );
    assert!(text_of(picture.document.root_element()).contains("rejected observations: 1"));
    for width in [0.0, f64::NAN, 1e9] {
        let options = TimelineOptions {
            width,
            idle_threshold: f64::NAN,
            max_label_levels: 0,
        };
        Picture::parse(&render_with(
            &input(&plant, &timelines, &events, (0.0, 1.0)),
            &options,
        ));
    }
}

fn event(time: f64, kind: EventKind) -> Event {
    Event {
        cycle: 0,
        time,
        kind,
    }
}
