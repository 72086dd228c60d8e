//! A hand-written Mars lander for the EDL program (thesis §7.2.2): the hardware answers the
//! executive's commands the way `models/mars_lander.ron`'s header says its sensors do, and the
//! environment sets the event triggers at scripted times. Faults are injected in the hardware,
//! never told to the executive: the primary separation pyro misfires (§3.3), the PDE drops into
//! its resettable fault at powered descent (§7.2.5), and leg deployment latches a spike on the
//! touchdown sensor (the Mars Polar Lander case, §1.1).
//!
//! Shared by `examples/edl_timeline` (which draws `docs/timeline.svg`) and
//! `tests/report_timeline_edl.rs`. The times follow `tests/mars_lander_estimation.rs`'s nominal
//! EDL: drag at 16,800 s, the Mach trigger at 17,040 s, ..., touchdown at 17,157 s.

use kairos::diagnostic::Source;
use kairos::executive::{Event, Executive, NamedValue};
use kairos::plant::Plant;
use kairos::rmpl::{self, LinkOptions};

/// When the environment sets each trigger (seconds from the start of the program).
pub mod script {
    /// Drag sensed: atmospheric entry.
    pub const ENTRY: f64 = 16800.0;
    /// The Mach trigger (parachute).
    pub const MACH: f64 = 17040.0;
    /// The altitude/velocity trigger (backshell, powered descent).
    pub const ALT_VEL: f64 = 17102.2;
    /// 40 m above the surface (radar off).
    pub const ALT_40M: f64 = 17143.0;
    /// 12 m above the surface (constant-velocity descent).
    pub const ALT_12M: f64 = 17151.0;
    /// The footpads touch the ground.
    pub const TOUCHDOWN: f64 = 17157.0;
    /// How long the engine heats before it reaches its standby temperature.
    pub const HEATING: f64 = 43.1;
    /// The PDE's resettable fault, once it is on for powered descent.
    pub const PDE_FAULT: f64 = ALT_VEL + 0.5;
}

/// Which faults the hardware has.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Faults {
    /// The primary separation pyro misfires; the backup works.
    pub misfire: bool,
    /// The PDE latches a resettable fault once on for powered descent.
    pub pde: bool,
    /// Leg deployment latches a spike on the touchdown sensor.
    pub spike: bool,
}

