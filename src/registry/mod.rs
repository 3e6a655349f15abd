//! The object registry: every object instance of a machine and every member's storage slot,
//! built from the catalog and `machine.toml`. Names resolve to slots here, once, at compile time.

pub mod catalog;
mod resolve;

pub use catalog::{Access, Hook, Instances, Kind, MemberDef, TypeDef, ValueType};
pub use resolve::Resolved;

use crate::config::machine::{
    MachineFile, TomlTable, TomlValue, BELT_SETUP_KEYS, PICKPLACE_SETUP_KEYS,
};
use crate::config::span_of;
use crate::diag::{nearest, Problem};
use crate::syntax::span::Span;
use indexmap::IndexMap;

/// Default update period: 1 ms.
pub const DEFAULT_UPDATE_NS: u64 = 1_000_000;

/// Index of a member's storage in the signal table.
pub type SlotId = u32;

/// Instance index used for a type's own members (`Jog.Select`).
pub const GLOBAL_INSTANCE: u32 = u32::MAX;

/// What one storage slot holds.
#[derive(Debug, Clone)]
pub struct SlotInfo {
    /// Canonical full name, e.g. `Queue.0.QueueOffset`.
    pub name: String,
    /// Its value type (user variables carry their own decimal places).
    pub ty: ValueType,
    /// The member definition.
    pub member: &'static MemberDef,
    /// The object's behaviour.
    pub kind: Kind,
    /// Instance index within its type (0-based), or [`GLOBAL_INSTANCE`].
    pub instance: u32,
    /// Value at the start of a run.
    pub initial: f64,
}

/// The instances of one type in this machine.
#[derive(Debug, Clone)]
pub struct TypeInstances {
    /// The catalog entry.
    pub def: &'static TypeDef,
    /// Number of instances.
    pub count: u32,
    /// First instance number as written (1 for I/O points, 0 for objects).
    pub first: u32,
    /// Instance names (lower-case) → index, for named instances (`Var.Count`, `Bit.Ready`).
    pub names: IndexMap<String, u32>,
    /// Display name of each instance (`0`, `Count`).
    pub display: Vec<String>,
    /// First slot of this type's storage.
    pub base: SlotId,
}

impl TypeInstances {
    /// The slot of `member_index` of `instance`.
    pub fn slot(&self, instance: u32, member_index: usize, global: bool) -> SlotId {
        let per = self.def.members.len() as u32;
        if global {
            self.base + self.count * per + member_index as u32
        } else {
            self.base + instance * per + member_index as u32
        }
    }
}

/// Every object of one machine.
#[derive(Debug, Clone)]
pub struct Registry {
    /// Per type, in catalog order.
    pub types: Vec<TypeInstances>,
    /// Every slot, in layout order.
    pub slots: Vec<SlotInfo>,
    /// Queue set-up: per queue instance (size, full level).
    pub queue_sizes: Vec<(u32, u32)>,
    /// What each queue compares its exit positions with.
    pub queue_sources: Vec<QueueSource>,
    /// Index set-up: per index instance.
    pub index_setups: Vec<IndexConfig>,
    /// Home set-up: per home instance.
    pub home_setups: Vec<HomeConfig>,
    /// PLS set-up: per PLS instance.
    pub pls_setups: Vec<PlsConfig>,
    /// Rollover of the servo axis (0: none).
    pub axis_rollover: f64,
    /// User units.
    pub units: Units,
}

/// User units: names, and how they relate to motor revolutions and encoder counts.
#[derive(Debug, Clone, PartialEq)]
pub struct Units {
    /// The servo axis's unit.
    pub motor: String,
    /// Servo units per motor revolution.
    pub motor_per_rev: f64,
    /// Motor encoder counts per revolution.
    pub motor_counts_per_rev: f64,
    /// The master's unit.
    pub master: String,
    /// Master encoder counts per master unit.
    pub master_counts_per_unit: f64,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            motor: "units".into(),
            motor_per_rev: 1.0,
            motor_counts_per_rev: 4096.0,
            master: "units".into(),
            master_counts_per_unit: 1000.0,
        }
    }
}

/// The set-up of one PLS that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlsConfig {
    /// The position the window is on.
    pub source: QueueSource,
    /// Rollover of that position (0: none).
    pub rollover: f64,
}

/// The set-up of one home that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HomeConfig {
    /// The slot of the reference input, if one is set.
    pub reference: Option<SlotId>,
    /// The offset is specified (`Home.N.Offset`), not calculated.
    pub specified_offset: bool,
}

/// The position a queue compares with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum QueueSource {
    /// The master (encoder) position.
    #[default]
    Master,
    /// The motor feedback position.
    Feedback,
    /// The motor command position.
    Command,
}

/// How an index moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndexType {
    /// By its distance from where it starts.
    #[default]
    Incremental,
    /// To its distance as a position.
    Absolute,
    /// Toward its distance (the limit) until the sensor, then `RegistrationOffset` further.
    Registration,
    /// To its distance as a position on the rolled-over axis, moving plus.
    RotaryPlus,
    /// To its distance as a position on the rolled-over axis, moving minus.
    RotaryMinus,
}

/// The set-up of one index that is not a member.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IndexConfig {
    /// Incremental or absolute.
    pub kind: IndexType,
    /// Velocity and accelerations per master unit instead of per second.
    pub synchronized: bool,
    /// The move takes `Index.N.Time`; its velocity is computed.
    pub timed: bool,
}

