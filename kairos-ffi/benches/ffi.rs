//! What the C ABI costs per cycle over the Rust call (DESIGN.md §14): the same quiet cycle of
//! the driver/valve executive (`models/driver_valve.ron`, `programs/valve_open.rmpl`, the valve
//! reported open from the start, so the program completes at once and every measured cycle is
//! the steady state of a flight loop) through `Executive::step` with `NamedValue`s, through
//! `kairos_step` with C strings (checking them, building the step with its event lines, freeing
//! it), and the propulsion executive's quiet cycle (everything off, the program content with
//! it) through `Executive::step` and through `kairos_fprime_step` by channel ids (the binding's
//! translation included). Run:
//! `cargo bench -p kairos-ffi --bench ffi`; numbers in BENCHMARKS.md.

use std::ffi::CString;
use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use kairos::executive::{Executive, NamedValue};
use kairos_ffi::*;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn path(relative: &str) -> CString {
    CString::new(root().join(relative).display().to_string()).expect("no NUL in a path")
}

/// Cycles run before measuring, so that estimation's caches are warm.
const WARM_UP: u32 = 20;

fn driver_valve(c: &mut Criterion) {
    let mut group = c.benchmark_group("driver_valve quiet cycle");
    let observed = [
        NamedValue::new("valve.flow_in", "nominal"),
        NamedValue::new("valve.flow_out", "nominal"),
    ];
    let mut executive = Executive::load(
        &root().join("models/driver_valve.ron"),
        &root().join("programs/valve_open.rmpl"),
    )
    .expect("loads")
    .build()
    .expect("builds");
    let mut now = 0.0;
    for _ in 0..WARM_UP {
        executive.step(now, &observed).expect("a cycle");
        now += 0.1;
    }
    group.bench_function("Executive::step", |b| {
        b.iter(|| {
            now += 0.1;
            black_box(executive.step(now, &observed).expect("a cycle"));
        })
    });

    let names: Vec<(CString, CString)> = (observed.iter())
        .map(|o| {
            (
                CString::new(o.variable.as_str()).expect("a name"),
                CString::new(o.value.to_string()).expect("a value"),
            )
        })
        .collect();
    let observations: Vec<KairosObservation> = (names.iter())
        .map(|(variable, value)| KairosObservation {
            variable: variable.as_ptr(),
            kind: KAIROS_VALUE_SYMBOL,
            symbol: value.as_ptr(),
            number: 0.0,
        })
        .collect();
    let mut handle = std::ptr::null_mut();
    // SAFETY: valid strings and out-pointers.
    let status = unsafe {
        kairos_executive_load(
            path("models/driver_valve.ron").as_ptr(),
            path("programs/valve_open.rmpl").as_ptr(),
            std::ptr::null(),
            &mut handle,
            std::ptr::null_mut(),
        )
    };
    assert_eq!(status, KairosStatus::Ok);
    let mut now = 0.0;
    let step_once = |now: f64| {
        let mut step = std::ptr::null_mut();
        // SAFETY: a live handle, valid observations; the step is freed at once.
        unsafe {
            let status = kairos_step(
                handle,
                now,
                observations.as_ptr(),
                observations.len(),
                &mut step,
            );
            assert_eq!(status, KairosStatus::Ok);
            black_box(kairos_step_summary(step));
            kairos_step_free(step);
        }
    };
    for _ in 0..WARM_UP {
        step_once(now);
        now += 0.1;
    }
    group.bench_function("kairos_step (C ABI)", |b| {
        b.iter(|| {
            now += 0.1;
            step_once(now);
        })
    });
    group.finish();
    // SAFETY: not used after this.
    unsafe { kairos_executive_free(handle) };
}

fn propulsion(c: &mut Criterion) {
    let mut group = c.benchmark_group("propulsion quiet cycle");
    // Everything off and closed, as at the start, and a program content with it (`engine =
    // off` holds at once): every measured cycle is the quiet steady state.
    let readings = [
        ("valve1.outlet", "low", 0x120, 0),
        ("valve2.outlet", "low", 0x121, 0),
        ("engine.power", "zero", 0x122, 0),
        ("engine.temp", "low", 0x123, 0),
        ("engine.thrust", "zero", 0x124, 0),
    ];
    let program = root().join("target/ffi-bench-off.rmpl");
    std::fs::write(&program, "Off() :: { engine = off }").expect("target/ is writable");
    let observed: Vec<NamedValue> = readings
        .iter()
        .map(|(v, x, _, _)| NamedValue::new(*v, *x))
        .collect();
    let mut executive = Executive::load(&root().join("models/propulsion.ron"), &program)
        .expect("loads")
        .kappa(5)
        .build()
        .expect("builds");
    let mut now = 0.0;
    for _ in 0..WARM_UP {
        executive.step(now, &observed).expect("a cycle");
        now += 1.0;
    }
    group.bench_function("Executive::step", |b| {
        b.iter(|| {
            now += 1.0;
            black_box(executive.step(now, &observed).expect("a cycle"));
        })
    });

    let telemetry: Vec<KairosTelemetry> = (readings.iter())
        .map(|&(_, _, channel, value)| KairosTelemetry {
            channel,
            kind: KAIROS_TLM_ENUM,
            integer: value,
            real: 0.0,
        })
        .collect();
    let mut options = kairos_options_default();
    options.kappa = 5;
    let mut handle = std::ptr::null_mut();
    let program = CString::new(program.display().to_string()).expect("a path");
    // SAFETY: valid strings, options and out-pointers.
    unsafe {
        let status = kairos_executive_load(
            path("models/propulsion.ron").as_ptr(),
            program.as_ptr(),
            &options,
            &mut handle,
            std::ptr::null_mut(),
        );
        assert_eq!(status, KairosStatus::Ok);
        let status = kairos_executive_bind_fprime(
            handle,
            path("models/fprime/PropulsionTopologyDictionary.json").as_ptr(),
            path("models/fprime/propulsion.binding.ron").as_ptr(),
        );
        assert_eq!(status, KairosStatus::Ok);
    }
    let mut now = 0.0;
    let step_once = |now: f64| {
        let mut step = std::ptr::null_mut();
        // SAFETY: a live handle, valid telemetry; the step is freed at once.
        unsafe {
            let status =
                kairos_fprime_step(handle, now, telemetry.as_ptr(), telemetry.len(), &mut step);
            assert_eq!(status, KairosStatus::Ok);
            black_box(kairos_step_summary(step));
            kairos_step_free(step);
        }
    };
    for _ in 0..WARM_UP {
        step_once(now);
        now += 1.0;
    }
    group.bench_function("kairos_fprime_step (C ABI, by channel id)", |b| {
        b.iter(|| {
            now += 1.0;
            step_once(now);
        })
    });
    group.finish();
    // SAFETY: not used after this.
    unsafe { kairos_executive_free(handle) };
}

criterion_group!(benches, driver_valve, propulsion);
criterion_main!(benches);
