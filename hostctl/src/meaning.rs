//! What a coded register value means, in words for people and as a JSON object for
//! programs: the registers whose number is a code or a set of bits, not a quantity
//! (EXCEPTIONDATA, STATUS, REGMASTER_LASTERROR, REGMASTER_TEMPSREAD, DISABLEDEXCEPTIONS,
//! RESET). `read` prints the words after the number, `watch` under its table, `--json`
//! adds the object beside the value.

use shared::exception::ExceptionType;
use shared::master::LinkError;
use shared::regs::{id, BoardKind, Register, COMMON, MASTER};

use crate::exception::Exception;
use crate::json;

/// REG_STATUS bit 0: in exception (reference §6.2).
pub const STATUS_EXCEPTION: u16 = 1;
/// REG_STATUS bit 2: a lift/lift board.
const STATUS_LL: u16 = 4;
/// REG_STATUS bit 3: a drive/steer board.
const STATUS_DS: u16 = 8;

/// REG_RESET's bits, in the order the slave acts on them (reference §6.2), and their words.
const RESET_BITS: [(u16, &str, &str); 3] = [
    (
        2,
        "hard_reset",
        "hard reset (the watchdog reboots the board)",
    ),
    (1, "leave_exception", "leave the exception"),
    (4, "zero_odometer", "zero the odometer"),
];

/// A coded register value, taken apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Meaning {
    /// EXCEPTIONDATA, a slave's or the master's.
    Exception(Exception),
    /// A controller's REG_STATUS: its board kind and whether it is in exception.
    Status(u16),
    /// REGMASTER_LASTERROR: the last PC-link error's code (0: none since boot).
    LastError(u8),
    /// REGMASTER_TEMPSREAD: bit 0 the ambient sensor, bit n controller n's, set while
    /// its register holds a reading.
    SensorsRead(u16),
    /// DISABLEDEXCEPTIONS: bit t set keeps type t from being raised.
    Masked(u16),
    /// REG_RESET: what a write asks the controller to do, and whether it is a lift
    /// board (no odometer).
    Reset(u16, bool),
}

impl Meaning {
    /// `raw` taken apart, when `reg` (read from or written to `device`) is coded.
    pub fn of(device: u8, reg: &Register, raw: u16) -> Option<Meaning> {
        let common = |i: u8| *reg == COMMON[usize::from(i)];
        let master = |i: u8| *reg == MASTER[usize::from(i)];
        if let Some(e) = Exception::of(device, reg, raw) {
            Some(Meaning::Exception(e))
        } else if common(id::REG_STATUS) {
            Some(Meaning::Status(raw))
        } else if master(id::REGMASTER_LASTERROR) {
            Some(Meaning::LastError(raw.to_le_bytes()[0]))
        } else if master(id::REGMASTER_TEMPSREAD) {
            Some(Meaning::SensorsRead(raw))
        } else if common(id::REG_DISABLEDEXCEPTIONS) {
            Some(Meaning::Masked(raw))
        } else if common(id::REG_RESET) {
            let lift = BoardKind::of_device(device) == Some(BoardKind::LiftLift);
            Some(Meaning::Reset(raw, lift))
        } else {
            None
        }
    }

    /// The same, read beside a STATUS with bit 0 set: an EXCEPTIONDATA is then the
    /// exception the board is in now ([`Exception::held`]).
    pub fn held(self) -> Meaning {
        match self {
            Meaning::Exception(e) => Meaning::Exception(e.held()),
            other => other,
        }
    }

