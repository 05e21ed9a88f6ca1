//! `init`: the peripherals and pins in their power-up state, and the logic for this
//! board's variant and EEPROM address.

use drivers::adc::Adc;
use drivers::eeprom::Eeprom;
use drivers::pcint::PortDChanges;
use drivers::pwm::Pwm;
use drivers::timebase::Timebase;
use drivers::twi_slave::TwiSlave;
use drivers::watchdog::{Timeout, Watchdog};
use executor::Device;
use shared::slave::{bus_address, Board, EdgeCounter, Variant};

use crate::clock::Clock;
use crate::encoder::Encoder;
use crate::registers::Registers;
use crate::sampler::Sampler;
use crate::stage::Stage;

/// PCMSK2: PD0 (encoder A) on drive/steer boards; nothing on lift/lift boards.
const fn encoder_mask(variant: Variant) -> u8 {
    if variant.has_drive() {
        1 << 0
    } else {
        0
    }
}

/// Everything `init` hands to the executor.
pub struct Parts<B: Board> {
    /// The register file and the ADC readings (TWI, ADC and tick).
    pub regs: Registers<B>,
    /// Encoder edges (encoder and tick).
    pub edges: EdgeCounter,
    /// The µs clock (compare A, encoder and tick).
    pub clock: Clock,
    /// The TWI, enabled only with a valid address (off otherwise: its task never runs).
    pub twi: TwiSlave,
    /// The ADC round robin.
    pub sampler: Sampler,
    /// The encoder pins.
    pub encoder: Encoder,
    /// EEPROM byte 0, the board's address: `init` hands it to the logic
    /// ([`crate::power_up::write`]).
    pub eeprom_byte: u8,
    /// Pins, PWM and watchdog.
    pub stage: Stage,
    /// Timer0, kept running.
    pub timebase: Timebase,
    /// PCMSK2, kept as set.
    pub changes: PortDChanges,
}

/// Brings the board up as `board`'s variant.
pub fn init<B: Board>(dp: Device, board: B) -> Parts<B> {
    let variant = board.variant();
    drivers::stack::paint();
    let (watchdog, _cause) = Watchdog::started(dp.WDT, &dp.CPU, Timeout::S1);
    // SAFETY: D9/D10 are used only by the PWM, D2/D3/D4/D7 and A2/A3 only by the
    // stage, PD0/PD1 only by the encoder (the USART stays off); each is taken once.
    let (mut stage, encoder) = unsafe {
        let pwm = Pwm::new(dp.TC1);
        (Stage::new(pwm, watchdog), Encoder::new())
    };
    stage.boot();
    let eeprom_byte = Eeprom::new(dp.EEPROM).read(0);
    // The same address the logic takes from the byte (`Core::set_eeprom`).
    let twi = match bus_address(eeprom_byte) {
        Some(addr) => TwiSlave::new(dp.TWI, addr),
        None => TwiSlave::off(dp.TWI),
    };
    let (timebase, stamp) = Timebase::start(dp.TC0);
    Parts {
        regs: Registers::new(board),
        edges: EdgeCounter::new(),
        clock: Clock::new(stamp),
        twi,
        sampler: Sampler::start(Adc::new(dp.ADC)),
        encoder,
        eeprom_byte,
        stage,
        timebase,
        changes: PortDChanges::new(dp.EXINT, encoder_mask(variant)),
    }
}
