//! Exception types as they travel in EXCEPTIONDATA (reference §6.1), and the master's
//! latched exception (§6.2, §6.3).

/// An exception type code.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum ExceptionType {
    /// A slave motor drew more than its threshold at a high duty (> 250).
    Overcurrent = 1,
    /// The state every board powers up in; never spread.
    Boot = 2,
    /// Raised on a slave by a write to its EXCEPTIONDATA (another board's fault, spread by the
    /// master, or a PC's own write); never spread.
    RemoteSlave = 3,
    /// Stopped, low control, high current (never raised by the original).
    ShortNc = 4,
    /// High duty, no motion, nominal current: the motor is blocked.
    Stall = 5,
    /// High duty, no motion, some current: the encoder or pot is not reporting motion.
    EncoderFault = 6,
    /// High duty, no motion, no current: the motor or its driver is disconnected.
    DriveFault = 7,
    /// A slave motor drew more than its threshold at a duty of 250 or less: a short, or a
    /// motor blocked before its controller reached full duty.
    ShortOc = 8,
    /// Master: a temperature sensor is missing from the OneWire bus.
    SensorMissing = 10,
    /// Master: a slave stopped answering on the I2C bus (new in this project).
    SlaveSilent = 11,
    /// Slave: armed by a ping, it heard no bus transaction for BUSTIMEOUT ms (the master
    /// or the cable is gone); new in this project, motor 5 (none).
    BusSilent = 12,
    /// Master: armed by REGMASTER_PCTIMEOUT, it heard no clean byte from the PC for that
    /// many ms (the PC program hung or the cable is gone); new in this project, slave 0,
    /// motor 0.
    PcSilent = 13,
}

impl ExceptionType {
    /// The wire code.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The type with this wire code.
    pub const fn from_code(code: u8) -> Option<ExceptionType> {
        use ExceptionType::*;
        Some(match code {
            1 => Overcurrent,
            2 => Boot,
            3 => RemoteSlave,
            4 => ShortNc,
            5 => Stall,
            6 => EncoderFault,
            7 => DriveFault,
            8 => ShortOc,
            10 => SensorMissing,
            11 => SlaveSilent,
            12 => BusSilent,
            13 => PcSilent,
            _ => return None,
        })
    }

    /// The name the manual gives it (reference §6.1; the project's own types named the same
    /// way): a stable identifier for programs, where [`ExceptionType::name`] is for people.
    pub const fn manual_name(self) -> &'static str {
        use ExceptionType::*;
        match self {
            Overcurrent => "OVERCURRENT",
            Boot => "BOOT",
            RemoteSlave => "REMOTESLAVE",
            ShortNc => "SHORTNC",
            Stall => "STALL",
            EncoderFault => "ENCODERFAULT",
            DriveFault => "DRIVEFAULT",
            ShortOc => "SHORTOC",
            SensorMissing => "SENSORMISSING",
            SlaveSilent => "SLAVESILENT",
            BusSilent => "BUSSILENT",
            PcSilent => "PCSILENT",
        }
    }

    /// A short name for people.
    pub const fn name(self) -> &'static str {
        use ExceptionType::*;
        match self {
            Overcurrent => "overcurrent",
            Boot => "boot",
            RemoteSlave => "remote (EXCEPTIONDATA written: another board's fault spread by the master, or a PC)",
            ShortNc => "short (not commanded)",
            Stall => "stall",
            EncoderFault => "encoder fault",
            DriveFault => "drive fault",
            ShortOc => "short (overcurrent at a duty of 250 or less: a short, or a blocked motor)",
            SensorMissing => "temperature sensor missing",
            SlaveSilent => "slave not answering",
            BusSilent => "master silent (slave heard no bus traffic)",
            PcSilent => "PC silent (master heard nothing for REGMASTER_PCTIMEOUT ms)",
        }
    }

    /// Whether the master raises and spreads this type when a ping finds it on a slave.
    pub const fn spreads(self) -> bool {
        !matches!(self, ExceptionType::Boot | ExceptionType::RemoteSlave)
    }
}

/// The exception the master has latched: its type, the slave (0 = the master itself)
/// and the motor (0 or 1; 0 when none).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct MasterException {
    /// What happened.
    pub kind: ExceptionType,
    /// Where: controller 1..9, or 0 for the master.
    pub slave: u8,
    /// Which motor of that slave.
    pub motor: u8,
}

impl MasterException {
    /// The state the master boots in.
    pub const BOOT: MasterException = MasterException {
        kind: ExceptionType::Boot,
        slave: 0,
        motor: 0,
    };

