//! The interrupt sources a task can be bound to, and the enable registers that gate them.
//!
//! On the ATmega328P an interrupt source is taken when its flag, its enable bit and the
//! global I flag are all set. The executor masks a source by clearing its enable bit, so
//! what it needs to know about each source is which register holds that bit, and what
//! else lives in that register that a read-modify-write must not disturb.

/// A register that holds the enable bit of at least one supported interrupt source.
///
/// The discriminant is the register's index in the executor's per-register tables.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Reg {
    /// External interrupt mask: INT0, INT1.
    Eimsk = 0,
    /// Pin-change interrupt control: PCIE0..2.
    Pcicr = 1,
    /// Timer/Counter0 interrupt mask.
    Timsk0 = 2,
    /// Timer/Counter1 interrupt mask.
    Timsk1 = 3,
    /// Timer/Counter2 interrupt mask.
    Timsk2 = 4,
    /// SPI control: SPIE beside the SPI driver's mode bits.
    Spcr = 5,
    /// ADC control and status A: ADIE beside ADIF (write one to clear) and ADSC (write one
    /// to start a conversion).
    Adcsra = 6,
    /// TWI control: TWIE beside TWINT (write one to clear, which also resumes the bus) and
    /// the bus-condition requests TWSTA/TWSTO/TWEA.
    Twcr = 7,
    /// USART0 control B: RXCIE0/TXCIE0/UDRIE0 beside the driver's enable and size bits.
    Ucsr0b = 8,
}

/// Number of [`Reg`]s; the length of every per-register table.
pub const REG_COUNT: usize = 9;

/// Every register, in index order.
pub const REGS: [Reg; REG_COUNT] = [
    Reg::Eimsk,
    Reg::Pcicr,
    Reg::Timsk0,
    Reg::Timsk1,
    Reg::Timsk2,
    Reg::Spcr,
    Reg::Adcsra,
    Reg::Twcr,
    Reg::Ucsr0b,
];

impl Reg {
    /// The register's index in per-register tables.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Data-space address (what `lds`/`sts` use; I/O address + 0x20 for the low ones).
    pub const fn addr(self) -> u16 {
        match self {
            Reg::Eimsk => 0x3D,
            Reg::Pcicr => 0x68,
            Reg::Timsk0 => 0x6E,
            Reg::Timsk1 => 0x6F,
            Reg::Timsk2 => 0x70,
            Reg::Spcr => 0x4C,
            Reg::Adcsra => 0x7A,
            Reg::Twcr => 0xBC,
            Reg::Ucsr0b => 0xC1,
        }
    }

    /// The interrupt-enable bits of the register (bits the executor owns).
    pub const fn enable_bits(self) -> u8 {
        match self {
            Reg::Eimsk => 0b0000_0011,
            Reg::Pcicr => 0b0000_0111,
            Reg::Timsk0 => 0b0000_0111,
            Reg::Timsk1 => 0b0010_0111,
            Reg::Timsk2 => 0b0000_0111,
            Reg::Spcr => 1 << 7,
            Reg::Adcsra => 1 << 3,
            Reg::Twcr => 1 << 0,
            Reg::Ucsr0b => 0b1110_0000,
        }
    }

    /// Bits that must be written as zero by anyone who only means to change enable bits,
    /// because writing back the one that was read has an effect: ADIF and TWINT are
    /// cleared by writing one (TWINT=1 also releases the TWI to its next bus action), and
    /// ADSC=1 starts a conversion. Writing zero to any of them does nothing.
    pub const fn write_zero_bits(self) -> u8 {
        match self {
            Reg::Adcsra => (1 << 4) | (1 << 6),
            Reg::Twcr => 1 << 7,
            _ => 0,
        }
    }

    /// True when the register holds nothing but enable bits (its other bits are reserved),
    /// so nothing but the executor writes it and a saved value can be written back verbatim.
    pub const fn is_pure(self) -> bool {
        matches!(
            self,
            Reg::Eimsk | Reg::Pcicr | Reg::Timsk0 | Reg::Timsk1 | Reg::Timsk2
        )
    }
}

