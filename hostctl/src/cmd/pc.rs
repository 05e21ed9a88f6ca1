//! The original PC library's view of the rover, as `hostctl run` replays it: each motor's
//! parameter block and demand, the frames its calls send (sendParams, setRequired,
//! calibrate, resetExceptions, the operator's emergency stop) and its position limits
//! (reference §8.2–§8.5, §10.3).
//!
//! Everything here builds frames; nothing is sent. The frames are byte-exact with the
//! reference's (the tests pin them).

use shared::mapping;
use shared::protocol::{self, Write};
use shared::regs::{id, BoardKind, Register};

use super::Frame;
use crate::error::{Allowed, HostError};

/// The rover's wheels.
pub const WHEELS: std::ops::RangeInclusive<u8> = 1..=6;

/// The wheel pairs fitted, as the library's init() mask has them: bit p for pair p, wheels
/// 2p+1 and 2p+2 on controllers 3p+1..3p+3. A bench rover may have one pair only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pairs(u8);

impl Pairs {
    /// All three pairs: the whole rover.
    pub const ALL: Pairs = Pairs(0b111);

    /// Reads a list such as `0,2`.
    pub fn parse(text: &str) -> Result<Pairs, HostError> {
        let bad = || HostError::BadPairs {
            given: text.to_owned(),
        };
        let mut mask = 0u8;
        for word in text.split(',') {
            match word.trim() {
                "0" => mask |= 1,
                "1" => mask |= 2,
                "2" => mask |= 4,
                _ => return Err(bad()),
            }
        }
        Ok(Pairs(mask))
    }

    /// The library's mask.
    pub fn mask(self) -> u8 {
        self.0
    }

    /// Whether pair `pair` (0..2) is fitted.
    fn has(self, pair: u8) -> bool {
        pair < 3 && self.0 & (1 << pair) != 0
    }

    /// Whether `wheel` (1..6) is fitted.
    pub fn has_wheel(self, wheel: u8) -> bool {
        (1..=6).contains(&wheel) && self.has((wheel - 1) / 2)
    }

    /// Whether `device` is there: the master always, a controller when its pair is fitted.
    pub fn has_device(self, device: u8) -> bool {
        device == 0 || ((1..=9).contains(&device) && self.has((device - 1) / 3))
    }

    /// The fitted controllers (1..=9), in order.
    pub fn devices(self) -> impl Iterator<Item = u8> {
        (1..=9).filter(move |&d| self.has_device(d))
    }

    /// The fitted wheels, in order.
    pub fn wheels(self) -> impl Iterator<Item = u8> {
        WHEELS.filter(move |&w| self.has_wheel(w))
    }

    /// `Ok` when `wheel` is fitted, else the error naming its pair.
    pub fn check_wheel(self, wheel: u8) -> Result<(), HostError> {
        Self::fitted(
            self.has_wheel(wheel),
            format!("wheel {wheel}"),
            (wheel.clamp(1, 6) - 1) / 2,
        )
    }

    /// `Ok` when `device` is there, else the error naming its pair.
    pub fn check_device(self, device: u8) -> Result<(), HostError> {
        let pair = (device.clamp(1, 9) - 1) / 3;
        Self::fitted(
            self.has_device(device),
            format!("controller {device}"),
            pair,
        )
    }

    /// `Ok` when `fitted`, else the error saying that `what` is on `pair`, left out.
    fn fitted(fitted: bool, what: String, pair: u8) -> Result<(), HostError> {
        if fitted {
            Ok(())
        } else {
            Err(HostError::PairLeftOut { what, pair })
        }
    }
}

/// REG_RESET's bit 1 (value 2), which reboots the board through its watchdog
/// (reference §6.2).
const HARD_RESET: u16 = 2;

/// One of a wheel's motors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motor {
    /// The drive motor (DS board).
    Drive,
    /// The steer motor (DS board).
    Steer,
    /// The lift motor (LL board, ONE for odd wheels, TWO for even ones).
    Lift,
}

impl Motor {
    /// The motor's name.
    pub fn name(self) -> &'static str {
        match self {
            Motor::Drive => "drive",
            Motor::Steer => "steer",
            Motor::Lift => "lift",
        }
    }

    /// Its place in per-motor arrays: drive, steer, lift.
    pub(crate) fn index(self) -> usize {
        match self {
            Motor::Drive => 0,
            Motor::Steer => 1,
            Motor::Lift => 2,
        }
    }
}

/// The controller that drives `motor` of `wheel` (1..=6): DS 3p+1/3p+2, LL 3p+3.
pub fn device_of(wheel: u8, motor: Motor) -> u8 {
    let pair = (wheel - 1) / 2;
    match motor {
        Motor::Drive | Motor::Steer => 3 * pair + if wheel % 2 == 1 { 1 } else { 2 },
        Motor::Lift => 3 * pair + 3,
    }
}