/// Highest instance count accepted for any type.
const MAX_INSTANCES: u32 = 4096; // also keeps instance numbers within u16 in bytecode

impl Registry {
    /// Build the registry of a machine. `program_numbers` are the programs loaded.
    pub fn build(machine: &MachineFile, program_numbers: &[u32]) -> Result<Registry, Vec<Problem>> {
        let (registry, problems) = Registry::build_reporting(machine, program_numbers);
        if problems.is_empty() {
            Ok(registry)
        } else {
            Err(problems)
        }
    }

    /// Build the registry and report every problem of the machine file; values in error are
    /// replaced by their defaults, so the rest of the file (and the programs) can still be
    /// checked against the result.
    pub fn build_reporting(
        machine: &MachineFile,
        program_numbers: &[u32],
    ) -> (Registry, Vec<Problem>) {
        Registry::build_with_basic(machine, program_numbers, &[])
    }

    /// [`Registry::build_reporting`], with the MotionBASIC variables the programs use
    /// (name as written, upper-case, and type).
    pub fn build_with_basic(
        machine: &MachineFile,
        program_numbers: &[u32],
        basic_vars: &[(String, ValueType)],
    ) -> (Registry, Vec<Problem>) {
        let mut problems = Vec::new();
        let axis_numbers = axis_numbers(machine, &mut problems);
        let belt_count = belt_count(machine, &mut problems);
        let mut counts: IndexMap<&'static str, u32> = IndexMap::new();
        for table in [&machine.io, &machine.objects] {
            for (key, value) in table {
                let span = span_of(value);
                match catalog::find_type(key) {
                    Some(def) if def.kind == Kind::Belt => problems.push(
                        Problem::error(
                            "pacer::machine::count",
                            span,
                            "the number of belts is not set here",
                            "not a count",
                        )
                        .with_help(
                            "the highest [pickplace.belt.N] section in machine.toml sets it",
                        ),
                    ),
                    Some(def) if matches!(def.instances, Instances::Numbered { .. }) => {
                        let n = *value.get_ref();
                        if n > MAX_INSTANCES
                            || (def.kind == Kind::Queue && n > 8)
                            || (def.kind == Kind::Profile && n != 2)
                        {
                            let limit = match def.kind {
                                Kind::Queue => "at most 8 queues".to_string(),
                                Kind::Profile => "there are exactly 2 profiles".to_string(),
                                _ => format!("at most {MAX_INSTANCES}"),
                            };
                            problems.push(Problem::error(
                                "pacer::machine::count",
                                span,
                                format!("{n} is not a valid count of {}", def.name),
                                limit,
                            ));
                        } else {
                            counts.insert(def.name, n);
                        }
                    }
                    Some(def) => problems.push(Problem::error(
                        "pacer::machine::count",
                        span,
                        format!("{} has no instance count", def.name),
                        "set in its own table",
                    )),
                    None => {
                        let names = catalog::TYPES
                            .iter()
                            .filter(|t| matches!(t.instances, Instances::Numbered { .. }))
                            .map(|t| t.name);
                        problems.push(
                            Problem::error(
                                "pacer::machine::count",
                                span,
                                format!("unknown object type `{key}`"),
                                "not an object type",
                            )
                            .with_help_opt(
                                nearest(key, names).map(|n| format!("did you mean `{n}`?")),
                            ),
                        )
                    }
                }
            }
        }
        let highest_program = program_numbers.iter().copied().max().map_or(0, |n| n + 1);

        let mut types = Vec::new();
        let mut slots: Vec<SlotInfo> = Vec::new();
        for def in catalog::TYPES {
            let (first, mut count) = match def.instances {
                Instances::Global => (0, 1),
                Instances::Numbered {
                    first,
                    default_count,
                } => (
                    first,
                    counts.get(def.name).copied().unwrap_or(default_count),
                ),
                Instances::Named => (0, 0),
            };
            if def.kind == Kind::Program {
                count = count.max(highest_program);
            }
            if def.kind == Kind::Axis {
                count = axis_numbers.iter().copied().max().unwrap_or(0);
            }
            // A machine without [pickplace] has no slots for the module at all: every slot
            // is scanned every update.
            if def.kind == Kind::PickPlace {
                count = u32::from(machine.pickplace.is_some());
            }
            if def.kind == Kind::Belt {
                count = belt_count;
            }
            let mut names = IndexMap::new();
            let mut display: Vec<String> = (0..count).map(|i| (first + i).to_string()).collect();
            let mut decimals: Vec<u8> = Vec::new();
            let mut initial: Vec<f64> = Vec::new();
            match def.kind {
                Kind::Var => {
                    for (name, decl) in &machine.variables {
                        let d = decl.get_ref();
                        let span = span_of(decl);
                        if !valid_ident(name) {
                            problems.push(Problem::error(
                                "pacer::machine::variable",
                                span,
                                format!("`{name}` is not a valid variable name"),
                                "letters, digits and _; not starting with a digit",
                            ));
                        }
                        if d.decimals > 9 {
                            problems.push(Problem::error(
                                "pacer::machine::variable",
                                span,
                                format!("Var.{name}: {} decimal places is too many", d.decimals),
                                "0 to 9",
                            ));
                        }
                        if crate::fixed::to_fixed(d.initial, d.decimals.min(9)).is_none() {
                            problems.push(Problem::error("pacer::machine::variable", span, format!("Var.{name}: initial value {} does not fit a 32-bit variable with {} decimals", d.initial, d.decimals), "out of range"));
                        }
                        names.insert(name.to_ascii_lowercase(), count);
                        display.push(name.clone());
                        decimals.push(d.decimals.min(9));
                        initial.push(round_to(d.initial, d.decimals.min(9)));
                        count += 1;
                    }
                }
                Kind::BasicVar => {
                    for (name, _) in basic_vars {
                        names.insert(name.to_ascii_lowercase(), count);
                        display.push(name.clone());
                        count += 1;
                    }
                }
                Kind::Bit => {
                    count = machine.bits.count.as_ref().map_or(32, |c| *c.get_ref());
                    if count > MAX_INSTANCES {
                        if let Some(c) = &machine.bits.count {
                            problems.push(Problem::error(
                                "pacer::machine::bits",
                                span_of(c),
                                format!("{count} bits is too many"),
                                format!("at most {MAX_INSTANCES}"),
                            ));
                        }
                        count = 32;
                    }
                    display = (0..count).map(|i| i.to_string()).collect();
                    for (name, number) in &machine.bits.names {
                        let n = *number.get_ref();
                        if n >= count {
                            problems.push(Problem::error(
                                "pacer::machine::bits",
                                span_of(number),
                                format!("Bit.{n} does not exist"),
                                format!("bits are 0 to {}", count.saturating_sub(1)),
                            ));
                        } else if !valid_ident(name) || name.chars().all(|c| c.is_ascii_digit()) {
                            problems.push(Problem::error(
                                "pacer::machine::bits",
                                span_of(number),
                                format!("`{name}` is not a valid bit name"),
                                "letters, digits and _",
                            ));
                        } else {
                            names.insert(name.to_ascii_lowercase(), n);
                            display[n as usize] = name.clone();
                        }
                    }
                    initial = vec![0.0; count as usize];
                    for on in &machine.bits.initially_on {
                        let key = on.get_ref();
                        let idx = key
                            .parse::<u32>()
                            .ok()
                            .filter(|n| *n < count)
                            .or_else(|| names.get(&key.to_ascii_lowercase()).copied());
                        match idx {
                            Some(i) => initial[i as usize] = 1.0,
                            None => problems.push(Problem::error(
                                "pacer::machine::bits",
                                span_of(on),
                                format!("no bit `{key}`"),
                                "unknown bit",
                            )),
                        }
                    }
                }
                _ => {}
            }
            let base = slots.len() as SlotId;
            for i in 0..count {
                for member in def.members {
                    let ty = match def.kind {
                        Kind::Var => ValueType::Fixed(decimals[i as usize]),
                        Kind::BasicVar => basic_vars[i as usize].1,
                        _ => member.ty,
                    };
                    let init = match def.kind {
                        Kind::Var | Kind::Bit => initial[i as usize],
                        _ => default_value(def.kind, member),
                    };
                    let name = match (def.default_member, def.kind) {
                        (
                            Some(_),
                            Kind::Var
                            | Kind::Bit
                            | Kind::DriveInput
                            | Kind::ModuleInput
                            | Kind::DriveOutput
                            | Kind::ModuleOutput,
                        ) => {
                            format!("{}.{}", def.name, display[i as usize])
                        }
                        _ => format!("{}.{}.{}", def.name, display[i as usize], member.name),
                    };
                    let name = if def.instances == Instances::Global {
                        format!("{}.{}", def.name, member.name)
                    } else {
                        name
                    };
                    let name = if def.name == catalog::BARE_GLOBAL_TYPE {
                        member.name.to_string()
                    } else if def.kind == Kind::BasicVar {
                        display[i as usize].clone()
                    } else {
                        name
                    };
                    slots.push(SlotInfo {
                        name,
                        ty,
                        member,
                        kind: def.kind,
                        instance: i,
                        initial: init,
                    });
                }
            }
            for member in def.global_members {
                slots.push(SlotInfo {
                    name: format!("{}.{}", def.name, member.name),
                    ty: member.ty,
                    member,
                    kind: def.kind,
                    instance: GLOBAL_INSTANCE,
                    initial: default_value(def.kind, member),
                });
            }
            types.push(TypeInstances {
                def,
                count,
                first,
                names,
                display,
                base,
            });
        }

        let queue_count = types
            .iter()
            .find(|t| t.def.kind == Kind::Queue)
            .map_or(0, |t| t.count);
        let mut queue_sizes = vec![(8u32, 8u32); queue_count as usize];
        let pls_count = types
            .iter()
            .find(|t| t.def.kind == Kind::Pls)
            .map_or(0, |t| t.count);
        let home_count = types
            .iter()
            .find(|t| t.def.kind == Kind::Home)
            .map_or(0, |t| t.count);
        let index_count = types
            .iter()
            .find(|t| t.def.kind == Kind::Index)
            .map_or(0, |t| t.count);
        let mut registry = Registry {
            types,
            slots,
            queue_sizes: Vec::new(),
            queue_sources: vec![QueueSource::Master; queue_count as usize],
            index_setups: vec![IndexConfig::default(); index_count as usize],
            home_setups: vec![HomeConfig::default(); home_count as usize],
            pls_setups: vec![PlsConfig::default(); pls_count as usize],
            axis_rollover: 0.0,
            units: Units::default(),
        };
        for (key, setup) in &machine.queue {
            let span = span_of(setup);
            let Some(n) = section_instance(
                key,
                queue_count,
                span,
                "pacer::machine::queue",
                "queue",
                ("queue", "queues"),
                &mut problems,
            ) else {
                continue;
            };
            let s = setup.get_ref();
            let size = s.size.as_ref().map_or(8, |v| *v.get_ref());
            if size == 0 || size > 10_000 {
                let sp = s.size.as_ref().map_or(span, span_of);
                problems.push(Problem::error(
                    "pacer::machine::queue",
                    sp,
                    format!("queue size {size} is out of range"),
                    "1 to 10000",
                ));
            }
            let full = s.full_level.as_ref().map_or(size, |v| *v.get_ref());
            if full > size {
                let sp = s.full_level.as_ref().map_or(span, span_of);
                problems.push(Problem::error(
                    "pacer::machine::queue",
                    sp,
                    format!("full level {full} is above the queue size {size}"),
                    "at most the size",
                ));
            }
            if let Some(src) = &s.source {
                let source = match src.get_ref().to_ascii_lowercase().as_str() {
                    "masterposn" => Some(QueueSource::Master),
                    "feedbackposn" => Some(QueueSource::Feedback),
                    "commandposn" => Some(QueueSource::Command),
                    _ => None,
                };
                if let Some(q) = source {
                    registry.queue_sources[n as usize] = q;
                } else {
                    problems.push(Problem::error(
                        "pacer::machine::queue",
                        span_of(src),
                        format!("unknown queue source `{}`", src.get_ref()),
                        "MasterPosn, FeedbackPosn or CommandPosn",
                    ));
                }
            }
            queue_sizes[n as usize] = (size, full);
            registry.set_initial(Kind::Queue, n, "QueueOffset", round_to(s.offset, 4));
            registry.set_initial(Kind::Queue, n, "QueueSize", f64::from(size));
            registry.set_initial(Kind::Queue, n, "FullLevel", f64::from(full));
        }
        for (n, (size, full)) in queue_sizes.iter().enumerate() {
            if !machine.queue.contains_key(&n.to_string()) {
                registry.set_initial(Kind::Queue, n as u32, "QueueSize", f64::from(*size));
                registry.set_initial(Kind::Queue, n as u32, "FullLevel", f64::from(*full));
            }
        }
        registry.queue_sizes = queue_sizes;
        registry.index_setups(machine, &mut problems);
        registry.home_setups(machine, &mut problems);
        registry.pls_setups(machine, &mut problems);
        registry.pickplace_initials(machine, &mut problems);
        if let Some(r) = &machine.machine.rollover {
            let value = *r.get_ref();
            if value.is_finite() && value >= 0.0 {
                registry.axis_rollover = value;
            } else {
                problems.push(Problem::error(
                    "pacer::machine::rollover",
                    span_of(r),
                    format!("a rollover of {value} is not possible"),
                    "0 (none) or more",
                ));
            }
        }
        let u = &machine.units;
        registry.units.motor = u.motor.clone();
        registry.units.master = u.master.clone();
        for (value, target, what) in [
            (
                &u.motor_per_rev,
                &mut registry.units.motor_per_rev,
                "motor_per_rev",
            ),
            (
                &u.motor_counts_per_rev,
                &mut registry.units.motor_counts_per_rev,
                "motor_counts_per_rev",
            ),
            (
                &u.master_counts_per_unit,
                &mut registry.units.master_counts_per_unit,
                "master_counts_per_unit",
            ),
        ] {
            if let Some(x) = value {
                let x_value = *x.get_ref();
                if x_value.is_finite() && x_value > 0.0 {
                    *target = x_value;
                } else {
                    problems.push(Problem::error(
                        "pacer::machine::units",
                        span_of(x),
                        format!("[units] {what} must be above 0, not {x_value}"),
                        "out of range",
                    ));
                }
            }
        }
        if registry.axis_rollover <= 0.0 {
            for (key, setup) in &machine.index {
                let Some(kind) = setup.get_ref().kind.as_ref() else {
                    continue;
                };
                if kind.get_ref().to_ascii_lowercase().starts_with("rotary") {
                    problems.push(
                        Problem::error(
                            "pacer::machine::index",
                            span_of(kind),
                            format!("[index.{key}] is rotary, but the axis has no rollover"),
                            "needs [machine] rollover",
                        )
                        .with_help("set e.g. rollover = 360.0 under [machine]"),
                    );
                }
            }
        }
        (registry, problems)
    }

