//! pacer: an interpreter and deterministic motion runtime for the program languages of
//! industrial motion controllers.

pub mod check;
pub mod config;
pub mod diag;
pub mod registry;
pub mod syntax;
