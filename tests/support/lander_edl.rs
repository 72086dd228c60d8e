//! The nominal EDL of §7.2.2 as a scripted plant would report it to mode estimation: sensor
//! changes and the executive's commands by time, written out as a replay log (JSON lines, for
//! `kairos estimate` and the lander's estimation tests) or built directly as log records (for the
//! benchmarks and `examples/me_profile.rs`, which replay all ≈ 170,000 cycles of 0.1 s).
#![allow(dead_code)] // each includer uses a different part

use std::collections::BTreeMap;

use kairos::estimation::log::LogRecord;
use kairos::plant::{Commands, Observation, Plant};

/// What every sensor reports before the EDL program's first command: the initial state of every
/// component of `models/mars_lander.ron`.
pub const BEFORE_EDL: [(&str, &str); 23] = [
    ("engine.power", "zero"),
    ("engine.temp", "low"),
    ("engine.thrust", "zero"),
    ("PDE.status", "off"),
    ("valve1.outlet", "low"),
    ("valve2.outlet", "low"),
    ("nav.reported", "earth-relative"),
    ("entry.drag", "none"),
    ("att.ACS", "cruise"),
    ("att.att_obs", "in-cruise-orient"),
    ("lander.sep_switch", "attached"),
    ("Mach_trigger.flag", "clear"),
    ("chute.deploy_switch", "stowed"),
    ("heatshield.sep_switch", "attached"),
    ("alt_vel_trigger.flag", "clear"),
    ("legs.deploy_switch", "stowed"),
    ("radar_altim.power", "zero"),
    ("backshield.sep_switch", "attached"),
    ("prop.reported", "idle"),
    ("alt_40m_trigger.flag", "clear"),
    ("alt_12m_trigger.flag", "clear"),
    ("touchdown_sensor.flag", "clear"),
    ("landing.flag", "clear"),
];

/// The executive's cycle near events (§7.2: 0.1 s).
pub const CYCLE: f64 = 0.1;

/// Name/value pairs.
pub type Pairs = Vec<(&'static str, &'static str)>;

/// A time in whole milliseconds (log times are multiples of 1 ms).
pub fn ms(time: f64) -> u64 {
    (time * 1000.0).round() as u64
}

/// A scripted plant's run: at chosen times, sensor changes and the commands the executive
/// issues. [`Timeline::times`] chooses the cycles to report: every event, a few cycles around
/// each, and a grid in between.
#[derive(Default, Clone)]
pub struct Timeline {
    /// By time in milliseconds: sensors that change then, commands issued then.
    pub events: BTreeMap<u64, (Pairs, Pairs)>,
}

impl Timeline {
    /// At `time`, the sensors report `sense` (from then on) and the executive commands
    /// `command`.
    pub fn at(
        &mut self,
        time: f64,
        sense: &[(&'static str, &'static str)],
        command: &[(&'static str, &'static str)],
    ) -> &mut Self {
        let (s, c) = self.events.entry(ms(time)).or_default();
        s.extend_from_slice(sense);
        c.extend_from_slice(command);
        self
    }

    /// The cycles (ms) up to `end`: each event, one cycle before it and five after, and every
    /// `grid` seconds.
    pub fn times(&self, end: f64, grid: f64) -> Vec<u64> {
        let mut times: Vec<u64> = Vec::new();
        for &t in self.events.keys() {
            times.extend((0..=6).map(|k| (t + k * ms(CYCLE)).saturating_sub(ms(CYCLE))));
        }
        times.extend((0..=ms(end)).step_by(ms(grid) as usize));
        times.retain(|&t| t <= ms(end));
        times.sort_unstable();
        times.dedup();
        times
    }