    /// `[index.N]` sections: type and time base, and initial member values.
    fn index_setups(&mut self, machine: &MachineFile, problems: &mut Vec<Problem>) {
        let count = self.index_setups.len() as u32;
        for (key, setup) in &machine.index {
            let span = span_of(setup);
            let Some(n) = section_instance(
                key,
                count,
                span,
                "pacer::machine::index",
                "index",
                ("index", "indexes"),
                problems,
            ) else {
                continue;
            };
            let s = setup.get_ref();
            let mut config = IndexConfig::default();
            if let Some(k) = &s.kind {
                match k.get_ref().to_ascii_lowercase().as_str() {
                    "incremental" => config.kind = IndexType::Incremental,
                    "absolute" => config.kind = IndexType::Absolute,
                    "registration" => config.kind = IndexType::Registration,
                    "rotaryplus" | "rotary plus" => config.kind = IndexType::RotaryPlus,
                    "rotaryminus" | "rotary minus" => config.kind = IndexType::RotaryMinus,
                    _ => problems.push(Problem::error(
                        "pacer::machine::index",
                        span_of(k),
                        format!("unknown index type `{}`", k.get_ref()),
                        "Incremental, Absolute, Registration, RotaryPlus or RotaryMinus",
                    )),
                }
            }
            if let Some(tb) = &s.time_base {
                match tb.get_ref().to_ascii_lowercase().as_str() {
                    "realtime" => config.synchronized = false,
                    "synchronized" => config.synchronized = true,
                    _ => problems.push(Problem::error(
                        "pacer::machine::index",
                        span_of(tb),
                        format!("unknown time base `{}`", tb.get_ref()),
                        "Realtime or Synchronized",
                    )),
                }
            }
            config.timed = s.time.is_some();
            self.index_setups[n as usize] = config;
            for (member, value) in [
                ("Time", s.time),
                ("Distance", s.distance),
                ("Velocity", s.velocity),
                ("Acceleration", s.acceleration),
                ("Deceleration", s.deceleration),
                ("RegistrationOffset", s.registration_offset),
            ] {
                if let Some(v) = value {
                    let signed = matches!(member, "Distance" | "RegistrationOffset");
                    if !v.is_finite() || (!signed && v <= 0.0) {
                        problems.push(Problem::error(
                            "pacer::machine::index",
                            span,
                            format!(
                                "[index.{n}] {}: {v} is out of range",
                                member.to_ascii_lowercase()
                            ),
                            "must be a number (above 0 for rates)",
                        ));
                    } else {
                        self.set_initial(Kind::Index, n, member, v);
                    }
                }
            }
        }
    }

