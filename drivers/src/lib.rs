//! Thin typed drivers for the ATmega328P peripherals that the Blodwen master and slave
//! firmwares use. This is the only layer (with the executor's audited core) that touches
//! registers; every decision lives in `shared` and is tested on the host.
//!
//! Each driver owns its PAC peripheral, so a peripheral cannot be driven from two places.
//! Pins are zero-sized types whose port and bit are constants, so setting one compiles to a
//! single `sbi`/`cbi` instruction, which is atomic and safe from any priority.
#![no_std]
#![feature(asm_experimental_arch)]

pub mod adc;
pub mod cpu;
pub mod eeprom;
pub mod fault_entry;
pub mod onewire;
pub mod pcint;
pub mod pin;
pub mod pwm;
pub mod rc_pins;
pub mod runtime;
pub mod stack;
pub mod tick;
pub mod timebase;
pub mod timer1;
pub mod twi;
pub mod twi_slave;
pub mod usart;
pub mod watchdog;

/// CPU clock of every Blodwen board.
pub const F_CPU: u32 = 16_000_000;
