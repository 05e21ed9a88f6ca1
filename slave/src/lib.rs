//! Blodwen slave board firmware (ATmega328P): two motor controllers on the rover's I2C
//! bus, at the address in EEPROM byte 0. One crate builds both images: `slave-drive`
//! (drive + steer, controllers 1, 2, 4, 5, 7, 8) and `slave-lift` (lift ONE + TWO,
//! controllers 3, 6, 9); each bin is one line, [`firmware!`] with its variant (and, on
//! drive/steer, its encoder task).
//!
//! Every decision is in `shared::slave` and tested on the host. This crate collects raw
//! facts in short interrupt tasks and applies the outputs of the control tick:
//!
//! | Task | Vector | Priority | Touches |
//! |---|---|---|---|
//! | `millis` | TIMER0_COMPA, 1 kHz | 3 | `clock` |
//! | `edge` | PCINT2 (PD0, encoder A; DS only) | 3 | `clock`, `edges`; encoder pins |
//! | `twi` | TWI | 2 | `regs`; the TWI |
//! | `sample` | ADC | 2 | `regs` (its ADC readings); the ADC |
//! | `control` | TIMER0_COMPB, 1 kHz | 1 | all three; the logic, pins, PWM, watchdog |
//! | idle | — | 0 | sleeps |
//!
//! The encoder and the clock are at the top priority, so no edge waits for anything but
//! another top task, and a timestamp never sees a millisecond counted twice.
#![no_std]
#![feature(abi_avr_interrupt)]

pub mod boot;
pub mod bus;
pub mod clock;
pub mod encoder;
mod panic;
pub mod registers;
pub mod sampler;
pub mod stage;

pub use shared::slave::Variant;

/// The whole firmware of a slave built as `board` ([`shared::slave::DriveSteerBoard`] or
/// [`shared::slave::LiftLiftBoard`]: the variant is a type, fixed at build time, so each
/// image carries only its own variant's code): the executor's application and its task
/// bodies. Used once, by each bin. The drive/steer bin adds `edge, encoder` (the names of
/// the encoder's edge task and its pins): a lift/lift board has no encoder, so its image
/// carries no edge task (236 B) and its PCINT2 vector, never unmasked, is the stray one.
#[macro_export]
macro_rules! firmware {
    ($board:ident $(, $edge:ident, $encoder:ident)?) => {
        use $crate::shared_types::*;

        // memcpy and memset, and the division `shared::slave::divide` calls, small
        // (drivers::runtime).
        drivers::mem_routines!();
        drivers::division_routines!();

        executor::app! {
            #[shared]
            struct Shared {
                regs: Registers<$board>,
                edges: EdgeCounter,
                clock: Clock,
            }

            #[local]
            struct Local {
                twi_port: TwiSlave,
                sampler: Sampler,
                $($encoder: Encoder,)?
                eeprom: u8,
                stage: Stage,
                _timebase: Timebase,
                _changes: PortDChanges,
            }

            #[init]
            fn init;

            #[task(binds = TIMER0_COMPA, priority = 3, shared = [clock])]
            fn millis;

            $(
                #[task(binds = PCINT2, priority = 3, shared = [clock, edges], local = [$encoder])]
                fn $edge;
            )?

            #[task(binds = TWI, priority = 2, shared = [regs], local = [twi_port])]
            fn twi;

            #[task(binds = ADC, priority = 2, shared = [regs], local = [sampler])]
            fn sample;

            // The logic is built at compile time (initial data, not stores at boot); the
            // first tick gives it its address.
            #[task(binds = TIMER0_COMPB, priority = 1, shared = [regs, edges, clock],
                   local = [eeprom, stage], const_local = [core: Core<$board> = Core::<$board>::POWER_UP])]
            fn control;
        }

        fn init(cx: init::Context) -> (Shared, Local) {
            let p = $crate::boot::init(cx.device, $board);
            (
                Shared {
                    regs: p.regs,
                    edges: p.edges,
                    clock: p.clock,
                },
                Local {
                    twi_port: p.twi,
                    sampler: p.sampler,
                    $($encoder: p.$encoder,)?
                    eeprom: p.eeprom_byte,
                    stage: p.stage,
                    _timebase: p.timebase,
                    _changes: p.changes,
                },
            )
        }

        fn millis(mut cx: millis::Context) {
            cx.shared.clock.advance();
        }

        $(
            fn $edge(mut cx: $edge::Context) {
                let clock = &*cx.shared.clock;
                cx.local
                    .$encoder
                    .on_change(&mut cx.shared.edges, || clock.now_units());
            }
        )?

        // Runs only on a board with a valid address: without one the TWI stays off.
        fn twi(mut cx: twi::Context) {
            $crate::bus::on_event(cx.local.twi_port, &mut cx.shared.regs);
        }

        fn sample(mut cx: sample::Context) {
            cx.local.sampler.on_complete(cx.shared.regs.adc());
        }

        fn control(mut cx: control::Context) {
            // No encoder on a lift/lift board: nothing to take (folded at build time).
            // The edges first: every edge taken then precedes the tick's time.
            let edges = if Board::variant($board).has_drive() {
                cx.shared.edges.lock(|e| e.take())
            } else {
                Default::default()
            };
            let now_us = cx.shared.clock.lock(|c| c.now_us());
            let core = &mut *cx.local.core;
            let byte = *cx.local.eeprom;
            if byte != 0 {
                // The first tick only (a load and a branch on the others). A byte of 0
                // gives no address, as the power-up logic has: nothing to set.
                core.set_eeprom(byte);
                *cx.local.eeprom = 0;
            }
            // One lock for everything the priority-2 tasks fill.
            let (adc, written, addressed) = cx
                .shared
                .regs
                .lock(|r| (r.adc().take(), r.take_written(), r.take_addressed()));
            let inputs = Inputs { edges, adc };
            if written {
                // One register a lock, lowest first, until none is marked.
                while let Some((reg, raw)) = cx.shared.regs.lock(|r| r.take_change()) {
                    core.apply(reg, raw);
                }
            }
            if addressed {
                core.bus_heard();
            }
            let outputs = core.step(now_us, &inputs);
            cx.shared.regs.lock(|r| core.publish(r.file()));
            cx.local.stage.apply(&outputs);
        }
    };
}

/// The types [`firmware!`] names, in one place.
#[doc(hidden)]
pub mod shared_types {
    pub use crate::clock::Clock;
    pub use crate::encoder::Encoder;
    pub use crate::registers::Registers;
    pub use crate::sampler::Sampler;
    pub use crate::stage::Stage;
    pub use drivers::pcint::PortDChanges;
    pub use drivers::timebase::Timebase;
    pub use drivers::twi_slave::TwiSlave;
    pub use shared::slave::{
        Board, Core, DriveSteerBoard, EdgeCounter, Inputs, LiftLiftBoard, Variant,
    };
}
