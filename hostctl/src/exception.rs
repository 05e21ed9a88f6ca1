//! EXCEPTIONDATA values taken apart (reference §6.2), in words for people and as a JSON
//! object for programs: a slave's is its type and motor; the master's is its type, the
//! controller that raised it (0: the master itself) and the motor. A motor is named as the
//! rover's wheels have it (controller 4's motor 0 is wheel 3's drive), so a reader need not
//! know the wiring.

use shared::exception::ExceptionType;
use shared::regs::{id, Register, COMMON, MASTER};

use crate::cmd::pc::Motor;
use crate::json;

/// An exception type's name ("overcurrent"), or "type N" for a code no board raises.
pub fn type_name(code: u8) -> String {
    match ExceptionType::from_code(code) {
        Some(t) => t.name().to_owned(),
        None => format!("type {code}"),
    }
}

/// The wheel and motor that motor `motor` (0 or 1) of controller `device` (1..=9) drives:
/// a DS board 3p+1 or 3p+2 has wheel 2p+1's or 2p+2's drive (0) and steer (1); the LL
/// board 3p+3 has the lifts of wheels 2p+1 (ONE, 0) and 2p+2 (TWO, 1). `None` for any
/// other motor (5: the whole board) or device.
pub fn wheel_motor(device: u8, motor: u8) -> Option<(u8, Motor)> {
    if !(1..=9).contains(&device) || motor > 1 {
        return None;
    }
    let (pair, slot) = ((device - 1) / 3, (device - 1) % 3);
    Some(match (slot, motor) {
        (2, m) => (2 * pair + 1 + m, Motor::Lift),
        (s, 0) => (2 * pair + 1 + s, Motor::Drive),
        (s, _) => (2 * pair + 1 + s, Motor::Steer),
    })
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
    /// The controller the motor belongs to: the one the master's value names, or the one
    /// a slave's value was read from.
    board: u8,
    /// A slave's value read beside its STATUS with bit 0 set: the board is in this
    /// exception now, not only last.
    held: bool,
}

impl Exception {
    /// `raw` taken apart, when `reg` is the master's EXCEPTIONDATA or, read from
    /// controller `device`, a slave's.
    pub fn of(device: u8, reg: &Register, raw: u16) -> Option<Exception> {
        if *reg == MASTER[usize::from(id::REGMASTER_EXCEPTIONDATA)] {
            Some(Exception::master(raw))
        } else if *reg == COMMON[usize::from(id::REG_EXCEPTIONDATA)] {
            Some(Exception::slave(device, raw))
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
            board: high & 0x0f,
            held: false,
        }
    }

    /// REG_EXCEPTIONDATA of controller `device` taken apart: type, motor.
    pub fn slave(device: u8, raw: u16) -> Exception {
        let [low, high] = raw.to_le_bytes();
        Exception {
            code: low,
            controller: None,
            motor: high,
            board: device,
            held: false,
        }
    }

