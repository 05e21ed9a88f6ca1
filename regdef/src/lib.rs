//! Register definition generator for the Blodwen rover.
//!
//! The rover's register tables (master, the common slave block, the drive/steer and
//! lift/lift slaves) are written once, in `shared/registers.def`. This crate parses that
//! file and generates from it:
//!
//! - the Rust tables and id constants that the `shared` crate `include!`s (its build
//!   script calls [`generate_tables`] and [`generate_ids`]);
//! - the Markdown reference `docs/registers.md` ([`generate_markdown`]), rewritten by
//!   `cargo run -p regdef -- write-docs` and checked for drift by this crate's tests.
//!
//! It runs only on the host (at build time and from the command line); nothing from it
//! reaches the firmware except the generated tables.

mod markdown;
mod model;
mod parse;
mod rust;

pub use markdown::generate_markdown;
pub use model::{Block, Definition, Entry};
pub use parse::{parse, ErrorKind, ParseError};
pub use rust::{generate_ids, generate_tables};

/// Path of the definition file, relative to the workspace root.
pub const DEF_PATH: &str = "shared/registers.def";
/// Path of the generated register reference, relative to the workspace root.
pub const DOC_PATH: &str = "docs/registers.md";
/// The command that rewrites [`DOC_PATH`]; quoted by drift errors.
pub const WRITE_DOCS_COMMAND: &str = "cargo run -p regdef -- write-docs";