    /// `[home.N]` sections: the reference input, initial members, specified or calculated offset.
    fn home_setups(&mut self, machine: &MachineFile, problems: &mut Vec<Problem>) {
        let count = self.home_setups.len() as u32;
        for (key, setup) in &machine.home {
            let span = span_of(setup);
            let Some(n) = section_instance(
                key,
                count,
                span,
                "pacer::machine::home",
                "home",
                ("home", "homes"),
                problems,
            ) else {
                continue;
            };
            let s = setup.get_ref();
            let reference = self.resolve_text(&s.reference).ok();
            match reference {
                Some(r)
                    if r.ty.is_bit()
                        && matches!(
                            r.kind,
                            Kind::DriveInput | Kind::ModuleInput | Kind::DriveIO
                        ) =>
                {
                    self.home_setups[n as usize] = HomeConfig {
                        reference: Some(r.slot),
                        specified_offset: s.offset.is_some(),
                    };
                }
                _ => problems.push(
                    Problem::error(
                        "pacer::machine::home",
                        span_of(&s.reference),
                        format!("`{}` is not an input", s.reference.get_ref()),
                        "the home reference must be an input",
                    )
                    .with_help("e.g. reference = \"ModuleInput.3\""),
                ),
            }
            for (member, value) in [
                ("Velocity", s.velocity),
                ("Acceleration", s.acceleration),
                ("Deceleration", s.deceleration),
                ("Offset", s.offset),
            ] {
                if let Some(v) = value {
                    let rate = matches!(member, "Acceleration" | "Deceleration");
                    if !v.is_finite() || (rate && v <= 0.0) || (member == "Velocity" && v == 0.0) {
                        problems.push(Problem::error(
                            "pacer::machine::home",
                            span,
                            format!(
                                "[home.{n}] {}: {v} is out of range",
                                member.to_ascii_lowercase()
                            ),
                            "must be a number (not 0 for a velocity, above 0 for a rate)",
                        ));
                    } else {
                        self.set_initial(Kind::Home, n, member, v);
                    }
                }
            }
        }
    }

