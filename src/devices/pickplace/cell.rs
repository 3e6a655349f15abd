//! The pick & place module as the registry sees it: program writes to `PickPlace.…` and
//! `Belt.N.…` go in (rising edges of the edge-controlled inputs are remembered until the
//! module's next cycle, so a pulse shorter than an update is never lost); each update the
//! scenario's belts move and feed workpieces, the module runs one cycle, and its outputs come
//! out into the members and its events into the trace.

use super::io::{BeltParams, Edges, Inputs, Params};
use super::module::{Event, Module};
use super::robot::AXES;
use super::setup::PickPlaceSetup;
use crate::devices::command::StartRef;
use crate::devices::{ActOutcome, Device, Now, Target, When};
use crate::registry::catalog::{BELT_TYPE, PICK_PLACE_TYPE};
use crate::registry::{Hook, Registry, SlotId};
use crate::trace;
use crate::world::belt::BeltProfile;
use crate::world::workpieces::WorkpieceFeed;

/// Slots of the module's members.
#[derive(Debug, Clone)]
struct Slots {
    execute: SlotId,
    abort: SlotId,
    ack: SlotId,
    home: SlotId,
    enable: SlotId,
    reset: SlotId,
    regulator: SlotId,
    stop: SlotId,
    halt: SlotId,
    stop_all: SlotId,
    interrupt: SlotId,
    jog_pos: SlotId,
    jog_neg: SlotId,
    select: SlotId,
    set_target: SlotId,
    override_: SlotId,
    hw_enable: SlotId,
    hw_pos: [SlotId; AXES],
    hw_neg: [SlotId; AXES],
    sw_enabled: [SlotId; AXES],
    params: ParamSlots,
    out: OutSlots,
}

#[derive(Debug, Clone)]
struct ParamSlots {
    scalars: [SlotId; 7],
    stop_dec: [SlotId; AXES],
    stop_jerk: [SlotId; AXES],
    jog: [[SlotId; 4]; 3],
    home_pos: [SlotId; 7],
    home_order: [SlotId; 7],
    limits: [[SlotId; 3]; 7],
    gripper: [SlotId; 2],
    coord: SlotId,
    target: [SlotId; 7],
    shape: [SlotId; 8],
    mode: SlotId,
}

#[derive(Debug, Clone)]
struct OutSlots {
    bits: [SlotId; 19],
    ints: [SlotId; 4],
    reals: [SlotId; 3],
    act_pos: [SlotId; AXES],
    act_vel: [SlotId; AXES],
    hw_pos: [SlotId; AXES],
    hw_neg: [SlotId; AXES],
    sw_active: [SlotId; AXES],
}

/// Slots of one belt's members.
#[derive(Debug, Clone)]
struct BeltSlots {
    receive: SlotId,
    valid: SlotId,
    initial: [SlotId; 6],
    aux: SlotId,
    park: [SlotId; 6],
    z_dist: SlotId,
    origin: [SlotId; 6],
    sync: SlotId,
    lower: SlotId,
    upper: SlotId,
    status: [SlotId; 5],
}

/// The module and its world: belts driven by the scenario and the workpieces it feeds.
#[derive(Debug, Clone)]
pub struct PickPlaceCell {
    module: Module,
    slots: Slots,
    belt_slots: Vec<BeltSlots>,
    profiles: Vec<BeltProfile>,
    feeds: Vec<WorkpieceFeed>,
    next_receive: usize,
    valids: Vec<(f64, usize, usize)>,
    next_valid: usize,
    edges: Edges,
    belt_edges: Vec<(bool, bool)>,
    program_ids: Vec<u32>,
    events: Vec<Event>,
    pulsed: Vec<SlotId>,
    /// Each belt's (travel, speed) and parameters this update, kept to spare allocations.
    belts_now: Vec<(f64, f64)>,
    belt_params_now: Vec<BeltParams>,
    /// Every axis brakes as on xStopALL while this is set (the I/O link is down).
    external_stop: bool,
}