    /// The JSON member it goes in, beside the value.
    pub fn key(&self) -> &'static str {
        match self {
            Meaning::Exception(_) => "exception",
            Meaning::Status(_) => "status",
            // Not `error`: a `--json` line with `error` is a failure.
            Meaning::LastError(_) => "last_error",
            Meaning::SensorsRead(_) => "sensors_read",
            Meaning::Masked(_) => "masked",
            Meaning::Reset(..) => "reset",
        }
    }

    /// The value in words.
    pub fn words(&self) -> String {
        match *self {
            Meaning::Exception(e) => e.words(),
            Meaning::Status(bits) => status_words(bits),
            Meaning::LastError(0) => "no PC-link error since boot".to_owned(),
            Meaning::LastError(code) => match LinkError::from_code(code) {
                Some(e) => format!("{}: {}", e.name(), e.describe()),
                None => format!("code {code}, which this master does not send"),
            },
            Meaning::SensorsRead(bits) => sensors_words(bits),
            Meaning::Masked(0) => "no exception type masked".to_owned(),
            Meaning::Masked(bits) => format!(
                "never raised: {}",
                masked_types(bits)
                    .map(|t| format!("{t} {}{}", crate::exception::type_name(t), mask_note(t)))
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
            Meaning::Reset(bits, lift) => reset_words(bits, lift),
        }
    }

    /// The value as a JSON object, with `text` as [`Meaning::words`] last.
    pub fn json(&self) -> String {
        let object = json::Object::new();
        let object = match *self {
            Meaning::Exception(e) => return e.json(),
            Meaning::Status(bits) => {
                let object = match board_of_status(bits) {
                    Some(board) => object.str("board", board),
                    None => object.raw("board", "null"),
                };
                object.bool("in_exception", bits & STATUS_EXCEPTION != 0)
            }
            Meaning::LastError(code) => {
                let object = object.int("code", code);
                match LinkError::from_code(code) {
                    Some(e) => object.str("name", e.name()),
                    None => object.raw("name", "null"),
                }
            }
            Meaning::SensorsRead(bits) => object.bool("ambient", bits & 1 != 0).raw(
                "boards",
                &json::array(boards(bits, true).map(|b| b.to_string())),
            ),
            Meaning::Masked(bits) => object.raw(
                "types",
                &json::array(masked_types(bits).map(|t| t.to_string())),
            ),
            Meaning::Reset(bits, _) => RESET_BITS
                .iter()
                .fold(object, |o, &(bit, key, _)| o.bool(key, bits & bit != 0)),
        };
        object.str("text", &self.words()).finish()
    }
}

/// The board kind STATUS names, if exactly one of its kind bits is set.
fn board_of_status(bits: u16) -> Option<&'static str> {
    match bits & (STATUS_DS | STATUS_LL) {
        STATUS_DS => Some("DS"),
        STATUS_LL => Some("LL"),
        _ => None,
    }
}

fn status_words(bits: u16) -> String {
    let board = match board_of_status(bits) {
        Some(board) => format!("{board} board"),
        None => "no board kind".to_owned(),
    };
    let state = if bits & STATUS_EXCEPTION != 0 {
        "in exception (its motors are stopped)"
    } else {
        "not in exception"
    };
    let other = bits & !(STATUS_EXCEPTION | STATUS_DS | STATUS_LL);
    if other == 0 {
        format!("{board}, {state}")
    } else {
        format!("{board}, {state}, unknown bits 0x{other:04x}")
    }
}

/// The controllers (1..=9) whose TEMPSREAD bit is `set`.
fn boards(bits: u16, set: bool) -> impl Iterator<Item = u8> {
    (1..=9u8).filter(move |n| (bits >> n & 1 != 0) == set)
}

fn sensors_words(bits: u16) -> String {
    let list = |set: bool| {
        let mut names: Vec<String> = Vec::new();
        if (bits & 1 != 0) == set {
            names.push("ambient".to_owned());
        }
        names.extend(boards(bits, set).map(|b| format!("board {b}")));
        names
    };
    let (read, unread) = (list(true), list(false));
    match (read.is_empty(), unread.is_empty()) {
        (_, true) => "every sensor holds a reading".to_owned(),
        (true, _) => "no sensor holds a reading yet".to_owned(),
        _ => format!(
            "reading: {}; no reading: {}",
            read.join(", "),
            unread.join(", ")
        ),
    }
}

/// What masking type `t` means beyond "never raised", where that misleads.
fn mask_note(t: u8) -> &'static str {
    match ExceptionType::from_code(t) {
        // The boot state is never raised: a board always boots into it.
        Some(ExceptionType::Boot) => " (no effect: every boot enters it)",
        Some(ExceptionType::RemoteSlave) => {
            " (the board then keeps driving when the master spreads another board's fault \
             or the PC-silence failsafe)"
        }
        _ => "",
    }
}

