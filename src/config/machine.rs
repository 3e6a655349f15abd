//! `machine.toml`: the update period, programs, I/O counts, user variables and bits, object
//! set-up and assignments.

use super::values::Duration;
use indexmap::IndexMap;
use serde::Deserialize;
use toml::Spanned;

/// The whole machine file.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineFile {
    /// General settings.
    #[serde(default)]
    pub machine: MachineSection,
    /// The programs, by number.
    #[serde(default, rename = "program")]
    pub programs: Vec<ProgramEntry>,
    /// How many points of each kind of digital I/O exist.
    #[serde(default)]
    pub io: IndexMap<String, Spanned<u32>>,
    /// Instance counts of other objects (`Capture = 4`).
    #[serde(default)]
    pub objects: IndexMap<String, Spanned<u32>>,
    /// User variables by name.
    #[serde(default)]
    pub variables: IndexMap<String, Spanned<VarDecl>>,
    /// User bits.
    #[serde(default)]
    pub bits: BitsSection,
    /// Queue set-up by instance number (`[queue.0]`).
    #[serde(default)]
    pub queue: IndexMap<String, Spanned<QueueSetup>>,
    /// User units of the servo axis and the master.
    #[serde(default)]
    pub units: UnitsSection,
    /// Index set-up by instance number (`[index.0]`).
    #[serde(default)]
    pub index: IndexMap<String, Spanned<IndexSetup>>,
    /// Home set-up by instance number (`[home.0]`).
    #[serde(default)]
    pub home: IndexMap<String, Spanned<HomeSetup>>,
    /// Jog set-up by instance number (`[jog.0]`).
    #[serde(default)]
    pub jog: IndexMap<String, Spanned<JogSetup>>,
    /// PLS set-up by instance number (`[pls.0]`).
    #[serde(default)]
    pub pls: IndexMap<String, Spanned<PlsSetup>>,
    /// Source → destination assignments.
    #[serde(default, rename = "assignment")]
    pub assignments: Vec<AssignmentEntry>,
    /// The servo loop of the PowerTools drive's axis (`[servo]`); without it the servo is
    /// ideal (feedback equals command).
    pub servo: Option<Spanned<ServoSection>>,
    /// ORION DSP axes by number (`[axis.1]`), for MotionBASIC programs.
    #[serde(default)]
    pub axis: IndexMap<String, Spanned<AxisSetup>>,
    /// The Track Pick & Place module (`[pickplace]`): its kinematics and limits, its members'
    /// initial values by the manual's names, and its belts (`[pickplace.belt.N]`). Checked by
    /// `config::pickplace` (members and set-up).
    pub pickplace: Option<Spanned<TomlTable>>,
    /// Real I/O over Modbus TCP (`[modbus]` and its `[[modbus.map]]` entries). Checked by
    /// `config::modbus` against the registry; the simulator ignores it.
    pub modbus: Option<Spanned<ModbusSection>>,
}

/// `[modbus]`: a Modbus TCP remote-I/O coupler and how its points map to pacer members.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModbusSection {
    /// Host name or IP address of the coupler (`--io modbus://HOST:PORT` overrides it).
    pub host: Option<Spanned<String>>,
    /// TCP port (default 502).
    pub port: Option<Spanned<i64>>,
    /// Modbus unit (slave) id, 0 to 255 (default 1).
    pub unit: Option<Spanned<i64>>,
    /// How long one request may take before it is a fault (default 100 ms).
    pub timeout: Option<Spanned<super::values::Duration>>,
    /// Unused addresses a read may span to merge two groups into one request (default 0:
    /// only contiguous addresses are merged).
    pub max_gap: Option<Spanned<i64>>,
    /// Run on the coupler by default (`--io sim` still simulates); default false: the
    /// simulator unless `--io modbus…` is given.
    pub enabled: Option<Spanned<bool>>,
    /// Consecutive late updates that make a real-time fault (default 10; 0: never).
    pub overrun_limit: Option<Spanned<i64>>,
    /// The process image's exchange cycle (default 5 ms).
    pub period: Option<Spanned<super::values::Duration>>,
    /// The oldest input image an update accepts before it is an I/O fault (default 100 ms).
    pub max_age: Option<Spanned<super::values::Duration>>,
    /// The map: one entry per run of points.
    #[serde(default)]
    pub map: Vec<Spanned<ModbusMapEntry>>,
}