impl PickPlaceCell {
    /// The module of a machine with its scenario's belts (`profiles`, in the set-up's belt
    /// order) and workpiece feeds.
    pub fn new(
        registry: &Registry,
        setup: &PickPlaceSetup,
        profiles: Vec<BeltProfile>,
        feeds: Vec<WorkpieceFeed>,
        dt: f64,
    ) -> PickPlaceCell {
        macro_rules! g {
            ($name:literal) => {
                crate::slot!(registry, PICK_PLACE_TYPE, 0, $name)
            };
        }
        macro_rules! ga {
            ($name:literal, $len:expr) => {
                crate::slots!(registry, PICK_PLACE_TYPE, 0, $name, $len)
            };
        }
        let params = ParamSlots {
            scalars: [
                g!("lrPathStopDec"),
                g!("lrPathStopJerk"),
                g!("lrPathHaltDec"),
                g!("lrPathJerk"),
                g!("lrPathVel"),
                g!("lrPathAcc"),
                g!("lrPathDec"),
            ],
            stop_dec: ga!("alrStopDec", AXES),
            stop_jerk: ga!("alrStopJerk", AXES),
            jog: [
                [
                    g!("lrCartesianJogJerk"),
                    g!("lrCartesianJogVel"),
                    g!("lrCartesianJogAcc"),
                    g!("lrCartesianJogDec"),
                ],
                [
                    g!("lrOrientationJogJerk"),
                    g!("lrOrientationJogVel"),
                    g!("lrOrientationJogAcc"),
                    g!("lrOrientationJogDec"),
                ],
                [
                    g!("lrRealAxisJogJerk"),
                    g!("lrRealAxisJogVel"),
                    g!("lrRealAxisJogAcc"),
                    g!("lrRealAxisJogDec"),
                ],
            ],
            home_pos: ga!("alrHomePosition", 7),
            home_order: ga!("aeHomingOrder", 7),
            limits: [
                [g!("lrXMaxVel"), g!("lrXMaxAccDec"), g!("lrXMaxJerk")],
                [g!("lrYMaxVel"), g!("lrYMaxAccDec"), g!("lrYMaxJerk")],
                [g!("lrZMaxVel"), g!("lrZMaxAccDec"), g!("lrZMaxJerk")],
                [g!("lrAMaxVel"), g!("lrAMaxAccDec"), g!("lrAMaxJerk")],
                [g!("lrBMaxVel"), g!("lrBMaxAccDec"), g!("lrBMaxJerk")],
                [g!("lrCMaxVel"), g!("lrCMaxAccDec"), g!("lrCMaxJerk")],
                [
                    g!("lrAux1MaxVel"),
                    g!("lrAux1MaxAccDec"),
                    g!("lrAux1MaxJerk"),
                ],
            ],
            gripper: [g!("lrGripperClosingTime"), g!("lrGripperOpenTime")],
            coord: g!("eTargetCoordSystem"),
            target: [
                g!("lrXTargetPos"),
                g!("lrYTargetPos"),
                g!("lrZTargetPos"),
                g!("lrATargetPos"),
                g!("lrBTargetPos"),
                g!("lrCTargetPos"),
                g!("lrAux1TargetPos"),
            ],
            shape: [
                g!("lrZStartDist"),
                g!("ePathMode"),
                g!("lrZDistElliptical"),
                g!("lrZTargetDist"),
                g!("lrBlendingRadius"),
                g!("xPosInWindow"),
                g!("lrPosInWindow"),
                g!("lrTimePosInWindow"),
            ],
            mode: g!("eTrackingMode"),
        };
        let out = OutSlots {
            bits: [
                g!("xError"),
                g!("xWarning"),
                g!("xAxesEnabled"),
                g!("xAxesGroupEnabled"),
                g!("xDone"),
                g!("xBusy"),
                g!("xAxesGroupHomed"),
                g!("xInPosition"),
                g!("xHwLimitSwitchActive"),
                g!("xSwLimitSwitchActive"),
                g!("xPathHold"),
                g!("xGripperCtrlActive"),
                g!("xPulseGripper"),
                g!("xProfileInPreparation"),
                g!("xAccDecSync"),
                g!("xSynchronised"),
                g!("xInTarget"),
                g!("xInParkPos"),
                g!("xInternalControlActive"),
            ],
            ints: [
                g!("eTMState"),
                g!("eErrorID"),
                g!("iProfilePointPassed"),
                g!("eSetTargetOut"),
            ],
            reals: [
                g!("lrSetPathVelOut"),
                g!("lrPathPreparationTime"),
                g!("lrPreCalcProfileTime"),
            ],
            act_pos: ga!("alrActPos", AXES),
            act_vel: ga!("alrActVel", AXES),
            hw_pos: ga!("axHwLimitSwitchPos", AXES),
            hw_neg: ga!("axHwLimitSwitchNeg", AXES),
            sw_active: ga!("axSwLimitSwitchActive", AXES),
        };
        let slots = Slots {
            execute: g!("xExecutePickAndPlace"),
            abort: g!("xAbort"),
            ack: g!("xAckGripper"),
            home: g!("xGroupHomeExecute"),
            enable: g!("xEnable"),
            reset: g!("xResetError"),
            regulator: g!("xRegulatorOnALL"),
            stop: g!("xPathStop"),
            halt: g!("xPathHalt"),
            stop_all: g!("xStopALL"),
            interrupt: g!("xPathInterrupt"),
            jog_pos: g!("xJogPos"),
            jog_neg: g!("xJogNeg"),
            select: g!("eSelectAxis"),
            set_target: g!("eSetTarget"),
            override_: g!("lrOverride"),
            hw_enable: g!("xGroupEnableHWLimit"),
            hw_pos: ga!("axHwLimitPos", AXES),
            hw_neg: ga!("axHwLimitNeg", AXES),
            sw_enabled: ga!("axSwLimitEnabled", AXES),
            params,
            out,
        };
        let mut belt_slots = Vec::new();
        for b in &setup.belts {
            let i = b.number - 1;
            macro_rules! f {
                ($name:literal) => {
                    crate::slot!(registry, BELT_TYPE, i, $name)
                };
            }
            macro_rules! a6 {
                ($name:literal) => {
                    crate::slots!(registry, BELT_TYPE, i, $name, 6)
                };
            }
            belt_slots.push(BeltSlots {
                receive: f!("xWorkpieceOnBeltReceive"),
                valid: f!("xValidPos"),
                initial: a6!("ascInitialObjectPosition"),
                aux: f!("lrAux1TargetPos"),
                park: a6!("alrParkPos"),
                z_dist: f!("lrZDistBelt"),
                origin: a6!("alrConveyorBeltOrigin"),
                sync: f!("lrSyncTimeOnBelt"),
                lower: f!("lrLowerSyncLimit"),
                upper: f!("lrUpperSyncLimit"),
                status: [
                    f!("Position"),
                    f!("Velocity"),
                    f!("Workpieces"),
                    f!("Picked"),
                    f!("Missed"),
                ],
            });
        }
        let index_of = |n: u32| setup.belts.iter().position(|b| b.number == n);
        let mut valids: Vec<(f64, usize, usize)> = feeds
            .iter()
            .enumerate()
            .filter_map(|(k, f)| index_of(f.belt).map(|i| (f.valid, i, k)))
            .collect();
        valids.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        let n = setup.belts.len();
        let mut profiles = profiles;
        profiles.resize(n, BeltProfile::stopped());
        PickPlaceCell {
            module: Module::new(setup, dt),
            slots,
            belt_slots,
            profiles,
            feeds,
            next_receive: 0,
            valids,
            next_valid: 0,
            edges: Edges::default(),
            belt_edges: vec![(false, false); n],
            program_ids: vec![1_000_000; n],
            events: Vec::new(),
            pulsed: Vec::new(),
            belts_now: Vec::with_capacity(n),
            belt_params_now: Vec::with_capacity(n),
            external_stop: false,
        }
    }

