//! The module's inputs, parameters and outputs as plain values, under the manual's names
//! (snake-cased); the kernel bridge copies them from and to the registry's members.

use super::robot::AXES;

/// States of the module (eTMState). The manual names them without numbers; pacer numbers them
/// in the manual's order, 0 being the block not executed (xEnable = FALSE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum TmState {
    Disabled = 0,
    Ready = 1,
    JogPos = 2,
    JogNeg = 3,
    Homing = 4,
    PreparingPath = 5,
    MovePp = 6,
    Stop = 7,
    PathInterrupt = 8,
    Error = 9,
}

impl TmState {
    /// The manual's name.
    pub fn name(self) -> &'static str {
        match self {
            TmState::Disabled => "DISABLED",
            TmState::Ready => "READY",
            TmState::JogPos => "JOGPOS",
            TmState::JogNeg => "JOGNEG",
            TmState::Homing => "HOMING",
            TmState::PreparingPath => "PREPARING_PATH",
            TmState::MovePp => "MOVE_PP",
            TmState::Stop => "STOP",
            TmState::PathInterrupt => "PATH_INTERRUPT",
            TmState::Error => "ERROR",
        }
    }
}

/// Error and warning numbers (eErrorID).
pub mod errors {
    /// Warning: the belt's workpiece list is full (30).
    pub const BELT_LIST_FULL: i32 = 17918;
    /// Positive software limit position.
    pub const SW_LIMIT_POS: i32 = 20306;
    /// Negative software limit position.
    pub const SW_LIMIT_NEG: i32 = 20307;
    /// Positive hardware limit switch.
    pub const HW_LIMIT_POS: i32 = 20500;
    /// Negative hardware limit switch.
    pub const HW_LIMIT_NEG: i32 = 20501;
    /// pacer: no kinematic solution for a point of the planned path or of a jog.
    pub const NO_SOLUTION: i32 = 29001;
    /// pacer: a parameter makes no path (negative radius, unknown mode, zero limits …).
    pub const INVALID_PARAMETER: i32 = 29002;
    /// pacer: the path cannot keep every axis within its limits even slowed down.
    pub const AXIS_LIMITS: i32 = 29003;
}

/// Level inputs, read every cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub struct Inputs {
    pub x_enable: bool,
    pub x_reset_error: bool,
    pub x_regulator_on_all: bool,
    pub x_path_stop: bool,
    pub x_path_halt: bool,
    pub x_stop_all: bool,
    pub x_path_interrupt: bool,
    pub x_jog_pos: bool,
    pub x_jog_neg: bool,
    pub e_select_axis: i32,
    pub e_set_target: i32,
    pub lr_override: f64,
    pub x_group_enable_hw_limit: bool,
    pub ax_hw_limit_pos: [bool; AXES],
    pub ax_hw_limit_neg: [bool; AXES],
    pub ax_sw_limit_enabled: [bool; AXES],
}

impl Default for Inputs {
    fn default() -> Self {
        Inputs {
            x_enable: false,
            x_reset_error: false,
            x_regulator_on_all: false,
            x_path_stop: false,
            x_path_halt: false,
            x_stop_all: false,
            x_path_interrupt: false,
            x_jog_pos: false,
            x_jog_neg: false,
            e_select_axis: 0,
            e_set_target: 0,
            lr_override: 1.0,
            x_group_enable_hw_limit: false,
            ax_hw_limit_pos: [false; AXES],
            ax_hw_limit_neg: [false; AXES],
            ax_sw_limit_enabled: [false; AXES],
        }
    }
}

/// Rising edges of the edge-controlled inputs since the last cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(missing_docs)]
pub struct Edges {
    pub x_execute_pick_and_place: bool,
    pub x_abort: bool,
    pub x_ack_gripper: bool,
    pub x_group_home_execute: bool,
}

/// The module's parameters (L_TT1P_scPar_TrackPickAndPlaceBase).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct Params {
    pub lr_path_stop_dec: f64,
    pub lr_path_stop_jerk: f64,
    pub lr_path_halt_dec: f64,
    pub lr_path_jerk: f64,
    pub lr_path_vel: f64,
    pub lr_path_acc: f64,
    pub lr_path_dec: f64,
    pub alr_stop_dec: [f64; AXES],
    pub alr_stop_jerk: [f64; AXES],
    /// Jog: [jerk, vel, acc, dec] for Cartesian, orientation and real axes.
    pub cartesian_jog: [f64; 4],
    pub orientation_jog: [f64; 4],
    pub real_axis_jog: [f64; 4],
    pub alr_home_position: [f64; 7],
    pub ae_homing_order: [i32; 7],
    /// Cartesian limits X, Y, Z, A, B, C, Aux1: [vel, acc/dec, jerk].
    pub cartesian_limits: [[f64; 3]; 7],
    pub lr_gripper_closing_time: f64,
    pub lr_gripper_open_time: f64,
    pub e_target_coord_system: i32,
    /// lrX…, lrY…, lrZ…, lrA…, lrB…, lrC…, lrAux1TargetPos.
    pub target: [f64; 7],
    pub lr_z_start_dist: f64,
    pub e_path_mode: i32,
    pub lr_z_dist_elliptical: f64,
    pub lr_z_target_dist: f64,
    pub lr_blending_radius: f64,
    pub x_pos_in_window: bool,
    pub lr_pos_in_window: f64,
    pub lr_time_pos_in_window: f64,
    pub e_tracking_mode: i32,
}