/// `[[modbus.map]]`: a run of Modbus points bound to pacer members.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModbusMapEntry {
    /// `coil`, `discrete_input`, `holding_register` or `input_register`.
    pub kind: Spanned<String>,
    /// The first Modbus address (0-based protocol address).
    pub address: Spanned<i64>,
    /// Bits: how many consecutive points, bound to consecutive instances starting at
    /// `member` (default 1). Registers: 1 (16-bit) or 2 (32-bit, high word first).
    pub count: Option<Spanned<i64>>,
    /// The pacer member: `DriveInput.1`, `DriveOutput.2`, `Var.Speed`, `Bit.Ready` ….
    pub member: Spanned<String>,
    /// Registers: engineering value = raw × scale + offset (default 1).
    pub scale: Option<Spanned<f64>>,
    /// Registers: see `scale` (default 0).
    pub offset: Option<Spanned<f64>>,
    /// Registers: the raw value is signed (two's complement; default false).
    pub signed: Option<Spanned<bool>>,
    /// Outputs (coils, holding registers): the value written in the safe state, in the
    /// member's units (default 0 / OFF).
    pub safe: Option<Spanned<f64>>,
}

/// The keys of `[pickplace]` that are not members of the module.
pub const PICKPLACE_SETUP_KEYS: &[&str] = &[
    "kinematics",
    "delta3",
    "start",
    "joint",
    "sw_limit",
    "belt",
    "prep_budget",
];

/// The keys of `[pickplace.belt.N]` that are not members of the belt: the belt drive's limits.
pub const BELT_SETUP_KEYS: &[&str] = &["max_vel", "max_acc", "max_jerk"];

/// A TOML table whose keys and values all keep their place in the file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TomlTable {
    /// The entries, in the order the TOML reader gives them (sorted by key).
    pub entries: Vec<(Spanned<String>, Spanned<TomlValue>)>,
}

impl TomlTable {
    /// The entry with this key (exactly as written).
    pub fn get(&self, key: &str) -> Option<&Spanned<TomlValue>> {
        self.entries
            .iter()
            .find(|(k, _)| k.get_ref() == key)
            .map(|(_, v)| v)
    }
}

/// A TOML value that keeps the place of every value inside it.
#[derive(Debug, Clone, PartialEq)]
pub enum TomlValue {
    /// `true` / `false`.
    Bool(bool),
    /// An integer.
    Integer(i64),
    /// A float (possibly `inf` or `nan`).
    Float(f64),
    /// A string.
    String(String),
    /// An array.
    Array(Vec<Spanned<TomlValue>>),
    /// A table (inline or not).
    Table(TomlTable),
}

impl TomlValue {
    /// A number (integer or float), if it is one.
    pub fn as_number(&self) -> Option<f64> {
        match self {
            TomlValue::Integer(i) => Some(*i as f64),
            TomlValue::Float(x) => Some(*x),
            _ => None,
        }
    }

    /// What it is, for messages: "a string", "an array", ….
    pub fn describe(&self) -> &'static str {
        match self {
            TomlValue::Bool(_) => "true/false",
            TomlValue::Integer(_) => "an integer",
            TomlValue::Float(_) => "a number",
            TomlValue::String(_) => "a string",
            TomlValue::Array(_) => "an array",
            TomlValue::Table(_) => "a table",
        }
    }
}

/// The key under which the toml deserializer hands over a date-time (which `[pickplace]`
/// never takes).
const TOML_DATETIME_KEY: &str = "$__toml_private_datetime";

impl<'de> Deserialize<'de> for TomlTable {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match TomlValue::deserialize(d)? {
            TomlValue::Table(t) => Ok(t),
            other => Err(serde::de::Error::custom(format!(
                "expected a table, found {}",
                other.describe()
            ))),
        }
    }
}

impl<'de> Deserialize<'de> for TomlValue {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(TomlValueVisitor)
    }
}

struct TomlValueVisitor;

impl<'de> serde::de::Visitor<'de> for TomlValueVisitor {
    type Value = TomlValue;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E>(self, v: bool) -> Result<TomlValue, E> {
        Ok(TomlValue::Bool(v))
    }

