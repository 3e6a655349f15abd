//! The device models of a machine and the vocabulary programs use to command them. The devices
//! never depend on the front end (syntax, check, compile): the front end depends on them.

pub mod command;
