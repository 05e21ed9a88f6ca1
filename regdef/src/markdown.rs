//! Generation of `docs/registers.md`, the human-readable register reference.

use std::fmt::Write as _;

use crate::model::{Definition, Entry};

fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

fn range_cell(e: &Entry) -> String {
    match e.range {
        Some((min, max)) => format!("{min} .. {max}"),
        None => "unmapped".to_string(),
    }
}

fn registers(n: usize) -> String {
    if n == 1 {
        "1 register".to_string()
    } else {
        format!("{n} registers")
    }
}

fn row(e: &Entry) -> String {
    let flag = e.flag_byte();
    format!(
        "| {} | `{}` | {} | {} | {} | {} | {flag} (0x{flag:02x}) | {} |",
        e.id,
        e.symbol,
        e.size,
        if e.writable { "W" } else { "R" },
        range_cell(e),
        if e.unit.is_empty() { "–" } else { &e.unit },
        cell(&e.meaning)
    )
}

/// The complete text of `docs/registers.md`: an introduction, then one table per block.
pub fn generate_markdown(def: &Definition) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Register reference");
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "<!-- Generated from {} by `{}`. Do not edit by hand. -->",
        crate::DEF_PATH,
        crate::WRITE_DOCS_COMMAND
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "Every register of the rover, generated from `{}`, the one definition that the \
         firmware, the host tool and the twin all use.",
        crate::DEF_PATH
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "- **Size**: bytes on the wire, little-endian. **W**: `W` means the master forwards \
         writes; a write frame naming an `R` register is refused whole (error reply 0x89, \
         docs/protocol.md)."
    );
    let _ = writeln!(
        out,
        "- **Range** `a .. b`: a value v is sent as trunc((clamp(v, a, b) - a) * F / (b - a)) \
         with F = 65534 (2 bytes) or 254 (1 byte). `unmapped` registers carry the integer \
         itself. The PC side maps in float32 as the original did; the slaves compute in \
         fixed point, so a monitoring register may read one count away from the original's \
         value (docs/protocol.md, \"How the slaves compute\")."
    );
    let _ = writeln!(
        out,
        "- **Flags**: the original firmware's table entry byte: bits 0-5 the size, bit 6 \
         (0x40) writable; 65 = writable 1-byte, 66 = writable 2-byte, 2 = read-only 2-byte."
    );
    for block in &def.blocks {
        let _ = writeln!(out);
        let title = if block.title.is_empty() {
            block.name.clone()
        } else {
            format!("{}: {}", block.name, block.title)
        };
        let _ = writeln!(out, "## {title}");
        let _ = writeln!(out);
        let first = def.full_table(block).len() - block.entries.len();
        let last = first + block.entries.len() - 1;
        match &block.base {
            Some(base) => {
                let _ = writeln!(
                    out,
                    "Ids 0..{} are the `{base}` block; this block adds ids {first}..{last} \
                     ({} in all).",
                    first.saturating_sub(1),
                    registers(last + 1)
                );
            }
            None => {
                let _ = writeln!(out, "Ids {first}..{last} ({}).", registers(last + 1));
            }
        }
        let _ = writeln!(out);
        let _ = writeln!(
            out,
            "| Id | Symbol | Size | W | Range | Unit | Flags | Meaning |"
        );
        let _ = writeln!(out, "|---|---|---|---|---|---|---|---|");
        for e in &block.entries {
            let _ = writeln!(out, "{}", row(e));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse;

    #[test]
    fn one_table_per_block_with_flags_and_escapes() {
        let def = parse(
            "block BASE : Base things\n0 REG_A 1 W unmapped - a|b\n\
             block SUB extends BASE\n1 REGS_B 2 R -4000 4000 ticks/s Speed.\n",
        )
        .unwrap();
        let md = generate_markdown(&def);
        assert!(md.contains("## BASE: Base things\n\nIds 0..0 (1 register).\n"));
        assert!(md.contains("| 0 | `REG_A` | 1 | W | unmapped | – | 65 (0x41) | a\\|b |\n"));
        assert!(md.contains(
            "## SUB\n\nIds 0..0 are the `BASE` block; this block adds ids 1..1 (2 registers in all)."
        ));
        assert!(
            md.contains("| 1 | `REGS_B` | 2 | R | -4000 .. 4000 | ticks/s | 2 (0x02) | Speed. |\n")
        );
        assert_eq!(md.matches("| Id | Symbol |").count(), 2);
    }
}