/// The board kind that drives `motor`.
fn board_kind(motor: Motor) -> BoardKind {
    match motor {
        Motor::Drive | Motor::Steer => BoardKind::DriveSteer,
        Motor::Lift => BoardKind::LiftLift,
    }
}

/// The wheel and position motor whose angle `reg` of `device` belongs to, by the register's
/// name (`REGDS_STEER_…`, `REGLL_ONE_…`, `REGLL_TWO_…`); `None` for any other register.
pub fn position_motor(device: u8, reg: &Register) -> Option<(u8, Motor)> {
    let (motor, odd) = if reg.name.starts_with("REGDS_STEER_") {
        (Motor::Steer, None)
    } else if reg.name.starts_with("REGLL_ONE_") {
        (Motor::Lift, Some(true))
    } else if reg.name.starts_with("REGLL_TWO_") {
        (Motor::Lift, Some(false))
    } else {
        return None;
    };
    WHEELS
        .into_iter()
        .find(|&w| device_of(w, motor) == device && odd.is_none_or(|odd| (w % 2 == 1) == odd))
        .map(|w| (w, motor))
}

/// A position motor's CALIBMIN and CALIBMAX registers on its board; `None` for a drive.
fn calib_registers(wheel: u8, motor: Motor) -> Option<[u8; 2]> {
    match motor {
        Motor::Drive => None,
        Motor::Steer => Some([id::REGDS_STEER_CALIBMIN, id::REGDS_STEER_CALIBMAX]),
        Motor::Lift => Some([
            id::REGLL_ONE_CALIBMIN + lift_offset(wheel),
            id::REGLL_ONE_CALIBMAX + lift_offset(wheel),
        ]),
    }
}

/// Offset of a wheel's lift registers on its LL board: 0 for ONE, 18 for TWO.
fn lift_offset(wheel: u8) -> u8 {
    if wheel % 2 == 1 {
        0
    } else {
        id::REGLL_TWO_REQPOS - id::REGLL_ONE_REQPOS
    }
}

/// The register that holds `motor`'s demand for `wheel`.
pub fn demand_register(wheel: u8, motor: Motor) -> u8 {
    match motor {
        Motor::Drive => id::REGDS_DRIVE_REQSPEED,
        Motor::Steer => id::REGDS_STEER_REQPOS,
        Motor::Lift => id::REGLL_ONE_REQPOS + lift_offset(wheel),
    }
}

/// One motor's parameter block, as the library holds it (reference §8.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Block {
    /// P gain.
    pub p: f32,
    /// I gain.
    pub i: f32,
    /// D gain.
    pub d: f32,
    /// Integral cap.
    pub cap: f32,
    /// Integral decay.
    pub decay: f32,
    /// Overcurrent threshold.
    pub overcurrent: f32,
    /// Stall check level.
    pub stall: f32,
    /// Dead zone.
    pub dead_zone: f32,
    /// Calibration (min, max), degrees (position motors only).
    pub calib: (f32, f32),
}

impl Block {
    /// The library's default block: all gains 0, overcurrent 10, stall check 255, dead
    /// zone 1, calibration −100/100.
    pub const DEFAULT: Block = Block {
        p: 0.0,
        i: 0.0,
        d: 0.0,
        cap: 0.0,
        decay: 0.0,
        overcurrent: 10.0,
        stall: 255.0,
        dead_zone: 1.0,
        calib: (-100.0, 100.0),
    };

    /// The position limits setRequired enforces: calibMin + 10 ..= calibMax − 10.
    pub fn limits(&self) -> (f32, f32) {
        (self.calib.0 + 10.0, self.calib.1 - 10.0)
    }
}

/// The library's steer calibration of wheels 1..6, degrees (reference §8.3).
pub const STEER_CALIBRATION: [(f32, f32); 6] = [
    (-56.0, 66.0),
    (-62.0, 59.0),
    (-59.0, 64.0),
    (-60.0, 65.0),
    (-66.0, 57.0),
    (-62.0, 60.0),
];

/// The library's lift calibration of wheels 1..6, degrees (reference §8.3).
pub const LIFT_CALIBRATION: [(f32, f32); 6] = [
    (-109.0, 109.0),
    (-102.0, 112.0),
    (-110.0, 105.0),
    (-101.0, 110.0),
    (-113.0, 113.0),
    (-109.0, 103.0),
];

/// A frame to send and the reply it must get.
#[derive(Debug, Clone, PartialEq)]
pub struct Send {
    /// The device addressed.
    pub device: u8,
    /// The frame.
    pub frame: Vec<u8>,
    /// The register written (for messages).
    pub what: &'static str,
}

impl Send {
    /// How many register writes the frame holds (its count byte).
    pub fn writes(&self) -> u8 {
        self.frame.get(2).copied().unwrap_or_default()
    }

    /// Whether the frame hard-resets a controller: its one write is REG_RESET with bit 1
    /// (value 2) set.
    pub fn hard_resets(&self) -> bool {
        self.reset_bits()
            .is_some_and(|bits| u16::from(bits) & HARD_RESET != 0)
    }

