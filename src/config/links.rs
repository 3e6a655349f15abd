//! The names `machine.toml` writes as text, resolved against the registry: assignments (source
//! → destination), each home's reference input and the inputs wired to DSP axes' fast inputs.
//! Every name that does not resolve, or names the wrong kind of member, is a problem located in
//! the string.

use super::desc::{Assignment, DspAxisDesc};
use super::machine::MachineFile;
use super::span_of;
use crate::devices::drive::setup::{DriveSetup, HomeConfig};
use crate::diag::Problem;
use crate::registry::{Access, Hook, Kind, Registry, Resolved};

/// Resolve a member name written as a TOML string, reporting a problem in place.
pub fn resolve_text(
    reg: &Registry,
    text: &toml::Spanned<String>,
    problems: &mut Vec<Problem>,
) -> Option<Resolved> {
    reg.resolve_text(text).map_err(|p| problems.push(p)).ok()
}

/// `[[assignment]]` entries, sources of one destination merged (ORed), in file order.
pub fn assignments(
    machine: &MachineFile,
    reg: &Registry,
    programs: &[u32],
    problems: &mut Vec<Problem>,
) -> Vec<Assignment> {
    let mut assignments: Vec<Assignment> = Vec::new();
    for a in &machine.assignments {
        let src = resolve_text(reg, &a.source, problems);
        let dst = resolve_text(reg, &a.destination, problems);
        let active_off = match &a.polarity {
            None => false,
            Some(p) => match p
                .get_ref()
                .to_ascii_lowercase()
                .replace([' ', '_'], "")
                .as_str()
            {
                "activeon" => false,
                "activeoff" => true,
                _ => {
                    problems.push(Problem::error(
                        "pacer::machine::assignment",
                        span_of(p),
                        format!("unknown polarity `{}`", p.get_ref()),
                        "ActiveOn or ActiveOff",
                    ));
                    false
                }
            },
        };
        let (Some(s), Some(d)) = (src, dst) else {
            continue;
        };
        if !s.ty.is_bit() || matches!(s.access, Access::Action | Access::Input) {
            problems.push(
                Problem::error(
                    "pacer::machine::assignment",
                    span_of(&a.source),
                    format!("{} cannot be an assignment source", s.name),
                    "not a readable bit",
                )
                .with_help("sources are bits: inputs, status bits, user bits"),
            );
            continue;
        }
        if !d.ty.is_bit() || d.access == Access::Read || d.access == Access::Input {
            problems.push(Problem::error("pacer::machine::assignment", span_of(&a.destination), format!("{} cannot be an assignment destination", d.name), "not a writable bit or action")
                .with_help("destinations are actions (Program.1.Initiate) or writable bits (DriveIO.1.Out, Capture.0.CaptureActivate)"));
            continue;
        }
        // A compound index runs into the index its program initiates next: an assignment has
        // no next instruction.
        if d.kind == Kind::Index && d.name.ends_with(".CompoundInitiate") {
            problems.push(
                Problem::error(
                    "pacer::machine::assignment",
                    span_of(&a.destination),
                    format!("{} cannot be an assignment destination", d.name),
                    "a compound index needs a program",
                )
                .with_help(
                    "a compound index runs on into the index its program initiates on the next \
                     line; assign Index.N.Initiate, or initiate the chain from a program",
                ),
            );
            continue;
        }
        if d.hook == Hook::ProgramInitiate && !programs.contains(&d.instance) {
            problems.push(Problem::error(
                "pacer::machine::assignment",
                span_of(&a.destination),
                format!("Program.{} is not loaded", d.instance),
                "no such program",
            ));
        }
        // Sources assigned to the same destination are ORed.
        let latched = s.kind == Kind::ModuleInput;
        match assignments.iter_mut().find(|x| x.dest.slot == d.slot) {
            Some(existing) => {
                existing.sources.push((s.slot, active_off));
                existing.latched |= latched;
            }
            None => assignments.push(Assignment {
                sources: vec![(s.slot, active_off)],
                dest: d,
                latched,
            }),
        }
    }
    assignments
}

/// `[home.N] reference`: the input whose rising edge ends each home's search.
pub fn home_references(
    machine: &MachineFile,
    reg: &Registry,
    drive: &mut DriveSetup,
    problems: &mut Vec<Problem>,
) {
    for (key, setup) in &machine.home {
        // A section naming no home was reported with the home's other values.
        let Some(n) = key.parse::<usize>().ok().filter(|n| *n < drive.homes.len()) else {
            continue;
        };
        let s = setup.get_ref();
        match reg.resolve_text(&s.reference).ok() {
            Some(r)
                if r.ty.is_bit()
                    && matches!(r.kind, Kind::DriveInput | Kind::ModuleInput | Kind::DriveIO) =>
            {
                drive.homes[n] = HomeConfig {
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
    }
}

/// `[axis.N] fast_input`: the inputs wired to the DSP axes' fast inputs.
pub fn fast_inputs(
    machine: &MachineFile,
    reg: &Registry,
    axes: &mut [DspAxisDesc],
    problems: &mut Vec<Problem>,
) {
    for (key, setup) in &machine.axis {
        let (Ok(n), Some(input)) = (key.parse::<u32>(), &setup.get_ref().fast_input) else {
            continue;
        };
        match resolve_text(reg, input, problems) {
            Some(r)
                if r.ty.is_bit()
                    && r.access == Access::Read
                    && matches!(r.kind, Kind::DriveInput | Kind::ModuleInput | Kind::DriveIO) =>
            {
                match axes.iter_mut().find(|a| a.config.number == n) {
                    Some(a) => a.fast_input = Some(r.slot),
                    None => problems.push(Problem::error(
                        "pacer::machine::axis",
                        span_of(input),
                        format!("axis {n} is not a DSP axis of this machine"),
                        "here",
                    )),
                }
            }
            Some(r) => problems.push(
                Problem::error(
                    "pacer::machine::axis",
                    span_of(input),
                    format!("{} is not an input", r.name),
                    "not an input",
                )
                .with_help("wire a DriveInput, ModuleInput or DriveIO point"),
            ),
            None => {}
        }
    }
}
