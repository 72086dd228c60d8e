//! The F´ binding end to end through the C ABI (DESIGN.md §10): the committed dictionary
//! (`models/fprime/PropulsionTopologyDictionary.json`, written by F´'s `fpp-to-dict` from
//! `Propulsion.fpp`) and binding (`propulsion.binding.ron`) drive the propulsion plant's
//! scripted hardware (`scenarios/propulsion/`) by channel ids and opcodes only, and the commands
//! that reach the hardware are the ones `kairos run` issues on the same scenario, cycle for
//! cycle — nominal, and with the PDE latching up (a diagnosis and a repair).
//!
//! The translation back and forth in this test is its own — channel ids and enumeration values
//! read from the dictionary's JSON, opcodes mapped to the plant's command values by hand — so
//! that it checks the binding rather than repeating it.

use std::ffi::{CStr, CString};
use std::path::Path;

use kairos::executive::NamedValue;
use kairos::executive::adapters::{ControlAdapter, MonitorAdapter};
use kairos::logic::ValueId;
use kairos::simulation::{self, RunOptions, Scenario, ScriptedPlant};
use kairos_ffi::*;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn path(relative: &str) -> CString {
    CString::new(root().join(relative).display().to_string()).expect("no NUL in a path")
}

/// The dictionary's JSON, read with serde_json on its own.
fn dictionary() -> serde_json::Value {
    let text =
        std::fs::read_to_string(root().join("models/fprime/PropulsionTopologyDictionary.json"))
            .expect("the dictionary is committed");
    serde_json::from_str(&text).expect("it is JSON")
}

/// Which channel reports which observable (the FPP model's names).
const CHANNELS: [(&str, &str); 5] = [
    ("valve1.outlet", "Prop.prop.Valve1Outlet"),
    ("valve2.outlet", "Prop.prop.Valve2Outlet"),
    ("engine.power", "Prop.prop.EnginePower"),
    ("engine.temp", "Prop.prop.EngineTemp"),
    ("engine.thrust", "Prop.prop.EngineThrust"),
];

/// The telemetry an observation is: the channel's id and the value of the constant named like
/// the observed value (`high` → `HIGH`), both looked up in the dictionary.
fn telemetry(dictionary: &serde_json::Value, observation: &NamedValue) -> KairosTelemetry {
    let (_, channel) = (CHANNELS.iter())
        .find(|(observable, _)| *observable == observation.variable)
        .unwrap_or_else(|| panic!("no channel for {observation}"));
    let channels = dictionary["telemetryChannels"]
        .as_array()
        .expect("channels");
    let entry = (channels.iter())
        .find(|c| c["name"] == *channel)
        .expect("the channel");
    let type_name = entry["type"]["name"].as_str().expect("an enumeration type");
    let types = dictionary["typeDefinitions"].as_array().expect("types");
    let definition = (types.iter())
        .find(|t| t["qualifiedName"] == type_name)
        .expect("the type");
    let constant = observation.value.to_string().to_uppercase();
    let constants = definition["enumeratedConstants"]
        .as_array()
        .expect("constants");
    let value = (constants.iter())
        .find(|c| c["name"] == constant.as_str())
        .and_then(|c| c["value"].as_i64())
        .unwrap_or_else(|| panic!("no constant {constant} in {type_name}"));
    KairosTelemetry {
        channel: u32::try_from(entry["id"].as_u64().expect("an id")).expect("a u32 id"),
        kind: KAIROS_TLM_ENUM,
        integer: value,
        real: 0.0,
    }
}

/// The plant command an F´ command stands for, by its mnemonic and arguments.
fn plant_command(name: &str, args: &[i64]) -> String {
    let value = match (name, args) {
        ("Prop.prop.PDE_ON", []) => "on",
        ("Prop.prop.PDE_OFF", []) => "off",
        ("Prop.prop.PDE_RESET", []) => "reset",
        ("Prop.prop.VALVE_OPEN", [1]) => "open1",
        ("Prop.prop.VALVE_OPEN", [2]) => "open2",
        ("Prop.prop.VALVE_CLOSE", [1]) => "close1",
        ("Prop.prop.VALVE_CLOSE", [2]) => "close2",
        ("Prop.prop.ENGINE_STANDBY", []) => "engine-standby",
        ("Prop.prop.ENGINE_FIRE", []) => "engine-fire",
        ("Prop.prop.ENGINE_OFF", []) => "engine-off",
        other => panic!("an F´ command the plant has no value for: {other:?}"),
    };
    format!("PDE.cmd = {value}")
}