    /// The same value, known to be the exception the board is in now (its STATUS bit 0
    /// is set): its words drop the note that the value outlives the exception.
    pub fn held(self) -> Exception {
        Exception { held: true, ..self }
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

    /// The wheel and motor it names ([`wheel_motor`]), if any: none for a whole board,
    /// which a SlaveSilent is whatever its motor field holds (the master fills in 0).
    pub fn wheel_motor(&self) -> Option<(u8, Motor)> {
        if self.whole_board() {
            return None;
        }
        wheel_motor(self.board, self.motor)
    }

    /// Whether it stands for a whole board: a motor field other than 0 and 1, or a board
    /// off the bus.
    fn whole_board(&self) -> bool {
        self.motor > 1 || self.code == ExceptionType::SlaveSilent as u8
    }

    fn motor_words(&self) -> String {
        match self.wheel_motor() {
            Some((wheel, m)) => format!("motor {} (wheel {wheel}'s {})", self.motor, m.name()),
            None if self.whole_board() => "the whole board".to_owned(),
            None => format!("motor {}", self.motor),
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
            None if self.held => format!("{}, {}", self.type_name(), self.motor_words()),
            None => format!(
                "{}, {} (the last exception)",
                self.type_name(),
                self.motor_words()
            ),
        }
    }

    /// The value as a JSON object: `type` (code), `name` (the manual's, as `OVERCURRENT`;
    /// null for the master's "none" or a code no board sends),
    /// `controller` (the master's only), `motor`, `wheel` and `wheel_motor` ("drive",
    /// "steer" or "lift") when the motor is one of a wheel's, and `text` (as
    /// [`Exception::words`]).
    pub fn json(&self) -> String {
        let object = json::Object::new().int("type", self.code);
        // The manual's name, an identifier to match on; null for none or a code unknown.
        let object = match ExceptionType::from_code(self.code) {
            Some(t) if !self.is_none() => object.str("name", t.manual_name()),
            _ => object.raw("name", "null"),
        };
        let object = match self.controller {
            Some(c) => object.int("controller", c),
            None => object,
        };
        let object = object.int("motor", self.motor);
        let object = match self.wheel_motor() {
            Some((wheel, m)) => object.int("wheel", wheel).str("wheel_motor", m.name()),
            None => object,
        };
        object.str("text", &self.words()).finish()
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
        // Whichever device it was read from (the master's is device 0).
        let e = Exception::of(0, master, 0x1401).expect("the master's EXCEPTIONDATA");
        assert_eq!((e.code, e.controller, e.motor), (1, Some(4), 1));
        // Controller 4 is pair 1's first DS board: wheel 3; motor 1 is its steer.
        assert_eq!(e.wheel_motor(), Some((3, Motor::Steer)));
        assert_eq!(
            e.words(),
            "overcurrent on controller 4, motor 1 (wheel 3's steer)"
        );
        assert_eq!(
            e.json(),
            r#"{"type":1,"name":"OVERCURRENT","controller":4,"motor":1,"wheel":3,"wheel_motor":"steer","text":"overcurrent on controller 4, motor 1 (wheel 3's steer)"}"#
        );
        // A lift board's motor 0 is its pair's odd wheel's lift.
        assert_eq!(
            Exception::master(0x0905).words(),
            "stall on controller 9, motor 0 (wheel 5's lift)"
        );
        let none = Exception::of(0, master, 0).expect("the master's EXCEPTIONDATA");
        assert!(none.is_none());
        assert_eq!(
            none.json(),
            r#"{"type":0,"name":null,"controller":0,"motor":0,"text":"no exception"}"#
        );
        // A controller off the bus is a whole board off it: the master's motor 0 is a filler.
        let silent = Exception::master(0x080b);
        assert_eq!(silent.wheel_motor(), None);
        assert_eq!(
            silent.words(),
            "slave not answering on controller 8, the whole board"
        );
        assert!(!silent.json().contains("wheel"), "{}", silent.json());
        // The master's own (controller 0): PC silence.
        let own = Exception::of(0, master, 13).expect("the master's EXCEPTIONDATA");
        assert_eq!(
            own.words(),
            "PC silent (master heard nothing for REGMASTER_PCTIMEOUT ms)"
        );
    }

    #[test]
    fn a_slave_value_is_type_and_motor_on_either_board() {
        for board in [BoardKind::DriveSteer, BoardKind::LiftLift] {
            let data = reg(board, "EXCEPTIONDATA");
            let e = Exception::of(6, data, 0x0502).expect("a slave's EXCEPTIONDATA");
            assert_eq!((e.code, e.controller, e.motor), (2, None, 5));
            assert!(!e.is_none());
            assert_eq!(
                e.json(),
                r#"{"type":2,"name":"BOOT","motor":5,"text":"boot, the whole board (the last exception)"}"#
            );
            assert_eq!(
                Exception::of(1, data, 0x0009).map(|e| e.words()),
                Some("type 9, motor 0 (wheel 1's drive) (the last exception)".to_owned())
            );
        }
        // Read from controller 6 (pair 1's lift board), motor 1 is wheel 4's lift.
        assert_eq!(
            Exception::slave(6, 0x0101).words(),
            "overcurrent, motor 1 (wheel 4's lift) (the last exception)"
        );
        // Read beside STATUS bit 0: the exception the board is in now.
        assert_eq!(
            Exception::slave(6, 0x0101).held().words(),
            "overcurrent, motor 1 (wheel 4's lift)"
        );
    }

    #[test]
    fn other_registers_are_no_exception_data() {
        assert_eq!(
            Exception::of(0, reg(BoardKind::Master, "TEMP1"), 0x1401),
            None
        );
        // REG_STATUS sits next to EXCEPTIONDATA in the common block.
        assert_eq!(
            Exception::of(1, reg(BoardKind::DriveSteer, "STATUS"), 2),
            None
        );
    }

    #[test]
    fn every_controller_motor_is_one_wheel_motor() {
        // The library's routing (reference §8): each of the 18 motors once.
        let mut seen = Vec::new();
        for device in 1..=9 {
            for motor in 0..=1 {
                let named = wheel_motor(device, motor).expect("a wheel's motor");
                assert!(!seen.contains(&named), "{named:?} twice");
                assert_eq!(crate::cmd::pc::device_of(named.0, named.1), device);
                seen.push(named);
            }
            assert_eq!(wheel_motor(device, 5), None);
        }
        assert_eq!(seen.len(), 18);
        assert_eq!(wheel_motor(0, 0), None);
        assert_eq!(wheel_motor(10, 0), None);
    }
}
