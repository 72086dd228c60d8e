//! The check that a file format's reference page (`docs/reference/*.md`) documents every field
//! and every enum variant its loader accepts, so that the reference cannot fall behind the code.
//!
//! The loader's serde types are traced with `serde-reflection` into a registry of containers
//! (structs and enums by their serde name, with their fields and variants: exactly what
//! deserialising accepts). The tracer explores an enum to its last variant only when the enum is
//! traced itself, so a test adds each enum of its format ([`add`]) before the file's root type;
//! one it forgets is named by [`registry`], not silently half-read. Each container is assigned a
//! section of a page — the text under the one heading whose title contains a given string, up to
//! the next heading. The page marks a documented name with a table row whose first cell starts
//! with it in backticks:
//! - a struct's field: `` | `name` | ... ``;
//! - an enum's variant: `` | `Variant` | ... `` or `` | `Variant(...)` | ... ``; a variant with
//!   named fields lists each as `field:` inside that first code span
//!   (`` | `Optional(from: …, to: …, every: …)` | ... ``).
//!
//! The check fails on a field or variant without its row, and on a row in an assigned section
//! that names nothing the loader accepts (a renamed or removed field), so the page can neither
//! miss a name nor keep a stale one. A container the registry holds that is not assigned to a
//! section fails too: a new type in a file format needs its section.

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::Deserialize;
use serde_reflection::{
    ContainerFormat, Error, Named, Registry, Tracer, TracerConfig, VariantFormat,
};

/// A tracer for [`add`] and [`registry`].
pub(crate) fn tracer() -> Tracer {
    Tracer::new(TracerConfig::default())
}

/// Traces `T` and what it contains. An enum is explored to its last variant only when traced
/// itself (`serde-reflection` cuts exploration inside a container it has seen once), so each
/// enum of a format is added on its own; [`registry`] names any that is not.
pub(crate) fn add<T: for<'de> Deserialize<'de>>(tracer: &mut Tracer) {
    if let Err(e) = tracer.trace_simple_type::<T>() {
        panic!("tracing {}: {e}", std::any::type_name::<T>());
    }
}

/// The containers traced: structs and enums by serde name, with their fields and variants.
pub(crate) fn registry(tracer: Tracer) -> Registry {
    match tracer.registry() {
        Ok(registry) => registry,
        Err(Error::MissingVariants(names)) => panic!(
            "enums met but not explored: {}; trace each with `reference::add` in this test",
            names.join(", ")
        ),
        Err(e) => panic!("tracing: {e}"),
    }
}

