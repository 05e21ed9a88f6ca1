//! Renders the session's [`Record`] as the JSON log written beside the images.

use crate::isp::IspOutcome;
use crate::record::Record;
use crate::session::Programmer;
use crate::target::{Memory, SIGNATURE};
use std::fmt::Write as _;

/// The JSON log of a finished session; `end` says why it finished.
pub fn render(p: &Programmer, end: &str) -> String {
    let r: &Record = p.record();
    let f = p.target().fuses;
    let mut s = String::new();
    // Writing to a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(s, "{{");
    let _ = writeln!(s, "  \"mode\": {},", string(p.mode().name()));
    let _ = writeln!(s, "  \"end\": {},", string(end));
    let _ = writeln!(
        s,
        "  \"signature\": \"{:02x}{:02x}{:02x}\",",
        SIGNATURE[0], SIGNATURE[1], SIGNATURE[2]
    );
    let _ = writeln!(
        s,
        "  \"fuses\": {{\"low\": {}, \"high\": {}, \"extended\": {}, \"lock\": {}}},",
        f.low, f.high, f.extended, f.lock
    );
    let _ = writeln!(s, "  \"syncs\": {},", r.syncs);
    let _ = writeln!(s, "  \"nosyncs\": {},", r.nosyncs);
    let _ = writeln!(s, "  \"unknown_commands\": {},", r.unknown);
    let _ = writeln!(s, "  \"progmode_entries\": {},", r.progmode_entries);
    let _ = writeln!(s, "  \"chip_erases\": {},", r.chip_erases);
    let _ = writeln!(s, "  \"flash_pages_read\": {},", r.flash_reads);
    let _ = writeln!(s, "  \"eeprom_pages_read\": {},", r.eeprom_reads);
    let _ = writeln!(
        s,
        "  \"flash_bytes_written\": {},",
        r.bytes_written(Memory::Flash)
    );
    let _ = writeln!(
        s,
        "  \"eeprom_bytes_written\": {},",
        r.bytes_written(Memory::Eeprom)
    );
    let writes: Vec<String> = r
        .writes
        .iter()
        .map(|w| {
            format!(
                "{{\"memory\": {}, \"address\": {}, \"length\": {}}}",
                string(w.memory.name()),
                w.addr,
                w.len
            )
        })
        .collect();
    let _ = writeln!(s, "  \"writes\": {},", list(&writes));
    let universal: Vec<String> = r
        .universal
        .iter()
        .map(|u| {
            format!(
                "{{\"instruction\": \"{:02x}{:02x}{:02x}{:02x}\", \"answer\": {}, \"outcome\": {}}}",
                u.instr[0],
                u.instr[1],
                u.instr[2],
                u.instr[3],
                u.answer,
                string(outcome_name(u.outcome))
            )
        })
        .collect();
    let _ = writeln!(s, "  \"universal\": {},", list(&universal));
    let refusals: Vec<String> = r
        .refusals
        .iter()
        .map(|x| {
            format!(
                "{{\"command\": {}, \"reason\": {}}}",
                x.command,
                string(&x.reason)
            )
        })
        .collect();
    let _ = writeln!(s, "  \"refusals\": {}", list(&refusals));
    let _ = writeln!(s, "}}");
    s
}

fn outcome_name(o: IspOutcome) -> &'static str {
    match o {
        IspOutcome::Read => "read",
        IspOutcome::ChipErase => "chip-erase",
        IspOutcome::Wrote => "wrote",
        IspOutcome::Ignored => "ignored",
    }
}

fn list(items: &[String]) -> String {
    if items.is_empty() {
        return "[]".to_string();
    }
    format!("[\n    {}\n  ]", items.join(",\n    "))
}

/// A JSON string literal for `text`.
fn string(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 2);
    s.push('"');
    for c in text.chars() {
        match c {
            '"' => s.push_str("\\\""),
            '\\' => s.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(s, "\\u{:04x}", c as u32);
            }
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Mode;

    #[test]
    fn strings_are_escaped() {
        assert_eq!(string("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
    }

    #[test]
    fn log_lists_writes_and_counts() {
        let mut p = Programmer::new(Mode::Isp);
        p.feed_all(&[0x50, 0x20, 0x64, 0x00, 0x02, b'F', 1, 2, 0x20]);
        p.feed_all(&[0x56, 0xac, 0x80, 0, 0, 0x20]);
        let log = render(&p, "port-closed");
        assert!(log.contains("\"mode\": \"isp\""), "{log}");
        assert!(log.contains("\"end\": \"port-closed\""), "{log}");
        assert!(log.contains("\"signature\": \"1e950f\""), "{log}");
        assert!(log.contains("{\"memory\": \"flash\", \"address\": 0, \"length\": 2}"));
        assert!(log.contains("\"flash_bytes_written\": 2,"));
        assert!(log.contains("\"chip_erases\": 1,"));
        assert!(log.contains("\"instruction\": \"ac800000\""));
        assert!(log.contains("\"refusals\": []"));
    }
}
