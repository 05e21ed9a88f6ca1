//! What kind of slave this is: its variant, its motors, its bus address and which
//! register of its table belongs to which motor.

use crate::regs::{id, BoardKind};

/// The two slave variants (reference §1). The variant is built into the firmware.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Variant {
    /// Drive motor (M1, encoder) and steer motor (M2, pot): controllers 1, 2, 4, 5, 7, 8.
    DriveSteer,
    /// Lift motors ONE (M1) and TWO (M2), both with pots: controllers 3, 6, 9.
    LiftLift,
}

/// A slave variant as a type parameter of [`super::Core`] and [`super::RegisterFile`].
///
/// [`Variant`] itself is one (the variant chosen at run time: host tests and tools); the
/// zero-sized [`DriveSteerBoard`] and [`LiftLiftBoard`] fix it at build time, so that
/// every `match` on the variant folds away and an image carries only its own variant's
/// code (no drive code in the lift image). The logic is the same generic code for all
/// three.
pub trait Board: Copy {
    /// The variant.
    fn variant(self) -> Variant;
}

impl Board for Variant {
    #[inline(always)]
    fn variant(self) -> Variant {
        self
    }
}

/// The drive/steer variant, fixed at build time.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct DriveSteerBoard;

impl Board for DriveSteerBoard {
    #[inline(always)]
    fn variant(self) -> Variant {
        Variant::DriveSteer
    }
}

/// The lift/lift variant, fixed at build time.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct LiftLiftBoard;

impl Board for LiftLiftBoard {
    #[inline(always)]
    fn variant(self) -> Variant {
        Variant::LiftLift
    }
}

/// REG_STATUS bit 0: the slave is in exception.
pub const STATUS_EXCEPTION: u16 = 0x0001;
/// REG_STATUS bit 2: a lift/lift board.
pub const STATUS_LIFT_LIFT: u16 = 0x0004;
/// REG_STATUS bit 3: a drive/steer board.
pub const STATUS_DRIVE_STEER: u16 = 0x0008;

impl Variant {
    /// The board kind whose register table this variant carries.
    pub const fn board(self) -> BoardKind {
        match self {
            Variant::DriveSteer => BoardKind::DriveSteer,
            Variant::LiftLift => BoardKind::LiftLift,
        }
    }

    /// The variant of a board kind; the master is not a slave.
    pub const fn of_board(board: BoardKind) -> Option<Variant> {
        match board {
            BoardKind::DriveSteer => Some(Variant::DriveSteer),
            BoardKind::LiftLift => Some(Variant::LiftLift),
            BoardKind::Master => None,
        }
    }

    /// The REG_STATUS bit that names the variant.
    pub const fn status_bit(self) -> u16 {
        match self {
            Variant::DriveSteer => STATUS_DRIVE_STEER,
            Variant::LiftLift => STATUS_LIFT_LIFT,
        }
    }

    /// Whether motor M1 is a speed-controlled drive (true on drive/steer boards).
    pub const fn has_drive(self) -> bool {
        matches!(self, Variant::DriveSteer)
    }
}

/// A motor of a slave, by its id in EXCEPTIONDATA.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum MotorId {
    /// Drive (DS) or lift ONE (LL); PWM D9, current ADC0.
    M1 = 0,
    /// Steer (DS) or lift TWO (LL); PWM D10, current ADC1.
    M2 = 1,
}

impl MotorId {
    /// Both motors, M1 first.
    pub const BOTH: [MotorId; 2] = [MotorId::M1, MotorId::M2];

    /// The index of the motor: 0 for M1, 1 for M2.
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// The I2C address an EEPROM byte 0 stands for: 1..=9, or `None` for any other value
/// (the board then stays off the bus and shows the bad-address LED pattern).
pub const fn bus_address(eeprom_byte: u8) -> Option<u8> {
    match eeprom_byte {
        1..=9 => Some(eeprom_byte),
        _ => None,
    }
}

/// A writable parameter of a motor.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Param {
    /// REQSPEED (drive) or REQPOS (steer, lift).
    Required,
    /// PGAIN.
    P,
    /// IGAIN.
    I,
    /// DGAIN.
    D,
    /// INTEGRALCAP.
    Cap,
    /// INTEGRALDECAY.
    Decay,
    /// OVERCURRENTTHRESH.
    Threshold,
    /// STALLCHECK.
    StallCheck,
    /// DEADZONE.
    DeadZone,
    /// CALIBMIN (position motors).
    CalibMin,
    /// CALIBMAX (position motors).
    CalibMax,
}

