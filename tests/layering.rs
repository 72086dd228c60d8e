//! The layering of ARCHITECTURE.md "Layers" (DESIGN.md §2: "`executive` is the only module that
//! knows about all the others; nothing in `logic`/`opsat` knows about plants or programs"),
//! checked on the code: every `crate::MODULE` or `kairos::MODULE` path outside comments in
//! `src/` names a module on a lower layer than the file's own. Equal layers are refused too, so
//! no two modules can import each other. The table is read from ARCHITECTURE.md itself, so the
//! map and the test cannot disagree; every module of `src/lib.rs` must have a row.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layer of each module, from the rows between the `<!-- layers` markers.
fn layers() -> BTreeMap<String, u32> {
    let text = std::fs::read_to_string("ARCHITECTURE.md").expect("ARCHITECTURE.md");
    let start = text.find("<!-- layers").expect("a `<!-- layers` marker");
    let end = text
        .find("<!-- /layers -->")
        .expect("a `<!-- /layers -->` marker");
    let mut layers = BTreeMap::new();
    for row in text[start..end].lines().filter(|l| l.starts_with('|')) {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let Ok(layer) = cells[1].parse::<u32>() else {
            continue; // the header and the rule
        };
        for name in cells[2].split(',') {
            let name = name.trim().trim_matches('`');
            assert!(
                layers.insert(name.to_string(), layer).is_none(),
                "`{name}` has two rows"
            );
        }
    }
    layers
}

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src/ is readable") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module a file under `src/` belongs to: `src/goalnet/stn.rs` → `goalnet`,
/// `src/dot.rs` → `dot`, `src/main.rs` → `cli`.
fn module_of(path: &Path) -> Option<String> {
    let rest = path.strip_prefix("src").ok()?;
    let first = rest.components().next()?.as_os_str().to_str()?;
    let name = first.strip_suffix(".rs").unwrap_or(first);
    match name {
        "lib" => None,
        "main" => Some("cli".to_string()),
        other => Some(other.to_string()),
    }
}

/// The module names that `line` reaches by path (`crate::x`, `kairos::x`), comments aside.
fn paths_in(line: &str) -> Vec<String> {
    let code = line.split("//").next().unwrap_or("");
    let mut found = Vec::new();
    for prefix in ["crate::", "kairos::"] {
        let mut rest = code;
        while let Some(at) = rest.find(prefix) {
            let after = &rest[at + prefix.len()..];
            let name: String = after
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            found.push(name);
            rest = after;
        }
    }
    found
}

#[test]
fn every_module_has_a_layer() {
    let layers = layers();
    let lib = std::fs::read_to_string("src/lib.rs").expect("src/lib.rs");
    for line in lib.lines() {
        if let Some(name) = line
            .strip_prefix("pub mod ")
            .and_then(|l| l.strip_suffix(';'))
        {
            assert!(
                layers.contains_key(name),
                "module `{name}` has no row in ARCHITECTURE.md's layer table"
            );
        }
    }
    assert!(layers.contains_key("cli"), "the command line has a layer");
}

#[test]
fn no_module_imports_one_on_its_own_layer_or_above() {
    let layers = layers();
    let mut files = Vec::new();
    sources(Path::new("src"), &mut files);
    files.sort();
    let mut upward = Vec::new();
    for file in &files {
        let Some(module) = module_of(file) else {
            continue;
        };
        let own = layers[&module];
        let text = std::fs::read_to_string(file).expect("a source file");
        for (n, line) in text.lines().enumerate() {
            for target in paths_in(line) {
                let Some(&theirs) = layers.get(&target) else {
                    continue; // `crate::SomeItem` re-exported at the root, not a module
                };
                if target != module && theirs >= own {
                    upward.push(format!(
                        "{}:{}: {module} (layer {own}) -> {target} (layer {theirs})",
                        file.display(),
                        n + 1
                    ));
                }
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that run sideways or up a layer (ARCHITECTURE.md \"Layers\"):\n{}",
        upward.join("\n")
    );
}

#[test]
fn the_checker_sees_paths_and_skips_comments() {
    assert_eq!(
        paths_in("use crate::plant::{Plant}; // crate::report"),
        ["plant"]
    );
    assert_eq!(
        paths_in("let x = kairos::executive::Executive::load(a);"),
        ["executive"]
    );
    assert!(paths_in("/// see [`crate::exploration`]").is_empty());
    assert_eq!(
        module_of(Path::new("src/goalnet/mission/submission.rs")).as_deref(),
        Some("goalnet")
    );
    assert_eq!(module_of(Path::new("src/main.rs")).as_deref(), Some("cli"));
}
