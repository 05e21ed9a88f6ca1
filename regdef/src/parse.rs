//! Parser for the line-based register definition format (described at the top of
//! `shared/registers.def`).

use std::collections::HashMap;
use std::fmt;

use crate::model::{Block, Definition, Entry};

/// A definition-file error and the line it was found on.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong there.
    pub kind: ErrorKind,
}

/// What is wrong with a line of the definition file.
#[derive(Clone, Debug, PartialEq)]
pub enum ErrorKind {
    /// A register line appears before the first `block` header.
    EntryOutsideBlock,
    /// A `block` header is not `block NAME [extends BASE] [: title]`.
    BadBlockHeader,
    /// A block name is not upper-case letters, digits and `_`, starting with a letter.
    BadBlockName(String),
    /// Two blocks have the same name.
    DuplicateBlock(String),
    /// `extends` names a block that is not defined above, or that itself extends another.
    UnknownBase(String),
    /// A block has no registers of its own.
    EmptyBlock(String),
    /// A register line ends before the named field.
    MissingField(&'static str),
    /// The id is not a number from 0 to 255.
    BadId(String),
    /// The id is not the next one: ids run on from the base block without gaps.
    IdOutOfOrder {
        /// Id written on the line.
        found: u8,
        /// Id the line must have.
        expected: usize,
    },
    /// A symbol is not upper-case letters, digits and `_` with a prefix ending in `_`.
    BadSymbol(String),
    /// A symbol is defined twice.
    DuplicateSymbol {
        /// The symbol.
        symbol: String,
        /// Line of its first definition.
        first_line: usize,
    },
    /// The size is not 1 or 2.
    BadSize(String),
    /// The access field is not `R` or `W`.
    BadAccess(String),
    /// A range bound is not a finite number.
    BadNumber(String),
    /// The range minimum is not below its maximum.
    EmptyRange {
        /// Lower bound as written.
        min: f32,
        /// Upper bound as written.
        max: f32,
    },
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.kind)
    }
}

impl std::error::Error for ParseError {}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EntryOutsideBlock => {
                write!(f, "register line before any `block NAME` header")
            }
            Self::BadBlockHeader => {
                write!(f, "expected `block NAME [extends BASE] [: title]`")
            }
            Self::BadBlockName(n) => write!(f, "bad block name `{n}` (use A-Z, 0-9, _)"),
            Self::DuplicateBlock(n) => write!(f, "block `{n}` is defined twice"),
            Self::UnknownBase(n) => write!(
                f,
                "`extends {n}`: no such block above, or it extends another block itself"
            ),
            Self::EmptyBlock(n) => write!(f, "block `{n}` has no registers"),
            Self::MissingField(field) => write!(f, "line ends before the {field} field"),
            Self::BadId(t) => write!(f, "id `{t}` is not a number from 0 to 255"),
            Self::IdOutOfOrder { found, expected } => write!(
                f,
                "id {found} is out of order: expected {expected} (ids run on without gaps; \
                 add new registers at the end of their block)"
            ),
            Self::BadSymbol(s) => write!(
                f,
                "bad symbol `{s}` (use A-Z, 0-9, _ with a prefix such as REG_, REGDS_)"
            ),
            Self::DuplicateSymbol { symbol, first_line } => {
                write!(f, "symbol `{symbol}` already defined on line {first_line}")
            }
            Self::BadSize(t) => write!(f, "size `{t}` must be 1 or 2"),
            Self::BadAccess(t) => write!(f, "access `{t}` must be R or W"),
            Self::BadNumber(t) => write!(f, "range bound `{t}` is not a finite number"),
            Self::EmptyRange { min, max } => {
                write!(
                    f,
                    "range {min} {max}: the minimum must be below the maximum"
                )
            }
        }
    }
}

/// Splits off the first whitespace-separated token; returns it and the rest, trimmed.
fn token(s: &str) -> Option<(&str, &str)> {
    let s = s.trim_start();
    if s.is_empty() {
        return None;
    }
    let end = s.find(char::is_whitespace).unwrap_or(s.len());
    Some((&s[..end], s[end..].trim_start()))
}

fn is_name(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_uppercase())
        && chars.all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

fn is_symbol(s: &str) -> bool {
    is_name(s) && matches!(s.split_once('_'), Some((p, rest)) if !p.is_empty() && !rest.is_empty())
}

