//! Random input through the C ABI never crashes and always ends in an error code or an event
//! (DESIGN.md §13): arrays of observations with unknown names, values outside the domain,
//! numbers (NaN and infinities among them), bad kind tags, NULL and non-UTF-8 strings; arrays of
//! F´ telemetry with unknown channel ids, values of the wrong type, enumeration values that are
//! no constant, bools that are not 0 or 1; times that are NaN or do not increase; readings in °C
//! of a monitored observable (NaN, infinities, out of range among them). A number for an
//! observable without a monitor is `KAIROS_STATUS_NO_MONITOR`. The status of
//! each call is checked against an oracle written from the documented contract (the first
//! offending item decides the code), a successful step against the events it must carry, and a
//! failed call must leave the handle usable.
//!
//! Fixed seed and case count by default; `KAIROS_PROPTEST_SEED` / `KAIROS_CASES` explore.

#[path = "../../tests/support/seeded.rs"]
mod seeded;

use std::ffi::{CStr, CString, c_char};
use std::path::Path;

use kairos_ffi::*;
use proptest::prelude::*;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn path(relative: &str) -> CString {
    CString::new(root().join(relative).display().to_string()).expect("no NUL in a path")
}

fn load(plant: &str, program: &str) -> *mut KairosExecutive {
    let mut handle = std::ptr::null_mut();
    // SAFETY: valid strings; NULL options and error are allowed.
    let status = unsafe {
        kairos_executive_load(
            path(plant).as_ptr(),
            path(program).as_ptr(),
            std::ptr::null(),
            &mut handle,
            std::ptr::null_mut(),
        )
    };
    assert_eq!(status, KairosStatus::Ok);
    handle
}

/// The driver/valve plant's observables and their values.
const OBSERVABLES: [(&str, &[&str]); 2] = [
    ("valve.flow_in", &["zero", "nominal"]),
    ("valve.flow_out", &["zero", "nominal"]),
];

/// One observation as C might hand it in.
#[derive(Debug, Clone)]
enum Item {
    Known(usize, usize),
    UnknownName(String),
    WrongValue(usize, String),
    Number(usize, f64),
    NullVariable,
    NullSymbol(usize),
    NotUtf8Variable,
    BadKind(usize, u32),
}

fn item() -> impl Strategy<Value = Item> {
    let number = prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        any::<f64>(),
    ];
    prop_oneof![
        4 => (0..2usize, 0..2usize).prop_map(|(v, x)| Item::Known(v, x)),
        1 => "[a-z._]{0,12}".prop_filter("not an observable", |s| OBSERVABLES.iter().all(|(o, _)| o != s)).prop_map(Item::UnknownName),
        1 => (0..2usize, "[a-z-]{0,8}").prop_filter("not a value", |(_, s)| s != "zero" && s != "nominal").prop_map(|(v, s)| Item::WrongValue(v, s)),
        1 => (0..2usize, number).prop_map(|(v, x)| Item::Number(v, x)),
        1 => Just(Item::NullVariable),
        1 => (0..2usize).prop_map(Item::NullSymbol),
        1 => Just(Item::NotUtf8Variable),
        1 => (0..2usize, 2..u32::MAX).prop_map(|(v, k)| Item::BadKind(v, k)),
    ]
}

/// The strings an array of items points into, kept alive for the call.
struct Strings(Vec<CString>);

impl Strings {
    fn keep(&mut self, text: &[u8]) -> *const c_char {
        self.0.push(CString::new(text).expect("no NUL"));
        self.0.last().expect("just pushed").as_ptr()
    }
}

fn observation(strings: &mut Strings, item: &Item) -> KairosObservation {
    let symbol = |variable, symbol| KairosObservation {
        variable,
        kind: KAIROS_VALUE_SYMBOL,
        symbol,
        number: 0.0,
    };
    match item {
        Item::Known(v, x) => symbol(
            strings.keep(OBSERVABLES[*v].0.as_bytes()),
            strings.keep(OBSERVABLES[*v].1[*x].as_bytes()),
        ),
        Item::UnknownName(name) => symbol(strings.keep(name.as_bytes()), strings.keep(b"zero")),
        Item::WrongValue(v, value) => symbol(
            strings.keep(OBSERVABLES[*v].0.as_bytes()),
            strings.keep(value.as_bytes()),
        ),
        Item::Number(v, x) => KairosObservation {
            variable: strings.keep(OBSERVABLES[*v].0.as_bytes()),
            kind: KAIROS_VALUE_NUMBER,
            symbol: std::ptr::null(),
            number: *x,
        },
        Item::NullVariable => symbol(std::ptr::null(), strings.keep(b"zero")),
        Item::NullSymbol(v) => symbol(strings.keep(OBSERVABLES[*v].0.as_bytes()), std::ptr::null()),
        Item::NotUtf8Variable => symbol(strings.keep(b"valve.\xff\xfe"), strings.keep(b"zero")),
        Item::BadKind(v, kind) => KairosObservation {
            variable: strings.keep(OBSERVABLES[*v].0.as_bytes()),
            kind: *kind,
            symbol: strings.keep(b"zero"),
            number: 0.0,
        },
    }
}

