//! The values the executor writes to enable registers: plain arithmetic, tested on the host.
//!
//! Every write the executor (or a driver going through `executor::hw`) makes to an enable
//! register is computed here from the value just read. The rule that keeps the AVR's
//! read-modify-write traps shut is the same everywhere: bits whose write-one has an effect
//! ([`Reg::write_zero_bits`]: TWINT, ADIF, ADSC) are written as zero, which does nothing,
//! so a pending TWI or ADC event survives any masking, and no conversion is started by
//! accident. Every other bit is written back as read, except the enable bits being changed.
//!
//! TWSTO is written back as read. The hardware clears it when the STOP it requested is
//! done; if that happens between the read and the write (one instruction apart), the write
//! sets it again while the TWI is already an unaddressed slave, where TWSTO=1 only
//! requests what is already the case (the datasheet's slave-mode recovery). Drivers must
//! therefore not combine TWSTO with TWSTA in one request; the rover's TWI code never does.

use crate::source::Reg;

/// The value that clears the enable bits `clear` in `reg`, whose current value is `current`.
pub const fn masked(reg: Reg, current: u8, clear: u8) -> u8 {
    current & !clear & !reg.write_zero_bits()
}

/// The value that sets the enable bits `set` in `reg`, whose current value is `current`.
///
/// Used to put back what [`masked`] cleared (`set` = the bits that were enabled before) and
/// to enable sources at start and when a gated source is armed.
pub const fn unmasked(reg: Reg, current: u8, set: u8) -> u8 {
    (current & !reg.write_zero_bits()) | set
}

/// The value a driver's write of `value` becomes: the driver's bits as it asked, the
/// enable bits as they are now (the executor owns those; masking may have cleared some).
pub const fn driver_write(reg: Reg, current: u8, value: u8) -> u8 {
    let owned = reg.enable_bits();
    (value & !owned) | (current & owned)
}

/// A model of one enable register's hardware behaviour, for host tests: write-one-to-clear
/// flags, write-one-to-start triggers, and flags the peripheral raises by itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RegModel {
    /// The register.
    pub reg: Reg,
    /// What a read returns.
    pub value: u8,
    /// How many times a write started something (ADSC written as one).
    pub starts: u32,
}

impl RegModel {
    /// A register holding `value`.
    pub const fn new(reg: Reg, value: u8) -> RegModel {
        RegModel {
            reg,
            value,
            starts: 0,
        }
    }

    /// The hardware raises a flag bit (TWINT when the bus needs attention, ADIF when a
    /// conversion completes).
    pub fn raise(&mut self, flag: u8) {
        self.value |= flag;
    }