    /// Whether the frame takes a controller out of its exception: its one write is
    /// REG_RESET with bit 0 set.
    pub fn leaves_exception(&self) -> bool {
        self.reset_bits().is_some_and(|bits| bits & 1 != 0)
    }

    /// The bits of a frame whose one write (length, address, count 1, id, value) is a
    /// controller's REG_RESET (the master's own reset register, id 0 too, is no such
    /// register).
    fn reset_bits(&self) -> Option<u8> {
        let one_reset =
            self.device != 0 && self.writes() == 1 && self.frame.get(3) == Some(&id::REG_RESET);
        one_reset.then(|| self.frame.get(4).copied()).flatten()
    }
}

/// One step of a library call: a frame, or a pause.
#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    /// Send a write frame; the master must answer 00.
    Write(Send),
    /// Sleep, as the library does between calibration frames.
    Pause(std::time::Duration),
}

/// The library's state for all six wheels: blocks and last demands (`None`: none sent
/// since the port opened, so the board's own required value is unknown here).
#[derive(Debug, Clone, PartialEq)]
pub struct Pc {
    blocks: [[Block; 3]; 6],
    demands: [[Option<f32>; 3]; 6],
    /// How many demands each motor has been sent: tells a new demand from an old one.
    sends: [[u32; 3]; 6],
    /// Each position motor's pot calibration as its board holds it: raw CALIBMIN and
    /// CALIBMAX as this session's writes left them (`None`: the board's power-up value, as
    /// opening the port rebooted it, or after a hard reset).
    on_board: [[[Option<u16>; 2]; 3]; 6],
    /// How many times each end of each calibration has been written: tells a calibration
    /// written again from one a board may have lost.
    calib_writes: [[[u32; 2]; 3]; 6],
    /// The pairs fitted: the library's calls reach only these.
    pairs: Pairs,
}

impl Default for Pc {
    fn default() -> Self {
        Pc::new()
    }
}

fn write_frame(device: u8, writes: &[Write], what: &'static str) -> Result<Op, HostError> {
    let mut frame = Frame::new();
    protocol::encode_write(device, writes, &mut frame)?;
    Ok(Op::Write(Send {
        device,
        frame: frame.to_vec(),
        what,
    }))
}

/// Maps `value` onto register `reg` of `kind`'s table, as the library does after its range
/// check; out of range is an error naming the register.
fn raw(kind: BoardKind, device: u8, reg: u8, value: f32) -> Result<Write, HostError> {
    let register =
        kind.register(reg)
            .ok_or(HostError::Encode(protocol::EncodeError::UnknownRegister(
                reg,
            )))?;
    if !mapping::in_range(value, register) {
        return Err(HostError::OutOfRange {
            given: value.to_string(),
            allowed: Allowed::of(register, device),
        });
    }
    Ok(Write {
        id: reg,
        raw: mapping::map(value, register),
    })
}

impl Pc {
    /// The library after init: default blocks, no demands sent.
    pub fn new() -> Pc {
        Pc::with_pairs(Pairs::ALL)
    }

    /// The library after init(mask) with `pairs` fitted.
    pub fn with_pairs(pairs: Pairs) -> Pc {
        Pc {
            pairs,
            blocks: [[Block::DEFAULT; 3]; 6],
            demands: [[None; 3]; 6],
            sends: [[0; 3]; 6],
            on_board: [[[None; 2]; 3]; 6],
            calib_writes: [[[0; 2]; 3]; 6],
        }
    }

    /// The pairs fitted.
    pub fn pairs(&self) -> Pairs {
        self.pairs
    }

    /// `motor`'s block for `wheel`.
    pub fn block(&self, wheel: u8, motor: Motor) -> Block {
        self.blocks[usize::from(wheel - 1)][motor.index()]
    }

    fn block_mut(&mut self, wheel: u8, motor: Motor) -> &mut Block {
        &mut self.blocks[usize::from(wheel - 1)][motor.index()]
    }

    /// Whether `motor` of `wheel` reads in degrees: a position motor only once its board
    /// holds the wheel's calibration, as `calibrate` sends it. Before that the board is on
    /// its boot calibration (−512..512); after `stop` on −100/100; after a write to CALIBMIN
    /// or CALIBMAX on what was written; after a hard reset on its boot calibration again.
    pub fn calibrated(&self, wheel: u8, motor: Motor) -> bool {
        let w = usize::from(wheel - 1);
        let table = match motor {
            Motor::Drive => return true,
            Motor::Steer => &STEER_CALIBRATION,
            Motor::Lift => &LIFT_CALIBRATION,
        };
        let (Some(regs), Some(&(min, max))) = (calib_registers(wheel, motor), table.get(w)) else {
            return false;
        };
        let kind = board_kind(motor);
        let held = self.on_board[w][motor.index()];
        regs.iter()
            .zip([min, max])
            .zip(held)
            .all(|((&reg, value), held)| {
                held.is_some() && held == kind.register(reg).map(|r| mapping::map(value, r))
            })
    }