    /// `[pls.N]` sections: source, rollover, initial window and direction.
    fn pls_setups(&mut self, machine: &MachineFile, problems: &mut Vec<Problem>) {
        let count = self.pls_setups.len() as u32;
        for (key, setup) in &machine.pls {
            let span = span_of(setup);
            let Some(n) = section_instance(
                key,
                count,
                span,
                "pacer::machine::pls",
                "pls",
                ("PLS", "PLS"),
                problems,
            ) else {
                continue;
            };
            let s = setup.get_ref();
            let mut config = PlsConfig {
                rollover: s.rollover,
                ..PlsConfig::default()
            };
            if !(s.rollover.is_finite() && s.rollover >= 0.0) {
                problems.push(Problem::error(
                    "pacer::machine::pls",
                    span,
                    format!("[pls.{n}] rollover {} must be 0 or more", s.rollover),
                    "out of range",
                ));
            }
            if let Some(src) = &s.source {
                match src.get_ref().to_ascii_lowercase().as_str() {
                    "masterposn" => config.source = QueueSource::Master,
                    "feedbackposn" => config.source = QueueSource::Feedback,
                    "commandposn" => config.source = QueueSource::Command,
                    _ => problems.push(Problem::error(
                        "pacer::machine::pls",
                        span_of(src),
                        format!("unknown PLS source `{}`", src.get_ref()),
                        "MasterPosn, FeedbackPosn or CommandPosn",
                    )),
                }
            }
            self.pls_setups[n as usize] = config;
            for (member, value) in [("OnPosn", s.on), ("OffPosn", s.off)] {
                if let Some(v) = value {
                    self.set_initial(Kind::Pls, n, member, v);
                }
            }
            if let Some(d) = &s.direction {
                let dir = match d.get_ref().to_ascii_lowercase().as_str() {
                    "both" => Some(0.0),
                    "plus" => Some(1.0),
                    "minus" => Some(-1.0),
                    _ => None,
                };
                match dir {
                    Some(x) => self.set_initial(Kind::Pls, n, "Direction", x),
                    None => problems.push(Problem::error(
                        "pacer::machine::pls",
                        span_of(d),
                        format!("unknown direction `{}`", d.get_ref()),
                        "Both, Plus or Minus",
                    )),
                }
            }
        }
    }