/// Parses a whole definition file.
pub fn parse(text: &str) -> Result<Definition, ParseError> {
    let mut blocks: Vec<Block> = Vec::new();
    let mut symbols: HashMap<String, usize> = HashMap::new();

    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let err = |kind| ParseError { line, kind };
        let content = raw.trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let Some((first, rest)) = token(content) else {
            continue;
        };
        if first == "block" {
            if let Some(open) = blocks.last() {
                if open.entries.is_empty() {
                    return Err(ParseError {
                        line: open.line,
                        kind: ErrorKind::EmptyBlock(open.name.clone()),
                    });
                }
            }
            let block = parse_header(rest, line, &blocks)?;
            blocks.push(block);
            continue;
        }
        let Some(block_index) = blocks.len().checked_sub(1) else {
            return Err(err(ErrorKind::EntryOutsideBlock));
        };
        let base_len = blocks[block_index]
            .base
            .as_deref()
            .and_then(|b| blocks.iter().find(|x| x.name == b))
            .map_or(0, |b| b.entries.len());
        let expected = base_len + blocks[block_index].entries.len();
        let entry = parse_entry(content, line, expected)?;
        if let Some(&first_line) = symbols.get(&entry.symbol) {
            return Err(err(ErrorKind::DuplicateSymbol {
                symbol: entry.symbol,
                first_line,
            }));
        }
        symbols.insert(entry.symbol.clone(), line);
        blocks[block_index].entries.push(entry);
    }
    if let Some(open) = blocks.last() {
        if open.entries.is_empty() {
            return Err(ParseError {
                line: open.line,
                kind: ErrorKind::EmptyBlock(open.name.clone()),
            });
        }
    }
    Ok(Definition { blocks })
}

fn parse_header(rest: &str, line: usize, blocks: &[Block]) -> Result<Block, ParseError> {
    let err = |kind| ParseError { line, kind };
    let (words, title) = match rest.split_once(':') {
        Some((words, title)) => (words, title.trim()),
        None => (rest, ""),
    };
    let words: Vec<&str> = words.split_whitespace().collect();
    let (name, base) = match words.as_slice() {
        [name] => (*name, None),
        [name, "extends", base] => (*name, Some(*base)),
        _ => return Err(err(ErrorKind::BadBlockHeader)),
    };
    if !is_name(name) {
        return Err(err(ErrorKind::BadBlockName(name.to_string())));
    }
    if blocks.iter().any(|b| b.name == name) {
        return Err(err(ErrorKind::DuplicateBlock(name.to_string())));
    }
    if let Some(base) = base {
        let ok = blocks.iter().any(|b| b.name == base && b.base.is_none());
        if !ok {
            return Err(err(ErrorKind::UnknownBase(base.to_string())));
        }
    }
    Ok(Block {
        name: name.to_string(),
        base: base.map(str::to_string),
        title: title.to_string(),
        entries: Vec::new(),
        line,
    })
}

fn parse_entry(content: &str, line: usize, expected: usize) -> Result<Entry, ParseError> {
    let err = |kind| ParseError { line, kind };
    let field = |s, name| token(s).ok_or(err(ErrorKind::MissingField(name)));

    let (id_text, rest) = field(content, "id")?;
    let id: u8 = id_text
        .parse()
        .map_err(|_| err(ErrorKind::BadId(id_text.to_string())))?;
    if usize::from(id) != expected {
        return Err(err(ErrorKind::IdOutOfOrder {
            found: id,
            expected,
        }));
    }

    let (symbol, rest) = field(rest, "symbol")?;
    if !is_symbol(symbol) {
        return Err(err(ErrorKind::BadSymbol(symbol.to_string())));
    }

    let (size_text, rest) = field(rest, "size")?;
    let size = match size_text {
        "1" => 1,
        "2" => 2,
        _ => return Err(err(ErrorKind::BadSize(size_text.to_string()))),
    };

    let (access, rest) = field(rest, "access")?;
    let writable = match access {
        "W" => true,
        "R" => false,
        _ => return Err(err(ErrorKind::BadAccess(access.to_string()))),
    };

    let (min_text, rest) = field(rest, "range")?;
    let (range, rest) = if min_text == "unmapped" {
        (None, rest)
    } else {
        let (max_text, rest) = field(rest, "range maximum")?;
        let min = number(min_text).ok_or(err(ErrorKind::BadNumber(min_text.to_string())))?;
        let max = number(max_text).ok_or(err(ErrorKind::BadNumber(max_text.to_string())))?;
        if min >= max {
            return Err(err(ErrorKind::EmptyRange { min, max }));
        }
        (Some((min, max)), rest)
    };

    let (unit, rest) = field(rest, "unit")?;
    let meaning = rest.trim();
    if meaning.is_empty() {
        return Err(err(ErrorKind::MissingField("meaning")));
    }
    Ok(Entry {
        id,
        symbol: symbol.to_string(),
        size,
        writable,
        range,
        unit: if unit == "-" {
            String::new()
        } else {
            unit.to_string()
        },
        meaning: meaning.to_string(),
        line,
    })
}