    /// How many times each end (CALIBMIN, CALIBMAX) of `motor` of `wheel` has been
    /// written in this session.
    pub fn calibration_writes(&self, wheel: u8, motor: Motor) -> [u32; 2] {
        self.calib_writes[usize::from(wheel - 1)][motor.index()]
    }

    /// How many demands `motor` of `wheel` has been sent in this session.
    pub fn demand_sends(&self, wheel: u8, motor: Motor) -> u32 {
        self.sends[usize::from(wheel - 1)][motor.index()]
    }

    /// Records `value` as the demand of `motor` of `wheel`.
    fn record_demand(&mut self, wheel: u8, motor: Motor, value: f32) {
        let (w, m) = (usize::from(wheel - 1), motor.index());
        // -0 (`turn 0` sends -0 to wheels 5 and 6, `steer 1 -0` to wheel 1) is recorded as
        // 0, the same raw value, so that a view never prints "-0".
        self.demands[w][m] = Some(value + 0.0);
        self.sends[w][m] = self.sends[w][m].wrapping_add(1);
    }

    /// The last demand sent to `motor` of `wheel` in this session, if any.
    pub fn demand(&self, wheel: u8, motor: Motor) -> Option<f32> {
        self.demands[usize::from(wheel - 1)][motor.index()]
    }

    /// Records a write sent directly (`write DEV REG VALUE`): a demand, an end of a pot
    /// calibration, or a hard reset (see [`Pc::calibrated`]).
    pub fn note_write(&mut self, device: u8, reg: u8, raw: u16, value: f32) {
        for wheel in WHEELS {
            for motor in [Motor::Drive, Motor::Steer, Motor::Lift] {
                if device_of(wheel, motor) == device && demand_register(wheel, motor) == reg {
                    self.record_demand(wheel, motor, value);
                }
            }
        }
        self.note_board_write(device, reg, raw);
    }

    /// Keeps track of the pot calibrations on the boards: a CALIBMIN or CALIBMAX write
    /// sets one end; REG_RESET with bit 1 set (value 2, [`HARD_RESET`]) reboots the board,
    /// back to its power-up ends. Bit 0 (clear) and bit 2 (odometer) leave them.
    fn note_board_write(&mut self, device: u8, reg: u8, raw: u16) {
        for wheel in WHEELS {
            for motor in [Motor::Steer, Motor::Lift] {
                if device_of(wheel, motor) != device {
                    continue;
                }
                let (w, m) = (usize::from(wheel - 1), motor.index());
                if reg == id::REG_RESET && raw & HARD_RESET != 0 {
                    self.on_board[w][m] = [None; 2];
                }
                if let Some(end) = calib_registers(wheel, motor)
                    .and_then(|regs| regs.iter().position(|&r| r == reg))
                {
                    self.on_board[w][m][end] = Some(raw);
                    self.calib_writes[w][m][end] = self.calib_writes[w][m][end].wrapping_add(1);
                }
            }
        }
    }

    /// sendParams: the whole block of `motor` of `wheel` as one write (reference §8.2).
    pub fn send_params(&mut self, wheel: u8, motor: Motor) -> Result<Op, HostError> {
        let b = self.block(wheel, motor);
        let device = device_of(wheel, motor);
        let (kind, regs, values): (BoardKind, Vec<u8>, Vec<f32>) = match motor {
            Motor::Drive => (
                BoardKind::DriveSteer,
                vec![
                    id::REGDS_DRIVE_PGAIN,
                    id::REGDS_DRIVE_IGAIN,
                    id::REGDS_DRIVE_DGAIN,
                    id::REGDS_DRIVE_INTEGRALCAP,
                    id::REGDS_DRIVE_INTEGRALDECAY,
                    id::REGDS_DRIVE_OVERCURRENTTHRESH,
                    id::REGDS_DRIVE_STALLCHECK,
                    id::REGDS_DRIVE_DEADZONE,
                ],
                vec![
                    b.p,
                    b.i,
                    b.d,
                    b.cap,
                    b.decay,
                    b.overcurrent,
                    b.stall,
                    b.dead_zone,
                ],
            ),
            Motor::Steer => (
                BoardKind::DriveSteer,
                vec![
                    id::REGDS_STEER_PGAIN,
                    id::REGDS_STEER_IGAIN,
                    id::REGDS_STEER_DGAIN,
                    id::REGDS_STEER_INTEGRALCAP,
                    id::REGDS_STEER_INTEGRALDECAY,
                    id::REGDS_STEER_OVERCURRENTTHRESH,
                    id::REGDS_STEER_CALIBMIN,
                    id::REGDS_STEER_CALIBMAX,
                    id::REGDS_STEER_STALLCHECK,
                    id::REGDS_STEER_DEADZONE,
                ],
                position_values(&b),
            ),
            Motor::Lift => {
                let off = lift_offset(wheel);
                (
                    BoardKind::LiftLift,
                    [
                        id::REGLL_ONE_PGAIN,
                        id::REGLL_ONE_IGAIN,
                        id::REGLL_ONE_DGAIN,
                        id::REGLL_ONE_INTEGRALCAP,
                        id::REGLL_ONE_INTEGRALDECAY,
                        id::REGLL_ONE_OVERCURRENTTHRESH,
                        id::REGLL_ONE_CALIBMIN,
                        id::REGLL_ONE_CALIBMAX,
                        id::REGLL_ONE_STALLCHECK,
                        id::REGLL_ONE_DEADZONE,
                    ]
                    .iter()
                    .map(|r| r + off)
                    .collect(),
                    position_values(&b),
                )
            }
        };
        let writes = regs
            .iter()
            .zip(&values)
            .map(|(&reg, &v)| raw(kind, device, reg, v))
            .collect::<Result<Vec<_>, _>>()?;
        for write in &writes {
            self.note_board_write(device, write.id, write.raw);
        }
        write_frame(device, &writes, "a parameter block")
    }

