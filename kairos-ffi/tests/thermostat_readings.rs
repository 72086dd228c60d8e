//! Numeric telemetry through the C ABI (`plant::monitor`, DESIGN.md §13): the thermostat's sensor
//! read in °C, cycle by cycle as scenarios/thermostat/telemetry.ron's scripted plant reports it
//! (hysteresis, persistence, a glitch, an out-of-range reading, a silent sensor), goes through
//! `kairos_step` as `KAIROS_VALUE_NUMBER` observations. The C ABI issues the same commands as the
//! Rust API given the same readings, the one command the scenario expects (`switch1.cmd = close`
//! once, no diagnosis), and reports what the monitor made of the readings as events.

use std::ffi::{CStr, CString};
use std::path::Path;

use kairos::executive::{EventKind, Executive, NamedValue};
use kairos_ffi::*;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

const PLANT: &str = "models/thermostat.ron";
const PROGRAM: &str = "programs/thermostat_stay_warm.rmpl";

/// The sensor's reading at `time` in the scenario, given when switch 1 was commanded closed;
/// `None` while the sensor is silent.
fn reading(time: f64, closed_at: Option<f64>) -> Option<f64> {
    let since = |t: f64| closed_at.is_some_and(|c| time >= c + t);
    let mut x = 5.2;
    if since(66.0) {
        x = 21.4;
    }
    if since(138.0) {
        x = 29.8;
    }
    for (at, value) in [
        (150.0, 26.8),
        (152.0, 29.9),
        (170.0, 19.1),
        (171.0, 29.9),
        (200.0, 999.0),
        (202.0, 30.1),
    ] {
        if time >= at {
            x = value;
        }
    }
    if (230.0..245.0).contains(&time) {
        return None;
    }
    if time >= 245.0 {
        x = 30.3;
    }
    Some(x)
}

/// One cycle's outcome: the commands (`variable = value`) and the event kinds.
type Cycle = (Vec<String>, Vec<KairosEventKind>);

fn through_c_abi() -> Vec<Cycle> {
    let path = |p: &str| CString::new(root().join(p).display().to_string()).expect("no NUL");
    let mut handle = std::ptr::null_mut();
    // SAFETY: valid strings; NULL options and error are allowed.
    let status = unsafe {
        kairos_executive_load(
            path(PLANT).as_ptr(),
            path(PROGRAM).as_ptr(),
            std::ptr::null(),
            &mut handle,
            std::ptr::null_mut(),
        )
    };
    assert_eq!(status, KairosStatus::Ok);
    let variable = c"sensor.reading";
    let mut closed_at = None;
    let mut cycles = Vec::new();
    for second in 0..=300 {
        let now = f64::from(second);
        let observations: Vec<KairosObservation> = reading(now, closed_at)
            .map(|x| KairosObservation {
                variable: variable.as_ptr(),
                kind: KAIROS_VALUE_NUMBER,
                symbol: std::ptr::null(),
                number: x,
            })
            .into_iter()
            .collect();
        let mut step = std::ptr::null_mut();
        // SAFETY: a live handle; the observation's string is static.
        let status = unsafe {
            kairos_step(
                handle,
                now,
                observations.as_ptr(),
                observations.len(),
                &mut step,
            )
        };
        assert_eq!(status, KairosStatus::Ok, "cycle at {now} s");
        // SAFETY: a live step, read and then freed.
        let cycle = unsafe {
            let summary = kairos_step_summary(step);
            let commands: Vec<String> = (0..summary.command_count)
                .map(|i| {
                    let c = kairos_step_command(step, i);
                    format!(
                        "{} = {}",
                        CStr::from_ptr(c.variable).to_str().expect("UTF-8"),
                        CStr::from_ptr(c.value).to_str().expect("UTF-8")
                    )
                })
                .collect();
            let events = (0..summary.event_count)
                .map(|i| kairos_step_event(step, i).kind)
                .collect();
            kairos_step_free(step);
            (commands, events)
        };
        if closed_at.is_none() && cycle.0.iter().any(|c| c == "switch1.cmd = close") {
            closed_at = Some(now);
        }
        cycles.push(cycle);
    }
    // SAFETY: the handle is not used after this.
    unsafe { kairos_executive_free(handle) };
    cycles
}

fn through_rust() -> Vec<Vec<String>> {
    let mut executive = Executive::load(&root().join(PLANT), &root().join(PROGRAM))
        .expect("loads")
        .build()
        .expect("builds");
    let mut closed_at = None;
    let mut cycles = Vec::new();
    for second in 0..=300 {
        let now = f64::from(second);
        let observed: Vec<NamedValue> = reading(now, closed_at)
            .map(|x| NamedValue::new("sensor.reading", x))
            .into_iter()
            .collect();
        let step = executive.step(now, &observed).expect("a cycle");
        assert!(
            !step
                .events
                .iter()
                .any(|e| matches!(e.kind, EventKind::Diagnosis { .. })),
            "no diagnosis at {now} s"
        );
        let commands: Vec<String> = (step.commands_named(executive.plant()).iter())
            .map(|c| format!("{} = {}", c.variable, c.value))
            .collect();
        if closed_at.is_none() && commands.iter().any(|c| c == "switch1.cmd = close") {
            closed_at = Some(now);
        }
        cycles.push(commands);
    }
    cycles
}

#[test]
fn celsius_readings_through_the_c_abi_command_as_the_rust_api_does() {
    let c = through_c_abi();
    let rust = through_rust();
    let c_commands: Vec<&Vec<String>> = c.iter().map(|(commands, _)| commands).collect();
    assert_eq!(c_commands, rust.iter().collect::<Vec<_>>());
    let issued: Vec<&String> = rust.iter().flatten().collect();
    assert_eq!(
        issued,
        ["switch1.cmd = close"],
        "one command, as the scenario expects"
    );
    let has = |second: usize, kind: KairosEventKind| c[second].1.contains(&kind);
    // Persistence 3: cold is known from the third reading.
    assert!((0..=3).any(|s| has(s, KairosEventKind::Monitored)));
    // 999 °C at 200 s is outside the valid range: an odd observation, the cycle goes on.
    assert!(has(200, KairosEventKind::ObservationRejected));
    // Silent from 230 s: stale after 5 s.
    assert!((230..=236).any(|s| has(s, KairosEventKind::Stale)));
}
