//! Writes the captured images and the log to the output directory.

use crate::error::SimError;
use crate::json;
use crate::serve::End;
use crate::session::Programmer;
use std::path::{Path, PathBuf};

/// Name of the raw flash image (32 KB, unwritten bytes 0xff).
pub const FLASH_FILE: &str = "flash.bin";
/// Name of the raw EEPROM image (1 KB, unwritten bytes 0xff).
pub const EEPROM_FILE: &str = "eeprom.bin";
/// Name of the JSON log of the session.
pub const LOG_FILE: &str = "log.json";

/// Writes `flash.bin`, `eeprom.bin` and `log.json` into `dir` (created if missing).
pub fn save(dir: &Path, prog: &Programmer, end: End) -> Result<(), SimError> {
    let fail = |path: PathBuf| move |source| SimError::Output { path, source };
    std::fs::create_dir_all(dir).map_err(fail(dir.to_path_buf()))?;
    let log = json::render(prog, end.name());
    let files: [(&str, &[u8]); 3] = [
        (FLASH_FILE, prog.target().flash()),
        (EEPROM_FILE, prog.target().eeprom()),
        (LOG_FILE, log.as_bytes()),
    ];
    for (name, bytes) in files {
        let path = dir.join(name);
        std::fs::write(&path, bytes).map_err(fail(path.clone()))?;
    }
    Ok(())
}