    /// setRequired: checks the demand as the library does (drive ±4000; positions within
    /// the calibration less 10°), records it and builds its write.
    pub fn set_required(&mut self, wheel: u8, motor: Motor, value: f32) -> Result<Op, HostError> {
        self.pairs.check_wheel(wheel)?;
        let device = device_of(wheel, motor);
        let reg = demand_register(wheel, motor);
        let kind = board_kind(motor);
        if motor != Motor::Drive {
            let (min, max) = self.block(wheel, motor).limits();
            if !(min..=max).contains(&value) {
                return Err(HostError::PositionLimit {
                    wheel,
                    motor: motor.name(),
                    value,
                    min,
                    max,
                });
            }
        }
        let write = raw(kind, device, reg, value)?;
        self.record_demand(wheel, motor, value);
        write_frame(device, &[write], "a demand")
    }

    /// calibrate()'s two sends of a position motor's parameters, `pause` apart: the block as
    /// `first` leaves it (the pot calibration), then as `then` leaves it (the gains).
    fn two_sends(
        &mut self,
        wheel: u8,
        motor: Motor,
        first: impl Fn(&mut Block),
        then: impl Fn(&mut Block),
        pause: &Op,
    ) -> Result<[Op; 3], HostError> {
        first(self.block_mut(wheel, motor));
        let calibration = self.send_params(wheel, motor)?;
        then(self.block_mut(wheel, motor));
        Ok([calibration, pause.clone(), self.send_params(wheel, motor)?])
    }

    /// Rover::calibrate() (reference §8.3): per wheel, drive parameters, then steer and lift
    /// each in two sends 50 ms apart.
    pub fn calibrate(&mut self) -> Result<Vec<Op>, HostError> {
        let pause = Op::Pause(std::time::Duration::from_millis(50));
        let mut ops = Vec::new();
        for wheel in self.pairs.wheels() {
            let w = usize::from(wheel - 1);
            let drive = self.block_mut(wheel, Motor::Drive);
            (drive.p, drive.i, drive.d) = (0.01, 0.0, 0.0);
            (drive.cap, drive.decay, drive.overcurrent) = (0.0, 0.0, 500.0);
            ops.push(self.send_params(wheel, Motor::Drive)?);

            let steer_calibration = |b: &mut Block| {
                b.calib = STEER_CALIBRATION[w];
                (b.cap, b.decay) = (0.0, 0.0);
            };
            let steer_gains = |b: &mut Block| {
                (b.p, b.i, b.d) = (0.0, 2.0, 0.0);
                (b.cap, b.decay, b.overcurrent) = (300.0, 0.95, 500.0);
                b.dead_zone = 0.5;
            };
            ops.extend(self.two_sends(
                wheel,
                Motor::Steer,
                steer_calibration,
                steer_gains,
                &pause,
            )?);

            let lift_calibration = |b: &mut Block| {
                b.calib = LIFT_CALIBRATION[w];
                (b.cap, b.decay) = (0.0, 0.0);
            };
            let lift_gains = |b: &mut Block| {
                (b.p, b.i, b.d) = (0.0, 5.0, 0.0);
                (b.cap, b.decay, b.overcurrent) = (50.0, 0.9, 500.0);
            };
            ops.extend(self.two_sends(wheel, Motor::Lift, lift_calibration, lift_gains, &pause)?);
        }
        Ok(ops)
    }

