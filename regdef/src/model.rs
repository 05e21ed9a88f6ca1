//! The parsed form of a register definition file.

/// A whole definition file: its blocks in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct Definition {
    /// Blocks in the order they appear in the file.
    pub blocks: Vec<Block>,
}

/// One `block` section of the definition file.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// Block name, e.g. `DS`.
    pub name: String,
    /// The block whose registers come first (`block DS extends COMMON`), if any.
    pub base: Option<String>,
    /// Title after the header's `:`, e.g. `Drive/steer slaves`; empty if none.
    pub title: String,
    /// The block's own registers, ids ascending without gaps.
    pub entries: Vec<Entry>,
    /// 1-based line of the `block` header.
    pub line: usize,
}

/// One register line.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// Register id; equals its index in the full table.
    pub id: u8,
    /// Symbol, e.g. `REGDS_DRIVE_REQSPEED`.
    pub symbol: String,
    /// Size in bytes: 1 or 2.
    pub size: u8,
    /// Whether the master forwards writes to it.
    pub writable: bool,
    /// Mapping range `(min, max)`, or `None` when the register is unmapped.
    pub range: Option<(f32, f32)>,
    /// Unit; empty when it has none.
    pub unit: String,
    /// One-line meaning.
    pub meaning: String,
    /// 1-based line in the definition file.
    pub line: usize,
}

impl Entry {
    /// The original firmware's flag byte: bits 0-5 the size, bit 6 (0x40) writable.
    pub fn flag_byte(&self) -> u8 {
        self.size | if self.writable { 0x40 } else { 0 }
    }

    /// The symbol without its prefix (everything up to the first `_`).
    pub fn short_name(&self) -> &str {
        match self.symbol.split_once('_') {
            Some((_, rest)) => rest,
            None => &self.symbol,
        }
    }
}

impl Definition {
    /// Finds a block by name.
    pub fn block(&self, name: &str) -> Option<&Block> {
        self.blocks.iter().find(|b| b.name == name)
    }

    /// The complete table of a block: its base's entries, then its own; index == id.
    pub fn full_table<'a>(&'a self, block: &'a Block) -> Vec<&'a Entry> {
        let mut out = Vec::new();
        if let Some(base) = block.base.as_deref().and_then(|n| self.block(n)) {
            out.extend(self.full_table(base));
        }
        out.extend(block.entries.iter());
        out
    }

    /// Every entry in file order (each symbol once).
    pub fn entries(&self) -> impl Iterator<Item = &Entry> {
        self.blocks.iter().flat_map(|b| b.entries.iter())
    }
}
