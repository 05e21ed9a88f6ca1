//! Which board, chip and motor slot serve each wheel (reference §1), and the chip index each
//! board has inside the twin.
//!
//! | Wheel | DS controller (drive M1, steer M2) | LL controller (lift) |
//! |---|---|---|
//! | 1, 2 | 1, 2 | 3 (ONE, TWO) |
//! | 3, 4 | 4, 5 | 6 (ONE, TWO) |
//! | 5, 6 | 7, 8 | 9 (ONE, TWO) |
//!
//! The twin adds the master first and then controllers 1..9 in order, so controller n is
//! chip n on the bus and chip 0 is the master.

use harness::Pin;
use physics::wheel::Motor;

/// The rover's wheel numbers.
pub const WHEELS: std::ops::RangeInclusive<u8> = 1..=6;
/// The slave controllers' I²C addresses.
pub const CONTROLLERS: std::ops::RangeInclusive<u8> = 1..=9;
/// The master's chip index on the twin's bus.
pub const MASTER_CHIP: usize = 0;
/// A slave board's LED1 and LED2 (reference §12: A2, A3).
pub const SLAVE_LEDS: [Pin; 2] = [Pin::a(2), Pin::a(3)];
/// The master's blue LED (D7, lit while the RC link is up) and status LED (D13).
pub const MASTER_LEDS: [Pin; 2] = [Pin::d(7), Pin::d(13)];

/// One of a wheel's three motors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Axis {
    /// The drive motor (DS board, M1).
    Drive,
    /// The steer gearmotor (DS board, M2).
    Steer,
    /// The lift gearmotor (LL board, ONE = M1 for odd wheels, TWO = M2 for even wheels).
    Lift,
}

impl Axis {
    /// All three, in the order the rover's tools list them.
    pub const ALL: [Axis; 3] = [Axis::Drive, Axis::Steer, Axis::Lift];

    /// The axis named `word` (`drive`, `steer` or `lift`).
    pub fn parse(word: &str) -> Option<Axis> {
        match word {
            "drive" => Some(Axis::Drive),
            "steer" => Some(Axis::Steer),
            "lift" => Some(Axis::Lift),
            _ => None,
        }
    }

    /// The axis's name.
    pub fn name(self) -> &'static str {
        match self {
            Axis::Drive => "drive",
            Axis::Steer => "steer",
            Axis::Lift => "lift",
        }
    }
}

/// Where one motor of one wheel sits: its controller (= chip index) and motor slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Place {
    /// The slave controller's I²C address, 1..=9.
    pub controller: u8,
    /// The motor slot on that board.
    pub motor: Motor,
}

impl Place {
    /// The chip index of the board on the twin's bus.
    pub fn chip(self) -> usize {
        usize::from(self.controller)
    }
}

/// The board and slot that drive `axis` of `wheel` (1..=6); None for another wheel number.
pub fn place(wheel: u8, axis: Axis) -> Option<Place> {
    if !WHEELS.contains(&wheel) {
        return None;
    }
    let pair = (wheel - 1) / 2;
    let odd = wheel % 2 == 1;
    Some(match axis {
        Axis::Drive | Axis::Steer => Place {
            controller: 3 * pair + if odd { 1 } else { 2 },
            motor: if axis == Axis::Drive {
                Motor::M1
            } else {
                Motor::M2
            },
        },
        Axis::Lift => Place {
            controller: 3 * pair + 3,
            motor: if odd { Motor::M1 } else { Motor::M2 },
        },
    })
}

/// The wheel and axis that slot `motor` of controller `n` drives: the inverse of [`place`],
/// found through it so the wiring is written once; None for a controller outside 1..=9.
pub fn wheel_of(n: u8, motor: Motor) -> Option<(u8, Axis)> {
    let slot = Place {
        controller: n,
        motor,
    };
    WHEELS
        .flat_map(|w| Axis::ALL.map(|a| (w, a)))
        .find(|&(w, a)| place(w, a) == Some(slot))
}

/// Whether controller `n` is a lift/lift board (3, 6, 9).
pub fn is_lift_board(n: u8) -> bool {
    CONTROLLERS.contains(&n) && n.is_multiple_of(3)
}

/// The firmware image a controller runs: `slave-lift` on 3, 6, 9, `slave-drive` elsewhere.
pub fn image_of(n: u8) -> &'static str {
    if is_lift_board(n) {
        "slave-lift"
    } else {
        "slave-drive"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wheels_map_to_the_rover_wiring() {
        let at = |w, a| place(w, a).map(|p| (p.controller, p.motor));
        assert_eq!(at(1, Axis::Drive), Some((1, Motor::M1)));
        assert_eq!(at(1, Axis::Steer), Some((1, Motor::M2)));
        assert_eq!(at(1, Axis::Lift), Some((3, Motor::M1)));
        assert_eq!(at(2, Axis::Lift), Some((3, Motor::M2)));
        assert_eq!(at(2, Axis::Drive), Some((2, Motor::M1)));
        assert_eq!(at(3, Axis::Drive), Some((4, Motor::M1)));
        assert_eq!(at(4, Axis::Steer), Some((5, Motor::M2)));
        assert_eq!(at(4, Axis::Lift), Some((6, Motor::M2)));
        assert_eq!(at(5, Axis::Drive), Some((7, Motor::M1)));
        assert_eq!(at(6, Axis::Drive), Some((8, Motor::M1)));
        assert_eq!(at(6, Axis::Lift), Some((9, Motor::M2)));
        assert_eq!(at(0, Axis::Drive), None);
        assert_eq!(at(7, Axis::Lift), None);
    }

    #[test]
    fn every_slot_of_every_controller_is_the_wheel_motor_that_places_there() {
        let mut seen = 0;
        for n in CONTROLLERS {
            for motor in [Motor::M1, Motor::M2] {
                let (wheel, axis) = wheel_of(n, motor).expect("a controller 1..9");
                let back = place(wheel, axis).map(|p| (p.controller, p.motor));
                assert_eq!(back, Some((n, motor)), "controller {n} {motor:?}");
                seen += 1;
            }
        }
        assert_eq!(seen, 18, "nine boards, two slots each");
        // Every slot against reference §1's wheel table, written out.
        use Axis::{Drive as D, Lift as L, Steer as S};
        let table: Vec<_> = CONTROLLERS
            .flat_map(|n| [Motor::M1, Motor::M2].map(|m| wheel_of(n, m)))
            .collect();
        #[rustfmt::skip]
        let expected = [
            (1, D), (1, S), (2, D), (2, S), (1, L), (2, L), // controllers 1, 2, 3
            (3, D), (3, S), (4, D), (4, S), (3, L), (4, L), // 4, 5, 6
            (5, D), (5, S), (6, D), (6, S), (5, L), (6, L), // 7, 8, 9
        ]
        .map(Some);
        assert_eq!(table, expected);
        assert_eq!(wheel_of(0, Motor::M1), None);
        assert_eq!(wheel_of(10, Motor::M1), None);
    }

    #[test]
    fn images_follow_the_board_kind() {
        let lifts: Vec<u8> = CONTROLLERS.filter(|&n| is_lift_board(n)).collect();
        assert_eq!(lifts, [3, 6, 9]);
        assert_eq!(image_of(3), "slave-lift");
        assert_eq!(image_of(8), "slave-drive");
        assert_eq!(Axis::parse("steer"), Some(Axis::Steer));
        assert_eq!(Axis::parse("Steer"), None);
    }
}
