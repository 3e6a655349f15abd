//! The Modbus map a machine runs with: where the coupler is, and every point bound to a member
//! slot with its direction, width, scaling and safe value (`config::modbus` checks
//! `machine.toml`'s `[modbus]` into it).

use crate::registry::{SlotId, ValueType};

/// Default TCP port of Modbus TCP.
pub const DEFAULT_PORT: u16 = 502;
/// Default unit id.
pub const DEFAULT_UNIT: u8 = 1;
/// Default time a request may take, nanoseconds (100 ms).
pub const DEFAULT_TIMEOUT_NS: u64 = 100_000_000;
/// The largest `max_gap` accepted (a register read holds at most 125 registers).
pub const MAX_GAP: u16 = 125;
/// Consecutive overruns that make a real-time fault unless the machine file says otherwise.
pub const DEFAULT_OVERRUN_LIMIT: u64 = 10;
/// Default exchange cycle of the process image, nanoseconds (5 ms: a cycle remote-I/O couplers
/// on Modbus TCP serve comfortably, short against mechanical inputs and outputs).
pub const DEFAULT_PERIOD_NS: u64 = 5_000_000;
/// Default oldest input image an update accepts, nanoseconds (100 ms).
pub const DEFAULT_MAX_AGE_NS: u64 = 100_000_000;

/// The four Modbus data tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Table {
    /// Read/write bits: pacer writes them (outputs).
    Coil,
    /// Read-only bits: pacer reads them (inputs).
    DiscreteInput,
    /// Read/write 16-bit registers: pacer writes them (outputs).
    HoldingRegister,
    /// Read-only 16-bit registers: pacer reads them (inputs).
    InputRegister,
}

/// The names of the tables as written in `machine.toml`, in [`Table::ALL`] order.
pub const TABLE_NAMES: [&str; 4] = [
    "coil",
    "discrete_input",
    "holding_register",
    "input_register",
];

impl Table {
    /// Every table, in the order requests are issued.
    pub const ALL: [Table; 4] = [
        Table::Coil,
        Table::DiscreteInput,
        Table::HoldingRegister,
        Table::InputRegister,
    ];

    /// The table named `name` in `machine.toml`.
    pub fn from_name(name: &str) -> Option<Table> {
        TABLE_NAMES
            .iter()
            .position(|n| n.eq_ignore_ascii_case(name))
            .map(|i| Table::ALL[i])
    }

    /// The name as written in `machine.toml`.
    pub fn name(self) -> &'static str {
        TABLE_NAMES[self as usize]
    }

    /// True for coils and discrete inputs.
    pub fn is_bit(self) -> bool {
        matches!(self, Table::Coil | Table::DiscreteInput)
    }

    /// True for the tables pacer writes (coils, holding registers).
    pub fn is_output(self) -> bool {
        matches!(self, Table::Coil | Table::HoldingRegister)
    }

    /// The most points one read request may cover (Modbus application protocol 1.1b3:
    /// functions 1/2 read 2000 bits, functions 3/4 read 125 registers).
    pub fn max_read(self) -> u16 {
        if self.is_bit() {
            2000
        } else {
            125
        }
    }

    /// The most points one write request may cover (function 15: 1968 coils, function 16: 123
    /// registers); 0 for the read-only tables.
    pub fn max_write(self) -> u16 {
        match self {
            Table::Coil => 1968,
            Table::HoldingRegister => 123,
            _ => 0,
        }
    }
}

