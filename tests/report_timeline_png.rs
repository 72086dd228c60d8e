//! The README's picture rendered to pixels (issue 19 item 3, "a timeline that shows the fault"):
//! the primary pyro misfire of the Mars EDL (thesis §7.2.5) drawn exactly as `kairos run
//! --timeline` draws it, laid out by a real SVG renderer (resvg, with the machine's fonts) and
//! checked on what a reader sees — the fault's labels inside the picture and painted, the
//! injected fault on its own row, and no two labels on top of each other. The PNG is written to
//! the test's output directory for a person to look at.

use std::path::Path;

use kairos::report::timeline::{InjectedFault, TimelineInput, render};
use kairos::simulation::{self, RunOptions};
use resvg::tiny_skia::{Pixmap, Transform};
use resvg::usvg::{self, Node, Rect};

/// The README picture's SVG: the scenario run and drawn as `kairos run` does.
fn readme_picture() -> String {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/mars_edl/lander_pyro_misfire.ron");
    let scenario = simulation::load(&path).expect("the scenario loads");
    let mut injected = Vec::new();
    let run = simulation::run(&scenario, RunOptions::default(), &mut |record| {
        injected.extend(InjectedFault::of_cycle(&scenario, record));
    })
    .expect("it runs");
    render(&TimelineInput {
        plant: &scenario.plant,
        program: scenario.program.thca(),
        timelines: &run.timelines,
        events: &run.events,
        injected: &injected,
        start: run.start,
        end: run.last_time,
        title: &scenario.name,
    })
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

/// The labels a reader must be able to tell apart: marks' labels, mode names and fault
/// callouts (the ids `report::timeline` gives them).
fn is_label(id: &str) -> bool {
    ["label-", "mode-", "fault-label-"]
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

/// Issue 19 item 3: the fault is labelled where it was estimated and diagnosed, the injection
/// has its own row, every label is inside the picture and visible, no two labels intersect.
#[test]
fn the_readme_picture_shows_the_fault_with_labels_that_do_not_overlap() {
    let svg = readme_picture();
    let mut options = usvg::Options::default();
    options.fontdb_mut().load_system_fonts();
    assert!(
        !options.fontdb.is_empty(),
        "the renderer needs a font (Debian: fonts-dejavu-core)"
    );
    let tree = usvg::Tree::from_str(&svg, &options).expect("the picture is valid SVG");
    let size = tree.size();
    let picture = Rect::from_xywh(0.0, 0.0, size.width(), size.height()).expect("a size");

    let mut boxes = Vec::new();
    text_boxes(tree.root(), &mut boxes);
    let labels: Vec<&(String, Rect)> = boxes.iter().filter(|(id, _)| is_label(id)).collect();
    assert!(
        labels.len() > 40,
        "the run's labels were laid out: {}",
        labels.len()
    );

    let mut pixmap = Pixmap::new(size.width().ceil() as u32, size.height().ceil() as u32)
        .expect("a picture this size fits in memory");
    resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
    let png = Path::new(env!("CARGO_TARGET_TMPDIR")).join("timeline_lander_pyro_misfire.png");
    pixmap.save_png(&png).expect("the PNG is written");
    println!("rendered: {}", png.display());

    // The diagnosis's label (faults row) and the fault segment's label (lander's lane).
    let fault_labels: Vec<&(String, Rect)> = labels
        .iter()
        .copied()
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

    for (k, (a_id, a)) in labels.iter().enumerate() {
        for (b_id, b) in &labels[k + 1..] {
            assert!(!intersect(a, b), "{a_id} {a:?} intersects {b_id} {b:?}");
        }
    }
}

/// `inner` lies within `outer`.
fn contains(outer: &Rect, inner: &Rect) -> bool {
    inner.left() >= outer.left()
        && inner.right() <= outer.right()
        && inner.top() >= outer.top()
        && inner.bottom() <= outer.bottom()
}