impl Param {
    /// The parameter whose discriminant is `index` (`Param::Required as u8` is 0 …
    /// `Param::CalibMax as u8` is 10), `None` above.
    pub const fn from_index(index: u8) -> Option<Param> {
        Some(match index {
            0 => Param::Required,
            1 => Param::P,
            2 => Param::I,
            3 => Param::D,
            4 => Param::Cap,
            5 => Param::Decay,
            6 => Param::Threshold,
            7 => Param::StallCheck,
            8 => Param::DeadZone,
            9 => Param::CalibMin,
            10 => Param::CalibMax,
            _ => return None,
        })
    }
}

/// A monitoring register of a motor, refreshed by the slave.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Monitor {
    /// ACTUALSPEED or ACTUALPOS.
    Actual,
    /// ERROR.
    Error,
    /// ERRORINTEGRAL.
    Integral,
    /// ERRORDERIV.
    Deriv,
    /// CONTROL.
    Control,
    /// INTERVALCTRL.
    Interval,
    /// CURRENT.
    Current,
}

impl Monitor {
    /// Every monitoring register, in table order.
    pub const ALL: [Monitor; 7] = [
        Monitor::Actual,
        Monitor::Error,
        Monitor::Integral,
        Monitor::Deriv,
        Monitor::Control,
        Monitor::Interval,
        Monitor::Current,
    ];
}

/// Where one motor's registers sit in its board's table.
///
/// Every motor block starts with the same fourteen registers (REQ…CURRENT) from `base`;
/// the tail (stall check, dead zone, calibration) is ordered differently on DS and LL.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Layout {
    /// Id of REQSPEED / REQPOS; P gain is base + 1 … CURRENT is base + 13.
    pub base: u8,
    /// Id of STALLCHECK.
    pub stall_check: u8,
    /// Id of DEADZONE.
    pub dead_zone: u8,
    /// Ids of CALIBMIN and CALIBMAX, for a position motor.
    pub calib: Option<(u8, u8)>,
}

/// DS M1, the drive.
const DS_DRIVE: Layout = Layout {
    base: id::REGDS_DRIVE_REQSPEED,
    stall_check: id::REGDS_DRIVE_STALLCHECK,
    dead_zone: id::REGDS_DRIVE_DEADZONE,
    calib: None,
};
/// DS M2, the steer.
const DS_STEER: Layout = Layout {
    base: id::REGDS_STEER_REQPOS,
    stall_check: id::REGDS_STEER_STALLCHECK,
    dead_zone: id::REGDS_STEER_DEADZONE,
    calib: Some((id::REGDS_STEER_CALIBMIN, id::REGDS_STEER_CALIBMAX)),
};
/// LL M1, lift ONE.
const LL_ONE: Layout = Layout {
    base: id::REGLL_ONE_REQPOS,
    stall_check: id::REGLL_ONE_STALLCHECK,
    dead_zone: id::REGLL_ONE_DEADZONE,
    calib: Some((id::REGLL_ONE_CALIBMIN, id::REGLL_ONE_CALIBMAX)),
};
/// LL M2, lift TWO.
const LL_TWO: Layout = Layout {
    base: id::REGLL_TWO_REQPOS,
    stall_check: id::REGLL_TWO_STALLCHECK,
    dead_zone: id::REGLL_TWO_DEADZONE,
    calib: Some((id::REGLL_TWO_CALIBMIN, id::REGLL_TWO_CALIBMAX)),
};

/// The parameter at an offset from [`Layout::base`] in the shared head of a motor
/// block: the offsets are the variants' own discriminants, so only the bound is new.
const fn head(offset: u8) -> Option<Param> {
    if offset <= Param::Threshold as u8 {
        Param::from_index(offset)
    } else {
        None
    }
}

impl Layout {
    /// The layout of a motor of a variant.
    pub const fn of(variant: Variant, motor: MotorId) -> Layout {
        match (variant, motor) {
            (Variant::DriveSteer, MotorId::M1) => DS_DRIVE,
            (Variant::DriveSteer, MotorId::M2) => DS_STEER,
            (Variant::LiftLift, MotorId::M1) => LL_ONE,
            (Variant::LiftLift, MotorId::M2) => LL_TWO,
        }
    }

    /// The parameter a register id holds, if it is one of this motor's parameters.
    pub const fn param(&self, reg: u8) -> Option<Param> {
        if let Some(offset) = reg.checked_sub(self.base) {
            if let Some(param) = head(offset) {
                return Some(param);
            }
        }
        if reg == self.stall_check {
            return Some(Param::StallCheck);
        }
        if reg == self.dead_zone {
            return Some(Param::DeadZone);
        }
        match self.calib {
            Some((min, _)) if reg == min => Some(Param::CalibMin),
            Some((_, max)) if reg == max => Some(Param::CalibMax),
            _ => None,
        }
    }