/// One mapped point: a bit, or a 16- or 32-bit register value, bound to one member slot.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Its table.
    pub table: Table,
    /// Its (first) address.
    pub address: u16,
    /// Addresses it covers: 1, or 2 for a 32-bit register value (high word first).
    pub width: u16,
    /// The member slot it reads into or writes from.
    pub slot: SlotId,
    /// The member's canonical name (for fault messages and the trace).
    pub member: String,
    /// Engineering value = raw × scale + offset.
    pub scale: f64,
    /// See `scale`.
    pub offset: f64,
    /// The raw register value is two's complement.
    pub signed: bool,
    /// Outputs: the value written in the safe state (member units).
    pub safe: f64,
    /// The member is a digital I/O point (`DriveIO.N.Out` …), not a program's variable: on a
    /// fault the machine's own value takes the safe value too, so the trace shows the output
    /// as the device has it. A variable fed to a register keeps its value (the program's data).
    pub io_point: bool,
    /// The member's value type: a value read from the device is stored as the member holds
    /// it (rounded to its decimal places, within its 32-bit range).
    pub ty: ValueType,
}

impl Point {
    /// A value read from the device as the member stores it, and whether it fitted: bits are
    /// 0/1; integers and fixed-point values are rounded to their places and, when outside
    /// their 32-bit range, held at its nearest end.
    pub fn store(&self, x: f64) -> (f64, bool) {
        let decimals = match self.ty {
            ValueType::Bit => return (f64::from(x != 0.0), true),
            ValueType::Real => return (x, true),
            ValueType::Integer => 0,
            ValueType::Fixed(d) => d,
        };
        match crate::fixed::to_fixed(x, decimals) {
            Some(v) => (v, true),
            None => {
                let scale = crate::fixed::POW10[usize::from(decimals.min(9))];
                let end = if x < 0.0 { i32::MIN } else { i32::MAX };
                (f64::from(end) / scale, false)
            }
        }
    }

    /// One past its last address (as u32: the last point may end at 65536).
    pub fn end(&self) -> u32 {
        u32::from(self.address) + u32::from(self.width)
    }

    /// The member value of raw words read from the device (`words.len()` is `width`; a bit is
    /// one word, 0 or 1).
    pub fn decode(&self, words: &[u16]) -> f64 {
        if self.table.is_bit() {
            return if words.first().copied().unwrap_or(0) != 0 {
                1.0
            } else {
                0.0
            };
        }
        let raw: f64 = match (self.width, self.signed) {
            (2, false) => f64::from(combine(words)),
            (2, true) => f64::from(combine(words) as i32),
            (_, false) => f64::from(words.first().copied().unwrap_or(0)),
            (_, true) => f64::from(words.first().copied().unwrap_or(0) as i16),
        };
        raw * self.scale + self.offset
    }

    /// The raw words for a member value: (value − offset) / scale rounded to the nearest raw
    /// value and saturated to the raw range. The flag is true when it saturated (the value
    /// did not fit).
    pub fn encode(&self, value: f64) -> (Vec<u16>, bool) {
        if self.table.is_bit() {
            return (vec![u16::from(value != 0.0)], false);
        }
        let raw = ((value - self.offset) / self.scale).round();
        let (lo, hi) = match (self.width, self.signed) {
            (2, false) => (0.0, f64::from(u32::MAX)),
            (2, true) => (f64::from(i32::MIN), f64::from(i32::MAX)),
            (_, false) => (0.0, f64::from(u16::MAX)),
            (_, true) => (f64::from(i16::MIN), f64::from(i16::MAX)),
        };
        let saturated = raw.is_nan() || raw < lo || raw > hi;
        let clamped = if raw.is_nan() { 0.0 } else { raw.clamp(lo, hi) };
        let words = match (self.width, self.signed) {
            (2, false) => split(clamped as u32),
            (2, true) => split(clamped as i32 as u32),
            (_, false) => vec![clamped as u16],
            (_, true) => vec![clamped as i16 as u16],
        };
        (words, saturated)
    }
}

fn combine(words: &[u16]) -> u32 {
    let hi = u32::from(words.first().copied().unwrap_or(0));
    let lo = u32::from(words.get(1).copied().unwrap_or(0));
    (hi << 16) | lo
}

fn split(v: u32) -> Vec<u16> {
    vec![(v >> 16) as u16, (v & 0xffff) as u16]
}

