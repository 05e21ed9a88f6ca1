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
pub mod power_up;
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

            // The logic is zero bytes at reset (`.bss`), made the power-up core by `init`
            // (`power_up`), with its address.
            #[task(binds = TIMER0_COMPB, priority = 1, shared = [regs, edges, clock],
                   local = [stage], const_local = [core: MaybeUninit<Core<$board>> = MaybeUninit::zeroed()])]
            fn control;
        }

        /// The core's size, and its power-up bytes laid out at compile time.
        const CORE_SIZE: usize = ::core::mem::size_of::<Core<$board>>();
        const CORE_IMAGE: Image<CORE_SIZE> = Core::<$board>::POWER_UP
            .image::<CORE_SIZE>()
            .bytes_at(Core::<$board>::CLOCK_AT, &$crate::power_up::CLOCK);
        // The image's bytes must be a valid core, in 1..=256 pairs (the writer's count):
        // checked at compile time.
        const _: () = assert!(CORE_IMAGE.len() >= 1 && CORE_IMAGE.len() <= 256);
        const _: Core<$board> = $crate::power_up::read::<$board, CORE_SIZE>(*CORE_IMAGE.bytes());
        flash_table! {
            /// The core's nonzero power-up bytes as (step, byte) pairs, in flash.
            static CORE_PAIRS: [[u8; 2]; CORE_IMAGE.len()] = CORE_IMAGE.pairs();
        }

        fn init(cx: init::Context) -> (Shared, Local) {
            let p = $crate::boot::init(cx.device, $board);
            // SAFETY: `init` runs once, before any task and with interrupts off, so the
            // control task's core (zero bytes until now) has no other user; the pairs
            // were made from its own type's power-up image, which `read` checked.
            unsafe {
                $crate::power_up::write(
                    control::__const_local::core.as_mut_ptr(),
                    CORE_PAIRS.as_slice(),
                    p.eeprom_byte,
                )
            };
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
            // SAFETY: `init` made it a valid core (`power_up::write`).
            let core = unsafe { cx.local.core.assume_init_mut() };
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
    pub use core::mem::MaybeUninit;
    pub use drivers::pcint::PortDChanges;
    pub use drivers::timebase::Timebase;
    pub use drivers::twi_slave::TwiSlave;
    pub use shared::flash_table;
    pub use shared::slave::image::Image;
    pub use shared::slave::{
        Board, Core, DriveSteerBoard, EdgeCounter, Inputs, LiftLiftBoard, Variant,
    };
}