/// An interrupt source a task can be bound to. Variant names are the ATmega328P vector
/// names, exactly as a task declaration writes them (`binds = TWI`).
#[allow(non_camel_case_types)]
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Source {
    /// External interrupt 0 (PD2).
    INT0,
    /// External interrupt 1 (PD3).
    INT1,
    /// Pin change on PCINT0..7 (port B).
    PCINT0,
    /// Pin change on PCINT8..14 (port C).
    PCINT1,
    /// Pin change on PCINT16..23 (port D).
    PCINT2,
    /// Timer2 compare match A.
    TIMER2_COMPA,
    /// Timer2 compare match B.
    TIMER2_COMPB,
    /// Timer2 overflow.
    TIMER2_OVF,
    /// Timer1 input capture.
    TIMER1_CAPT,
    /// Timer1 compare match A.
    TIMER1_COMPA,
    /// Timer1 compare match B.
    TIMER1_COMPB,
    /// Timer1 overflow.
    TIMER1_OVF,
    /// Timer0 compare match A.
    TIMER0_COMPA,
    /// Timer0 compare match B.
    TIMER0_COMPB,
    /// Timer0 overflow.
    TIMER0_OVF,
    /// SPI serial transfer complete.
    SPI_STC,
    /// USART0 receive complete.
    USART_RX,
    /// USART0 data register empty.
    USART_UDRE,
    /// USART0 transmit complete.
    USART_TX,
    /// ADC conversion complete.
    ADC,
    /// TWI (I²C) event: TWINT set.
    TWI,
}

/// Every supported source, in vector order.
pub const SOURCES: [Source; 21] = [
    Source::INT0,
    Source::INT1,
    Source::PCINT0,
    Source::PCINT1,
    Source::PCINT2,
    Source::TIMER2_COMPA,
    Source::TIMER2_COMPB,
    Source::TIMER2_OVF,
    Source::TIMER1_CAPT,
    Source::TIMER1_COMPA,
    Source::TIMER1_COMPB,
    Source::TIMER1_OVF,
    Source::TIMER0_COMPA,
    Source::TIMER0_COMPB,
    Source::TIMER0_OVF,
    Source::SPI_STC,
    Source::USART_RX,
    Source::USART_UDRE,
    Source::USART_TX,
    Source::ADC,
    Source::TWI,
];

impl Source {
    /// The register that holds the source's enable bit.
    pub const fn reg(self) -> Reg {
        match self {
            Source::INT0 | Source::INT1 => Reg::Eimsk,
            Source::PCINT0 | Source::PCINT1 | Source::PCINT2 => Reg::Pcicr,
            Source::TIMER0_COMPA | Source::TIMER0_COMPB | Source::TIMER0_OVF => Reg::Timsk0,
            Source::TIMER1_CAPT
            | Source::TIMER1_COMPA
            | Source::TIMER1_COMPB
            | Source::TIMER1_OVF => Reg::Timsk1,
            Source::TIMER2_COMPA | Source::TIMER2_COMPB | Source::TIMER2_OVF => Reg::Timsk2,
            Source::SPI_STC => Reg::Spcr,
            Source::USART_RX | Source::USART_UDRE | Source::USART_TX => Reg::Ucsr0b,
            Source::ADC => Reg::Adcsra,
            Source::TWI => Reg::Twcr,
        }
    }