/// A validated Modbus set-up: where the coupler is and every mapped point.
#[derive(Debug, Clone, PartialEq)]
pub struct IoMap {
    /// Host from the machine file (the command line may give one instead).
    pub host: Option<String>,
    /// TCP port.
    pub port: u16,
    /// Unit id.
    pub unit: u8,
    /// Time one request may take, nanoseconds.
    pub timeout_ns: u64,
    /// Unused addresses a read may span to merge two groups.
    pub max_gap: u16,
    /// Run on the coupler unless `--io sim` is given.
    pub enabled: bool,
    /// Consecutive overruns that make a real-time fault (0: never).
    pub overrun_limit: u64,
    /// The process image's exchange cycle, nanoseconds.
    pub period_ns: u64,
    /// The oldest input image an update accepts, nanoseconds.
    pub max_age_ns: u64,
    /// The points, in the order of the map (a run of bits is one point per bit).
    pub points: Vec<Point>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reg(width: u16, signed: bool, scale: f64, offset: f64) -> Point {
        Point {
            table: Table::HoldingRegister,
            address: 0,
            width,
            slot: 0,
            member: "Var.X".into(),
            scale,
            offset,
            signed,
            safe: 0.0,
            io_point: false,
            ty: ValueType::Real,
        }
    }

    #[test]
    fn values_read_are_stored_as_their_member_holds_them() {
        let mut p = reg(2, false, 0.1, 0.0);
        p.ty = ValueType::Fixed(1);
        // 2475 × 0.1 is 247.50000000000003 in binary: stored as the variable's 247.5.
        assert_eq!(p.store(p.decode(&[0, 2475])), (247.5, true));
        p.ty = ValueType::Integer;
        p.scale = 1.0;
        // An unsigned 32-bit count past the signed range is held at its end, and said.
        assert_eq!(
            p.store(p.decode(&[0xFFFF, 0xFFFF])),
            (f64::from(i32::MAX), false)
        );
        assert_eq!(p.store(-3e9), (f64::from(i32::MIN), false));
        p.ty = ValueType::Fixed(3);
        assert_eq!(p.store(3e6), (f64::from(i32::MAX) / 1000.0, false));
        p.ty = ValueType::Bit;
        assert_eq!(p.store(5.0), (1.0, true));
        p.ty = ValueType::Real;
        assert_eq!(p.store(4294967295.0), (4294967295.0, true));
    }

    #[test]
    fn registers_scale_both_ways() {
        let p = reg(1, false, 0.1, -5.0);
        assert_eq!(p.encode(20.0), (vec![250], false));
        assert!((p.decode(&[250]) - 20.0).abs() < 1e-9);
        // Below the raw range: saturated at 0, and said so.
        assert_eq!(p.encode(-10.0), (vec![0], true));
    }

    #[test]
    fn signed_and_32_bit_values() {
        let p = reg(1, true, 1.0, 0.0);
        assert_eq!(p.encode(-2.0), (vec![0xfffe], false));
        assert_eq!(p.decode(&[0xfffe]), -2.0);
        assert_eq!(p.encode(40000.0), (vec![0x7fff], true));
        let p = reg(2, true, 1.0, 0.0);
        assert_eq!(p.encode(-70000.0), (vec![0xfffe, 0xee90], false));
        assert_eq!(p.decode(&[0xfffe, 0xee90]), -70000.0);
        let p = reg(2, false, 1.0, 0.0);
        assert_eq!(p.encode(65537.0), (vec![1, 1], false));
        assert_eq!(p.decode(&[1, 1]), 65537.0);
    }

    #[test]
    fn tables_by_name() {
        assert_eq!(Table::from_name("Coil"), Some(Table::Coil));
        assert_eq!(
            Table::from_name("input_register"),
            Some(Table::InputRegister)
        );
        assert_eq!(Table::from_name("register"), None);
        assert!(Table::HoldingRegister.is_output());
        assert!(!Table::DiscreteInput.is_output());
    }
}
