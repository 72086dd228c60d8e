//! Shards: one campaign or one search split between processes (the tasks of a Slurm job array,
//! `scripts/slurm/`), each writing its part into a directory of its own, and joined by
//! `kairos campaign merge` / `kairos explore merge`.
//!
//! Each shard's directory holds a manifest, [`MANIFEST`], saying what it is part of: the
//! subcommand, the kairos version, the scenario (name, path, and a digest of its file's bytes),
//! the options every shard must share (a campaign's seed, runs, forced faults and noise; a
//! search's faults, depth and budget) and which shard it is. A merge refuses shards whose
//! manifests differ in anything but the shard index — naming the first field that differs and
//! the two directories — and shards that are missing or given twice: a merge of shards of two
//! campaigns would be a table of nothing. The digest covers the scenario file itself, not the
//! files it includes; two shards that load different plant models under one scenario file are
//! not told apart.

use std::collections::BTreeMap;
use std::hash::Hasher;
use std::path::{Path, PathBuf};

use rustc_hash::FxHasher;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::Failure;

/// The manifest's file name in a shard's directory.
pub const MANIFEST: &str = "shard.json";

/// What a shard is part of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// `campaign` or `explore`.
    pub kind: String,
    /// The kairos version that ran it (records of two versions need not agree).
    pub kairos: String,
    /// The scenario's name.
    pub scenario: String,
    /// The scenario file, as an absolute path where it could be made one.
    pub path: PathBuf,
    /// FxHash (rustc-hash) of the scenario file's bytes, hexadecimal.
    pub digest: String,
    /// The options every shard shares, by name.
    pub options: BTreeMap<String, Value>,
    /// This shard's index.
    pub shard: u64,
    /// The number of shards.
    pub shards: u64,
}

impl Manifest {
    /// The manifest of shard `shard` of `shards` of a `kind` run of the scenario at `path`.
    pub fn new(
        kind: &str,
        path: &Path,
        scenario: &str,
        options: BTreeMap<String, Value>,
        (shard, shards): (u64, u64),
    ) -> Result<Manifest, Failure> {
        let bytes = std::fs::read(path)
            .map_err(|e| Failure::io(format!("error: cannot read {}: {e}", path.display())))?;
        let mut hasher = FxHasher::default();
        hasher.write(&bytes);
        Ok(Manifest {
            kind: kind.to_string(),
            kairos: env!("CARGO_PKG_VERSION").to_string(),
            scenario: scenario.to_string(),
            path: std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
            digest: format!("{:016x}", hasher.finish()),
            options,
            shard,
            shards,
        })
    }

    /// Writes the manifest into the shard's directory.
    pub fn write(&self, dir: &Path) -> Result<(), Failure> {
        let path = dir.join(MANIFEST);
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| Failure::failed(format!("error: cannot encode the manifest: {e}")))?;
        std::fs::write(&path, text + "\n")
            .map_err(|e| Failure::io(format!("error: cannot write {}: {e}", path.display())))
    }

    /// The first field other than the shard index in which `self` and `other` differ, with
    /// both values.
    fn difference(&self, other: &Manifest) -> Option<(String, String, String)> {
        let show = |v: &dyn std::fmt::Debug| format!("{v:?}");
        let fields = [
            ("kind", show(&self.kind), show(&other.kind)),
            ("kairos version", show(&self.kairos), show(&other.kairos)),
            ("scenario", show(&self.scenario), show(&other.scenario)),
            (
                "scenario file's digest",
                show(&self.digest),
                show(&other.digest),
            ),
            ("number of shards", show(&self.shards), show(&other.shards)),
        ];
        if let Some((name, a, b)) = fields.into_iter().find(|(_, a, b)| a != b) {
            return Some((name.to_string(), a, b));
        }
        let names: std::collections::BTreeSet<&String> =
            self.options.keys().chain(other.options.keys()).collect();
        names.into_iter().find_map(|name| {
            let (a, b) = (self.options.get(name), other.options.get(name));
            let json = |v: Option<&Value>| v.map_or_else(|| "none".to_string(), Value::to_string);
            (a != b).then(|| (format!("--{name}"), json(a), json(b)))
        })
    }
}

/// Reads the manifests of `dirs` (in order) and checks that they are the shards `0/n` to
/// `n−1/n` of one `kind` run, each once.
pub fn read_all(kind: &str, dirs: &[PathBuf]) -> Result<Vec<Manifest>, Failure> {
    let mut manifests: Vec<Manifest> = Vec::new();
    for dir in dirs {
        let path = dir.join(MANIFEST);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            Failure::bad_input(format!(
                "error: cannot read {}: {e}\n  expected: the directory a `kairos {kind} --out` \
                 wrote (it holds {MANIFEST}, which says what the shard is part of)",
                path.display()
            ))
        })?;
        let manifest: Manifest = serde_json::from_str(&text).map_err(|e| {
            Failure::bad_input(format!(
                "error: {}:{}:{}: not a shard manifest: {e}",
                path.display(),
                e.line(),
                e.column()
            ))
        })?;
        if manifest.kind != kind {
            return Err(Failure::bad_input(format!(
                "error: {} is a shard of `kairos {}`, not of `kairos {kind}`",
                dir.display(),
                manifest.kind
            )));
        }
        if let Some((first, (field, a, b))) = (manifests.iter().zip(dirs))
            .find_map(|(other, d)| other.difference(&manifest).map(|diff| (d, diff)))
        {
            return Err(Failure::bad_input(format!(
                "error: {} and {} are shards of different runs: their {field} differ ({a} and \
                 {b})",
                first.display(),
                dir.display()
            )));
        }
        if let Some(twice) = (manifests.iter().zip(dirs)).find(|(m, _)| m.shard == manifest.shard) {
            return Err(Failure::bad_input(format!(
                "error: shard {}/{} is given twice: {} and {}",
                manifest.shard,
                manifest.shards,
                twice.1.display(),
                dir.display()
            )));
        }
        manifests.push(manifest);
    }
    let Some(first) = manifests.first() else {
        return Err(Failure::bad_input("error: no shard to merge"));
    };
    if let Some(odd) = manifests.iter().find(|m| m.shard >= m.shards) {
        return Err(Failure::bad_input(format!(
            "error: a manifest names shard {}/{}, which does not exist",
            odd.shard, odd.shards
        )));
    }
    let given: std::collections::BTreeSet<u64> = manifests.iter().map(|m| m.shard).collect();
    // Distinct indices below the count: at most 10 missing ones are looked for, among at most
    // as many present ones as were given.
    let missing: Vec<String> = (0..first.shards)
        .filter(|i| !given.contains(i))
        .take(10)
        .map(|i| format!("{i}/{}", first.shards))
        .collect();
    if !missing.is_empty() {
        return Err(Failure::bad_input(format!(
            "error: shard{} {} missing: {} of {} given",
            if missing.len() == 1 { "" } else { "s" },
            missing.join(", "),
            manifests.len(),
            first.shards
        )));
    }
    Ok(manifests)
}