    /// The instances of a type.
    pub fn of(&self, kind: Kind) -> &TypeInstances {
        // The registry holds every catalog type, so the lookup cannot fail.
        self.types
            .iter()
            .find(|t| t.def.kind == kind)
            .unwrap_or(&self.types[0])
    }

    /// The slot of a member by name (for kernel code that knows its members). The one
    /// instance of a global type (`Gear`, `PickPlace`) is 0, or [`GLOBAL_INSTANCE`]. None when
    /// the machine has no such instance (no `[pickplace]`: no `PickPlace` slots).
    pub fn slot_of(&self, kind: Kind, instance: u32, member: &str) -> Option<SlotId> {
        let t = self.of(kind);
        let instance = if instance == GLOBAL_INSTANCE && t.def.instances == Instances::Global {
            0
        } else {
            instance
        };
        if instance == GLOBAL_INSTANCE {
            let idx = t.def.global_members.iter().position(|m| m.name == member)?;
            return Some(t.slot(0, idx, true));
        }
        let idx = t.def.members.iter().position(|m| m.name == member)?;
        (instance < t.count).then(|| t.slot(instance, idx, false))
    }

    fn set_initial(&mut self, kind: Kind, instance: u32, member: &str, value: f64) {
        if let Some(s) = self.slot_of(kind, instance, member) {
            self.slots[s as usize].initial = value;
        }
    }

    /// Number of slots.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }
}

fn default_value(kind: Kind, member: &MemberDef) -> f64 {
    match (kind, member.name) {
        (Kind::Queue, "QueueEmpty") => 1.0,
        (Kind::Queue, "QueueSize" | "FullLevel") => 8.0,
        (Kind::Program, "Task") => -1.0,
        (Kind::Motion, "FeedRateOverride") => 100.0,
        (Kind::Pls, "Enable") => 1.0,
        _ => member.initial,
    }
}

/// The DSP axis numbers `[axis.N]` defines, checking each set-up.
fn axis_numbers(machine: &MachineFile, problems: &mut Vec<Problem>) -> Vec<u32> {
    let mut numbers = Vec::new();
    for (key, setup) in &machine.axis {
        let span = span_of(setup);
        let n = match key.parse::<u32>() {
            Ok(n) if (1..=16).contains(&n) => n,
            _ => {
                problems.push(Problem::error(
                    "pacer::machine::axis",
                    span,
                    format!("`axis.{key}`: axes are numbered 1 to 16"),
                    "not an axis number",
                ));
                continue;
            }
        };
        numbers.push(n);
    }
    for (key, setup) in &machine.axis {
        let s = setup.get_ref();
        let positive = |v: &Option<toml::Spanned<f64>>, what: &str, p: &mut Vec<Problem>| {
            if let Some(v) = v {
                if !(v.get_ref().is_finite() && *v.get_ref() > 0.0) {
                    p.push(Problem::error(
                        "pacer::machine::axis",
                        span_of(v),
                        format!("axis.{key}: {what} must be a positive number"),
                        "not positive",
                    ));
                }
            }
        };
        positive(&s.units_per_rev, "units_per_rev", problems);
        positive(&s.accel, "accel", problems);
        positive(&s.speed, "speed", problems);
        if let Some(q) = &s.queue {
            if !(1..=64).contains(q.get_ref()) {
                problems.push(Problem::error(
                    "pacer::machine::axis",
                    span_of(q),
                    format!("axis.{key}: a queue of {} moves", q.get_ref()),
                    "1 to 64",
                ));
            }
        }
        if let Some(p) = &s.pacer {
            let n = *p.get_ref();
            if !numbers.contains(&n) || key.parse::<u32>().ok() == Some(n) {
                problems.push(
                    Problem::error(
                        "pacer::machine::axis",
                        span_of(p),
                        format!("axis.{key}: pacer {n} is not another axis of this machine"),
                        "no such axis",
                    )
                    .with_help(format!("axes defined: {numbers:?}")),
                );
            }
        }
    }
    numbers
}

fn valid_ident(s: &str) -> bool {
    let mut c = s.chars();
    matches!(c.next(), Some(ch) if ch.is_ascii_alphabetic() || ch == '_')
        && c.all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
}

pub use crate::fixed::{round_to, POW10};

