//! What the executor's emulator tests share: loading an `exec_*` image and reading its
//! UART report.
#![allow(dead_code)]

use std::collections::HashMap;

use harness::Avr;

/// Loads `target/firmware/<name>.elf` (the harness makes enable bits level-sensitive and
/// keeps write-one-to-clear flags, as on the chip: see the harness's `fidelity` module).
pub fn boot(name: &str) -> Avr {
    Avr::firmware(name)
        .unwrap_or_else(|e| panic!("{name}: {e} (build the images with scripts/firmware.sh)"))
}

/// Runs until the firmware prints a line starting with `prefix` and returns the rest of
/// it (without the newline).
pub fn report(avr: &mut Avr, prefix: &str, max_us: u64) -> String {
    loop {
        let line = avr
            .uart_read_until(b"\n", max_us)
            .unwrap_or_else(|e| panic!("no `{prefix}` line: {e}"));
        let text = String::from_utf8_lossy(&line).trim_end().to_string();
        if let Some(rest) = text.strip_prefix(prefix) {
            return rest.trim_start().to_string();
        }
    }
}

/// Splits `a=1 b=2` into a map.
pub fn fields(line: &str) -> HashMap<String, u32> {
    line.split_whitespace()
        .filter_map(|kv| {
            let (k, v) = kv.split_once('=')?;
            Some((k.to_string(), v.parse().ok()?))
        })
        .collect()
}
