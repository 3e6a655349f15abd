//! The runnable image from the checked description: the devices in update order and the
//! machine's programs, assignments and world. Nothing here can fail: every value was checked by
//! the configuration stage and every program by the front end.

use super::project::ProgramFile;
use crate::compile::{Chunk, Layout};
use crate::config::desc::{MachineDesc, ScenarioDesc};
use crate::devices::drive::Drive;
use crate::devices::orion::Orion;
use crate::devices::pickplace::cell::PickPlaceCell;
use crate::devices::Device;
use crate::registry::{Hook, Registry};
use crate::vm::MachineImage;
use indexmap::IndexMap;

/// The image of machine `name`. The configuration stage built its DSP axes once already, so
/// the one error there is (a DSP model refusing its set-up) cannot happen; it is returned, not
/// dropped, all the same.
pub fn image(
    name: String,
    desc: MachineDesc,
    registry: Registry,
    scenario: ScenarioDesc,
    programs: &[ProgramFile],
    compiled: Vec<(u32, Chunk)>,
    layout: &Layout,
) -> Result<MachineImage, String> {
    let tick = desc.update_ns as f64 / 1e9;
    // The devices, in the order they update: the drive, the DSP axes, pick & place.
    let mut devices: Vec<Box<dyn Device>> = vec![Box::new(Drive::new(
        &registry,
        &desc.drive,
        scenario.axis_marks.clone(),
    ))];
    if !desc.dsp.is_empty() {
        devices.push(Box::new(Orion::new(
            &registry,
            &desc.dsp,
            &scenario.mark_tracks,
            tick,
        )?));
    }
    if let Some(setup) = &desc.pickplace {
        let profiles = if scenario.belt_profiles.is_empty() {
            Vec::new()
        } else {
            setup
                .belts
                .iter()
                .map(|b| {
                    scenario
                        .belt_profiles
                        .get(&b.number)
                        .cloned()
                        .unwrap_or_default()
                })
                .collect()
        };
        devices.push(Box::new(PickPlaceCell::new(
            &registry,
            setup,
            profiles,
            scenario.feeds.clone(),
            tick,
        )));
    }
    let mut chunks = Vec::new();
    let mut by_number = IndexMap::new();
    for (number, chunk) in compiled {
        by_number.insert(number, chunks.len());
        chunks.push(chunk);
    }
    crate::compile::link_calls(&mut chunks, &by_number, layout);
    let mut autostart: Vec<u32> = programs
        .iter()
        .filter(|p| p.autostart)
        .map(|p| p.number)
        .collect();
    let started_by_assignment = desc
        .assignments
        .iter()
        .any(|a| a.dest.hook == Hook::ProgramInitiate);
    if autostart.is_empty() && !started_by_assignment {
        autostart.extend(programs.first().map(|p| p.number));
    }
    let initial = layout.initial_values(&registry);
    Ok(MachineImage {
        strings: layout.strings.clone(),
        name,
        tick_ns: desc.update_ns,
        budget: desc.budget,
        tasks: desc.tasks,
        units: desc.drive.units.clone(),
        registry,
        initial,
        chunks,
        programs: by_number,
        autostart,
        assignments: desc.assignments,
        edges: scenario.edges,
        master: scenario.master,
        products: scenario.products,
        duration_ns: scenario.duration_ns,
        seed: scenario.seed,
        devices,
    })
}