    /// The module.
    pub fn module(&self) -> &Module {
        &self.module
    }

    /// The belts' speed profiles, in the module's belt order.
    pub fn profiles(&self) -> &[BeltProfile] {
        &self.profiles
    }

    /// The scenario's workpiece feeds, in time order.
    pub fn feeds(&self) -> &[WorkpieceFeed] {
        &self.feeds
    }

    /// A program writes a member: stored, and a rising edge of an edge-controlled input is
    /// remembered for the next cycle.
    pub fn store(&mut self, slot: SlotId, value: f64, v: &mut [f64]) {
        let rising = value != 0.0 && v[slot as usize] == 0.0;
        v[slot as usize] = value;
        if !rising {
            return;
        }
        let s = &self.slots;
        if slot == s.execute {
            self.edges.x_execute_pick_and_place = true;
        } else if slot == s.abort {
            self.edges.x_abort = true;
        } else if slot == s.ack {
            self.edges.x_ack_gripper = true;
        } else if slot == s.home {
            self.edges.x_group_home_execute = true;
        } else if let Some(i) = self.belt_slots.iter().position(|b| b.receive == slot) {
            self.belt_edges[i].0 = true;
        } else if let Some(i) = self.belt_slots.iter().position(|b| b.valid == slot) {
            self.belt_edges[i].1 = true;
        }
    }

