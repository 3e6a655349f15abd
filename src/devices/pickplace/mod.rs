//! The Track Pick & Place module (Lenze L_TT1P_TrackPickAndPlaceBase): conveyor-tracking pick &
//! place on a Cartesian or Delta3 robot, planned in Cartesian space. The pure model is the
//! module (`module`, `plan`, `path`, `law`, `trajectory`, `track`, `frame`, `robot`,
//! `kinematics`); `cell` binds it to the `PickPlace` and `Belt.N` members and to the
//! scenario's belts as a [`crate::devices::Device`].

pub mod cell;
pub mod frame;
pub mod io;
pub mod kinematics;
pub mod law;
pub mod module;
pub mod path;
pub mod plan;
pub mod robot;
pub mod setup;
pub mod track;
pub mod trajectory;