/// The status the contract gives an array: the first item that is not a symbolic observation
/// with a UTF-8 name decides it.
fn expected_status(items: &[Item]) -> KairosStatus {
    for item in items {
        match item {
            Item::NullVariable | Item::NullSymbol(_) => return KairosStatus::NullArgument,
            Item::NotUtf8Variable => return KairosStatus::InvalidUtf8,
            Item::BadKind(..) => return KairosStatus::InvalidArgument,
            Item::Number(..) => return KairosStatus::NoMonitor,
            Item::Known(..) | Item::UnknownName(_) | Item::WrongValue(..) => {}
        }
    }
    KairosStatus::Ok
}

/// How a cycle's time relates to the previous one's.
#[derive(Debug, Clone, Copy)]
enum Time {
    Later,
    Same,
    NaN,
}

fn time() -> impl Strategy<Value = Time> {
    prop_oneof![6 => Just(Time::Later), 1 => Just(Time::Same), 1 => Just(Time::NaN)]
}

/// The events of a step: kinds and lines (every line must be UTF-8 text).
///
/// # Safety
/// `step` is a live step.
unsafe fn events(step: *const KairosStep) -> Vec<(KairosEventKind, String)> {
    // SAFETY: a live step (the contract).
    let summary = unsafe { kairos_step_summary(step) };
    (0..summary.event_count)
        .map(|i| {
            // SAFETY: a live step; the line is valid until it is freed.
            let event = unsafe { kairos_step_event(step, i) };
            assert!(!event.line.is_null());
            // SAFETY: a NUL-terminated string owned by the step.
            let line = unsafe { CStr::from_ptr(event.line) }
                .to_str()
                .expect("UTF-8")
                .to_string();
            (event.kind, line)
        })
        .collect()
}

/// Checks one call's outcome against the oracle; returns whether the cycle ran.
fn check_step(
    status: KairosStatus,
    expected: KairosStatus,
    step: *mut KairosStep,
    rejected: usize,
) -> Result<bool, TestCaseError> {
    prop_assert_eq!(status, expected);
    if status != KairosStatus::Ok {
        prop_assert!(step.is_null(), "no step on an error");
        return Ok(false);
    }
    prop_assert!(!step.is_null());
    // SAFETY: a live step, freed below and not used after.
    let (summary, events) = unsafe { (kairos_step_summary(step), events(step)) };
    let events_rejected = events
        .iter()
        .filter(|(k, _)| *k == KairosEventKind::ObservationRejected)
        .count();
    prop_assert!(
        events_rejected >= rejected,
        "each bad name or value is an event: {:?}",
        events
    );
    prop_assert_eq!(
        summary.flags & KAIROS_STEP_OBSERVATIONS_REJECTED != 0,
        events_rejected > 0
    );
    // SAFETY: the step is not used after this.
    unsafe { kairos_step_free(step) };
    Ok(true)
}