/// The instance a `[section.N]` key names, or a problem located on the section; `what` is its
/// object in the singular and the plural.
fn section_instance(
    key: &str,
    count: u32,
    span: Span,
    code: &'static str,
    section: &str,
    what: (&str, &str),
    problems: &mut Vec<Problem>,
) -> Option<u32> {
    let n = key.parse::<u32>().ok().filter(|n| *n < count);
    if n.is_none() {
        problems.push(Problem::error(
            code,
            span,
            format!("[{section}.{key}]: no such {}", what.0),
            format!("{} are 0 to {}", what.1, count.saturating_sub(1)),
        ));
    }
    n
}

const CODE_PICKPLACE: &str = "pacer::machine::pickplace";

/// The belt sections `[pickplace.belt.N]`, checked: the valid ones, number and table.
pub fn belt_sections<'m>(
    machine: &'m MachineFile,
    mut problems: Option<&mut Vec<Problem>>,
) -> Vec<(u32, &'m TomlTable)> {
    let mut belts = Vec::new();
    let Some(pp) = &machine.pickplace else {
        return belts;
    };
    let Some(value) = pp.get_ref().get("belt") else {
        return belts;
    };
    let TomlValue::Table(table) = value.get_ref() else {
        if let Some(p) = problems.as_deref_mut() {
            p.push(
                Problem::error(
                    CODE_PICKPLACE,
                    span_of(value),
                    format!(
                        "`belt` is {}, not a table of belts",
                        value.get_ref().describe()
                    ),
                    "not a table",
                )
                .with_help("give each belt a section: [pickplace.belt.1]"),
            );
        }
        return belts;
    };
    for (key, section) in &table.entries {
        let number = key
            .get_ref()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=catalog::MAX_BELTS).contains(n));
        let Some(n) = number else {
            if let Some(p) = problems.as_deref_mut() {
                p.push(
                    Problem::error(
                        CODE_PICKPLACE,
                        span_of(key),
                        format!("[pickplace.belt.{}]: no such belt", key.get_ref()),
                        "not a belt number",
                    )
                    .with_help(format!(
                        "belts are numbered 1 to {} (CV1 … CV{})",
                        catalog::MAX_BELTS,
                        catalog::MAX_BELTS
                    )),
                );
            }
            continue;
        };
        if belts.iter().any(|(m, _)| *m == n) {
            if let Some(p) = problems.as_deref_mut() {
                p.push(Problem::error(
                    CODE_PICKPLACE,
                    span_of(key),
                    format!("belt {n} is set up twice"),
                    "again",
                ));
            }
            continue;
        }
        match section.get_ref() {
            TomlValue::Table(t) => belts.push((n, t)),
            other => {
                if let Some(p) = problems.as_deref_mut() {
                    p.push(
                        Problem::error(
                            CODE_PICKPLACE,
                            span_of(section),
                            format!("belt {n} is {}, not a table", other.describe()),
                            "not a table",
                        )
                        .with_help(format!("write its settings under [pickplace.belt.{n}]")),
                    );
                }
            }
        }
    }
    belts.sort_by_key(|(n, _)| *n);
    belts
}

/// The number of belts: the highest `[pickplace.belt.N]`; reports bad belt numbers.
fn belt_count(machine: &MachineFile, problems: &mut Vec<Problem>) -> u32 {
    belt_sections(machine, Some(problems))
        .iter()
        .map(|(n, _)| *n)
        .max()
        .unwrap_or(0)
}

impl Registry {
    /// `[pickplace]` and `[pickplace.belt.N]`: the initial values of the members they name.
    /// The other keys (kinematics, limits) are `load::pickplace::setup`'s.
    fn pickplace_initials(&mut self, machine: &MachineFile, problems: &mut Vec<Problem>) {
        let Some(pp) = &machine.pickplace else {
            return;
        };
        for (key, value) in &pp.get_ref().entries {
            if !PICKPLACE_SETUP_KEYS.contains(&key.get_ref().as_str()) {
                self.member_initial(Kind::PickPlace, 0, key, value, problems);
            }
        }
        for (n, table) in belt_sections(machine, None) {
            for (key, value) in &table.entries {
                if !BELT_SETUP_KEYS.contains(&key.get_ref().as_str()) {
                    self.member_initial(Kind::Belt, n - 1, key, value, problems);
                }
            }
        }
    }

