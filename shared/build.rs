//! Generates the register tables and id constants from `registers.def` into OUT_DIR.

use std::path::PathBuf;
use std::process::exit;

fn main() {
    println!("cargo:rerun-if-changed=registers.def");
    println!("cargo:rerun-if-changed=build.rs");
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let def_path = manifest.join("registers.def");
    let text = match std::fs::read_to_string(&def_path) {
        Ok(text) => text,
        Err(e) => {
            eprintln!("{}: {e}", def_path.display());
            exit(1);
        }
    };
    let def = match regdef::parse(&text) {
        Ok(def) => def,
        Err(e) => {
            eprintln!("{}:{}: {}", def_path.display(), e.line, e.kind);
            exit(1);
        }
    };
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    for (name, source) in [
        ("register_tables.rs", regdef::generate_tables(&def)),
        ("register_ids.rs", regdef::generate_ids(&def)),
    ] {
        let path = out.join(name);
        if let Err(e) = std::fs::write(&path, source) {
            eprintln!("{}: {e}", path.display());
            exit(1);
        }
    }
}