proptest! {
    #![proptest_config(seeded::config(64))]

    /// Observations by name.
    #[test]
    fn random_observations_end_in_an_error_code_or_an_event(
        cycles in prop::collection::vec((time(), prop::collection::vec(item(), 0..6)), 1..8),
    ) {
        let handle = load("models/driver_valve.ron", "programs/valve_open.rmpl");
        let mut last: Option<f64> = None;
        let mut next = 0.0;
        for (time, items) in &cycles {
            let now = match time {
                Time::Later => next,
                Time::Same => last.unwrap_or(next),
                Time::NaN => f64::NAN,
            };
            let mut strings = Strings(Vec::new());
            let observations: Vec<KairosObservation> = items.iter().map(|i| observation(&mut strings, i)).collect();
            let mut expected = expected_status(items);
            if expected == KairosStatus::Ok && (now.is_nan() || last.is_some_and(|l| now <= l)) {
                expected = KairosStatus::Time;
            }
            let rejected = items.iter().filter(|i| matches!(i, Item::UnknownName(_) | Item::WrongValue(..))).count();
            let mut step = std::ptr::null_mut();
            // SAFETY: a live handle; the observations' strings live in `strings`.
            let status = unsafe { kairos_step(handle, now, observations.as_ptr(), observations.len(), &mut step) };
            if check_step(status, expected, step, rejected)? {
                last = Some(now);
                next = now + 0.1;
            } else {
                // SAFETY: a live handle.
                let message = unsafe { CStr::from_ptr(kairos_executive_last_error(handle)) };
                prop_assert!(!message.to_bytes().is_empty(), "an error has a message");
            }
        }
        // A NULL array is empty only with a count of 0.
        let mut step = std::ptr::null_mut();
        // SAFETY: a live handle; NULL with a count is refused before it is read.
        let status = unsafe { kairos_step(handle, next + 1.0, std::ptr::null(), 3, &mut step) };
        prop_assert_eq!(status, KairosStatus::NullArgument);
        // SAFETY: as above; NULL with 0 is an empty report, and the handle still works.
        let status = unsafe { kairos_step(handle, next + 1.0, std::ptr::null(), 0, &mut step) };
        prop_assert_eq!(status, KairosStatus::Ok);
        // SAFETY: the step and the handle are not used after this.
        unsafe {
            kairos_step_free(step);
            kairos_executive_free(handle);
        }
    }
}

/// The thermostat's sensor monitor's valid range (models/thermostat.ron, °C).
const SENSOR_RANGE: std::ops::RangeInclusive<f64> = -50.0..=150.0;

fn reading() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -60.0..160.0f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => any::<f64>(),
    ]
}

proptest! {
    #![proptest_config(seeded::config(64))]

    /// Numbers for a monitored observable (the thermostat's sensor in °C) are readings: the
    /// cycle runs, and each reading that is not a number or is outside the monitor's valid range
    /// is an `ObservationRejected` event, as in the Rust API (`plant::monitor`).
    #[test]
    fn random_readings_of_a_monitored_observable_run_or_are_events(
        cycles in prop::collection::vec(prop::collection::vec(reading(), 0..5), 1..8),
    ) {
        let handle = load("models/thermostat.ron", "programs/thermostat_stay_warm.rmpl");
        let mut now = 0.0;
        for readings in &cycles {
            let observations: Vec<KairosObservation> = readings
                .iter()
                .map(|&x| KairosObservation {
                    variable: c"sensor.reading".as_ptr(),
                    kind: KAIROS_VALUE_NUMBER,
                    symbol: std::ptr::null(),
                    number: x,
                })
                .collect();
            let rejected = readings.iter().filter(|x| !SENSOR_RANGE.contains(*x)).count();
            let mut step = std::ptr::null_mut();
            // SAFETY: a live handle; the observations' strings are static.
            let status = unsafe { kairos_step(handle, now, observations.as_ptr(), observations.len(), &mut step) };
            prop_assert!(check_step(status, KairosStatus::Ok, step, rejected)?);
            now += 1.0;
        }
        // SAFETY: the handle is not used after this.
        unsafe { kairos_executive_free(handle) };
    }
}

/// The channels of the committed dictionary: five enumerations with two constants (0 and 1),
/// then one F32.
const ENUM_CHANNELS: std::ops::Range<u32> = 0x120..0x125;
const FLOAT_CHANNEL: u32 = 0x125;

fn telemetry() -> impl Strategy<Value = KairosTelemetry> {
    let channel = prop_oneof![4 => 0x120..0x126u32, 1 => any::<u32>()];
    let integer = prop_oneof![4 => -1..3i64, 1 => any::<i64>()];
    let real = prop_oneof![Just(f64::NAN), Just(f64::INFINITY), any::<f64>()];
    (
        channel,
        prop_oneof![6 => 0..4u32, 1 => 4..u32::MAX],
        integer,
        real,
    )
        .prop_map(|(channel, kind, integer, real)| KairosTelemetry {
            channel,
            kind,
            integer,
            real,
        })
}

