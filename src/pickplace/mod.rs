//! The Track Pick & Place module (Lenze L_TT1P_TrackPickAndPlaceBase): conveyor-tracking pick &
//! place on a Cartesian or Delta3 robot, planned in Cartesian space.

pub mod frame;
pub mod io;
pub mod law;
pub mod module;
pub mod path;
pub mod plan;
pub mod robot;
pub mod setup;
pub mod track;
pub mod trajectory;