    /// The operator's emergency stop (reference §10.3): wait 180 ms, then for each wheel and
    /// each of drive, steer, lift: defaults with overcurrent 200 (calibration −100/100 for
    /// positions), sendParams, setRequired(0). 36 frames.
    pub fn emergency_stop(&mut self) -> Result<Vec<Op>, HostError> {
        let mut ops = vec![Op::Pause(std::time::Duration::from_millis(180))];
        for wheel in self.pairs.wheels() {
            for motor in [Motor::Drive, Motor::Steer, Motor::Lift] {
                *self.block_mut(wheel, motor) = Block {
                    overcurrent: 200.0,
                    ..Block::DEFAULT
                };
                ops.push(self.send_params(wheel, motor)?);
                ops.push(self.set_required(wheel, motor, 0.0)?);
            }
        }
        Ok(ops)
    }
}

/// A position block's values in sendParams order: P, I, D, cap, decay, overcurrent,
/// calibration min and max, stall check, dead zone.
fn position_values(b: &Block) -> Vec<f32> {
    vec![
        b.p,
        b.i,
        b.d,
        b.cap,
        b.decay,
        b.overcurrent,
        b.calib.0,
        b.calib.1,
        b.stall,
        b.dead_zone,
    ]
}

/// resetExceptions() (reference §8.5): REG_RESET = 1 to controllers 3p+1, 3p+2, 3p+3 of
/// each pair, then REGMASTER_RESET = 1 to the master.
pub fn reset_exceptions() -> Result<Vec<Op>, HostError> {
    reset_exceptions_of(Pairs::ALL)
}

/// The first frames of hostctl's `stop`, before the library's emergency stop: a write of
/// REG_EXCEPTIONDATA to each fitted controller, which raises REMOTESLAVE there and so turns
/// both its bridges off at its next 1-ms tick. The library's stop alone leaves a drive's
/// output decaying ×0.96 a 150-ms window under power (its gains go to 0, and the speed
/// form's u is never reset, reference §7.1): some 20 s from full duty.
pub fn bridges_off(pairs: Pairs) -> Result<Vec<Op>, HostError> {
    pairs.devices().map(bridge_off).collect()
}

/// [`bridges_off`] of one controller: its REG_EXCEPTIONDATA write.
pub fn bridge_off(device: u8) -> Result<Op, HostError> {
    write_frame(
        device,
        &[Write {
            id: id::REG_EXCEPTIONDATA,
            raw: 0,
        }],
        "REG_EXCEPTIONDATA",
    )
}

/// REG_RESET = 1 to one device (REGMASTER_RESET on the master): it leaves its exception.
pub fn reset_of(device: u8) -> Result<Op, HostError> {
    let reg = if device == 0 {
        id::REGMASTER_RESET
    } else {
        id::REG_RESET
    };
    write_frame(device, &[Write { id: reg, raw: 1 }], "REG_RESET")
}