    /// The PC-silence failsafe's exception (REGMASTER_PCTIMEOUT): slave 0, motor 0.
    pub const PC_SILENT: MasterException = MasterException {
        kind: ExceptionType::PcSilent,
        slave: 0,
        motor: 0,
    };

    /// REGMASTER_EXCEPTIONDATA: type in bits 0-7, slave in 8-11, motor in 12-15.
    pub const fn data(self) -> u16 {
        // Built as its two bytes: the high one is the slave nibble under the motor's.
        u16::from_le_bytes([self.kind as u8, (self.slave & 0xf) | (self.motor << 4)])
    }
}

/// The master's exception latch: only the first exception is kept until a reset.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct MasterLatch(Option<MasterException>);

impl MasterLatch {
    /// The latch at power-up: in the boot exception.
    pub const fn boot() -> Self {
        MasterLatch(Some(MasterException::BOOT))
    }

    /// Latches `e` unless an exception is already latched. Returns true if it was latched
    /// (the caller then spreads it to the slaves).
    pub fn raise(&mut self, e: MasterException) -> bool {
        if self.0.is_some() {
            return false;
        }
        self.0 = Some(e);
        true
    }

    /// Leaves the exception state (a write to REGMASTER_RESET).
    pub fn clear(&mut self) {
        self.0 = None;
    }

    /// The latched exception, if any.
    pub const fn current(&self) -> Option<MasterException> {
        self.0
    }

    /// REGMASTER_EXCEPTIONDATA: 0 when not in exception.
    pub const fn data(&self) -> u16 {
        match self.0 {
            Some(e) => e.data(),
            None => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exception_data_matches_the_reference_examples() {
        assert_eq!(MasterLatch::boot().data(), 0x0002);
        let oc = MasterException {
            kind: ExceptionType::Overcurrent,
            slave: 4,
            motor: 1,
        };
        assert_eq!(oc.data(), 0x1401);
        let sensor = MasterException {
            kind: ExceptionType::SensorMissing,
            slave: 0,
            motor: 0,
        };
        assert_eq!(sensor.data(), 0x000a);
        // Only the low nibbles of slave and motor are kept.
        let wide = MasterException {
            kind: ExceptionType::Stall,
            slave: 0x1f,
            motor: 0x12,
        };
        assert_eq!(wide.data(), 0x2f05);
    }

    #[test]
    fn manual_names_are_the_references_and_distinct_identifiers() {
        // Reference §6.1's names for the original's types, code by code.
        let manual = [
            (1, "OVERCURRENT"),
            (2, "BOOT"),
            (3, "REMOTESLAVE"),
            (4, "SHORTNC"),
            (5, "STALL"),
            (6, "ENCODERFAULT"),
            (7, "DRIVEFAULT"),
            (8, "SHORTOC"),
        ];
        for (code, name) in manual {
            let t = ExceptionType::from_code(code).expect("a type of the manual");
            assert_eq!(t.manual_name(), name);
        }
        let types: Vec<ExceptionType> = (0..=255).filter_map(ExceptionType::from_code).collect();
        assert_eq!(types.len(), 12);
        for (i, t) in types.iter().enumerate() {
            let name = t.manual_name();
            assert!(name.bytes().all(|b| b.is_ascii_uppercase()), "{name}");
            assert!(
                types[..i].iter().all(|o| o.manual_name() != name),
                "{name} twice"
            );
        }
    }

    #[test]
    fn only_the_first_exception_is_latched_until_cleared() {
        let mut latch = MasterLatch::boot();
        let oc = MasterException {
            kind: ExceptionType::Overcurrent,
            slave: 4,
            motor: 1,
        };
        assert!(!latch.raise(oc), "boot is latched, so nothing else is");
        latch.clear();
        assert_eq!(latch.data(), 0);
        assert!(latch.raise(oc));
        assert!(!latch.raise(MasterException::BOOT));
        assert_eq!(latch.current(), Some(oc));
    }

    #[test]
    fn codes_round_trip_and_boot_and_remote_do_not_spread() {
        for code in 0..=255u8 {
            if let Some(t) = ExceptionType::from_code(code) {
                assert_eq!(t.code(), code);
            }
        }
        assert!(!ExceptionType::Boot.spreads());
        assert!(!ExceptionType::RemoteSlave.spreads());
        assert!(ExceptionType::Overcurrent.spreads());
        assert!(ExceptionType::ShortOc.spreads());
        assert_eq!(ExceptionType::from_code(12), Some(ExceptionType::BusSilent));
        assert!(ExceptionType::BusSilent.spreads());
        assert_eq!(ExceptionType::from_code(13), Some(ExceptionType::PcSilent));
        assert_eq!(MasterException::PC_SILENT.data(), 0x000d);
        assert_eq!(ExceptionType::from_code(14), None);
    }
}