    /// Per cycle of `times` (sorted), the sensors' readings and the commands issued then.
    fn cycles<'a>(
        &'a self,
        times: &'a [u64],
    ) -> impl Iterator<Item = (u64, BTreeMap<&'static str, &'static str>, Pairs)> + 'a {
        let mut sensors: BTreeMap<&'static str, &'static str> = BEFORE_EDL.into_iter().collect();
        let mut applied = self.events.range(..).peekable();
        times.iter().map(move |&t| {
            let mut commands = Vec::new();
            // Sensor changes between reported cycles still take effect.
            while let Some(&(&at, (sense, command))) = applied.peek() {
                if at > t {
                    break;
                }
                sensors.extend(sense.iter().copied());
                if at == t {
                    commands = command.clone();
                }
                applied.next();
            }
            (t, sensors.clone(), commands)
        })
    }

    /// The log up to `end` with quiet lines every `grid` seconds (see [`Timeline::times`]), as
    /// JSON lines.
    pub fn text(&self, end: f64, grid: f64) -> String {
        let times = self.times(end, grid);
        let mut text = String::new();
        for (t, sensors, commands) in self.cycles(&times) {
            let pairs = |list: &mut dyn Iterator<Item = (&&str, &&str)>| {
                list.map(|(k, v)| format!("\"{k}\": \"{v}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let observed = pairs(&mut sensors.iter());
            text += &format!(
                "{{\"time\": {}, \"observations\": {{{observed}}}",
                t as f64 / 1000.0
            );
            if !commands.is_empty() {
                let issued = pairs(&mut commands.iter().map(|(k, v)| (k, v)));
                text += &format!(", \"commands\": {{{issued}}}");
            }
            text += "}\n";
        }
        text
    }

    /// The log records of the cycles `times` (ms, sorted), built without going through JSON.
    pub fn records(&self, plant: &Plant, times: &[u64]) -> Vec<LogRecord> {
        let named = |name: &str, value: &str| {
            let x = plant.table().variable_id(name).expect("a variable");
            let v = plant.table().variable(x).value(value).expect("a value");
            (x, v)
        };
        self.cycles(times)
            .enumerate()
            .map(|(line, (t, sensors, commands))| {
                let observed: Vec<_> = sensors.iter().map(|(k, v)| named(k, v)).collect();
                let issued: Vec<_> = commands.iter().map(|(k, v)| named(k, v)).collect();
                LogRecord {
                    time: t as f64 / 1000.0,
                    observation: Observation::new(plant, &observed).expect("observables"),
                    commands: Commands::new(plant, &issued).expect("controls"),
                    monitored: Vec::new(),
                    line: line + 1,
                }
            })
            .collect()
    }
}

/// The nominal EDL timeline of §7.2.2 (and the scenario list), with the commands the
/// executive issues one per cycle, each answered in the next cycle's observations.
pub mod edl {
    /// Engine standby command (via the PDE) and its confirmation (§3.3: "After 43 seconds").
    pub const STANDBY: f64 = 43.2;
    /// `nav = inertial` 16,200 s after standby (§3.1).
    pub const NAV: f64 = 16243.3;
    /// The entry slew 240 s later (§3.1), 12 s long (§3.3).
    pub const SLEW: f64 = 16483.4;
    pub const ENTRY_ORIENT: f64 = 16495.4;
    /// Separation: the primary pyro fires the cycle after entry-orient is confirmed.
    pub const SEPARATE: f64 = 16495.5;
    /// Drag sensed at the predicted entry time.
    pub const ENTRY: f64 = 16800.0;
    pub const MACH: f64 = 17040.0;
    pub const CHUTE: f64 = MACH + 0.1;
    pub const HEATSHIELD: f64 = CHUTE + 0.1 + 10.0;
    pub const LEGS: f64 = HEATSHIELD + 0.1 + 10.0;
    pub const RADAR: f64 = LEGS + 0.1 + 1.5;
    pub const ALT_VEL: f64 = 17102.2;
    /// The backshell goes, then the engine fires 0.5 s later (§7.2.2).
    pub const BACKSHELL: f64 = ALT_VEL + 0.1;
    pub const POWERED: f64 = BACKSHELL + 0.1 + 0.5;
    pub const ALT_40M: f64 = 17143.0;
    pub const ALT_12M: f64 = 17151.0;
    pub const TOUCHDOWN: f64 = 17157.0;
    pub const END: f64 = 17158.0;
}

/// What can go wrong in [`nominal_edl`].
#[derive(Default, Clone, Copy)]
pub struct Faults {
    /// The primary separation pyro misfires (§3.3); the backup is fired the next cycle.
    pub misfire: bool,
    /// Leg deployment latches a touchdown-sensor spike (§1.1); the program resets it once the
    /// engine fires (Figure B-4).
    pub spike: bool,
}

/// The nominal EDL (§7.2.2) with `faults`: every command and the sensor change that answers it.
pub fn nominal_edl(faults: Faults) -> Timeline {
    use edl::*;
    let mut t = Timeline::default();
    t.at(0.0, &[], &[("PDE.cmd", "on")])
        .at(
            0.1,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(0.2, &[("engine.power", "nominal")], &[])
        .at(
            STANDBY,
            &[("engine.temp", "nominal")],
            &[("PDE.cmd", "off")],
        )
        .at(STANDBY + 0.1, &[("PDE.status", "off")], &[])
        .at(NAV, &[], &[("nav.cmd", "inertial")])
        .at(NAV + 0.1, &[("nav.reported", "inertial")], &[])
        .at(SLEW, &[], &[("att.cmd", "to-entry")])
        .at(
            SLEW + 0.1,
            &[("att.ACS", "entry"), ("att.att_obs", "off-set-point")],
            &[],
        )
        .at(ENTRY_ORIENT, &[("att.att_obs", "in-entry-orient")], &[])
        .at(SEPARATE, &[], &[("lander.cmd", "fire-primary")]);
    if faults.misfire {
        t.at(SEPARATE + 0.1, &[], &[("lander.cmd", "fire-backup")])
            .at(SEPARATE + 0.2, &[("lander.sep_switch", "separated")], &[]);
    } else {
        t.at(SEPARATE + 0.1, &[("lander.sep_switch", "separated")], &[]);
    }
    t.at(ENTRY, &[("entry.drag", "sensed")], &[])
        .at(ENTRY + 0.1, &[], &[("att.cmd", "to-vel-vector")])
        .at(
            ENTRY + 0.2,
            &[("att.ACS", "vel-vector"), ("att.att_obs", "off-set-point")],
            &[],
        )
        .at(
            ENTRY + 15.0,
            &[("att.att_obs", "in-vel-vector-orient")],
            &[],
        )
        .at(MACH, &[("Mach_trigger.flag", "set")], &[])
        .at(CHUTE, &[], &[("chute.cmd", "fire")])
        .at(CHUTE + 0.1, &[("chute.deploy_switch", "deployed")], &[])
        .at(HEATSHIELD, &[], &[("heatshield.cmd", "fire")])
        .at(
            HEATSHIELD + 0.1,
            &[("heatshield.sep_switch", "separated")],
            &[],
        )
        .at(LEGS, &[], &[("legs.cmd", "fire")])
        .at(LEGS + 0.1, &[("legs.deploy_switch", "deployed")], &[]);
    if faults.spike {
        t.at(LEGS + 0.1, &[("touchdown_sensor.flag", "set")], &[]);
    }
    t.at(RADAR, &[], &[("radar_altim.cmd", "on")])
        .at(RADAR + 0.1, &[("radar_altim.power", "nominal")], &[])
        .at(ALT_VEL, &[("alt_vel_trigger.flag", "set")], &[])
        .at(BACKSHELL, &[], &[("backshield.cmd", "fire")])
        .at(
            BACKSHELL + 0.1,
            &[("backshield.sep_switch", "separated")],
            &[],
        )
        // §6.3.3's sequence for `engine = firing` from standby: PDE on, open 1, open 2, fire,
        // PDE off; then the landing attitude and the gravity turn.
        .at(POWERED, &[], &[("PDE.cmd", "on")])
        .at(
            POWERED + 0.1,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "open1")],
        )
        .at(
            POWERED + 0.2,
            &[("valve1.outlet", "high")],
            &[("PDE.cmd", "open2")],
        )
        .at(
            POWERED + 0.3,
            &[("valve2.outlet", "high")],
            &[("PDE.cmd", "engine-fire")],
        )
        .at(
            POWERED + 0.4,
            &[("engine.thrust", "nominal")],
            &[("PDE.cmd", "off")],
        )
        .at(
            POWERED + 0.5,
            &[("PDE.status", "off")],
            &[("att.cmd", "to-landing")],
        )
        .at(
            POWERED + 0.6,
            &[("att.ACS", "landing"), ("att.att_obs", "off-set-point")],
            &[("prop.cmd", "gravity-turn")],
        )
        .at(POWERED + 0.7, &[("prop.reported", "gravity-turn")], &[]);
    if faults.spike {
        t.at(POWERED + 0.7, &[], &[("touchdown_sensor.cmd", "reset")])
            .at(POWERED + 0.8, &[("touchdown_sensor.flag", "clear")], &[]);
    }
    t.at(POWERED + 20.0, &[("att.att_obs", "in-landing-orient")], &[])
        .at(ALT_40M, &[("alt_40m_trigger.flag", "set")], &[])
        .at(ALT_40M + 0.1, &[], &[("radar_altim.cmd", "off")])
        .at(ALT_40M + 0.2, &[("radar_altim.power", "zero")], &[])
        .at(ALT_12M, &[("alt_12m_trigger.flag", "set")], &[])
        .at(ALT_12M + 0.1, &[], &[("prop.cmd", "const-vel-descent")])
        .at(
            ALT_12M + 0.2,
            &[("prop.reported", "const-vel-descent")],
            &[],
        )
        // Touchdown: engine off (firing -> standby -> off through the PDE), landing = success.
        .at(TOUCHDOWN, &[("touchdown_sensor.flag", "set")], &[])
        .at(TOUCHDOWN + 0.1, &[], &[("PDE.cmd", "on")])
        .at(
            TOUCHDOWN + 0.2,
            &[("PDE.status", "nominal")],
            &[("PDE.cmd", "engine-standby")],
        )
        .at(
            TOUCHDOWN + 0.3,
            &[("engine.thrust", "zero")],
            &[("PDE.cmd", "engine-off")],
        )
        .at(
            TOUCHDOWN + 0.4,
            &[("engine.power", "zero"), ("engine.temp", "low")],
            &[("PDE.cmd", "off"), ("landing.cmd", "set-success")],
        )
        .at(
            TOUCHDOWN + 0.5,
            &[("PDE.status", "off"), ("landing.flag", "set")],
            &[],
        );
    t
}