/// [`reset_exceptions`] on the pairs fitted.
pub fn reset_exceptions_of(pairs: Pairs) -> Result<Vec<Op>, HostError> {
    [1, 2, 3, 4, 5, 6, 7, 8, 9, 0]
        .into_iter()
        .filter(|&device| pairs.has_device(device))
        .map(reset_of)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fake::hex;

    fn frames(ops: &[Op]) -> Vec<String> {
        ops.iter()
            .filter_map(|op| match op {
                Op::Write(s) => Some(hex(&s.frame)),
                Op::Pause(_) => None,
            })
            .collect()
    }

    #[test]
    fn the_bridges_off_frames_write_exceptiondata_to_each_fitted_controller() {
        let f = frames(&bridges_off(Pairs::ALL).unwrap());
        assert_eq!(f.len(), 9);
        assert_eq!(f[0], "06 12 01 05 00 00");
        assert_eq!(f[8], "06 92 01 05 00 00");
        let front = Pairs::parse("0").unwrap();
        assert_eq!(
            frames(&bridges_off(front).unwrap()),
            [
                "06 12 01 05 00 00",
                "06 22 01 05 00 00",
                "06 32 01 05 00 00"
            ]
        );
        assert_eq!(frames(&[reset_of(4).unwrap()]), ["05 42 01 00 01"]);
    }

    #[test]
    fn calibrate_sends_the_reference_frames_for_wheel_1() {
        let mut pc = Pc::new();
        let ops = pc.calibrate().unwrap();
        let f = frames(&ops);
        assert_eq!(f.len(), 30, "five sends per wheel");
        assert_eq!(
            f[0],
            "19 12 08 0a 41 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f ff 7f 18 fe 19 05"
        );
        assert_eq!(
            f[1],
            "1d 12 0a 1b 00 00 1c 00 00 1d ff 7f 1e 00 00 1f 00 00 20 8f 02 2a 43 2b c4 28 fe 29 05"
        );
        assert_eq!(
            f[2],
            "1d 12 0a 1b 00 00 1c 32 33 1d ff 7f 1e cc 4c 1f 31 f3 20 ff 7f 2a 43 2b c4 28 fe 29 02"
        );
        assert_eq!(
            f[4],
            "1d 32 0a 0a 00 00 0b ff 7f 0c ff 7f 0d cc 0c 0e 64 e6 0f ff 7f 17 0b 18 f2 19 fe 1a 05"
        );
        // Two 50-ms pauses per wheel.
        let pauses = ops.iter().filter(|o| matches!(o, Op::Pause(_))).count();
        assert_eq!(pauses, 12);
        // Wheel 2's lift is TWO on controller 3 (ids + 18), with its own calibration.
        assert!(f[9].starts_with("1d 32 0a 1c 00 00"), "{}", f[9]);
        assert!(f[9].contains(" 29 13 2a f5 "), "{}", f[9]);
    }

    #[test]
    fn calibration_bytes_match_the_per_wheel_table() {
        let mut pc = Pc::new();
        let f = frames(&pc.calibrate().unwrap());
        let steer = [
            "43 2b c4", "3d 2b bd", "40 2b c2", "3f 2b c3", "39 2b bb", "3d 2b be",
        ];
        let lift = ["0b", "13", "0a", "14", "07", "0b"];
        for w in 0..6 {
            assert!(
                f[5 * w + 2].contains(steer[w]),
                "wheel {}: {}",
                w + 1,
                f[5 * w + 2]
            );
            assert!(
                f[5 * w + 4].contains(&format!(" {} ", lift[w])),
                "{}",
                f[5 * w + 4]
            );
        }
        // The raw steer bytes agree with the master's RC set-up table.
        for (w, &(lo, hi)) in shared::master::rc::setup::STEER_CALIBRATION
            .iter()
            .enumerate()
        {
            assert!(f[5 * w + 2].contains(&format!("2a {lo:02x} 2b {hi:02x}")));
        }
    }

    #[test]
    fn emergency_stop_sends_36_frames_starting_with_the_reference_ones() {
        let mut pc = Pc::new();
        pc.calibrate().unwrap();
        let ops = pc.emergency_stop().unwrap();
        assert_eq!(ops[0], Op::Pause(std::time::Duration::from_millis(180)));
        let f = frames(&ops);
        assert_eq!(f.len(), 36);
        assert_eq!(
            f[0],
            "19 12 08 0a 00 00 0b 00 00 0c ff 7f 0d 00 00 0e 00 00 0f 32 33 18 fe 19 05"
        );
        assert_eq!(f[1], "06 12 01 09 ff 7f");
        // Steer: calibration -100/100 goes to the slave (0x15 / 0xe8 on ±120).
        assert!(f[2].contains("2a 15 2b e8"), "{}", f[2]);
        assert_eq!(f[3], "06 12 01 1a ff 7f");
        assert_eq!(f[5], "06 32 01 09 ff 7f");
        assert_eq!(
            f[35], "06 92 01 1b ff 7f",
            "wheel 6 lift TWO on controller 9"
        );
        assert_eq!(pc.block(3, Motor::Steer).limits(), (-90.0, 90.0));
    }

    #[test]
    fn demands_follow_the_library_checks() {
        let mut pc = Pc::new();
        let f = |op: Op| match op {
            Op::Write(s) => hex(&s.frame),
            Op::Pause(_) => String::new(),
        };
        assert_eq!(
            f(pc.set_required(1, Motor::Drive, 1000.0).unwrap()),
            "06 12 01 09 fe 9f"
        );
        assert_eq!(
            f(pc.set_required(1, Motor::Steer, 40.0).unwrap()),
            "06 12 01 1a 98 99"
        );
        assert_eq!(
            f(pc.set_required(2, Motor::Lift, 20.0).unwrap()),
            "06 32 01 1b cb 8c"
        );
        assert_eq!(pc.demand(1, Motor::Drive), Some(1000.0));
        assert_eq!(
            pc.demand(2, Motor::Drive),
            None,
            "nothing sent to wheel 2's drive"
        );
        // Before calibrate the limits are -90..90; after, calibMax - 10 (wheel 1: 56).
        assert!(pc.set_required(1, Motor::Steer, 60.0).is_ok());
        pc.calibrate().unwrap();
        let err = pc.set_required(1, Motor::Steer, 57.0).unwrap_err();
        assert_eq!(
            err.to_string(),
            "wheel 1 steer 57 is outside its limits -46..56 (the calibration less 10°)"
        );
        assert_eq!(
            pc.demand(1, Motor::Steer),
            Some(60.0),
            "a refused demand is not recorded"
        );
        pc.note_write(6, 27, 0, 12.5);
        assert_eq!(
            pc.demand(4, Motor::Lift),
            Some(12.5),
            "TWO on controller 6 is wheel 4"
        );
        assert!(matches!(
            pc.set_required(1, Motor::Drive, 4000.5),
            Err(HostError::OutOfRange { .. })
        ));
    }

    #[test]
    fn the_boards_calibration_follows_direct_writes_and_hard_resets() {
        let mut pc = Pc::new();
        assert!(!pc.calibrated(1, Motor::Steer), "boot calibration");
        assert!(pc.calibrated(1, Motor::Drive), "a speed has no pot");
        pc.calibrate().unwrap();
        let on_wheels =
            |pc: &Pc, motor| -> Vec<bool> { WHEELS.map(|w| pc.calibrated(w, motor)).collect() };
        let all: Vec<bool> = vec![true; 6];
        assert_eq!(on_wheels(&pc, Motor::Steer), all);
        assert_eq!(on_wheels(&pc, Motor::Lift), all);
        // Wheel 3's steer CALIBMIN written to -50 (its table says -59), then back.
        let min = BoardKind::DriveSteer
            .register(id::REGDS_STEER_CALIBMIN)
            .unwrap();
        pc.note_write(4, min.id, mapping::map(-50.0, min), -50.0);
        assert_eq!(
            on_wheels(&pc, Motor::Steer),
            [true, true, false, true, true, true]
        );
        pc.note_write(4, min.id, mapping::map(-59.0, min), -59.0);
        assert_eq!(on_wheels(&pc, Motor::Steer), all);
        // REG_RESET 1 clears exceptions only; 2 (or 6) reboots the board: controller 6 is
        // the LL board of wheels 3 and 4, controller 1 the DS board of wheel 1.
        pc.note_write(6, id::REG_RESET, 1, 1.0);
        assert_eq!(on_wheels(&pc, Motor::Lift), all);
        pc.note_write(6, id::REG_RESET, 2, 2.0);
        assert_eq!(
            on_wheels(&pc, Motor::Lift),
            [true, true, false, false, true, true]
        );
        pc.note_write(1, id::REG_RESET, 6, 6.0);
        assert_eq!(
            on_wheels(&pc, Motor::Steer),
            [false, true, true, true, true, true]
        );
        // Only both ends written back make it the wheel's calibration again.
        let max = BoardKind::DriveSteer
            .register(id::REGDS_STEER_CALIBMAX)
            .unwrap();
        pc.note_write(1, min.id, mapping::map(-56.0, min), -56.0);
        assert!(!pc.calibrated(1, Motor::Steer));
        pc.note_write(1, max.id, mapping::map(66.0, max), 66.0);
        assert!(pc.calibrated(1, Motor::Steer));
        // REG_RESET 4 zeroes the odometer only.
        pc.note_write(1, id::REG_RESET, 4, 4.0);
        assert!(pc.calibrated(1, Motor::Steer));
        // Wheel 6's lift is TWO on controller 9 (ids + 18): its CALIBMAX, not ONE's.
        let two_max = BoardKind::LiftLift
            .register(id::REGLL_ONE_CALIBMAX + 18)
            .unwrap();
        pc.note_write(9, two_max.id, mapping::map(90.0, two_max), 90.0);
        assert_eq!(
            on_wheels(&pc, Motor::Lift),
            [true, true, false, false, true, false]
        );
    }

    #[test]
    fn a_position_register_names_its_wheel_and_motor() {
        let reg = |kind: BoardKind, id| kind.register(id).unwrap();
        let steer = reg(BoardKind::DriveSteer, id::REGDS_STEER_ACTUALPOS);
        assert_eq!(position_motor(1, steer), Some((1, Motor::Steer)));
        assert_eq!(position_motor(8, steer), Some((6, Motor::Steer)));
        let one = reg(BoardKind::LiftLift, id::REGLL_ONE_ACTUALPOS);
        let two = reg(BoardKind::LiftLift, id::REGLL_TWO_ACTUALPOS);
        assert_eq!(position_motor(6, one), Some((3, Motor::Lift)));
        assert_eq!(position_motor(6, two), Some((4, Motor::Lift)));
        let drive = reg(BoardKind::DriveSteer, id::REGDS_DRIVE_ACTUALSPEED);
        assert_eq!(position_motor(1, drive), None);
        assert_eq!(position_motor(3, steer), None, "controller 3 has no steer");
    }

    #[test]
    fn reset_exceptions_is_the_reference_sequence() {
        let f = frames(&reset_exceptions().unwrap());
        assert_eq!(f[0], "05 12 01 00 01");
        assert_eq!(f[2], "05 32 01 00 01");
        assert_eq!(f[8], "05 92 01 00 01");
        assert_eq!(f[9], "05 02 01 00 01");
        assert_eq!(f.len(), 10);
    }

    #[test]
    fn wheels_map_to_controllers() {
        let d: Vec<u8> = WHEELS.map(|w| device_of(w, Motor::Drive)).collect();
        assert_eq!(d, [1, 2, 4, 5, 7, 8]);
        let l: Vec<u8> = WHEELS.map(|w| device_of(w, Motor::Lift)).collect();
        assert_eq!(l, [3, 3, 6, 6, 9, 9]);
        assert_eq!(demand_register(4, Motor::Lift), 27);
        assert_eq!(demand_register(3, Motor::Lift), 9);
    }
}
