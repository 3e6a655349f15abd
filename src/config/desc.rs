//! The typed description of a machine and its world, as the configuration stage leaves it:
//! every value checked, every name resolved. The registry and the devices are built from it
//! and cannot fail.

use crate::devices::drive::setup::DriveSetup;
use crate::devices::drive::AxisMarks;
use crate::devices::orion::MarkTrack;
use crate::devices::pickplace::setup::PickPlaceSetup;
use crate::io::map::IoMap;
use crate::registry::{Resolved, SlotId};
use crate::world::belt::BeltProfile;
use crate::world::master::MasterProfile;
use crate::world::products::Product;
use crate::world::workpieces::WorkpieceFeed;
use crate::world::Edge;
use indexmap::IndexMap;

pub use crate::registry::objects::{BitsDesc, Initial, ObjectsDesc, VarDesc};

/// One DSP axis (`[axis.N]`).
pub type DspAxisDesc = crate::devices::orion::AxisSetUp;

/// An assignment: a bit source drives a destination member every update.
#[derive(Debug, Clone)]
pub struct Assignment {
    /// Source slots (bits) with their polarity (Active Off: on while the source is off). Several
    /// sources assigned to one destination are ORed, as on the drive.
    pub sources: Vec<(SlotId, bool)>,
    /// The destination member.
    pub dest: Resolved,
    /// A source latches in hardware (a module input): its edges carry exact times.
    pub latched: bool,
}

/// A program `machine.toml` lists (`[[program]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct ProgramDesc {
    /// Its number.
    pub number: u32,
    /// Its file, as written (relative to the machine file).
    pub file: String,
    /// It starts with the run.
    pub autostart: bool,
    /// Where the entry names the file.
    pub span: crate::span::Span,
}

/// A machine, checked.
#[derive(Debug, Clone)]
pub struct MachineDesc {
    /// Its name, if the file gives one.
    pub name: Option<String>,
    /// Update period, ns.
    pub update_ns: u64,
    /// Instructions per task turn.
    pub budget: u64,
    /// Number of tasks.
    pub tasks: usize,
    /// Its objects.
    pub objects: ObjectsDesc,
    /// The drive's set-up.
    pub drive: DriveSetup,
    /// The DSP axes, in file order.
    pub dsp: Vec<DspAxisDesc>,
    /// The pick & place module's set-up, when it has one.
    pub pickplace: Option<PickPlaceSetup>,
    /// Assignments in file order (several sources of one destination merged).
    pub assignments: Vec<Assignment>,
    /// The Modbus map, when `[modbus]` gives one.
    pub io_map: Option<IoMap>,
}

/// A scenario, checked: the world the machine runs in.
#[derive(Debug, Clone, Default)]
pub struct ScenarioDesc {
    /// Input edges.
    pub edges: Vec<Edge>,
    /// The master axis.
    pub master: MasterProfile,
    /// Sensors tied to the servo axis.
    pub axis_marks: Vec<AxisMarks>,
    /// The products, per stream: the sensor slot and the products.
    pub products: Vec<(SlotId, Vec<Product>)>,
    /// Marks on the DSP axes.
    pub mark_tracks: Vec<MarkTrack>,
    /// The pick & place belts' speed profiles, by belt number.
    pub belt_profiles: IndexMap<u32, BeltProfile>,
    /// The workpieces the belts bring.
    pub feeds: Vec<WorkpieceFeed>,
    /// The run's duration, if the scenario sets one.
    pub duration_ns: Option<u64>,
    /// `[run] seed`, if the scenario sets one (MotionBASIC's RND starts from it).
    pub seed: Option<u64>,
}