impl Params {
    /// The manual's initial values.
    pub fn manual() -> Params {
        Params {
            lr_path_stop_dec: 10000.0,
            lr_path_stop_jerk: 100000.0,
            lr_path_halt_dec: 100.0,
            lr_path_jerk: 100000.0,
            lr_path_vel: 10.0,
            lr_path_acc: 100.0,
            lr_path_dec: 100.0,
            alr_stop_dec: [10000.0; AXES],
            alr_stop_jerk: [100000.0; AXES],
            cartesian_jog: [10000.0, 10.0, 100.0, 100.0],
            orientation_jog: [10000.0, 10.0, 100.0, 100.0],
            real_axis_jog: [10000.0, 10.0, 100.0, 100.0],
            alr_home_position: [0.0; 7],
            ae_homing_order: [0; 7],
            cartesian_limits: [[10.0, 100.0, 10000.0]; 7],
            lr_gripper_closing_time: 0.0,
            lr_gripper_open_time: 0.0,
            e_target_coord_system: 0,
            target: [0.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0],
            lr_z_start_dist: 0.0,
            e_path_mode: 0,
            lr_z_dist_elliptical: 0.0,
            lr_z_target_dist: 0.0,
            lr_blending_radius: 0.0,
            x_pos_in_window: false,
            lr_pos_in_window: 0.5,
            lr_time_pos_in_window: 50.0,
            e_tracking_mode: 0,
        }
    }
}

/// One belt's parameters (ascConveyorBeltPar[i]) and its input lrAux1TargetPos.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct BeltParams {
    pub alr_park_pos: [f64; 6],
    pub lr_z_dist_belt: f64,
    pub alr_conveyor_belt_origin: [f64; 6],
    pub lr_sync_time_on_belt: f64,
    pub lr_lower_sync_limit: f64,
    pub lr_upper_sync_limit: f64,
    pub lr_aux1_target_pos: f64,
}

/// The module's outputs.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub struct Outputs {
    pub e_tm_state: TmState,
    pub x_error: bool,
    pub x_warning: bool,
    pub e_error_id: i32,
    pub x_axes_enabled: bool,
    pub x_done: bool,
    pub x_busy: bool,
    pub x_axes_group_homed: bool,
    pub x_in_position: bool,
    pub x_hw_limit_switch_active: bool,
    pub x_sw_limit_switch_active: bool,
    pub ax_hw_limit_switch_pos: [bool; AXES],
    pub ax_hw_limit_switch_neg: [bool; AXES],
    pub ax_sw_limit_switch_active: [bool; AXES],
    pub x_path_hold: bool,
    pub x_gripper_ctrl_active: bool,
    pub x_pulse_gripper: bool,
    pub lr_set_path_vel_out: f64,
    pub lr_path_preparation_time: f64,
    pub lr_pre_calc_profile_time: f64,
    pub alr_act_pos: [f64; AXES],
    pub alr_act_vel: [f64; AXES],
    pub i_profile_point_passed: i32,
    pub x_profile_in_preparation: bool,
    pub x_acc_dec_sync: bool,
    pub x_synchronised: bool,
    pub x_in_target: bool,
    pub x_in_park_pos: bool,
    pub e_set_target_out: i32,
}

impl Default for Outputs {
    fn default() -> Self {
        Outputs {
            e_tm_state: TmState::Disabled,
            x_error: false,
            x_warning: false,
            e_error_id: 0,
            x_axes_enabled: false,
            x_done: false,
            x_busy: false,
            x_axes_group_homed: false,
            x_in_position: false,
            x_hw_limit_switch_active: false,
            x_sw_limit_switch_active: false,
            ax_hw_limit_switch_pos: [false; AXES],
            ax_hw_limit_switch_neg: [false; AXES],
            ax_sw_limit_switch_active: [false; AXES],
            x_path_hold: false,
            x_gripper_ctrl_active: false,
            x_pulse_gripper: false,
            lr_set_path_vel_out: 0.0,
            lr_path_preparation_time: 0.0,
            lr_pre_calc_profile_time: 0.0,
            alr_act_pos: [0.0; AXES],
            alr_act_vel: [0.0; AXES],
            i_profile_point_passed: 0,
            x_profile_in_preparation: false,
            x_acc_dec_sync: false,
            x_synchronised: false,
            x_in_target: false,
            x_in_park_pos: false,
            e_set_target_out: 0,
        }
    }
}