/// The status the contract gives a telemetry array, and how many values become rejected
/// observations (enumeration values that are no constant).
fn expected_telemetry(items: &[KairosTelemetry]) -> (KairosStatus, usize) {
    let mut rejected = 0;
    for item in items {
        if item.kind > KAIROS_TLM_FLOAT
            || (item.kind == KAIROS_TLM_BOOL && !(0..=1).contains(&item.integer))
        {
            return (KairosStatus::InvalidArgument, 0);
        }
        let enumeration = ENUM_CHANNELS.contains(&item.channel);
        if !enumeration && item.channel != FLOAT_CHANNEL {
            return (KairosStatus::UnknownChannel, 0);
        }
        let fits = if enumeration {
            item.kind == KAIROS_TLM_ENUM
        } else {
            item.kind == KAIROS_TLM_FLOAT || item.kind == KAIROS_TLM_INTEGER
        };
        if !fits {
            return (KairosStatus::WrongType, 0);
        }
        if enumeration && !(0..=1).contains(&item.integer) {
            rejected += 1;
        }
    }
    (KairosStatus::Ok, rejected)
}

proptest! {
    #![proptest_config(seeded::config(64))]

    /// Telemetry by channel id through the committed F´ binding.
    #[test]
    fn random_telemetry_ends_in_an_error_code_or_an_event(
        cycles in prop::collection::vec(prop::collection::vec(telemetry(), 0..8), 1..6),
    ) {
        let handle = load("models/propulsion.ron", "programs/propulsion_fire.rmpl");
        // SAFETY: a live handle and valid strings.
        let status = unsafe {
            kairos_executive_bind_fprime(
                handle,
                path("models/fprime/PropulsionTopologyDictionary.json").as_ptr(),
                path("models/fprime/propulsion.binding.ron").as_ptr(),
            )
        };
        prop_assert_eq!(status, KairosStatus::Ok);
        let mut now = 0.0;
        for items in &cycles {
            let (expected, rejected) = expected_telemetry(items);
            let mut step = std::ptr::null_mut();
            // SAFETY: a live handle, `items.len()` values.
            let status = unsafe { kairos_fprime_step(handle, now, items.as_ptr(), items.len(), &mut step) };
            if check_step(status, expected, step, rejected)? {
                now += 1.0;
            }
        }
        // SAFETY: the handle is not used after this.
        unsafe { kairos_executive_free(handle) };
    }
}

/// Every call on a NULL handle is `KAIROS_STATUS_NULL_ARGUMENT`, every accessor on a NULL step an
/// empty answer, and every free function takes NULL.
#[test]
fn null_handles_and_steps_are_refused_or_empty() {
    let mut step = std::ptr::null_mut();
    // SAFETY: NULL handles and steps are part of the contract; the rest is valid.
    unsafe {
        assert_eq!(
            kairos_step(std::ptr::null_mut(), 0.0, std::ptr::null(), 0, &mut step),
            KairosStatus::NullArgument
        );
        assert_eq!(
            kairos_fprime_step(std::ptr::null_mut(), 0.0, std::ptr::null(), 0, &mut step),
            KairosStatus::NullArgument
        );
        assert_eq!(
            kairos_step(
                std::ptr::null_mut(),
                0.0,
                std::ptr::null(),
                0,
                std::ptr::null_mut()
            ),
            KairosStatus::NullArgument
        );
        assert_eq!(
            kairos_submit(std::ptr::null_mut(), c"Network()".as_ptr()),
            KairosStatus::NullArgument
        );
        assert!(kairos_executive_last_error(std::ptr::null()).is_null());
        assert_eq!(
            kairos_step_summary(std::ptr::null()),
            KairosStepSummary::default()
        );
        assert!(kairos_step_command(std::ptr::null(), 0).variable.is_null());
        assert!(kairos_step_mode(std::ptr::null(), 0).value.is_null());
        assert!(kairos_step_estimate_probability(std::ptr::null(), 0).is_nan());
        assert_eq!(
            kairos_step_event(std::ptr::null(), 0).kind,
            KairosEventKind::None
        );
        assert!(
            kairos_step_fprime_command(std::ptr::null(), 0)
                .name
                .is_null()
        );
        assert_eq!(
            kairos_step_fprime_arg(std::ptr::null(), 0, 0).kind,
            KairosArgKind::None
        );
        kairos_step_free(std::ptr::null_mut());
        kairos_executive_free(std::ptr::null_mut());
        kairos_string_free(std::ptr::null_mut());
        let mut handle = std::ptr::null_mut();
        let mut error = std::ptr::null_mut();
        let status = kairos_executive_load(
            std::ptr::null(),
            c"x".as_ptr(),
            std::ptr::null(),
            &mut handle,
            &mut error,
        );
        assert_eq!(status, KairosStatus::NullArgument);
        assert!(handle.is_null());
        assert_eq!(CStr::from_ptr(error).to_str(), Ok("plant_path is NULL"));
        kairos_string_free(error);
    }
}