/// The commands `kairos run` issues on the scenario, with their times.
fn commands_of_kairos_run(scenario: &Scenario) -> Vec<(f64, String)> {
    let mut issued = Vec::new();
    let outcome = simulation::run(scenario, RunOptions::default(), &mut |record| {
        for &(x, v) in &record.step.command {
            issued.push((
                record.step.time,
                NamedValue::of(&scenario.plant, x, v).to_string(),
            ));
        }
    })
    .expect("the scenario runs");
    assert!(outcome.passed(), "the scenario's expectations hold");
    issued
}

/// The same cycles through the C ABI, by channel ids and opcodes.
fn commands_through_the_c_abi(scenario: &Scenario) -> Vec<(f64, String)> {
    let dictionary = dictionary();
    let mut options = kairos_options_default();
    options.kappa = u32::try_from(scenario.kappa).expect("a small κ");
    let mut handle = std::ptr::null_mut();
    let mut error = std::ptr::null_mut();
    // SAFETY: valid strings, options and out-pointers.
    let status = unsafe {
        kairos_executive_load(
            path("models/propulsion.ron").as_ptr(),
            path("programs/propulsion_fire.rmpl").as_ptr(),
            &options,
            &mut handle,
            &mut error,
        )
    };
    assert_eq!(status, KairosStatus::Ok);
    // SAFETY: a live handle and valid strings.
    let status = unsafe {
        kairos_executive_bind_fprime(
            handle,
            path("models/fprime/PropulsionTopologyDictionary.json").as_ptr(),
            path("models/fprime/propulsion.binding.ron").as_ptr(),
        )
    };
    assert_eq!(status, KairosStatus::Ok);
    let mut plant = ScriptedPlant::new(&scenario.script);
    let mut issued = Vec::new();
    let mut time = 0.0;
    while time <= scenario.end {
        let observed: Vec<KairosTelemetry> = (plant.observe(time).iter())
            .map(|o| telemetry(&dictionary, o))
            .collect();
        let mut step = std::ptr::null_mut();
        // SAFETY: a live handle, `observed.len()` values, a valid out-pointer.
        let status = unsafe {
            kairos_fprime_step(handle, time, observed.as_ptr(), observed.len(), &mut step)
        };
        assert_eq!(status, KairosStatus::Ok);
        // SAFETY: a live step.
        let summary = unsafe { kairos_step_summary(step) };
        let mut sent = Vec::new();
        for i in 0..summary.fprime_command_count {
            // SAFETY: a live step; its strings are valid until it is freed.
            let (name, args) = unsafe {
                let command = kairos_step_fprime_command(step, i);
                let name = CStr::from_ptr(command.name)
                    .to_str()
                    .expect("UTF-8")
                    .to_string();
                let args: Vec<i64> = (0..command.arg_count)
                    .map(|a| kairos_step_fprime_arg(step, i, a).integer)
                    .collect();
                (name, args)
            };
            let command = plant_command(&name, &args);
            issued.push((time, command.clone()));
            let (variable, value) = command.split_once(" = ").expect("an assignment");
            sent.push(NamedValue::new(variable, value));
        }
        plant
            .send(time, &sent)
            .expect("the hardware takes PDE commands");
        // The estimate rules of a script see ŝ: its modes by name, back to the plant's ids.
        let modes: Vec<ValueId> = (0..summary.component_count)
            .map(|c| {
                // SAFETY: a live step.
                let mode = unsafe { CStr::from_ptr(kairos_step_mode(step, c).value) };
                let component = &scenario.plant.components()[c];
                component
                    .mode_named(mode.to_str().expect("UTF-8"))
                    .expect("a mode of it")
            })
            .collect();
        plant.estimated(&modes);
        let settled = summary.flags & KAIROS_STEP_SETTLED != 0;
        // SAFETY: the step is not used after this.
        unsafe { kairos_step_free(step) };
        if settled && plant.is_quiet(scenario.end) {
            break;
        }
        time += scenario.cycle;
    }
    // SAFETY: the handle is not used after this.
    unsafe { kairos_executive_free(handle) };
    issued
}

fn check(scenario: &str) {
    let scenario = simulation::load(&root().join(scenario)).expect("the scenario loads");
    let expected = commands_of_kairos_run(&scenario);
    assert!(expected.len() >= 6, "{expected:?}");
    assert_eq!(commands_through_the_c_abi(&scenario), expected);
}

/// §6.3.3 from cold: on, engine-standby, open1, open2, engine-fire, off.
#[test]
fn the_nominal_firing_by_channel_ids_and_opcodes_is_kairos_runs() {
    check("scenarios/propulsion/nominal.ron");
}

/// §7.2.4: the PDE latches up, is diagnosed from the unanswered standby command and reset.
#[test]
fn the_pde_reset_by_channel_ids_and_opcodes_is_kairos_runs() {
    check("scenarios/propulsion/pde_resettable.ron");
}
