//! Driver access to the registers where a peripheral's own bits sit beside an enable bit
//! the executor owns: TWCR (TWIE), ADCSRA (ADIE), UCSR0B (RXCIE0/TXCIE0/UDRIE0) and SPCR
//! (SPIE).
//!
//! Drivers write these registers only through this module. A write keeps the enable bits
//! as the executor has them (a task's own entry may have masked its source, and a driver
//! writing TWIE=1 there would let the task preempt itself), and happens with interrupts
//! disabled between the read and the write. Sources are switched on and off with
//! [`crate::gate`] instead. The registers that hold nothing but enable bits (EIMSK, PCICR,
//! TIMSKn) are the executor's alone.

use crate::source::Reg;

/// A register shared between a driver and the executor.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum DriverReg {
    /// TWI control register.
    Twcr,
    /// ADC control and status register A.
    Adcsra,
    /// USART0 control register B.
    Ucsr0b,
    /// SPI control register.
    Spcr,
}

impl DriverReg {
    /// The register in the executor's table.
    pub const fn reg(self) -> Reg {
        match self {
            DriverReg::Twcr => Reg::Twcr,
            DriverReg::Adcsra => Reg::Adcsra,
            DriverReg::Ucsr0b => Reg::Ucsr0b,
            DriverReg::Spcr => Reg::Spcr,
        }
    }
}

/// Writes `value` to `reg`, except its enable bits, which stay as they are. Write-one
/// bits act as the driver asks: TWINT=1 resumes the bus, ADSC=1 starts a conversion.
#[inline(always)]
pub fn write(reg: DriverReg, value: u8) {
    crate::port::driver_write(reg.reg(), value);
}

/// Changes `reg` by `f`, atomically. `f` receives the value with TWINT, ADIF and ADSC read
/// as zero, so handing it back unchanged acts on nothing; enable bits in the result are
/// ignored.
#[inline(always)]
pub fn modify(reg: DriverReg, f: impl FnOnce(u8) -> u8) {
    crate::port::driver_modify(reg.reg(), f);
}

/// Reads `reg` as it is (including flags and enable bits).
#[inline(always)]
pub fn read(reg: DriverReg) -> u8 {
    crate::port::driver_read(reg.reg())
}
