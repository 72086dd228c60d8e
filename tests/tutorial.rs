//! The tutorial cannot rot (`docs/tutorial.md`, "your first system"): every `kairos` command in
//! its shell blocks runs here with the exit code the tutorial says (`# exits N` at the end of
//! the line; 0 when it says nothing) and, where a line is followed by `# prints: TEXT`, prints
//! TEXT; and every file excerpt — a fenced block whose info string names a file, as in
//! ```` ```ron models/power.ron ```` — appears in that file verbatim, piece by piece (a line
//! `// …` or `# …` in an excerpt stands for lines left out); and its flight loop,
//! `examples/power.rs`, runs as it says.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/example.rs"]
mod example;

/// A fenced block of the tutorial: its info string and its lines.
struct Block {
    info: String,
    lines: Vec<String>,
    /// Where it starts, for messages.
    line: usize,
}

fn blocks() -> Vec<Block> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/tutorial.md"))
        .expect("docs/tutorial.md");
    let mut blocks = Vec::new();
    let mut open: Option<Block> = None;
    for (n, line) in text.lines().enumerate() {
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(info)) => {
                open = Some(Block {
                    info: info.trim().to_string(),
                    lines: Vec::new(),
                    line: n + 1,
                });
            }
            (Some(_), Some(_)) => blocks.extend(open.take()),
            (Some(block), None) => block.lines.push(line.to_string()),
            (None, None) => {}
        }
    }
    assert!(
        open.is_none(),
        "docs/tutorial.md ends inside a fenced block"
    );
    blocks
}

/// `kairos run "a b" c` → `["run", "a b", "c"]` (double quotes group; nothing else is special).
fn words(command: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    let mut started = false;
    for c in command.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                started = true;
            }
            ' ' if !quoted => {
                if started {
                    words.push(std::mem::take(&mut word));
                    started = false;
                }
            }
            c => {
                word.push(c);
                started = true;
            }
        }
    }
    if started {
        words.push(word);
    }
    words
}

#[test]
fn every_command_of_the_tutorial_runs_as_it_says() {
    let mut ran = 0;
    for block in blocks().iter().filter(|b| b.info == "sh") {
        let mut lines = block.lines.iter().peekable();
        while let Some(line) = lines.next() {
            let Some(command) = line.trim().strip_prefix("kairos ") else {
                continue;
            };
            let (command, expected) = match command.split_once("# exits ") {
                Some((command, code)) => (command, code.trim().parse().expect("an exit code")),
                None => (command.split('#').next().unwrap_or(command), 0),
            };
            let args = words(command.trim());
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let (code, stdout, stderr) = cli::kairos(&args);
            assert_eq!(
                code, expected,
                "docs/tutorial.md:{}: `kairos {command}`\n{stdout}\n{stderr}",
                block.line
            );
            while let Some(print) = lines
                .peek()
                .and_then(|l| l.trim().strip_prefix("# prints: "))
            {
                assert!(
                    stdout.contains(print) || stderr.contains(print),
                    "docs/tutorial.md:{}: `kairos {command}` does not print `{print}`:\n{stdout}\n{stderr}",
                    block.line
                );
                lines.next();
            }
            ran += 1;
        }
    }
    assert!(ran >= 10, "the tutorial runs {ran} commands");
}

#[test]
fn every_excerpt_is_in_its_file() {
    let mut checked = 0;
    for block in blocks() {
        let Some((_, path)) = block.info.split_once(' ') else {
            continue;
        };
        let path = path.trim();
        let file = std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR")))
            .unwrap_or_else(|e| panic!("docs/tutorial.md:{}: {path}: {e}", block.line));
        let elided = |l: &str| matches!(l.trim(), "// …" | "# …");
        for piece in block.lines.split(|l| elided(l)) {
            let piece = piece.join("\n");
            assert!(
                piece.trim().is_empty() || file.contains(piece.trim_matches('\n')),
                "docs/tutorial.md:{}: this excerpt is not in {path}:\n{piece}",
                block.line
            );
        }
        checked += 1;
    }
    assert!(checked >= 5, "the tutorial shows {checked} excerpts");
}

#[test]
fn quoted_words_stay_together() {
    assert_eq!(
        words(r#"plan models/power.ron --goal "payload = powered""#),
        ["plan", "models/power.ron", "--goal", "payload = powered"]
    );
}

/// Section 7's flight loop, `examples/power.rs` (built by `cargo test` with the other
/// examples), runs the window to its end through regulator A's failure.
#[test]
fn the_tutorials_flight_loop_runs() {
    example::runs_and_prints(
        "power",
        &[
            "#100 DIAGNOSIS reg_a = failed",
            "#100 command reg_b.cmd = on",
            "goal achieved payload = unpowered",
            "settled at 306 s",
        ],
    );
}