/// Where a container is documented: its serde name, the page (a file of `docs/reference/`)
/// and a string the section's heading contains.
pub(crate) type Assignment = (&'static str, &'static str, &'static str);

/// Panics naming every field or variant of `registry` that its assigned section does not
/// document, every documentation row that names nothing, and every container without a section.
pub(crate) fn assert_documented(registry: &Registry, assignments: &[Assignment]) {
    let mut pages: BTreeMap<&str, Page> = BTreeMap::new();
    let mut problems = Vec::new();
    for (name, container) in registry {
        let Some(&(_, file, heading)) = assignments.iter().find(|(n, _, _)| n == name) else {
            problems.push(format!(
                "the loader reads `{name}`, which no section of docs/reference/ is assigned to: \
                 give it a section and assign it in this test"
            ));
            continue;
        };
        let page = pages.entry(file).or_insert_with(|| Page::read(file));
        match page.section(heading) {
            Ok(rows) => problems.extend(check_section(name, container, rows, file, heading)),
            Err(problem) => problems.push(problem),
        }
    }
    for (name, file, _) in assignments {
        if !registry.contains_key(*name) {
            problems.push(format!(
                "`{name}` is assigned to docs/reference/{file}, but the loader reads no such type"
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "the reference is out of step with the loader:\n- {}",
        problems.join("\n- ")
    );
}

/// The names a container accepts, each with the field names its row must list (those of a
/// variant with named fields; none otherwise).
fn accepted(container: &ContainerFormat) -> Vec<(String, Vec<String>)> {
    let names = |fields: &[Named<_>]| fields.iter().map(|f| f.name.clone()).collect::<Vec<_>>();
    match container {
        ContainerFormat::Struct(fields) => names(fields).into_iter().map(|f| (f, vec![])).collect(),
        ContainerFormat::Enum(variants) => variants
            .values()
            .map(|v| {
                let fields = match &v.value {
                    VariantFormat::Struct(fields) => names(fields),
                    _ => Vec::new(),
                };
                (v.name.clone(), fields)
            })
            .collect(),
        // Tuple and newtype structs have no names to document.
        _ => Vec::new(),
    }
}

/// The problems of one container's section.
fn check_section(
    name: &str,
    container: &ContainerFormat,
    rows: &[String],
    file: &str,
    heading: &str,
) -> Vec<String> {
    let at = format!("docs/reference/{file}, section \"{heading}\"");
    let accepted = accepted(container);
    let mut problems = Vec::new();
    for (item, fields) in &accepted {
        let Some(row) = rows.iter().find(|row| names(row, item)) else {
            problems.push(format!(
                "`{name}` accepts `{item}`, which {at} does not document (a row `| \\`{item}\\` |`)"
            ));
            continue;
        };
        for field in fields {
            if !row.contains(&format!("{field}:")) {
                problems.push(format!(
                    "`{name}::{item}` accepts the field `{field}`, which its row in {at} does \
                     not list (`{field}:` in `{row}`)"
                ));
            }
        }
    }
    for row in rows {
        if !accepted.iter().any(|(item, _)| names(row, item)) {
            problems.push(format!(
                "{at} documents `{row}`, which `{name}` does not accept"
            ));
        }
    }
    problems
}

/// True when a row's code span `row` names `item`: it is `item`, or `item` followed by `(` or
/// a space.
fn names(row: &str, item: &str) -> bool {
    row.strip_prefix(item)
        .is_some_and(|rest| rest.is_empty() || rest.starts_with('(') || rest.starts_with(' '))
}

/// A reference page: per heading, the first code span of each table row's first cell.
struct Page {
    file: String,
    sections: Vec<(String, Vec<String>)>,
}

impl Page {
    fn read(file: &str) -> Page {
        let path: PathBuf = [env!("CARGO_MANIFEST_DIR"), "docs", "reference", file]
            .iter()
            .collect();
        let text = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        Page {
            file: file.to_string(),
            sections: sections(&text),
        }
    }

    /// The rows under the one heading that contains `heading`.
    fn section(&self, heading: &str) -> Result<&[String], String> {
        let found: Vec<&(String, Vec<String>)> = (self.sections.iter())
            .filter(|(title, _)| title.contains(heading))
            .collect();
        match found.as_slice() {
            [(_, rows)] => Ok(rows),
            [] => Err(format!(
                "docs/reference/{} has no heading containing \"{heading}\"",
                self.file
            )),
            _ => Err(format!(
                "docs/reference/{} has several headings containing \"{heading}\"",
                self.file
            )),
        }
    }
}

/// Splits markdown into headings and, under each, the first code span of every table row's
/// first cell (fenced code blocks skipped).
fn sections(text: &str) -> Vec<(String, Vec<String>)> {
    let mut sections: Vec<(String, Vec<String>)> = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        let line = line.trim_start();
        if line.starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        if line.starts_with('#') {
            let title = line.trim_start_matches('#').trim().to_string();
            sections.push((title, Vec::new()));
        } else if let Some(rest) = line.strip_prefix('|') {
            let first_cell = rest.split('|').next().unwrap_or("");
            let mut spans = first_cell.split('`');
            if let (Some(_), Some(code)) = (spans.next(), spans.next()) {
                if let Some((_, rows)) = sections.last_mut() {
                    rows.push(code.to_string());
                }
            }
        }
    }
    sections
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    #[allow(dead_code)]
    enum Shape {
        Dot,
        Circle(f64),
        Box { width: f64, height: f64 },
    }

    #[derive(Deserialize)]
    #[serde(rename = "Drawing")]
    #[allow(dead_code)]
    struct DrawingFile {
        name: String,
        shapes: Vec<Shape>,
        nested: Option<Vec<Vec<Shape>>>,
    }

    fn drawing() -> Registry {
        let mut tracer = tracer();
        add::<Shape>(&mut tracer);
        add::<DrawingFile>(&mut tracer);
        registry(tracer)
    }

    /// Every variant of an enum traced on its own is in the registry, with its fields.
    #[test]
    fn enums_are_traced_to_their_last_variant() {
        let registry = drawing();
        let Some(ContainerFormat::Enum(variants)) = registry.get("Shape") else {
            panic!("no enum `Shape` in {registry:?}");
        };
        let names: Vec<&str> = variants.values().map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["Dot", "Circle", "Box"]);
        let drawing = registry.get("Drawing").map(accepted);
        assert_eq!(
            drawing,
            Some(vec![
                ("name".into(), vec![]),
                ("shapes".into(), vec![]),
                ("nested".into(), vec![])
            ])
        );
    }

    /// Rows are read from tables only, per heading, their first code span; a variant's row
    /// must list its named fields; a stale row and a missing one are both problems.
    #[test]
    fn sections_are_checked_both_ways() {
        let page = "# Drawing\n\nText with `name` is not a row.\n\n| field | meaning |\n|---|---|\n\
                    | `name` | its name |\n| `shapes` | what it holds |\n| `colour` | gone |\n\n\
                    ```\n| `nested` | in a code block |\n```\n## Shapes\n\
                    | `Dot` | a dot |\n| `Circle(radius)` | a circle |\n| `Box(width: w)` | a box |\n";
        let sections = sections(page);
        assert_eq!(sections.len(), 2);
        assert_eq!(sections[0].1, ["name", "shapes", "colour"]);
        let registry = drawing();
        let drawing = check_section("Drawing", &registry["Drawing"], &sections[0].1, "p", "D");
        assert_eq!(drawing.len(), 2, "{drawing:?}");
        assert!(drawing[0].contains("`nested`"), "{drawing:?}");
        assert!(drawing[1].contains("`colour`"), "{drawing:?}");
        let shapes = check_section("Shape", &registry["Shape"], &sections[1].1, "p", "S");
        assert_eq!(shapes.len(), 1, "{shapes:?}");
        assert!(shapes[0].contains("`height`"), "{shapes:?}");
    }

    /// An enum met inside a struct but not traced itself is named, not silently half-read.
    #[test]
    #[should_panic(expected = "enums met but not explored: Shape")]
    fn an_enum_left_out_is_named() {
        let mut tracer = tracer();
        add::<DrawingFile>(&mut tracer);
        registry(tracer);
    }
}