    fn visit_i64<E>(self, v: i64) -> Result<TomlValue, E> {
        Ok(TomlValue::Integer(v))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<TomlValue, E> {
        i64::try_from(v)
            .map(TomlValue::Integer)
            .map_err(|_| E::custom(format!("{v} is too large")))
    }

    fn visit_f64<E>(self, v: f64) -> Result<TomlValue, E> {
        Ok(TomlValue::Float(v))
    }

    fn visit_str<E>(self, v: &str) -> Result<TomlValue, E> {
        Ok(TomlValue::String(v.to_string()))
    }

    fn visit_string<E>(self, v: String) -> Result<TomlValue, E> {
        Ok(TomlValue::String(v))
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<TomlValue, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element::<Spanned<TomlValue>>()? {
            items.push(item);
        }
        Ok(TomlValue::Array(items))
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<TomlValue, A::Error> {
        let mut entries = Vec::new();
        loop {
            // A date-time comes as a map whose one key carries no span.
            let key = match map.next_key::<Spanned<String>>() {
                Ok(Some(key)) => key,
                Ok(None) => break,
                Err(e) if e.to_string().contains(TOML_DATETIME_KEY) => {
                    return Err(serde::de::Error::custom(
                        "a date or time is not a value here; give a number",
                    ))
                }
                Err(e) => return Err(e),
            };
            let value = map.next_value::<Spanned<TomlValue>>()?;
            entries.push((key, value));
        }
        Ok(TomlValue::Table(TomlTable { entries }))
    }
}

/// `[servo]`: the drive's position / velocity loop, its motor and load, its limits. Checked
/// by `config::servo`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServoSection {
    /// `ideal` (feedback equals command, the default) or `cascade` (the loop below).
    pub model: Option<Spanned<String>>,
    /// Loop updates per second, Hz (default 8000).
    pub loop_rate: Option<Spanned<f64>>,
    /// Position gain, 1/s.
    pub position_gain: Option<Spanned<f64>>,
    /// Velocity gain (the velocity loop's bandwidth), rad/s.
    pub velocity_gain: Option<Spanned<f64>>,
    /// Velocity integral gain, 1/s².
    pub velocity_integral: Option<Spanned<f64>>,
    /// Velocity feedforward, percent.
    pub velocity_feedforward: Option<Spanned<f64>>,
    /// Acceleration feedforward, percent.
    pub acceleration_feedforward: Option<Spanned<f64>>,
    /// Rotor inertia, kg·m².
    pub motor_inertia: Option<Spanned<f64>>,
    /// Load inertia reflected to the motor, kg·m².
    pub load_inertia: Option<Spanned<f64>>,
    /// The drive's inertia ratio setting (default: the load's over the motor's).
    pub inertia_ratio: Option<Spanned<f64>>,
    /// Peak torque, N·m.
    pub torque_limit: Option<Spanned<f64>>,
    /// Highest velocity, units/s.
    pub velocity_limit: Option<Spanned<f64>>,
    /// FollowingErrorLimit at the start, units; giving it sets FollowingErrorEnable.
    pub following_error_limit: Option<Spanned<f64>>,
    /// From a capture input's edge to the encoder count latched (default 1 µs).
    pub latch_delay: Option<Spanned<Duration>>,
    /// Encoder counts per motor revolution (default: `[units] motor_counts_per_rev` for the
    /// drive, 4096 for a DSP axis).
    pub counts_per_rev: Option<Spanned<f64>>,
}

/// `[axis.N]`: one DSP axis (the motor data and links MotionBASIC's set-up menus give).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSetup {
    /// A name for messages (`web`, `knife`).
    pub name: Option<String>,
    /// User units per motor revolution (speeds in MOVE … AT are RPM).
    pub units_per_rev: Option<Spanned<f64>>,
    /// The axis whose position drives this axis's GEAR statements (the MotionData link).
    pub pacer: Option<Spanned<u32>>,
    /// Depth of the axis's motion queue (default 4).
    pub queue: Option<Spanned<u32>>,
    /// Acceleration for MOVE TO/FOR without IN, units/s² (default: 10 revolutions/s²).
    pub accel: Option<Spanned<f64>>,
    /// Speed for MOVE TO/FOR without AT, RPM (default 100).
    pub speed: Option<Spanned<f64>>,
    /// An input wired to the axis's fast input (REGIST), e.g. "ModuleInput.1".
    pub fast_input: Option<Spanned<String>>,
    /// The axis's servo loop (`[axis.N.servo]`, the keys of `[servo]`); without it, ideal.
    pub servo: Option<Spanned<ServoSection>>,
}

/// `[machine]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MachineSection {
    /// A name for the trace and the summary.
    pub name: Option<String>,
    /// The trajectory update period (default 1 ms).
    pub update: Option<Spanned<Duration>>,
    /// Instructions a task may run in one update before it must yield (default 10000).
    pub budget: Option<Spanned<u64>>,
    /// Number of tasks (default 4).
    pub tasks: Option<Spanned<u32>>,
    /// The servo axis's positions roll over at this value, e.g. 360 for a rotary table
    /// (default 0: no rollover).
    pub rollover: Option<Spanned<f64>>,
}

/// `[[program]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProgramEntry {
    /// Program number (`Program.N`).
    pub number: Spanned<u32>,
    /// File, relative to the machine file.
    pub file: Spanned<String>,
    /// Start this program when the run starts.
    #[serde(default)]
    pub autostart: bool,
}

/// `[variables.NAME]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VarDecl {
    /// Decimal places kept (0 to 9).
    #[serde(default)]
    pub decimals: u8,
    /// Value at the start of the run.
    #[serde(default)]
    pub initial: f64,
}

