//! The interactive run report end to end in a real browser: `kairos run
//! --report` on the Mars EDL's primary pyro misfire (thesis §7.2.5), opened in headless
//! Chromium at the first diagnosis by the same key the reader presses (`f`, played from the URL
//! fragment `#keys=f`), and the panel read back from the DOM: the diagnosed component and mode
//! with its probability, the schematic and the marginals agreeing. A screenshot goes to the
//! test's output directory for a person to look at.
//!
//! Chromium is Debian's `chromium` (`.ci/run` installs it). The README's test command must pass
//! on a fresh machine with only Rust installed, so without Chromium the test prints a notice
//! saying how to install it and passes — unless the environment variable `CI` is set, where a
//! missing browser is a broken CI machine and the test fails loudly.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Debian's Chromium, or the reason the test cannot run.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join("chromium"))
        .find(|candidate| candidate.is_file())
}

/// Runs headless Chromium on `url` with `extra` arguments (a fresh profile, nothing fetched
/// from the network); its standard output.
fn browse(chromium: &Path, profile: &Path, url: &str, extra: &[&str]) -> String {
    let output = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--window-size=1500,1400",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .output()
        .expect("chromium starts");
    assert!(
        output.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// The inner HTML of the element with `id` in a dumped DOM (the page's panels hold no nested
/// element of the same tag).
fn element<'a>(dom: &'a str, tag: &str, id: &str) -> &'a str {
    let open = format!("id=\"{id}\"");
    let start = dom
        .find(&open)
        .unwrap_or_else(|| panic!("no #{id} in the page"));
    let end = dom[start..]
        .find(&format!("</{tag}>"))
        .map_or(dom.len(), |e| start + e);
    &dom[start..end]
}

/// The run report (docs/report.md): open it, step to the diagnosis, read what the panel shows.
#[test]
fn the_report_steps_to_the_diagnosis_in_a_headless_browser() {
    let Some(chromium) = chromium() else {
        let install = "this test needs Debian's chromium: `apt-get install -y chromium` \
                       (.ci/run installs it)";
        assert!(std::env::var_os("CI").is_none(), "CI is set and {install}");
        eprintln!("SKIPPED the browser test: {install}");
        return;
    };
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report_html_browser");
    let profile = out.join("profile");
    // A fresh profile every run: nothing carried over from the last one.
    let _ = std::fs::remove_dir_all(&profile);
    std::fs::create_dir_all(&profile).expect("the output directory");
    let report = out.join("lander_pyro_misfire.html");
    let scenario =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/mars_edl/lander_pyro_misfire.ron");
    let run = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .arg("run")
        .arg(&scenario)
        .arg("--report")
        .arg(&report)
        .arg("--quiet")
        .output()
        .expect("kairos runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let page = std::fs::read_to_string(&report).expect("the report is written");
    for remote in [
        "<link",
        "src=\"http",
        "href=\"http",
        "fetch(",
        "XMLHttpRequest",
    ] {
        assert!(
            !page.contains(remote),
            "the page loads nothing: found {remote}"
        );
    }

    let url = format!("file://{}#keys=f", report.display());
    let dom = browse(&chromium, &profile, &url, &["--dump-dom"]);

    let events = element(&dom, "ul", "r-events");
    assert!(
        events.contains("Diagnosis: lander = unsuccessful-attempt (p 1.00)"),
        "the events panel shows the diagnosis: {events}"
    );
    let cycle = element(&dom, "h2", "r-cycle");
    assert!(
        cycle.contains("t = 4:35:00"),
        "at the diagnosis's cycle: {cycle}"
    );
    let marginal = element(&dom, "tr", "marginal-lander");
    assert!(
        marginal.contains("unsuccessful-attempt") && marginal.contains("1.000"),
        "the lander's marginal: {marginal}"
    );
    let at = dom
        .find("data-node=\"lander\"")
        .expect("the schematic has the lander");
    let tag_start = dom[..at].rfind("<g").expect("the box's tag");
    let tag = &dom[tag_start..at + dom[at..].find('>').expect("a closed tag")];
    assert!(
        tag.contains("fault"),
        "the schematic marks the lander faulty: {tag}"
    );
    let id = &tag[tag.find("id=\"schematic-node-").expect("the box's id") + 4..];
    let id = &id[..id.find('"').expect("a closed id")];
    let mode = element(&dom, "text", &id.replace("node", "mode"));
    assert!(
        mode.contains("unsuccessful-attempt"),
        "the lander's box: {mode}"
    );

    let shot = out.join("report_at_diagnosis.png");
    browse(
        &chromium,
        &profile,
        &url,
        &[&format!("--screenshot={}", shot.display())],
    );
    assert!(shot.is_file(), "the screenshot is written");
    println!("screenshot: {}", shot.display());
}