    fn inputs(&self, v: &[f64]) -> Inputs {
        let s = &self.slots;
        let b = |x: SlotId| v[x as usize] != 0.0;
        let i = |x: SlotId| v[x as usize] as i32;
        Inputs {
            x_enable: b(s.enable),
            x_reset_error: b(s.reset),
            x_regulator_on_all: b(s.regulator),
            x_path_stop: b(s.stop),
            x_path_halt: b(s.halt),
            x_stop_all: b(s.stop_all) || self.external_stop,
            x_path_interrupt: b(s.interrupt),
            x_jog_pos: b(s.jog_pos),
            x_jog_neg: b(s.jog_neg),
            e_select_axis: i(s.select),
            e_set_target: i(s.set_target),
            lr_override: v[s.override_ as usize],
            x_group_enable_hw_limit: b(s.hw_enable),
            ax_hw_limit_pos: s.hw_pos.map(b),
            ax_hw_limit_neg: s.hw_neg.map(b),
            ax_sw_limit_enabled: s.sw_enabled.map(b),
        }
    }

    fn params(&self, v: &[f64]) -> Params {
        let p = &self.slots.params;
        let r = |x: SlotId| v[x as usize];
        let sc = p.scalars.map(r);
        let jog = p.jog.map(|k| k.map(r));
        Params {
            lr_path_stop_dec: sc[0],
            lr_path_stop_jerk: sc[1],
            lr_path_halt_dec: sc[2],
            lr_path_jerk: sc[3],
            lr_path_vel: sc[4],
            lr_path_acc: sc[5],
            lr_path_dec: sc[6],
            alr_stop_dec: p.stop_dec.map(r),
            alr_stop_jerk: p.stop_jerk.map(r),
            cartesian_jog: jog[0],
            orientation_jog: jog[1],
            real_axis_jog: jog[2],
            alr_home_position: p.home_pos.map(r),
            ae_homing_order: p.home_order.map(|x| r(x) as i32),
            cartesian_limits: p.limits.map(|l| l.map(r)),
            lr_gripper_closing_time: r(p.gripper[0]),
            lr_gripper_open_time: r(p.gripper[1]),
            e_target_coord_system: r(p.coord) as i32,
            target: p.target.map(r),
            lr_z_start_dist: r(p.shape[0]),
            e_path_mode: r(p.shape[1]) as i32,
            lr_z_dist_elliptical: r(p.shape[2]),
            lr_z_target_dist: r(p.shape[3]),
            lr_blending_radius: r(p.shape[4]),
            x_pos_in_window: r(p.shape[5]) != 0.0,
            lr_pos_in_window: r(p.shape[6]),
            lr_time_pos_in_window: r(p.shape[7]),
            e_tracking_mode: r(p.mode) as i32,
        }
    }

