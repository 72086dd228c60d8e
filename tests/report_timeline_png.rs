//! The README's picture rendered to pixels ("a timeline that shows the fault"):
//! the primary pyro misfire of the Mars EDL (thesis §7.2.5) drawn exactly as `kairos run
//! --timeline` draws it, laid out by a real SVG renderer (resvg, with the machine's fonts) and
//! checked on what a reader sees — the fault's labels inside the picture and painted, the
//! injected fault on its own row, and no two labels on top of each other — and a mission's
//! timeline, its time points and XGoals drawn beside the modes. The PNGs are written to the
//! test's output directory for a person to look at.

use std::path::Path;

use kairos::report::timeline::{InjectedFault, TimelineInput, render};
use kairos::simulation::{self, RunOptions};
use resvg::tiny_skia::{Pixmap, Transform};
use resvg::usvg::{self, Node, Rect};

/// The README picture's SVG: the scenario run and drawn as `kairos run` does.
fn readme_picture() -> String {
    picture_of("scenarios/mars_edl/lander_pyro_misfire.ron")
}

/// A scenario's timeline SVG, run and drawn as `kairos run --timeline` does.
fn picture_of(scenario: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(scenario);
    let scenario = simulation::load(&path).expect("the scenario loads");
    let mut injected = Vec::new();
    let run = simulation::run(&scenario, RunOptions::default(), &mut |record| {
        injected.extend(InjectedFault::of_cycle(&scenario, record));
    })
    .expect("it runs");
    render(&TimelineInput::of_run(&scenario, &run, &injected))
}

/// Every text element with an id, with its laid-out box (glyph outlines, in picture pixels).
fn text_boxes(group: &usvg::Group, boxes: &mut Vec<(String, Rect)>) {
    for node in group.children() {
        match node {
            Node::Group(g) => text_boxes(g, boxes),
            Node::Text(t) if !t.id().is_empty() => {
                boxes.push((t.id().to_string(), t.abs_bounding_box()));
            }
            _ => {}
        }
    }
}

/// The labels a reader must be able to tell apart: marks' labels, mode names, fault callouts
/// and XGoals' labels (the ids `report::timeline` gives them).
fn is_label(id: &str) -> bool {
    ["label-", "mode-", "fault-label-", "xgoal-"]
        .iter()
        .any(|prefix| id.starts_with(prefix))
}

fn intersect(a: &Rect, b: &Rect) -> bool {
    a.left() < b.right() && b.left() < a.right() && a.top() < b.bottom() && b.top() < a.bottom()
}

/// How many pixels inside `area` are close to the fault red (#d62728): the label was painted,
/// not hidden under a break's band or another drawing.
fn red_pixels(pixmap: &Pixmap, area: &Rect) -> usize {
    let (x0, y0) = (
        area.left().floor().max(0.0) as u32,
        area.top().floor().max(0.0) as u32,
    );
    let x1 = (area.right().ceil() as u32).min(pixmap.width());
    let y1 = (area.bottom().ceil() as u32).min(pixmap.height());
    let mut count = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            if let Some(p) = pixmap.pixel(x, y) {
                let (r, g, b) = (p.red(), p.green(), p.blue());
                if r > 150 && g < 90 && b < 90 {
                    count += 1;
                }
            }
        }
    }
    count
}

/// The fault is labelled where it was estimated and diagnosed, the injection
/// has its own row, every label is inside the picture and visible, no two labels intersect.
#[test]
fn the_readme_picture_shows_the_fault_with_labels_that_do_not_overlap() {
    let svg = readme_picture();
    let Rendered {
        picture,
        labels,
        pixmap,
    } = render_png(&svg, "timeline_lander_pyro_misfire.png");
    assert!(
        labels.len() > 40,
        "the run's labels were laid out: {}",
        labels.len()
    );

    // The diagnosis's label (faults row) and the fault segment's label (lander's lane).
    let fault_labels: Vec<&(String, Rect)> = labels
        .iter()
        .filter(|(id, _)| id.starts_with("label-faults-") || id.starts_with("fault-label-lander"))
        .collect();
    assert_eq!(fault_labels.len(), 2, "{fault_labels:?}");
    for (id, area) in &fault_labels {
        assert!(
            contains(&picture, area),
            "{id} {area:?} lies outside the picture {picture:?}"
        );
        assert!(
            red_pixels(&pixmap, area) > 20,
            "{id} at {area:?} is not painted in the fault colour"
        );
    }
    assert!(
        labels
            .iter()
            .any(|(id, _)| id.starts_with("label-injected-")),
        "the injected fault is labelled on its own row"
    );

    assert_apart(&labels);
}

/// No two labels intersect.
fn assert_apart(labels: &[(String, Rect)]) {
    for (k, (a_id, a)) in labels.iter().enumerate() {
        for (b_id, b) in &labels[k + 1..] {
            assert!(!intersect(a, b), "{a_id} {a:?} intersects {b_id} {b:?}");
        }
    }
}

/// A picture laid out and painted.
struct Rendered {
    /// The picture's area.
    picture: Rect,
    /// Its labels (`is_label`) with their boxes.
    labels: Vec<(String, Rect)>,
    /// Its pixels.
    pixmap: Pixmap,
}

