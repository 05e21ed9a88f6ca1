//! Command-line front end of the register generator.
//!
//! `cargo run -p regdef -- write-docs` rewrites `docs/registers.md` from
//! `shared/registers.def`; `check-docs` only compares; `rust` and `ids` print the
//! generated Rust that `shared`'s build script writes.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

const USAGE: &str = "usage: regdef <write-docs | check-docs | rust | ids> [WORKSPACE_ROOT]";

fn workspace_root(arg: Option<String>) -> PathBuf {
    match arg {
        Some(root) => PathBuf::from(root),
        None => {
            let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
            manifest.parent().unwrap_or(manifest).to_path_buf()
        }
    }
}

fn load(root: &Path) -> Result<regdef::Definition, String> {
    let path = root.join(regdef::DEF_PATH);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    regdef::parse(&text).map_err(|e| format!("{}:{}: {}", path.display(), e.line, e.kind))
}

fn run(command: &str, root: &Path) -> Result<(), String> {
    let def = load(root)?;
    let doc_path = root.join(regdef::DOC_PATH);
    match command {
        "write-docs" => {
            std::fs::write(&doc_path, regdef::generate_markdown(&def))
                .map_err(|e| format!("{}: {e}", doc_path.display()))?;
            println!("wrote {}", doc_path.display());
        }
        "check-docs" => {
            let current = std::fs::read_to_string(&doc_path).unwrap_or_default();
            if current != regdef::generate_markdown(&def) {
                return Err(format!(
                    "{} is out of date with {}: run `{}`",
                    regdef::DOC_PATH,
                    regdef::DEF_PATH,
                    regdef::WRITE_DOCS_COMMAND
                ));
            }
            println!("{} is up to date", regdef::DOC_PATH);
        }
        "rust" => print!("{}", regdef::generate_tables(&def)),
        "ids" => print!("{}", regdef::generate_ids(&def)),
        _ => return Err(USAGE.to_string()),
    }
    Ok(())
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(command) = args.next() else {
        eprintln!("{USAGE}");
        return ExitCode::FAILURE;
    };
    let root = workspace_root(args.next());
    match run(&command, &root) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("regdef: {message}");
            ExitCode::FAILURE
        }
    }
}