    /// A CPU write, with the datasheet's semantics for the register's special bits.
    pub fn write(&mut self, v: u8) {
        match self.reg {
            Reg::Twcr => {
                const TWINT: u8 = 1 << 7;
                const TWWC: u8 = 1 << 3;
                // TWINT: one clears it. TWWC is read-only.
                let flag = if v & TWINT != 0 {
                    0
                } else {
                    self.value & TWINT
                };
                self.value = flag | (self.value & TWWC) | (v & !(TWINT | TWWC));
            }
            Reg::Adcsra => {
                const ADSC: u8 = 1 << 6;
                const ADIF: u8 = 1 << 4;
                if v & ADSC != 0 {
                    self.starts += 1;
                }
                let flag = if v & ADIF != 0 { 0 } else { self.value & ADIF };
                // ADSC reads one while a conversion runs; writing zero does not stop it.
                let busy = (self.value | v) & ADSC;
                self.value = flag | busy | (v & !(ADIF | ADSC));
            }
            Reg::Ucsr0b => {
                const RXB80: u8 = 1 << 1;
                self.value = (self.value & RXB80) | (v & !RXB80);
            }
            _ => self.value = v,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::{Source, REGS};

    const TWINT: u8 = 1 << 7;
    const TWEA: u8 = 1 << 6;
    const TWSTA: u8 = 1 << 5;
    const TWSTO: u8 = 1 << 4;
    const TWEN: u8 = 1 << 2;
    const TWIE: u8 = 1 << 0;
    const ADEN: u8 = 1 << 7;
    const ADSC: u8 = 1 << 6;
    const ADIF: u8 = 1 << 4;
    const ADIE: u8 = 1 << 3;

    #[test]
    fn masking_twi_never_writes_twint() {
        let current = TWINT | TWEA | TWEN | TWIE;
        assert_eq!(masked(Reg::Twcr, current, TWIE), TWEA | TWEN);
    }

    #[test]
    fn masking_twi_keeps_start_stop_and_ack_requests() {
        let current = TWSTA | TWSTO | TWEA | TWEN | TWIE;
        assert_eq!(
            masked(Reg::Twcr, current, TWIE),
            TWSTA | TWSTO | TWEA | TWEN
        );
        assert_eq!(
            unmasked(Reg::Twcr, TWSTA | TWSTO | TWEA | TWEN, TWIE),
            current
        );
    }

    #[test]
    fn a_pending_twi_event_survives_mask_and_restore() {
        let mut twcr = RegModel::new(Reg::Twcr, TWEA | TWEN | TWIE);
        let before = twcr.value;
        twcr.write(masked(Reg::Twcr, twcr.value, TWIE));
        twcr.raise(TWINT); // the bus event arrives while the source is masked
        twcr.write(unmasked(Reg::Twcr, twcr.value, before & TWIE));
        assert_eq!(twcr.value, TWINT | TWEA | TWEN | TWIE);
    }

    #[test]
    fn the_naive_read_modify_write_loses_the_twi_event() {
        // What the trap looks like: reading TWCR and writing it back with TWIE cleared.
        let mut twcr = RegModel::new(Reg::Twcr, TWINT | TWEA | TWEN | TWIE);
        twcr.write(twcr.value & !TWIE);
        assert_eq!(twcr.value & TWINT, 0);
    }

    #[test]
    fn masking_adc_neither_clears_adif_nor_starts_a_conversion() {
        let mut adc = RegModel::new(Reg::Adcsra, ADEN | ADSC | ADIE | 0b111);
        let before = adc.value;
        adc.write(masked(Reg::Adcsra, adc.value, ADIE));
        // The running conversion completes while masked: ADSC drops, ADIF rises.
        adc.value = (adc.value & !ADSC) | ADIF;
        adc.write(unmasked(Reg::Adcsra, adc.value, before & ADIE));
        assert_eq!(adc.value, ADEN | ADIF | ADIE | 0b111);
        assert_eq!(adc.starts, 0);
        // The naive way starts a second conversion and drops the result's flag.
        let mut naive = RegModel::new(Reg::Adcsra, ADEN | ADSC | ADIF | ADIE);
        naive.write(naive.value & !ADIE);
        assert_eq!(naive.starts, 1);
        assert_eq!(naive.value & ADIF, 0);
    }

    #[test]
    fn masking_touches_only_the_bits_asked_for() {
        for reg in REGS {
            for current in 0..=255u8 {
                let clear = reg.enable_bits();
                let v = masked(reg, current, clear);
                assert_eq!(v & clear, 0);
                let others = !clear & !reg.write_zero_bits();
                assert_eq!(v & others, current & others, "{reg:?} {current:#x}");
                assert_eq!(v & reg.write_zero_bits(), 0);
            }
        }
    }

    #[test]
    fn unmask_restores_exactly_what_mask_cleared() {
        for reg in REGS {
            for current in 0..=255u8 {
                let m = reg.enable_bits();
                let saved = current & m;
                let back = unmasked(reg, masked(reg, current, m), saved);
                let keep = !reg.write_zero_bits();
                assert_eq!(back & keep, current & keep, "{reg:?} {current:#x}");
            }
        }
    }

    #[test]
    fn driver_writes_cannot_touch_enable_bits() {
        // The TWI task's own entry masked TWIE; its driver resumes the bus with a full
        // TWCR value that includes TWIE. The executor's copy of TWIE wins.
        let v = driver_write(Reg::Twcr, TWEA | TWEN, TWINT | TWEA | TWEN | TWIE);
        assert_eq!(v, TWINT | TWEA | TWEN);
        let v = driver_write(Reg::Twcr, TWEN | TWIE, TWINT | TWEN | TWSTO);
        assert_eq!(v, TWINT | TWEN | TWSTO | TWIE);
        let rx = Source::USART_RX.bit();
        let udre = Source::USART_UDRE.bit();
        let v = driver_write(Reg::Ucsr0b, rx, 0b0001_1000 | udre);
        assert_eq!(v, 0b0001_1000 | rx);
    }
}