    /// The belts' parameters into `out` (kept between updates: no allocation per update).
    fn belt_params(slots: &[BeltSlots], v: &[f64], out: &mut Vec<BeltParams>) {
        let r = |x: SlotId| v[x as usize];
        out.clear();
        out.extend(slots.iter().map(|b| BeltParams {
            alr_park_pos: b.park.map(r),
            lr_z_dist_belt: r(b.z_dist),
            alr_conveyor_belt_origin: b.origin.map(r),
            lr_sync_time_on_belt: r(b.sync),
            lr_lower_sync_limit: r(b.lower),
            lr_upper_sync_limit: r(b.upper),
            lr_aux1_target_pos: r(b.aux),
        }));
    }

    /// One cycle of the module at this update.
    fn generate(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), String> {
        let t = now.seconds();
        for s in self.pulsed.drain(..) {
            v[s as usize] = 0.0;
        }
        // The scenario's detector: receive edges at their exact instants, the belt travel
        // latched there; valid-position edges after their delay.
        while let Some(f) = self.feeds.get(self.next_receive) {
            if f.receive > t {
                break;
            }
            if let Some(i) = self.belt_slots_index(f.belt) {
                let travel = self.profiles[i].position(f.receive);
                let id = f.id;
                self.module.receive(i, id, travel, &mut self.events);
                let s = self.belt_slots[i].receive;
                v[s as usize] = 1.0;
                self.pulsed.push(s);
            }
            self.next_receive += 1;
        }
        while let Some(&(at, i, k)) = self.valids.get(self.next_valid) {
            if at > t {
                break;
            }
            let pos = self.feeds[k].position;
            self.module.validate(i, pos);
            let bs = &self.belt_slots[i];
            for (s, x) in bs.initial.iter().zip(pos) {
                v[*s as usize] = x;
            }
            v[bs.valid as usize] = 1.0;
            self.pulsed.push(bs.valid);
            self.next_valid += 1;
        }
        // A program's detector: edges at this update's travel.
        for i in 0..self.belt_slots.len() {
            let (receive, valid) = std::mem::take(&mut self.belt_edges[i]);
            if receive {
                let travel = self.profiles[i].position(t);
                self.program_ids[i] += 1;
                let id = self.program_ids[i];
                self.module.receive(i, id, travel, &mut self.events);
            }
            if valid {
                let pos = self.belt_slots[i].initial.map(|s| v[s as usize]);
                self.module.validate(i, pos);
            }
        }
        self.belts_now.clear();
        self.belts_now
            .extend(self.profiles.iter().map(|p| (p.position(t), p.velocity(t))));
        let inputs = self.inputs(v);
        let params = self.params(v);
        Self::belt_params(&self.belt_slots, v, &mut self.belt_params_now);
        let edges = std::mem::take(&mut self.edges);
        let out = self.module.cycle(
            t,
            &inputs,
            edges,
            &params,
            &self.belt_params_now,
            &self.belts_now,
            &mut self.events,
        );
        let o = &self.slots.out;
        let bits = [
            out.x_error,
            out.x_warning,
            out.x_axes_enabled,
            out.x_axes_enabled,
            out.x_done,
            out.x_busy,
            out.x_axes_group_homed,
            out.x_in_position,
            out.x_hw_limit_switch_active,
            out.x_sw_limit_switch_active,
            out.x_path_hold,
            out.x_gripper_ctrl_active,
            out.x_pulse_gripper,
            out.x_profile_in_preparation,
            out.x_acc_dec_sync,
            out.x_synchronised,
            out.x_in_target,
            out.x_in_park_pos,
            false,
        ];
        for (s, b) in o.bits.iter().zip(bits) {
            v[*s as usize] = f64::from(u8::from(b));
        }
        let ints = [
            out.e_tm_state as i32,
            out.e_error_id,
            out.i_profile_point_passed,
            out.e_set_target_out,
        ];
        for (s, x) in o.ints.iter().zip(ints) {
            v[*s as usize] = f64::from(x);
        }
        let reals = [
            out.lr_set_path_vel_out,
            out.lr_path_preparation_time,
            out.lr_pre_calc_profile_time,
        ];
        for (s, x) in o.reals.iter().zip(reals) {
            v[*s as usize] = x;
        }
        for i in 0..AXES {
            v[o.act_pos[i] as usize] = out.alr_act_pos[i];
            v[o.act_vel[i] as usize] = out.alr_act_vel[i];
            v[o.hw_pos[i] as usize] = f64::from(u8::from(out.ax_hw_limit_switch_pos[i]));
            v[o.hw_neg[i] as usize] = f64::from(u8::from(out.ax_hw_limit_switch_neg[i]));
            v[o.sw_active[i] as usize] = f64::from(u8::from(out.ax_sw_limit_switch_active[i]));
        }
        for (b, (bs, &(travel, vel))) in self
            .module
            .belts
            .iter()
            .zip(self.belt_slots.iter().zip(&self.belts_now))
        {
            let st = [
                travel,
                vel,
                b.pieces.len() as f64,
                f64::from(b.picked),
                f64::from(b.missed),
            ];
            for (s, x) in bs.status.iter().zip(st) {
                v[*s as usize] = x;
            }
        }
        self.trace(now);
        Ok(())
    }

