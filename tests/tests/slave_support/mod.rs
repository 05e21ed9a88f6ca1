//! What the slave emulator tests share: a real slave image on an emulated I2C bus, with
//! the test as the bus master (the bus's Rust peer) and the physics plant closing the
//! loop, plus register access the way the master relays a PC program's requests.
#![allow(dead_code)]

use harness::bus::Bus;
use harness::{Avr, Pin};
use physics::emulator::Plant;
use physics::wheel::SlaveBoardModel;
use shared::mapping;
use shared::regs::{BoardKind, Register};

/// The image of a board kind.
pub fn image(board: BoardKind) -> &'static str {
    match board {
        BoardKind::LiftLift => "slave-lift",
        _ => "slave-drive",
    }
}

/// One slave on a bus, closed over its board model.
pub struct Rig {
    pub bus: Bus,
    pub plant: Plant,
    pub chip: usize,
    pub addr: u8,
    pub board: BoardKind,
}

/// Loads the image for controller `addr` (1..=9: 3, 6, 9 are lift/lift) with EEPROM
/// byte 0 = `addr`, puts it on a bus with its board model.
pub fn rig(addr: u8) -> Rig {
    let board = BoardKind::of_device(addr).expect("a slave address");
    rig_with(board, addr, addr)
}

/// As [`rig`], with any EEPROM byte (a bad address keeps the board off the bus); the
/// board model is that of controller `model`.
pub fn rig_with(board: BoardKind, eeprom: u8, model: u8) -> Rig {
    let name = image(board);
    let mut avr = Avr::firmware(name)
        .unwrap_or_else(|e| panic!("{name}: {e} (build the images with scripts/firmware.sh)"));
    avr.eeprom_write(0, &[eeprom]);
    let mut bus = Bus::new();
    bus.set_peer_khz(400);
    let chip = bus.add_slave(avr).unwrap();
    let plant = Plant::single_on(chip, SlaveBoardModel::for_controller(model).unwrap());
    Rig {
        bus,
        plant,
        chip,
        addr: eeprom,
        board,
    }
}

/// Plant::single for a chip index other than 0.
trait SingleOn {
    fn single_on(chip: usize, model: SlaveBoardModel) -> Plant;
}

impl SingleOn for Plant {
    fn single_on(chip: usize, model: SlaveBoardModel) -> Plant {
        let mut plant = Plant::new();
        plant.attach(chip, model);
        plant
    }
}

impl Rig {
    /// Runs chip and plant for `us` µs.
    pub fn run_us(&mut self, us: u64) {
        self.plant.run_us(&mut self.bus, us).unwrap();
    }

    /// The table entry of register `id`.
    pub fn reg(&self, id: u8) -> &'static Register {
        self.board.register(id).unwrap()
    }

    /// Writes raw `value` to register `id` as the master relays a write: START, SLA+W,
    /// id, LSB [MSB], STOP.
    pub fn write_raw(&mut self, id: u8, value: u16) {
        let [lo, hi] = value.to_le_bytes();
        let bytes: Vec<u8> = match self.board.size_of(id) {
            Some(1) => vec![id, lo],
            _ => vec![id, lo, hi],
        };
        self.bus.write(self.addr, &bytes).unwrap();
    }

    /// Writes an engineering value, mapped as the PC library maps it.
    pub fn write_value(&mut self, id: u8, value: f32) {
        let raw = mapping::map(value, self.reg(id));
        self.write_raw(id, raw);
    }

    /// Reads `n` bytes from register `first` on, as the master does: START, SLA+W, id,
    /// STOP; START, SLA+R, n bytes, STOP.
    pub fn read_bytes(&mut self, first: u8, n: usize) -> Vec<u8> {
        self.bus.write(self.addr, &[first]).unwrap();
        self.bus.read(self.addr, n).unwrap()
    }

    /// Reads one register's raw value.
    pub fn read_raw(&mut self, id: u8) -> u16 {
        let size = usize::from(self.board.size_of(id).unwrap_or(1));
        let b = self.read_bytes(id, size);
        if size == 1 {
            u16::from(b[0])
        } else {
            u16::from_le_bytes([b[0], b[1]])
        }
    }

    /// Reads one register as its engineering value.
    pub fn read_value(&mut self, id: u8) -> f32 {
        let raw = self.read_raw(id);
        mapping::unmap(raw, self.reg(id))
    }

    /// The chip.
    pub fn avr(&self) -> std::cell::RefMut<'_, Avr> {
        self.bus.chip(self.chip).unwrap()
    }

    /// A pin's level.
    pub fn pin(&self, pin: Pin) -> bool {
        self.avr().pin(pin)
    }

    /// A PWM pin's duty (0 when the timer does not drive it).
    pub fn duty(&self, pin: Pin) -> f32 {
        let avr = self.avr();
        avr.pwm_duty(pin)
            .unwrap_or(if avr.pin(pin) { 1.0 } else { 0.0 })
    }

    /// Leaves the boot exception (REG_RESET = 1) and waits for the tick to take it.
    pub fn reset_exceptions(&mut self) {
        self.write_raw(0, 1);
        self.run_us(3_000);
    }
}

/// calibrate()'s drive block for every wheel (the §8.3 drive frame's register values):
/// P 0.01, I 0, D 0, cap 0, decay 0, overcurrent 500, stall check 255, dead zone 1.
pub const DRIVE_GAINS: &[(u8, u16)] = &[
    (0x0a, 0x0041),
    (0x0b, 0x0000),
    (0x0c, 0x7fff),
    (0x0d, 0x0000),
    (0x0e, 0x0000),
    (0x0f, 0x7fff),
    (0x18, 0xfe),
    (0x19, 0x05),
];

/// calibrate()'s second steer send for wheel 1: P 0, I 2, D 0, cap 300, decay 0.95,
/// overcurrent 500, calibration −56/66, stall check 255, dead zone 0.5.
pub const STEER_GAINS_WHEEL_1: &[(u8, u16)] = &[
    (0x1b, 0x0000),
    (0x1c, 0x3332),
    (0x1d, 0x7fff),
    (0x1e, 0x4ccc),
    (0x1f, 0xf331),
    (0x20, 0x7fff),
    (0x2a, 0x43),
    (0x2b, 0xc4),
    (0x28, 0xfe),
    (0x29, 0x02),
];

/// calibrate()'s second lift send for lift ONE of pair 0 (wheel 1): P 0, I 5, D 0,
/// cap 50, decay 0.9, overcurrent 500, calibration −109/109, stall check 255, dead
/// zone 1.
pub const LIFT_GAINS_WHEEL_1: &[(u8, u16)] = &[
    (0x0a, 0x0000),
    (0x0b, 0x7fff),
    (0x0c, 0x7fff),
    (0x0d, 0x0ccc),
    (0x0e, 0xe664),
    (0x0f, 0x7fff),
    (0x17, 0x0b),
    (0x18, 0xf2),
    (0x19, 0xfe),
    (0x1a, 0x05),
];
