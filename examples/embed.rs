//! Embedding kairos in your own flight loop (DESIGN.md §10): load a plant model
//! and a program in one call, then each cycle hand the executive what the sensors read, by name,
//! and send what it commands, by name. The "hardware" here is the driver and valve of thesis
//! §6.1 (`models/driver_valve.ron`) simulated in a few lines: the driver relays commands once it
//! is on, the valve passes the flow when open.
//!
//! Run it with `cargo run --example embed`.

use std::path::Path;

use kairos::executive::{Executive, NamedValue};

/// The device as its own firmware would see it.
#[derive(Default)]
struct DriverAndValve {
    driver_on: bool,
    valve_open: bool,
}

impl DriverAndValve {
    /// Applies one command sent to the driver.
    fn command(&mut self, command: &NamedValue) {
        match command.value.symbol().unwrap_or_default() {
            "on" => self.driver_on = true,
            "off" => self.driver_on = false,
            "open" if self.driver_on => self.valve_open = true,
            "close" if self.driver_on => self.valve_open = false,
            _ => {}
        }
    }

    /// What the flow sensors read.
    fn sensors(&self) -> Vec<NamedValue> {
        let flow_out = if self.valve_open { "nominal" } else { "zero" };
        vec![
            NamedValue::new("valve.flow_in", "nominal"),
            NamedValue::new("valve.flow_out", flow_out),
        ]
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut executive = Executive::load(
        &root.join("models/driver_valve.ron"),
        &root.join("programs/valve_open.rmpl"),
    )?
    .kappa(10)
    .build()?;
    let mut device = DriverAndValve::default();
    let mut believed = Vec::new();
    for cycle in 0..50 {
        let now = f64::from(cycle) * 0.1;
        let step = executive.step(now, &device.sensors())?;
        let plant = executive.plant();
        let modes = step.modes_named(plant);
        let p = step
            .top_estimates(plant, 1)
            .first()
            .map_or(0.0, |e| e.probability);
        for mode in modes.iter().filter(|m| !believed.contains(*m)) {
            println!("{now:5.1} s  believed {mode} (the most likely state: p {p:.2})");
        }
        believed = modes;
        // Events (goals asserted and achieved, diagnoses, …) worded as the mission log words
        // them, with the plant's and the program's names.
        for event in &step.events {
            println!("{now:5.1} s  event {}", event.named(&executive));
        }
        for command in step.commands_named(plant) {
            println!("{now:5.1} s  send {command}");
            device.command(&command);
        }
        if step.is_settled() {
            println!("{now:5.1} s  settled");
            return Ok(());
        }
    }
    Err("the valve did not open in 5 s".into())
}
