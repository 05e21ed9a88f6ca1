//! EXCEPTIONDATA values taken apart (reference §6.2), in words for people and as a JSON
//! object for programs: a slave's is its type and motor; the master's is its type, the
//! controller that raised it (0: the master itself) and the motor.

use shared::exception::ExceptionType;
use shared::regs::{id, Register, COMMON, MASTER};

use crate::json;

/// An exception type's name ("overcurrent"), or "type N" for a code no board raises.
pub fn type_name(code: u8) -> String {
    match ExceptionType::from_code(code) {
        Some(t) => t.name().to_owned(),
        None => format!("type {code}"),
    }
}

/// One EXCEPTIONDATA value, taken apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Exception {
    /// The type code (low byte).
    pub code: u8,
    /// The master's: the controller that raised it (0 = the master); None on a slave.
    pub controller: Option<u8>,
    /// The motor: 0 or 1, anything else none (e.g. 5 for a whole board).
    pub motor: u8,
}

impl Exception {
    /// `raw` taken apart, when `reg` is a slave's or the master's EXCEPTIONDATA.
    pub fn of(reg: &Register, raw: u16) -> Option<Exception> {
        if *reg == MASTER[usize::from(id::REGMASTER_EXCEPTIONDATA)] {
            Some(Exception::master(raw))
        } else if *reg == COMMON[usize::from(id::REG_EXCEPTIONDATA)] {
            Some(Exception::slave(raw))
        } else {
            None
        }
    }

    /// REGMASTER_EXCEPTIONDATA taken apart: type, controller, motor.
    pub fn master(raw: u16) -> Exception {
        let [low, high] = raw.to_le_bytes();
        Exception {
            code: low,
            controller: Some(high & 0x0f),
            motor: high >> 4,
        }
    }

    /// A slave's REG_EXCEPTIONDATA taken apart: type, motor.
    pub fn slave(raw: u16) -> Exception {
        let [low, high] = raw.to_le_bytes();
        Exception {
            code: low,
            controller: None,
            motor: high,
        }
    }

    /// Whether the value says nothing happened: the master's 0 (a slave always holds its
    /// last exception, so its value is never "none").
    pub fn is_none(&self) -> bool {
        self.controller == Some(0) && self.code == 0 && self.motor == 0
    }

    /// The type's name ([`type_name`]).
    pub fn type_name(&self) -> String {
        type_name(self.code)
    }

    fn motor_words(&self) -> String {
        match self.motor {
            0 | 1 => format!("motor {}", self.motor),
            m => format!("motor {m} (none)"),
        }
    }

    /// The value in words, as `read` prints it after the number.
    pub fn words(&self) -> String {
        match self.controller {
            _ if self.is_none() => "no exception".to_owned(),
            Some(0) => self.type_name(),
            Some(c) => format!(
                "{} on controller {c}, {}",
                self.type_name(),
                self.motor_words()
            ),
            None => format!(
                "{}, {} (the last exception)",
                self.type_name(),
                self.motor_words()
            ),
        }
    }

    /// The value as a JSON object: `type` (code), `name` (null for the master's "none"),
    /// `controller` (the master's only), `motor`, and `text` (as [`Exception::words`]).
    pub fn json(&self) -> String {
        let object = json::Object::new().int("type", self.code);
        let object = if self.is_none() {
            object.raw("name", "null")
        } else {
            object.str("name", &self.type_name())
        };
        let object = match self.controller {
            Some(c) => object.int("controller", c),
            None => object,
        };
        object
            .int("motor", self.motor)
            .str("text", &self.words())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shared::regs::BoardKind;

    fn reg(board: BoardKind, name: &str) -> &'static Register {
        board.lookup(name).expect("a register of the table")
    }

    #[test]
    fn the_master_value_is_type_controller_and_motor() {
        let master = reg(BoardKind::Master, "EXCEPTIONDATA");
        // Reference §6.2: 0x1401 is an overcurrent on controller 4, motor 1.
        let e = Exception::of(master, 0x1401).expect("the master's EXCEPTIONDATA");
        assert_eq!(
            e,
            Exception {
                code: 1,
                controller: Some(4),
                motor: 1
            }
        );
        assert_eq!(e.words(), "overcurrent on controller 4, motor 1");
        assert_eq!(
            e.json(),
            r#"{"type":1,"name":"overcurrent","controller":4,"motor":1,"text":"overcurrent on controller 4, motor 1"}"#
        );
        let none = Exception::of(master, 0).expect("the master's EXCEPTIONDATA");
        assert!(none.is_none());
        assert_eq!(
            none.json(),
            r#"{"type":0,"name":null,"controller":0,"motor":0,"text":"no exception"}"#
        );
        // The master's own (controller 0): PC silence.
        let own = Exception::of(master, 13).expect("the master's EXCEPTIONDATA");
        assert_eq!(
            own.words(),
            "PC silent (master heard nothing for REGMASTER_PCTIMEOUT ms)"
        );
    }

    #[test]
    fn a_slave_value_is_type_and_motor_on_either_board() {
        for board in [BoardKind::DriveSteer, BoardKind::LiftLift] {
            let data = reg(board, "EXCEPTIONDATA");
            let e = Exception::of(data, 0x0502).expect("a slave's EXCEPTIONDATA");
            assert_eq!(
                e,
                Exception {
                    code: 2,
                    controller: None,
                    motor: 5
                }
            );
            assert!(!e.is_none());
            assert_eq!(
                e.json(),
                r#"{"type":2,"name":"boot","motor":5,"text":"boot, motor 5 (none) (the last exception)"}"#
            );
            assert_eq!(
                Exception::of(data, 0x0009).map(|e| e.words()),
                Some("type 9, motor 0 (the last exception)".to_owned())
            );
        }
    }

    #[test]
    fn other_registers_are_no_exception_data() {
        assert_eq!(Exception::of(reg(BoardKind::Master, "TEMP1"), 0x1401), None);
        // REG_STATUS sits next to EXCEPTIONDATA in the common block.
        assert_eq!(Exception::of(reg(BoardKind::DriveSteer, "STATUS"), 2), None);
    }
}