    /// The id of a parameter of this motor (`None` for calibration on the drive).
    pub const fn param_id(&self, param: Param) -> Option<u8> {
        Some(match param {
            Param::Required => self.base,
            Param::P => self.base + 1,
            Param::I => self.base + 2,
            Param::D => self.base + 3,
            Param::Cap => self.base + 4,
            Param::Decay => self.base + 5,
            Param::Threshold => self.base + 6,
            Param::StallCheck => self.stall_check,
            Param::DeadZone => self.dead_zone,
            Param::CalibMin => match self.calib {
                Some((min, _)) => min,
                None => return None,
            },
            Param::CalibMax => match self.calib {
                Some((_, max)) => max,
                None => return None,
            },
        })
    }

    /// The id of a monitoring register of this motor.
    pub const fn monitor_id(&self, monitor: Monitor) -> u8 {
        self.base
            + match monitor {
                Monitor::Actual => 7,
                Monitor::Error => 8,
                Monitor::Integral => 9,
                Monitor::Deriv => 10,
                Monitor::Control => 11,
                Monitor::Interval => 12,
                Monitor::Current => 13,
            }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regs::id;
    use crate::slave::{AdcSample, Core, EdgeSample, Inputs, Outputs, RegisterFile, TICK_US};

    #[test]
    fn the_head_of_a_block_is_its_first_seven_parameters_in_order() {
        let order = [
            Param::Required,
            Param::P,
            Param::I,
            Param::D,
            Param::Cap,
            Param::Decay,
            Param::Threshold,
        ];
        for offset in 0..=u8::MAX {
            assert_eq!(
                head(offset),
                order.get(usize::from(offset)).copied(),
                "{offset}"
            );
        }
        for variant in [Variant::DriveSteer, Variant::LiftLift] {
            for motor in MotorId::BOTH {
                let layout = Layout::of(variant, motor);
                for (offset, param) in order.into_iter().enumerate() {
                    let reg = layout.base + offset as u8;
                    assert_eq!(layout.param(reg), Some(param));
                    assert_eq!(layout.param_id(param), Some(reg));
                }
            }
        }
    }

    /// Runs a board for `ticks` ms with writes, pot movement and encoder edges; returns
    /// every tick's outputs and register file contents.
    fn run<B: Board>(board: B, writes: &[(u8, u16)], ticks: u32) -> Vec<(Outputs, Vec<u16>)> {
        let mut core = Core::new(board, 4);
        let mut regs = RegisterFile::new(board);
        let mut trace = Vec::new();
        for t in 0..ticks {
            if t == 700 {
                for &(reg, raw) in writes {
                    regs.start_write();
                    regs.write(reg);
                    let [lo, hi] = raw.to_le_bytes();
                    regs.write(lo);
                    regs.write(hi);
                    regs.stop();
                }
            }
            let pot = 300 + (t % 400) as u16;
            let inputs = Inputs {
                edges: EdgeSample {
                    rising: (t % 3) as u16,
                    b_high: 0,
                    last_edge: crate::slave::clock::units(t * TICK_US),
                },
                adc: AdcSample {
                    current: [40, 60],
                    current_peak: [45, 70],
                    ch6: pot,
                    ch7: 1023 - pot,
                },
            };
            let out = core.tick(t * TICK_US, &inputs, &mut regs);
            trace.push((out, (0..regs.len()).map(|r| regs.get(r)).collect()));
        }
        trace
    }

    #[test]
    fn build_time_boards_behave_as_the_run_time_variant() {
        // REG_RESET bit 0 leaves the boot exception; then gains and demands.
        let ds = [
            (id::REG_RESET, 1),
            (id::REGDS_DRIVE_REQSPEED, 0x9000),
            (id::REGDS_DRIVE_PGAIN, 0x0041),
            (id::REGDS_STEER_REQPOS, 0x8800),
            (id::REGDS_STEER_IGAIN, 0x3332),
        ];
        let a = run(DriveSteerBoard, &ds, 1_500);
        let b = run(Variant::DriveSteer, &ds, 1_500);
        assert!(a == b, "drive/steer differs");
        let last = &a[a.len() - 1];
        assert_eq!(last.1[usize::from(id::REG_STATUS)], STATUS_DRIVE_STEER);
        let ll = [
            (id::REG_RESET, 1),
            (id::REGLL_ONE_REQPOS, 0x9000),
            (id::REGLL_ONE_PGAIN, 0x7000),
            (id::REGLL_TWO_REQPOS, 0x7000),
        ];
        let a = run(LiftLiftBoard, &ll, 1_500);
        let b = run(Variant::LiftLift, &ll, 1_500);
        assert!(a == b, "lift/lift differs");
        let last = &a[a.len() - 1];
        assert_eq!(last.1[usize::from(id::REG_STATUS)], STATUS_LIFT_LIFT);
        assert!(last.0.motors.iter().any(|m| m.duty() > 0), "the lifts move");
    }
}