/// Lays `svg` out with the machine's fonts, paints it and writes it to the test's output
/// directory as `png` for a person to look at.
fn render_png(svg: &str, png: &str) -> Rendered {
    let mut options = usvg::Options::default();
    options.fontdb_mut().load_system_fonts();
    assert!(
        !options.fontdb.is_empty(),
        "the renderer needs a font (Debian: fonts-dejavu-core)"
    );
    let tree = usvg::Tree::from_str(svg, &options).expect("the picture is valid SVG");
    let size = tree.size();
    let picture = Rect::from_xywh(0.0, 0.0, size.width(), size.height()).expect("a size");
    let mut boxes = Vec::new();
    text_boxes(tree.root(), &mut boxes);
    let labels = boxes.into_iter().filter(|(id, _)| is_label(id)).collect();
    let mut pixmap = Pixmap::new(size.width().ceil() as u32, size.height().ceil() as u32)
        .expect("a picture this size fits in memory");
    resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
    let png = Path::new(env!("CARGO_TARGET_TMPDIR")).join(png);
    pixmap.save_png(&png).expect("the PNG is written");
    println!("rendered: {}", png.display());
    Rendered {
        picture,
        labels,
        pixmap,
    }
}

/// The ids of the labels inside the SVG groups whose class has `class` (`time-point forced`).
fn label_ids_in(svg: &str, class: &str) -> Vec<String> {
    let document = roxmltree::Document::parse(svg).expect("the picture is XML");
    document
        .descendants()
        .filter(|n| n.attribute("class").is_some_and(|c| c.contains(class)))
        .flat_map(|n| n.descendants())
        .filter_map(|n| n.attribute("id"))
        .filter(|id| is_label(id))
        .map(str::to_string)
        .collect()
}

/// DESIGN.md §15.3, mds-goal-networks.md §2.4: a mission's timeline shows its
/// time points on the network row with their windows and its XGoals as bars under their state
/// variables' lanes. With switch 1 sticking open under StayWarm, the maintained XGoals of
/// switch 1 and the temperature are outlined as failed from their goals' failures; every label
/// — the points', the XGoals', the modes', the diagnosis's — is laid out apart from the others.
#[test]
fn a_mission_timeline_shows_time_points_and_xgoal_bars_apart() {
    let svg = picture_of("scenarios/thermostat/switch1_sticks_open_mission.ron");
    let Rendered {
        picture, labels, ..
    } = render_png(&svg, "timeline_thermostat_switch1_sticks_open_mission.png");
    let points = label_ids_in(&svg, "time-point");
    for point in ["TP_H", "TP_A", "TP_S", "TP_E"] {
        assert!(
            svg.contains(&format!("time point {point} fired")),
            "{point} is drawn"
        );
    }
    assert!(points.len() >= 4, "the points are labelled: {points:?}");
    let xgoals: Vec<&(String, Rect)> = labels
        .iter()
        .filter(|(id, _)| id.starts_with("xgoal-"))
        .collect();
    for lane in ["switch1", "switch2", "sensor", "temperature"] {
        assert!(
            xgoals
                .iter()
                .any(|(id, _)| id.starts_with(&format!("xgoal-{lane}-"))),
            "an XGoal on {lane} is labelled: {xgoals:?}"
        );
    }
    assert!(svg.contains("Maintain temperature ∈ {warm-low, warm, warm-high}"));
    assert_eq!(
        svg.matches("class=\"xgoal-bar failed\"").count(),
        2,
        "heater1's and stay-warm's XGoals are outlined as failed"
    );
    for (id, area) in &labels {
        assert!(contains(&picture, area), "{id} {area:?} lies outside");
    }
    assert_apart(&labels);
}

/// mds-goal-networks.md §2.4 (b): a point forced at its latest time is drawn in the fault
/// colour on the network row, its label inside the picture and painted, clear of every other
/// label. With switch 1 stuck open from power-on, TP_S is forced at 161 s.
#[test]
fn a_forced_time_point_is_visible_in_the_fault_colour() {
    let svg = picture_of("scenarios/thermostat/switch1_stuck_open_mission.ron");
    let Rendered {
        picture,
        labels,
        pixmap,
    } = render_png(&svg, "timeline_thermostat_switch1_stuck_open_mission.png");
    let forced = label_ids_in(&svg, "time-point forced");
    assert_eq!(forced.len(), 1, "one point is forced: {forced:?}");
    let (id, area) = labels
        .iter()
        .find(|(id, _)| *id == forced[0])
        .expect("the forced point's label is laid out");
    assert!(contains(&picture, area), "{id} {area:?} lies outside");
    assert!(
        red_pixels(&pixmap, area) > 20,
        "{id} at {area:?} is not painted in the fault colour"
    );
    assert!(svg.contains("TP_S forced"), "the label names the point");
    assert_apart(&labels);
}

/// `inner` lies within `outer`.
fn contains(outer: &Rect, inner: &Rect) -> bool {
    inner.left() >= outer.left()
        && inner.right() <= outer.right()
        && inner.top() >= outer.top()
        && inner.bottom() <= outer.bottom()
}