/// `[bits]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BitsSection {
    /// Bits `Bit.0 .. Bit.(count-1)` (default 32).
    pub count: Option<Spanned<u32>>,
    /// Names for bits: `Ready = 3` makes `Bit.Ready` mean `Bit.3`.
    #[serde(default)]
    pub names: IndexMap<String, Spanned<u32>>,
    /// Bits that start ON, by number or name.
    #[serde(default)]
    pub initially_on: Vec<Spanned<String>>,
}

/// `[queue.N]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QueueSetup {
    /// A descriptive name ("Label").
    pub name: Option<String>,
    /// Capacity (default 8).
    pub size: Option<Spanned<u32>>,
    /// QueueOffset at the start, in source units.
    #[serde(default)]
    pub offset: f64,
    /// Count at which QueueFull turns on (default: the size).
    pub full_level: Option<Spanned<u32>>,
    /// What exit positions are compared with: MasterPosn, FeedbackPosn or CommandPosn.
    pub source: Option<Spanned<String>>,
}

/// `[[assignment]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssignmentEntry {
    /// A bit member: an input, a status bit, a user bit.
    pub source: Spanned<String>,
    /// A bit member or an action.
    pub destination: Spanned<String>,
    /// "ActiveOn" (default) or "ActiveOff".
    pub polarity: Option<Spanned<String>>,
}

/// `[index.N]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexSetup {
    /// "Incremental" (default), "Absolute" or "Registration".
    #[serde(rename = "type")]
    pub kind: Option<Spanned<String>>,
    /// "Realtime" (default) or "Synchronized" (velocity per master unit, acceleration per
    /// master unit²).
    pub time_base: Option<Spanned<String>>,
    /// Distance (incremental) or position (absolute).
    pub distance: Option<f64>,
    /// Velocity.
    pub velocity: Option<f64>,
    /// Acceleration.
    pub acceleration: Option<f64>,
    /// Deceleration.
    pub deceleration: Option<f64>,
    /// Distance past the sensor at which a registration index stops.
    pub registration_offset: Option<f64>,
    /// A timed index: the move takes this long (seconds, or master units when synchronized);
    /// its velocity is computed, never above `velocity`.
    pub time: Option<f64>,
}

/// `[home.N]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HomeSetup {
    /// The reference input, e.g. `ModuleInput.3` (its rising edge ends the search).
    pub reference: Spanned<String>,
    /// Home velocity (signed: the direction of the search), units per second.
    pub velocity: Option<f64>,
    /// Acceleration.
    pub acceleration: Option<f64>,
    /// Deceleration.
    pub deceleration: Option<f64>,
    /// Specified offset from the reference to the home position; without it the offset is
    /// calculated (the axis stops as soon as it can after the reference).
    pub offset: Option<f64>,
}

/// `[jog.N]`: the jog's settings at the start (programs may change them).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JogSetup {
    /// Jog velocity, units per second (above 0; the initiate gives the direction).
    pub velocity: Option<f64>,
    /// Acceleration.
    pub acceleration: Option<f64>,
    /// Deceleration.
    pub deceleration: Option<f64>,
}

/// `[pls.N]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlsSetup {
    /// What the window is on: MasterPosn (default), FeedbackPosn or CommandPosn.
    pub source: Option<Spanned<String>>,
    /// The source position rolls over at this value (0: no rollover).
    #[serde(default)]
    pub rollover: f64,
    /// `PLS.N.OnPosn` at the start.
    pub on: Option<f64>,
    /// `PLS.N.OffPosn` at the start.
    pub off: Option<f64>,
    /// "Both" (default), "Plus" or "Minus": the direction of travel in which the PLS is active.
    pub direction: Option<Spanned<String>>,
}

/// `[units]`: what a unit of the servo axis and of the master is.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitsSection {
    /// Name of the servo axis's user unit (default "units").
    #[serde(default = "default_unit")]
    pub motor: String,
    /// Servo user units per motor revolution (default 1).
    pub motor_per_rev: Option<Spanned<f64>>,
    /// Motor encoder counts per revolution (default 4096).
    pub motor_counts_per_rev: Option<Spanned<f64>>,
    /// Name of the master's user unit (default "units").
    #[serde(default = "default_unit")]
    pub master: String,
    /// Master encoder counts per master unit (default 1000).
    pub master_counts_per_unit: Option<Spanned<f64>>,
}

impl Default for UnitsSection {
    fn default() -> Self {
        UnitsSection {
            motor: default_unit(),
            motor_per_rev: None,
            motor_counts_per_rev: None,
            master: default_unit(),
            master_counts_per_unit: None,
        }
    }
}

fn default_unit() -> String {
    "units".to_string()
}
