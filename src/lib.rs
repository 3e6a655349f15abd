//! pacer: an interpreter and deterministic motion runtime for the program languages of
//! industrial motion controllers.

pub mod check;
pub mod compile;
pub mod config;
pub mod devices;
pub mod diag;
pub mod export;
pub mod fixed;
pub mod io;
pub mod load;
pub mod registry;
pub mod repl;
pub mod span;
pub mod sweep;
pub mod syntax;
pub mod trace;
pub mod vm;
pub mod world;