/// The exception type codes whose DISABLEDEXCEPTIONS bit is set.
fn masked_types(bits: u16) -> impl Iterator<Item = u8> {
    (0..16u8).filter(move |t| bits >> t & 1 != 0)
}

fn reset_words(bits: u16, lift: bool) -> String {
    const HARD: u16 = 2;
    const ODOMETER: u16 = 4;
    let known = RESET_BITS.iter().fold(0, |all, &(bit, _, _)| all | bit);
    if bits & HARD != 0 {
        // The board spins until its watchdog fires: nothing after the hard reset happens,
        // and it comes back in its boot state.
        let rest = bits & !HARD;
        return if rest == 0 {
            "hard reset (the watchdog reboots the board into its boot state)".to_owned()
        } else {
            format!(
                "hard reset (the watchdog reboots the board into its boot state); bits \
                 0x{rest:02x} do nothing, as the board reboots first"
            )
        };
    }
    let asked: Vec<&str> = RESET_BITS
        .iter()
        .filter(|&&(bit, _, _)| bits & bit != 0 && !(lift && bit == ODOMETER))
        .map(|&(_, _, words)| words)
        .collect();
    let mut text = if asked.is_empty() {
        "nothing asked (the board writes it back to 0 once it has acted)".to_owned()
    } else {
        asked.join(", then ")
    };
    let idle = bits & !known | if lift { bits & ODOMETER } else { 0 };
    if idle != 0 {
        let why = if lift && idle & ODOMETER != 0 {
            " (a lift board has no odometer)"
        } else {
            ""
        };
        text.push_str(&format!("; bits 0x{idle:02x} do nothing{why}"));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use shared::regs::BoardKind;

    fn meaning(board: BoardKind, name: &str, device: u8, raw: u16) -> Option<Meaning> {
        let reg = board.lookup(name).expect("a register of the table");
        Meaning::of(device, reg, raw)
    }

    fn words(board: BoardKind, name: &str, device: u8, raw: u16) -> String {
        meaning(board, name, device, raw)
            .expect("a coded register")
            .words()
    }

    #[test]
    fn status_names_the_board_and_its_exception() {
        use BoardKind::*;
        // Reference §6.2: boot values 0x0009 (DS) and 0x0005 (LL).
        let boot = meaning(DriveSteer, "STATUS", 1, 9).expect("coded");
        assert_eq!(
            boot.words(),
            "DS board, in exception (its motors are stopped)"
        );
        assert_eq!(
            boot.json(),
            r#"{"board":"DS","in_exception":true,"text":"DS board, in exception (its motors are stopped)"}"#
        );
        assert_eq!(
            words(LiftLift, "STATUS", 3, 4),
            "LL board, not in exception"
        );
        assert_eq!(
            words(LiftLift, "STATUS", 3, 0x25),
            "LL board, in exception (its motors are stopped), unknown bits 0x0020"
        );
        assert_eq!(
            meaning(DriveSteer, "STATUS", 1, 0).map(|m| m.json()),
            Some(
                r#"{"board":null,"in_exception":false,"text":"no board kind, not in exception"}"#
                    .to_owned()
            )
        );
    }

    #[test]
    fn last_error_is_named_as_the_protocol_document_names_it() {
        let none = meaning(BoardKind::Master, "LASTERROR", 0, 0).expect("coded");
        assert_eq!(none.words(), "no PC-link error since boot");
        assert_eq!(
            none.json(),
            r#"{"code":0,"name":null,"text":"no PC-link error since boot"}"#
        );
        assert_eq!(
            none.key(),
            "last_error",
            "a member named `error` marks a failure"
        );
        let e = meaning(BoardKind::Master, "LASTERROR", 0, 12).expect("coded");
        assert_eq!(e.words(), "NoAnswer: a slave did not answer on the I2C bus");
        assert_eq!(
            e.json(),
            r#"{"code":12,"name":"NoAnswer","text":"NoAnswer: a slave did not answer on the I2C bus"}"#
        );
        // Every code has the name docs/protocol.md's table gives it.
        let doc = include_str!("../../docs/protocol.md");
        for e in LinkError::ALL {
            let row = format!("| {} | {} |", e.code(), e.name());
            assert!(doc.contains(&row), "protocol.md has no row `{row}`");
        }
        for code in 1..=14 {
            let text = words(BoardKind::Master, "LASTERROR", 0, code);
            assert!(!text.contains("does not send"), "{code}: {text}");
        }
        assert_eq!(
            words(BoardKind::Master, "LASTERROR", 0, 15),
            "code 15, which this master does not send"
        );
    }

    #[test]
    fn temps_read_lists_the_sensors_with_and_without_a_reading() {
        let m = meaning(BoardKind::Master, "TEMPSREAD", 0, 0b11_1111_0111).expect("coded");
        assert_eq!(
            m.words(),
            "reading: ambient, board 1, board 2, board 4, board 5, board 6, board 7, board 8, \
             board 9; no reading: board 3"
        );
        assert_eq!(
            m.json(),
            format!(
                r#"{{"ambient":true,"boards":[1,2,4,5,6,7,8,9],"text":"{}"}}"#,
                m.words()
            )
        );
        assert_eq!(
            words(BoardKind::Master, "TEMPSREAD", 0, 0),
            "no sensor holds a reading yet"
        );
        assert_eq!(
            words(BoardKind::Master, "TEMPSREAD", 0, 0x3ff),
            "every sensor holds a reading"
        );
    }

    #[test]
    fn a_mask_names_the_types_it_keeps_from_being_raised() {
        use BoardKind::*;
        assert_eq!(
            words(DriveSteer, "DISABLEDEXCEPTIONS", 1, 0),
            "no exception type masked"
        );
        let m = meaning(LiftLift, "DISABLEDEXCEPTIONS", 3, (1 << 5) | (1 << 12)).expect("coded");
        assert_eq!(
            m.words(),
            "never raised: 5 stall; 12 master silent (slave heard no bus traffic)"
        );
        assert_eq!(
            m.json(),
            format!(r#"{{"types":[5,12],"text":"{}"}}"#, m.words())
        );
        assert_eq!(
            words(DriveSteer, "DISABLEDEXCEPTIONS", 1, 1 << 9),
            "never raised: 9 type 9"
        );
        assert_eq!(
            words(DriveSteer, "DISABLEDEXCEPTIONS", 1, 0b1100),
            "never raised: 2 boot (no effect: every boot enters it); 3 remote (EXCEPTIONDATA \
             written: another board's fault spread by the master, or a PC) (the board then \
             keeps driving when the master spreads another board's fault or the PC-silence \
             failsafe)"
        );
    }

    #[test]
    fn reset_bits_are_the_actions_in_the_order_the_board_takes_them() {
        let m = meaning(BoardKind::DriveSteer, "RESET", 1, 7).expect("coded");
        assert_eq!(
            m.words(),
            "hard reset (the watchdog reboots the board into its boot state); bits 0x05 do \
             nothing, as the board reboots first"
        );
        assert_eq!(
            m.json(),
            format!(
                r#"{{"hard_reset":true,"leave_exception":true,"zero_odometer":true,"text":"{}"}}"#,
                m.words()
            )
        );
        assert_eq!(
            words(BoardKind::DriveSteer, "RESET", 1, 0x19),
            "leave the exception; bits 0x18 do nothing"
        );
        assert_eq!(
            words(BoardKind::DriveSteer, "RESET", 1, 5),
            "leave the exception, then zero the odometer"
        );
        assert_eq!(
            words(BoardKind::LiftLift, "RESET", 3, 5),
            "leave the exception; bits 0x04 do nothing (a lift board has no odometer)"
        );
    }

    #[test]
    fn quantities_and_exception_data_are_not_taken_for_other_codes() {
        use BoardKind::*;
        assert_eq!(meaning(Master, "TEMP1", 0, 5), None);
        assert_eq!(meaning(DriveSteer, "DRIVE_REQSPEED", 1, 5), None);
        assert!(matches!(
            meaning(DriveSteer, "EXCEPTIONDATA", 1, 0x0502),
            Some(Meaning::Exception(_))
        ));
        assert_eq!(
            meaning(Master, "EXCEPTIONDATA", 0, 0).map(|m| m.key()),
            Some("exception")
        );
    }
}
