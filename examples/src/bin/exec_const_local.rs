//! Executor example: local resources declared with their values (`const_local`) sit in
//! static memory from reset, built at compile time: `init` never returns them, and each
//! keeps its state from one run of its task to the next.
//!
//! `bump` (PCINT0, priority 1) owns `count: u16 = 1000`: each run records the count in the
//! shared `seen` and adds one. Idle owns `greeting` (non-zero bytes, so in `.data`) and
//! `fired: u8 = 40`. It prints the greeting, fires `bump` three times, counting in `fired`,
//! then prints `const_local first=1000 last=1002 runs=3 fired=43`.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use exec_support::{setup_triggers, trigger, wait_for_events, Trigger, Uart};

/// What `bump` saw of its own count.
pub struct Seen {
    first: u16,
    last: u16,
    runs: u8,
}

executor::app! {
    #[shared]
    struct Shared {
        seen: Seen,
    }

    #[local]
    struct Local {
        uart: Uart,
    }

    #[init]
    fn init;

    #[idle(shared = [seen], local = [uart],
           const_local = [greeting: [u8; 23] = *b"exec_const_local ready\n", fired: u8 = 40])]
    fn idle;

    #[task(binds = PCINT0, priority = 1, shared = [seen], const_local = [count: u16 = 1000])]
    fn bump;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    setup_triggers(&dp.PORTB, &dp.PORTC, &dp.PORTD, &dp.EXINT);
    let uart = Uart::new(dp.USART0);
    (
        Shared {
            seen: Seen {
                first: 0,
                last: 0,
                runs: 0,
            },
        },
        Local { uart },
    )
}

fn idle(mut cx: idle::Context) -> ! {
    let uart = &mut *cx.local.uart;
    uart.put_str(&*cx.local.greeting);
    for n in 1..=3 {
        trigger(Trigger::Pcint0);
        *cx.local.fired += 1;
        // Wait (bounded) for this run before firing the next.
        wait_for_events(n, || usize::from(cx.shared.seen.lock(|s| s.runs)));
    }
    let (first, last, runs) = cx.shared.seen.lock(|s| (s.first, s.last, s.runs));
    uart.put_str(b"const_local ");
    uart.field(b"first", u32::from(first));
    uart.field(b"last", u32::from(last));
    uart.field(b"runs", u32::from(runs));
    uart.field(b"fired", u32::from(*cx.local.fired));
    uart.put(b'\n');
    loop {
        cx.sleep.sleep();
    }
}

fn bump(mut cx: bump::Context) {
    let count = *cx.local.count;
    cx.shared.seen.lock(|s| {
        if s.runs == 0 {
            s.first = count;
        }
        s.last = count;
        s.runs += 1;
    });
    *cx.local.count += 1;
}