impl Faults {
    /// All three.
    pub fn all() -> Faults {
        Faults {
            misfire: true,
            pde: true,
            spike: true,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Engine {
    Off,
    Heating(f64),
    Standby,
    Firing,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Pde {
    Off,
    On,
    Resettable,
}

/// The lander's hardware and environment.
#[derive(Debug, Clone)]
pub struct Lander {
    faults: Faults,
    pde: Pde,
    pde_fault_pending: bool,
    engine: Engine,
    valves: [bool; 2],
    inertial: bool,
    /// The ACS's set-point and when the attitude gets there.
    attitude: (&'static str, f64),
    separated: bool,
    misfired: bool,
    chute: bool,
    heatshield: bool,
    legs: bool,
    backshell: bool,
    radar: bool,
    prop: &'static str,
    spike: bool,
    landed: bool,
}

impl Lander {
    /// The lander before the EDL program starts.
    pub fn new(faults: Faults) -> Lander {
        Lander {
            faults,
            pde: Pde::Off,
            pde_fault_pending: faults.pde,
            engine: Engine::Off,
            valves: [false; 2],
            inertial: false,
            attitude: ("cruise", 0.0),
            separated: false,
            misfired: false,
            chute: false,
            heatshield: false,
            legs: false,
            backshell: false,
            radar: false,
            prop: "idle",
            spike: false,
            landed: false,
        }
    }

    /// The next time something happens by itself after `time`, if any.
    pub fn next_event(&self, time: f64) -> Option<f64> {
        let heated = match self.engine {
            Engine::Heating(since) => Some(since + script::HEATING),
            _ => None,
        };
        let scripted = [
            script::ENTRY,
            script::MACH,
            script::ALT_VEL,
            script::ALT_40M,
            script::ALT_12M,
            script::TOUCHDOWN,
            script::PDE_FAULT,
        ];
        scripted
            .into_iter()
            .chain(heated)
            .chain([self.attitude.1])
            .filter(|&t| t > time)
            .reduce(f64::min)
    }

    /// Every observable, as the sensors report them at `time`.
    pub fn observe(&mut self, time: f64) -> Vec<NamedValue> {
        self.advance(time);
        let flag = |set: bool| if set { "set" } else { "clear" };
        let switch = |on: bool, yes: &'static str, no: &'static str| if on { yes } else { no };
        let (set_point, settled_at) = self.attitude;
        let in_orient = format!("in-{set_point}-orient");
        let attitude = if time >= settled_at {
            in_orient.as_str()
        } else {
            "off-set-point"
        };
        let hot = matches!(self.engine, Engine::Standby | Engine::Firing);
        let pairs: [(&str, &str); 23] = [
            (
                "engine.power",
                switch(self.engine != Engine::Off, "nominal", "zero"),
            ),
            ("engine.temp", switch(hot, "nominal", "low")),
            (
                "engine.thrust",
                switch(self.engine == Engine::Firing, "nominal", "zero"),
            ),
            (
                "PDE.status",
                match self.pde {
                    Pde::Off => "off",
                    Pde::On => "nominal",
                    Pde::Resettable => "fault",
                },
            ),
            ("valve1.outlet", switch(self.valves[0], "high", "low")),
            ("valve2.outlet", switch(self.valves[1], "high", "low")),
            (
                "nav.reported",
                switch(self.inertial, "inertial", "earth-relative"),
            ),
            (
                "entry.drag",
                switch(time >= script::ENTRY, "sensed", "none"),
            ),
            ("att.ACS", set_point),
            ("att.att_obs", attitude),
            (
                "lander.sep_switch",
                switch(self.separated, "separated", "attached"),
            ),
            ("Mach_trigger.flag", flag(time >= script::MACH)),
            (
                "chute.deploy_switch",
                switch(self.chute, "deployed", "stowed"),
            ),
            (
                "heatshield.sep_switch",
                switch(self.heatshield, "separated", "attached"),
            ),
            ("alt_vel_trigger.flag", flag(time >= script::ALT_VEL)),
            (
                "legs.deploy_switch",
                switch(self.legs, "deployed", "stowed"),
            ),
            ("radar_altim.power", switch(self.radar, "nominal", "zero")),
            (
                "backshield.sep_switch",
                switch(self.backshell, "separated", "attached"),
            ),
            ("prop.reported", self.prop),
            ("alt_40m_trigger.flag", flag(time >= script::ALT_40M)),
            ("alt_12m_trigger.flag", flag(time >= script::ALT_12M)),
            (
                "touchdown_sensor.flag",
                flag(self.spike || time >= script::TOUCHDOWN),
            ),
            ("landing.flag", flag(self.landed)),
        ];
        pairs
            .iter()
            .map(|&(variable, value)| NamedValue::new(variable, value))
            .collect()
    }

    /// What happens by itself up to `time`: heating ends, the PDE fault strikes.
    fn advance(&mut self, time: f64) {
        if let Engine::Heating(since) = self.engine {
            if time >= since + script::HEATING {
                self.engine = Engine::Standby;
            }
        }
        if self.pde_fault_pending && self.pde == Pde::On && time >= script::PDE_FAULT {
            self.pde_fault_pending = false;
            self.pde = Pde::Resettable;
        }
    }

    /// The hardware acts on one command issued at `time`.
    pub fn command(&mut self, time: f64, command: &NamedValue) {
        let value = command.value.as_str();
        match command.variable.as_str() {
            "PDE.cmd" => self.pde_command(time, value),
            "nav.cmd" => self.inertial = value == "inertial",
            "att.cmd" => self.slew(time, value),
            "lander.cmd" => self.separate(value),
            "chute.cmd" => self.chute = true,
            "heatshield.cmd" => self.heatshield = true,
            "legs.cmd" => {
                self.legs = true;
                self.spike |= self.faults.spike;
            }
            "radar_altim.cmd" => self.radar = value == "on",
            "backshield.cmd" => self.backshell = true,
            "prop.cmd" => self.prop = self.prop_mode(value),
            "touchdown_sensor.cmd" => self.spike = false,
            "landing.cmd" => self.landed = true,
            _ => {}
        }
    }

    fn pde_command(&mut self, time: f64, value: &str) {
        match (value, self.pde) {
            ("on", Pde::Off) | ("reset", Pde::Resettable) => self.pde = Pde::On,
            ("off", _) => self.pde = Pde::Off,
            (relayed, Pde::On) => self.relay(time, relayed),
            _ => {}
        }
    }

    fn relay(&mut self, time: f64, command: &str) {
        match (command, self.engine) {
            ("open1", _) => self.valves[0] = true,
            ("open2", _) => self.valves[1] = true,
            ("close1", _) => self.valves[0] = false,
            ("close2", _) => self.valves[1] = false,
            ("engine-standby", Engine::Off) => self.engine = Engine::Heating(time),
            ("engine-standby", Engine::Firing) => self.engine = Engine::Standby,
            ("engine-fire", Engine::Standby) if self.valves == [true, true] => {
                self.engine = Engine::Firing
            }
            ("engine-off", _) => self.engine = Engine::Off,
            _ => {}
        }
    }

    /// The ACS switches set-point at once; the attitude gets there after a slew.
    fn slew(&mut self, time: f64, command: &str) {
        let (set_point, seconds) = match command {
            "to-entry" => ("entry", 12.0),
            "to-vel-vector" => ("vel-vector", 15.0),
            "to-landing" => ("landing", 20.0),
            _ => ("cruise", 30.0),
        };
        self.attitude = (set_point, time + seconds);
    }

    fn separate(&mut self, pyro: &str) {
        if pyro == "fire-primary" && self.faults.misfire && !self.misfired {
            self.misfired = true;
        } else {
            self.separated = true;
        }
    }

    fn prop_mode(&self, command: &str) -> &'static str {
        match command {
            "gravity-turn" => "gravity-turn",
            "const-vel-descent" => "const-vel-descent",
            "idle" => "idle",
            _ => self.prop,
        }
    }
}

/// A finished EDL run.
pub struct Run {
    /// The executive, with its timelines.
    pub executive: Executive,
    /// Every step's events.
    pub events: Vec<Event>,
    /// The last cycle's time.
    pub end: f64,
}

/// Loads `models/mars_lander.ron` and `programs/mars_edl.rmpl` into an executive (κ = 10).
pub fn edl_executive() -> Executive {
    let root = env!("CARGO_MANIFEST_DIR");
    let read = |path: &str| {
        let text = std::fs::read_to_string(format!("{root}/{path}"))
            .unwrap_or_else(|e| panic!("{path}: {e}"));
        Source::new(path, text)
    };
    let plant = Plant::load(&read("models/mars_lander.ron")).expect("the lander model loads");
    let options = LinkOptions {
        plant: Some(plant.table()),
        ..LinkOptions::default()
    };
    let program = rmpl::load(&read("programs/mars_edl.rmpl"), &options).expect("the EDL links");
    Executive::builder(plant, program)
        .kappa(10)
        .build()
        .expect("the executive builds")
}

/// Runs the EDL program against the lander until the run settles (or 17,400 s): cycles 0.1 s
/// apart for a second after any command or change, a second apart near activity, ten seconds
/// apart through quiet stretches, and a cycle at each scripted event.
pub fn run_edl(faults: Faults) -> Run {
    let mut executive = edl_executive();
    let mut lander = Lander::new(faults);
    let mut events = Vec::new();
    let (mut time, mut busy_until, mut active_until) = (0.0, 0.0, 0.0);
    let mut previous: Vec<NamedValue> = Vec::new();
    loop {
        let observation = lander.observe(time);
        let step = executive.step(time, &observation).expect("time increases");
        for &(var, value) in &step.command {
            lander.command(time, &NamedValue::of(executive.plant(), var, value));
        }
        let changed =
            observation != previous || !step.command.is_empty() || !step.events.is_empty();
        events.extend(step.events.iter().cloned());
        if step.is_settled() || time >= 17400.0 {
            return Run {
                executive,
                events,
                end: time,
            };
        }
        if changed {
            busy_until = time + 1.0;
            active_until = time + 60.0;
        }
        previous = observation;
        let step = if time < busy_until {
            0.1
        } else if time < active_until {
            1.0
        } else {
            10.0
        };
        let next = round(time + step);
        time = lander
            .next_event(time)
            .map_or(next, |event| next.min(event));
    }
}

/// A time to the tenth of a second, so that cycle times add up exactly.
fn round(time: f64) -> f64 {
    (time * 10.0).round() / 10.0
}