fn number(text: &str) -> Option<f32> {
    text.parse::<f32>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "\
# comment
block BASE
0 REG_A 1 W unmapped - First register.
1 REG_B 2 R -20 100 degC Second,   spaced   meaning.

block SUB extends BASE : Sub block: with a colon
2 REGS_C 2 W 0 0.5 - Third.
";

    fn error_of(text: &str) -> ParseError {
        match parse(text) {
            Ok(d) => panic!("expected an error, parsed {d:?}"),
            Err(e) => e,
        }
    }

    #[test]
    fn parses_blocks_entries_and_fields() {
        let def = parse(GOOD).unwrap();
        assert_eq!(def.blocks.len(), 2);
        let base = &def.blocks[0];
        assert_eq!(base.name, "BASE");
        assert_eq!(base.base, None);
        assert_eq!(base.line, 2);
        assert_eq!(base.entries[0].symbol, "REG_A");
        assert_eq!(base.entries[0].size, 1);
        assert!(base.entries[0].writable);
        assert_eq!(base.entries[0].range, None);
        assert_eq!(base.entries[0].unit, "");
        assert_eq!(base.entries[0].flag_byte(), 65);
        let b = &base.entries[1];
        assert_eq!((b.id, b.size, b.writable), (1, 2, false));
        assert_eq!(b.range, Some((-20.0, 100.0)));
        assert_eq!(b.unit, "degC");
        assert_eq!(b.meaning, "Second,   spaced   meaning.");
        assert_eq!(b.flag_byte(), 2);
        assert_eq!(b.line, 4);
        let sub = &def.blocks[1];
        assert_eq!(sub.base.as_deref(), Some("BASE"));
        assert_eq!(sub.title, "Sub block: with a colon");
        assert_eq!(base.title, "");
        assert_eq!(sub.entries[0].id, 2);
        assert_eq!(sub.entries[0].flag_byte(), 66);
        assert_eq!(sub.entries[0].short_name(), "C");
        let full: Vec<u8> = def.full_table(sub).iter().map(|e| e.id).collect();
        assert_eq!(full, vec![0, 1, 2]);
    }

    #[test]
    fn errors_carry_line_numbers_and_kinds() {
        let cases: Vec<(&str, usize, ErrorKind)> =
            vec![
            ("0 REG_A 1 W unmapped - x", 1, ErrorKind::EntryOutsideBlock),
            ("block\n", 1, ErrorKind::BadBlockHeader),
            ("block A B\n", 1, ErrorKind::BadBlockHeader),
            ("block a\n", 1, ErrorKind::BadBlockName("a".into())),
            (
                "block A\n0 REG_A 1 W unmapped - x\nblock A\n",
                3,
                ErrorKind::DuplicateBlock("A".into()),
            ),
            ("block A extends B\n", 1, ErrorKind::UnknownBase("B".into())),
            ("block A\nblock B\n", 1, ErrorKind::EmptyBlock("A".into())),
            ("\nblock A\n", 2, ErrorKind::EmptyBlock("A".into())),
            ("block A\n0 REG_A 1 W\n", 2, ErrorKind::MissingField("range")),
            (
                "block A\n0 REG_A 1 W 0\n",
                2,
                ErrorKind::MissingField("range maximum"),
            ),
            (
                "block A\n0 REG_A 1 W unmapped\n",
                2,
                ErrorKind::MissingField("unit"),
            ),
            (
                "block A\n0 REG_A 1 W unmapped -   \n",
                2,
                ErrorKind::MissingField("meaning"),
            ),
            ("block A\nx REG_A\n", 2, ErrorKind::BadId("x".into())),
            ("block A\n300 REG_A\n", 2, ErrorKind::BadId("300".into())),
            (
                "block A\n0 REG_A 1 W unmapped - x\n2 REG_B 1 W unmapped - x\n",
                3,
                ErrorKind::IdOutOfOrder {
                    found: 2,
                    expected: 1,
                },
            ),
            (
                "block A\n0 REG_A 1 W unmapped - x\nblock B extends A\n0 REGB_X 1 W unmapped - x\n",
                4,
                ErrorKind::IdOutOfOrder {
                    found: 0,
                    expected: 1,
                },
            ),
            ("block A\n0 RESET 1 W\n", 2, ErrorKind::BadSymbol("RESET".into())),
            ("block A\n0 reg_a 1 W\n", 2, ErrorKind::BadSymbol("reg_a".into())),
            (
                "block A\n0 REG_A 1 W unmapped - x\n1 REG_A 1 W unmapped - x\n",
                3,
                ErrorKind::DuplicateSymbol {
                    symbol: "REG_A".into(),
                    first_line: 2,
                },
            ),
            ("block A\n0 REG_A 4 W\n", 2, ErrorKind::BadSize("4".into())),
            ("block A\n0 REG_A 1 RW\n", 2, ErrorKind::BadAccess("RW".into())),
            (
                "block A\n0 REG_A 1 W zero 1 - x\n",
                2,
                ErrorKind::BadNumber("zero".into()),
            ),
            (
                "block A\n0 REG_A 1 W 0 inf - x\n",
                2,
                ErrorKind::BadNumber("inf".into()),
            ),
            (
                "block A\n0 REG_A 1 W 5 5 - x\n",
                2,
                ErrorKind::EmptyRange { min: 5.0, max: 5.0 },
            ),
        ];
        for (text, line, kind) in cases {
            let e = error_of(text);
            assert_eq!((e.line, &e.kind), (line, &kind), "input {text:?}");
        }
    }

    #[test]
    fn error_message_names_line_and_fix() {
        let e = error_of("block A\n0 REG_A 1 W unmapped - x\n5 REG_B 1 W unmapped - x\n");
        assert_eq!(
            e.to_string(),
            "line 3: id 5 is out of order: expected 1 (ids run on without gaps; \
             add new registers at the end of their block)"
        );
    }
}