    /// The source's enable bit within [`Source::reg`], as a mask.
    pub const fn bit(self) -> u8 {
        match self {
            Source::INT0 => 1 << 0,
            Source::INT1 => 1 << 1,
            Source::PCINT0 => 1 << 0,
            Source::PCINT1 => 1 << 1,
            Source::PCINT2 => 1 << 2,
            Source::TIMER0_OVF | Source::TIMER1_OVF | Source::TIMER2_OVF => 1 << 0,
            Source::TIMER0_COMPA | Source::TIMER1_COMPA | Source::TIMER2_COMPA => 1 << 1,
            Source::TIMER0_COMPB | Source::TIMER1_COMPB | Source::TIMER2_COMPB => 1 << 2,
            Source::TIMER1_CAPT => 1 << 5,
            Source::SPI_STC => 1 << 7,
            Source::USART_RX => 1 << 7,
            Source::USART_TX => 1 << 6,
            Source::USART_UDRE => 1 << 5,
            Source::ADC => 1 << 3,
            Source::TWI => 1 << 0,
        }
    }

    /// The vector number (the index in the interrupt table; reset is 0).
    pub const fn vector(self) -> u8 {
        match self {
            Source::INT0 => 1,
            Source::INT1 => 2,
            Source::PCINT0 => 3,
            Source::PCINT1 => 4,
            Source::PCINT2 => 5,
            Source::TIMER2_COMPA => 7,
            Source::TIMER2_COMPB => 8,
            Source::TIMER2_OVF => 9,
            Source::TIMER1_CAPT => 10,
            Source::TIMER1_COMPA => 11,
            Source::TIMER1_COMPB => 12,
            Source::TIMER1_OVF => 13,
            Source::TIMER0_COMPA => 14,
            Source::TIMER0_COMPB => 15,
            Source::TIMER0_OVF => 16,
            Source::SPI_STC => 17,
            Source::USART_RX => 18,
            Source::USART_UDRE => 19,
            Source::USART_TX => 20,
            Source::ADC => 21,
            Source::TWI => 24,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn register_indices_match_the_table_order() {
        for (i, reg) in REGS.iter().enumerate() {
            assert_eq!(reg.index(), i);
        }
    }

    #[test]
    fn every_source_bit_is_an_enable_bit_of_its_register() {
        for s in SOURCES {
            assert_eq!(s.bit().count_ones(), 1, "{s:?}");
            assert_eq!(s.reg().enable_bits() & s.bit(), s.bit(), "{s:?}");
            assert_eq!(s.reg().write_zero_bits() & s.bit(), 0, "{s:?}");
        }
    }

    #[test]
    fn enable_bits_are_exactly_the_union_of_the_sources() {
        for reg in REGS {
            let union = SOURCES
                .iter()
                .filter(|s| s.reg() == reg)
                .fold(0u8, |acc, s| acc | s.bit());
            assert_eq!(union, reg.enable_bits(), "{reg:?}");
        }
    }

    #[test]
    fn no_two_sources_share_a_bit_or_a_vector() {
        for (i, a) in SOURCES.iter().enumerate() {
            for b in &SOURCES[i + 1..] {
                assert!(!(a.reg() == b.reg() && a.bit() == b.bit()), "{a:?} {b:?}");
                assert_ne!(a.vector(), b.vector(), "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn datasheet_addresses_and_traps() {
        assert_eq!(Reg::Twcr.addr(), 0xBC);
        assert_eq!(Reg::Adcsra.addr(), 0x7A);
        assert_eq!(Reg::Ucsr0b.addr(), 0xC1);
        assert_eq!(Reg::Pcicr.addr(), 0x68);
        assert_eq!(Reg::Timsk1.addr(), 0x6F);
        // TWINT is bit 7 of TWCR; ADIF bit 4 and ADSC bit 6 of ADCSRA.
        assert_eq!(Reg::Twcr.write_zero_bits(), 0x80);
        assert_eq!(Reg::Adcsra.write_zero_bits(), 0x50);
        assert!(Reg::Pcicr.is_pure());
        assert!(!Reg::Twcr.is_pure());
        assert!(!Reg::Ucsr0b.is_pure());
        assert_eq!(Source::TWI.vector(), 24);
        assert_eq!(Source::USART_UDRE.vector(), 19);
    }
}