    /// One `key = value` of a pick & place section: a member, an element (`"alrStopDec[2]"`)
    /// or a whole array (`alrStopDec = [ … ]`).
    fn member_initial(
        &mut self,
        kind: Kind,
        instance: u32,
        key: &toml::Spanned<String>,
        value: &toml::Spanned<TomlValue>,
        problems: &mut Vec<Problem>,
    ) {
        let t = self.of(kind);
        let members = t.def.members;
        let (section, setup_keys) = if kind == Kind::Belt {
            (
                format!("[pickplace.belt.{}]", instance + 1),
                BELT_SETUP_KEYS,
            )
        } else {
            ("[pickplace]".to_string(), PICKPLACE_SETUP_KEYS)
        };
        let name = key.get_ref().as_str();
        let (first, len, array) = match catalog::member_position(members, name) {
            Some(i) => (i, 1, false),
            None => match catalog::find_array(members, name) {
                Some((first, len)) => (first, len, true),
                None => {
                    problems.push(unknown_key(key, members, setup_keys, &section));
                    return;
                }
            },
        };
        let def = &members[first];
        if def.access != Access::ReadWrite {
            let what = if kind == Kind::Belt {
                "a status of the belt"
            } else {
                "an output of the module"
            };
            problems.push(
                Problem::error(
                    CODE_PICKPLACE,
                    span_of(key),
                    format!(
                        "{section}: `{}` is {what}; it cannot be given a value",
                        base_name(def.name, array)
                    ),
                    "read-only",
                )
                .with_help("only inputs and parameters take values here"),
            );
            return;
        }
        let slots: Vec<SlotId> = (0..len)
            .map(|i| t.slot(instance, first + i, false))
            .collect();
        if !array {
            if let Some(x) = member_value(def, value, &section, problems) {
                self.slots[slots[0] as usize].initial = x;
            }
            return;
        }
        let base = base_name(def.name, true);
        let TomlValue::Array(items) = value.get_ref() else {
            problems.push(
                Problem::error(
                    CODE_PICKPLACE,
                    span_of(value),
                    format!(
                        "{section}: `{base}` is an array of {len}: it takes {len} values, not {}",
                        value.get_ref().describe()
                    ),
                    "not an array",
                )
                .with_help(format!(
                    "give all {len} values in [ ], or one element as \"{base}[1]\" = …"
                )),
            );
            return;
        };
        if items.len() != len {
            problems.push(
                Problem::error(
                    CODE_PICKPLACE,
                    span_of(value),
                    format!(
                        "{section}: `{base}` has {len} elements, not {}",
                        items.len()
                    ),
                    format!("{} values", items.len()),
                )
                .with_help(format!(
                    "give exactly {len} values, or set single elements as \"{base}[k]\" = …"
                )),
            );
            return;
        }
        for (i, item) in items.iter().enumerate() {
            if let Some(x) = member_value(&members[first + i], item, &section, problems) {
                self.slots[slots[i] as usize].initial = x;
            }
        }
    }
}

/// `alrStopDec[1]` → `alrStopDec` for an array's element.
fn base_name(name: &str, array: bool) -> &str {
    match catalog::split_index(name) {
        Some((base, _)) if array => base,
        _ => name,
    }
}

/// The problem for a key of a pick & place section that names nothing.
fn unknown_key(
    key: &toml::Spanned<String>,
    members: &'static [MemberDef],
    setup_keys: &[&'static str],
    section: &str,
) -> Problem {
    let name = key.get_ref();
    let span = span_of(key);
    if let Some((base, index)) = catalog::split_index(name) {
        if let Some((_, len)) = catalog::find_array(members, base) {
            return Problem::error(
                CODE_PICKPLACE,
                span,
                format!("{section}: `{name}`: {base} has no element {index}"),
                "index out of range",
            )
            .with_help(format!("its elements are {base}[1] to {base}[{len}]"));
        }
    }
    let mut candidates: Vec<&str> = setup_keys.to_vec();
    for m in members {
        let base = base_name(m.name, true);
        if !candidates.contains(&base) {
            candidates.push(base);
        }
    }
    let help = match nearest(name, candidates.iter().copied()) {
        Some(n) => format!("did you mean `{n}`?"),
        None => format!(
            "keys are the manual's names of the inputs and parameters, and {}",
            setup_keys.join(", ")
        ),
    };
    Problem::error(
        CODE_PICKPLACE,
        span,
        format!("{section}: unknown key `{name}`"),
        "unknown key",
    )
    .with_help(help)
}

/// The value `value` gives the member `def`, or a problem located on it.
fn member_value(
    def: &MemberDef,
    value: &toml::Spanned<TomlValue>,
    section: &str,
    problems: &mut Vec<Problem>,
) -> Option<f64> {
    let v = value.get_ref();
    let span = span_of(value);
    let name = format!("{section}: `{}`", def.name);
    let problem = |message: String, label: &str, help: &str| {
        Problem::error(CODE_PICKPLACE, span, message, label).with_help(help)
    };
    let result = match (def.ty, v) {
        (ValueType::Bit, TomlValue::Bool(b)) => Ok(f64::from(u8::from(*b))),
        (ValueType::Bit, TomlValue::Integer(i @ (0 | 1))) => Ok(*i as f64),
        (ValueType::Bit, _) => Err(problem(
            format!("{name} is a bit, not {}", v.describe()),
            "not a bit",
            "give true or false (or 1 or 0)",
        )),
        (_, TomlValue::Float(x)) if !x.is_finite() => Err(problem(
            format!("{name} must be a finite number, not {x}"),
            "not finite",
            "give a finite number",
        )),
        (ValueType::Integer | ValueType::Fixed(_), _) => match v.as_number() {
            Some(x)
                if x.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&x) =>
            {
                Ok(x)
            }
            Some(x) => Err(problem(
                format!("{name} is an integer: {x} is not one"),
                "not an integer",
                "give a whole number",
            )),
            None => Err(problem(
                format!("{name} takes an integer, not {}", v.describe()),
                "not an integer",
                "give a whole number",
            )),
        },
        (ValueType::Real, _) => v.as_number().ok_or_else(|| {
            problem(
                format!("{name} takes a number, not {}", v.describe()),
                "not a number",
                "give a number, e.g. 100.0",
            )
        }),
    };
    result.map_err(|p| problems.push(p)).ok()
}