    fn belt_slots_index(&self, number: u32) -> Option<usize> {
        self.module.belt_index(number)
    }

    fn trace(&mut self, now: &mut Now<'_>) {
        for e in self.events.drain(..) {
            let event = match e {
                Event::State(s) => trace::Event::PpState {
                    state: s.name().into(),
                },
                Event::Planned {
                    target,
                    duration,
                    scale,
                } => trace::Event::PpPath {
                    target,
                    duration,
                    scale,
                },
                Event::Pick { belt, id, position } => trace::Event::Pick {
                    belt,
                    id,
                    x: position[0],
                    y: position[1],
                    z: position[2],
                },
                Event::Place { belt, id, position } => trace::Event::Place {
                    belt,
                    id,
                    x: position[0],
                    y: position[1],
                    z: position[2],
                },
                Event::Reached {
                    target,
                    id,
                    position,
                } => trace::Event::PpTarget {
                    target,
                    id,
                    x: position[0],
                    y: position[1],
                    z: position[2],
                },
                Event::Missed { belt, id, x } => trace::Event::Missed { belt, id, x },
                Event::Gripper { close } => trace::Event::Gripper {
                    action: if close { "close" } else { "open" }.into(),
                },
                Event::Error { id, message } => trace::Event::PpError {
                    id,
                    message: message.into(),
                },
                Event::Warning { id, message } => trace::Event::PpWarning {
                    id,
                    message: message.into(),
                },
                Event::Homed { order } => trace::Event::PpHomed { order },
            };
            now.trace.emit(now.tick, &event);
        }
    }
}

impl Device for PickPlaceCell {
    fn name(&self) -> &'static str {
        "pick & place"
    }

    fn serves(&self, hook: Hook) -> bool {
        hook == Hook::PickPlace
    }

    fn update(&mut self, v: &mut [f64], now: &mut Now<'_>) -> Result<(), String> {
        self.generate(v, now)
    }

    fn write(
        &mut self,
        target: Target,
        value: f64,
        _when: When,
        v: &mut [f64],
        _now: &mut Now<'_>,
    ) -> Result<(), String> {
        self.store(target.slot, value, v);
        Ok(())
    }

    fn act(
        &mut self,
        target: Target,
        _start: StartRef,
        _profile: u8,
        _when: When,
        _v: &mut [f64],
        _now: &mut Now<'_>,
    ) -> Result<ActOutcome, String> {
        Err(format!("{:?} is not an action", target.hook))
    }

    /// While the I/O link is down every axis brakes as on xStopALL.
    fn moving(&self, _master_moves: bool, out: &mut Vec<crate::devices::Moving>) {
        if let Some(settles) = self.module.motion() {
            out.push(crate::devices::Moving {
                name: "PickPlace".into(),
                settles,
            });
        }
    }

    fn hold(&mut self, down: bool) {
        self.external_stop = down;
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
