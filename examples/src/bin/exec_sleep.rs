//! Executor example: idle sleeps the CPU whenever there is nothing to do and wakes on an
//! interrupt.
//!
//! `tick` (Timer1 compare A, every 1 ms) counts ticks. Idle checks for a new tick and
//! otherwise sleeps with `sleep_unless`, whose check runs with interrupts off and whose
//! SLEEP directly follows SEI, so a tick can never slip in between and be slept through.
//! Every wake-up is counted; after ten ticks idle prints `sleep ticks=10 wakes=10`: one
//! wake-up per interrupt, no busy looping.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use exec_support::Uart;

executor::app! {
    #[shared]
    struct Shared {
        ticks: u16,
    }

    #[local]
    struct Local {
        uart: Uart,
    }

    #[init]
    fn init;

    #[idle(shared = [ticks], local = [uart])]
    fn idle;

    #[task(binds = TIMER1_COMPA, priority = 1, shared = [ticks])]
    fn tick;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    let mut uart = Uart::new(dp.USART0);
    uart.put_str(b"exec_sleep ready\n");
    // CTC mode (WGM12), prescaler 1, OCR1A = 15999: a compare match every 16000 cycles
    // (1 ms at 16 MHz). The executor sets OCIE1A at start.
    // SAFETY: documented OCR1A/TCCR1 values.
    unsafe {
        dp.TC1.ocr1a().write(|w| w.bits(15_999));
        dp.TC1.tccr1a().write(|w| w.bits(0));
        dp.TC1.tccr1b().write(|w| w.bits(0b0000_1001));
    }
    (Shared { ticks: 0 }, Local { uart })
}

fn idle(mut cx: idle::Context) -> ! {
    let mut seen = 0u16;
    let mut wakes = 0u32;
    loop {
        let now = cx.shared.ticks.lock(|t| *t);
        if now != seen {
            seen = now;
            if seen == 10 {
                let uart = &mut *cx.local.uart;
                uart.put_str(b"sleep ");
                uart.field(b"ticks", u32::from(seen));
                uart.field(b"wakes", wakes);
                uart.put(b'\n');
            }
        }
        let ticks = &mut cx.shared.ticks;
        cx.sleep.sleep_unless(|| ticks.lock(|t| *t) != seen);
        wakes += 1;
    }
}

fn tick(mut cx: tick::Context) {
    *cx.shared.ticks += 1;
}
