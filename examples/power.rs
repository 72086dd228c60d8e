//! The power subsystem of the tutorial (`docs/tutorial.md`) in your own loop: load
//! `models/power.ron` and `programs/power.rmpl` in one call, then each second hand the executive
//! what the bus and payload sensors read and apply what it commands. The "hardware" is a few lines
//! of Rust: two regulators feeding a bus, a load switch, a payload one cycle behind its supply —
//! and regulator A fails 100 s in. The executive diagnoses it from the voltage alone and switches
//! regulator B on; every event is printed worded with the plant's and the program's names.
//!
//! Run it with `cargo run --example power`.

use std::path::Path;

use kairos::executive::{Executive, NamedValue};

/// The subsystem as its own hardware would behave.
#[derive(Default)]
struct PowerSubsystem {
    reg_a_on: bool,
    reg_b_on: bool,
    reg_a_failed: bool,
    switch_closed: bool,
    /// Whether the payload's supply was up at the last tick: the payload follows it a second
    /// later (the model's payload is one cycle behind its supply).
    supplied: bool,
    payload_powered: bool,
}

impl PowerSubsystem {
    fn bus_up(&self) -> bool {
        (self.reg_a_on && !self.reg_a_failed) || self.reg_b_on
    }

    /// Applies one command.
    fn command(&mut self, command: &NamedValue) {
        let on = command.value == "on";
        match command.variable.as_str() {
            "reg_a.cmd" => self.reg_a_on = on,
            "reg_b.cmd" => self.reg_b_on = on,
            "load_switch.cmd" => self.switch_closed = command.value == "close",
            _ => {}
        }
    }

    /// One second passes, to `now`: regulator A fails at 100 s, and the payload follows what
    /// its supply was a second ago.
    fn tick(&mut self, now: f64) {
        if now >= 100.0 {
            self.reg_a_failed = true;
        }
        self.payload_powered = self.supplied;
        self.supplied = self.switch_closed && self.bus_up();
    }

    /// What the sensors read.
    fn sensors(&self) -> Vec<NamedValue> {
        let level = |up: bool| if up { "nominal" } else { "none" };
        vec![
            NamedValue::new("bus.voltage", level(self.bus_up())),
            NamedValue::new("payload.current", level(self.payload_powered)),
        ]
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut executive = Executive::load(
        &root.join("models/power.ron"),
        &root.join("programs/power.rmpl"),
    )?
    .build()?;
    let mut hardware = PowerSubsystem::default();
    for second in 0..340 {
        let now = f64::from(second);
        let step = executive.step(now, &hardware.sensors())?;
        for event in &step.events {
            println!("{}", event.named(&executive));
        }
        for command in step.commands_named(executive.plant()) {
            hardware.command(&command);
        }
        if step.is_settled() {
            println!("settled at {now} s");
            return Ok(());
        }
        hardware.tick(now + 1.0);
    }
    Err("the payload window did not complete in 340 s".into())
}
