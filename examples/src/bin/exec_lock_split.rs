//! Executor example: a lock stays whole when one level's sources sit in two registers.
//!
//! `edge` (INT1, enable bit in EIMSK) and `pin` (PCINT0, enable bit in PCICR) are both at
//! priority 1, so a lock of ceiling 1 taken by idle must clear two registers. Each round,
//! idle raises PD5 ("armed"), takes the lock on `held`, and inside it fires INT1 on itself:
//! `edge` must wait for the unlock. The emulator test toggles PB1 (PCINT0) at the worst
//! instant, after the lock has cleared INT1 and before it has cleared PCIE0. If `pin` could
//! run there, its exit would enable level 1 again (a task's exit sets its own level back)
//! and `edge` would run inside the lock; it counts each run that sees the lock held.
//! Idle prints `split rounds=R pin=P edge=E inside=V`.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use core::ptr::{read_volatile, write_volatile};

use exec_support::{busy, trigger, Trigger, Uart};

/// Lock rounds idle runs.
const ROUNDS: u16 = 20;

/// What idle's lock guards, and what `edge` saw of it.
pub struct Held {
    /// True while idle is inside its lock (written and read volatile: the runs that must
    /// not happen are exactly the ones the compiler cannot see).
    inside: bool,
    /// Runs of `edge`.
    runs: u16,
    /// Runs of `edge` that found `inside` set: each one is two `&mut` at once.
    inside_runs: u16,
}

executor::app! {
    #[shared]
    struct Shared {
        held: Held,
        pin_runs: u16,
    }

    #[local]
    struct Local {
        uart: Uart,
    }

    #[init]
    fn init;

    #[idle(shared = [held, pin_runs], local = [uart])]
    fn idle;

    #[task(binds = INT1, priority = 1, shared = [held])]
    fn edge;

    #[task(binds = PCINT0, priority = 1, shared = [pin_runs])]
    fn pin;

    // Never fires (Timer2 stays stopped): it only makes level 1 a masked level, not the
    // top one, whose locks would simply clear the global flag.
    #[task(binds = TIMER2_COMPA, priority = 2)]
    fn top;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    // SAFETY: plain sense, direction and mask values: INT1 on any change of PD3 (an
    // output idle toggles), PD5 an output (the "armed" flag the test reads), PB1 an input
    // the test drives, routed to PCINT0.
    unsafe {
        dp.EXINT.eicra().write(|w| w.bits(0b0100));
        dp.PORTD.ddrd().write(|w| w.bits((1 << 3) | (1 << 5)));
        dp.EXINT.pcmsk0().write(|w| w.bits(1 << 1));
    }
    let uart = Uart::new(dp.USART0);
    (
        Shared {
            held: Held {
                inside: false,
                runs: 0,
                inside_runs: 0,
            },
            pin_runs: 0,
        },
        Local { uart },
    )
}

/// Sets PD5, which tells the test that the next lock may be probed.
fn arm(on: bool) {
    // SAFETY: PORTD (data 0x2b), read back so that only PD5 changes (PD3's level, which
    // idle toggles through PIND, is kept). Only idle writes PORTD.
    unsafe {
        let port = read_volatile(0x2b as *const u8);
        let v = if on { port | 1 << 5 } else { port & !(1 << 5) };
        write_volatile(0x2b as *mut u8, v);
    }
}

fn idle(mut cx: idle::Context) -> ! {
    cx.local.uart.put_str(b"exec_lock_split ready\n");
    for _ in 0..ROUNDS {
        arm(true);
        cx.shared.held.lock(|h| {
            // SAFETY: a plain field of the locked resource.
            unsafe { write_volatile(&mut h.inside, true) };
            trigger(Trigger::Int1);
            busy(10);
            // SAFETY: as above.
            unsafe { write_volatile(&mut h.inside, false) };
        });
        arm(false);
        // Room for `edge` and the test's pin change to be served.
        busy(20);
    }
    let (runs, inside_runs) = cx.shared.held.lock(|h| (h.runs, h.inside_runs));
    let pins = cx.shared.pin_runs.lock(|n| *n);
    let uart = &mut *cx.local.uart;
    uart.put_str(b"split ");
    uart.field(b"rounds", ROUNDS.into());
    uart.field(b"pin", pins.into());
    uart.field(b"edge", runs.into());
    uart.field(b"inside", inside_runs.into());
    uart.put(b'\n');
    loop {
        cx.sleep.sleep();
    }
}

fn edge(mut cx: edge::Context) {
    let h = &mut *cx.shared.held;
    h.runs += 1;
    // SAFETY: a plain field of the resource.
    if unsafe { read_volatile(&h.inside) } {
        h.inside_runs += 1;
    }
}

fn pin(mut cx: pin::Context) {
    *cx.shared.pin_runs += 1;
}

fn top(_cx: top::Context) {}
