//! Executor example: a gated source that the driver switches on and off at run time
//! (USART_UDRE), without fighting the executor's masking.
//!
//! `send` (USART_UDRE, priority 1, `gated = true`) moves one byte from the `tx` queue to
//! UDR0 per interrupt and disarms itself when the queue is empty, from inside its own
//! masked entry. `tick` (Timer1 compare A every 2 ms, priority 2) queues a line and arms
//! `send` while its own entry holds `send` masked; `init` queues the first line and arms
//! `send` before anything runs. Whichever frame holds the source, it comes on exactly when
//! a driver wants it and nothing masks it. The UART output is `gate start`, `tick 1` ..
//! `tick 5`, `done`, one per line, after which the source stays off and the CPU sleeps in
//! the executor's own idle (the application declares none).
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use avr_device::atmega328p::{TC1, USART0};

/// A byte queue for the transmitter.
pub struct Queue {
    buf: [u8; 64],
    head: u8,
    len: u8,
}

impl Queue {
    const fn new() -> Queue {
        Queue {
            buf: [0; 64],
            head: 0,
            len: 0,
        }
    }

    /// Appends `s` (bytes beyond the capacity are dropped).
    fn push_str(&mut self, s: &[u8]) {
        for &b in s {
            if usize::from(self.len) < self.buf.len() {
                let tail = (usize::from(self.head) + usize::from(self.len)) % self.buf.len();
                self.buf[tail] = b;
                self.len += 1;
            }
        }
    }

    /// Takes the oldest byte.
    fn pop(&mut self) -> Option<u8> {
        if self.len == 0 {
            return None;
        }
        let b = self.buf[usize::from(self.head)];
        self.head = ((usize::from(self.head) + 1) % self.buf.len()) as u8;
        self.len -= 1;
        Some(b)
    }
}

executor::app! {
    #[shared]
    struct Shared {
        tx: Queue,
    }

    #[local]
    struct Local {
        usart: USART0,
        timer: TC1,
        ticks: u8,
    }

    #[init]
    fn init;

    #[task(binds = USART_UDRE, priority = 1, shared = [tx], local = [usart], gated = true)]
    fn send;

    #[task(binds = TIMER1_COMPA, priority = 2, shared = [tx], local = [timer, ticks])]
    fn tick;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    let usart = dp.USART0;
    // 115200 8N1, transmitter on. UDRIE belongs to the executor (the source is gated).
    usart.ucsr0a().write(|w| w.u2x0().set_bit());
    usart.ucsr0c().write(|w| w.ucsz0().chr8());
    // SAFETY: 16 with U2X0 is 115200 baud at 16 MHz.
    usart.ubrr0().write(|w| unsafe { w.bits(16) });
    usart.ucsr0b().write(|w| w.txen0().set_bit());
    // CTC (WGM12), prescaler 8, OCR1A = 3999: a compare match every 2 ms.
    // SAFETY: documented OCR1A/TCCR1 values.
    unsafe {
        dp.TC1.ocr1a().write(|w| w.bits(3_999));
        dp.TC1.tccr1a().write(|w| w.bits(0));
        dp.TC1.tccr1b().write(|w| w.bits(0b0000_1010));
    }
    let mut tx = Queue::new();
    tx.push_str(b"gate start\n");
    // Before start: no frame holds the source, so this sets UDRIE0 at once.
    send::arm();
    (
        Shared { tx },
        Local {
            usart,
            timer: dp.TC1,
            ticks: 0,
        },
    )
}

fn send(mut cx: send::Context) {
    match cx.shared.tx.lock(|q| q.pop()) {
        // SAFETY: UDR0 takes any byte; this interrupt means it is empty.
        Some(b) => {
            cx.local.usart.udr0().write(|w| unsafe { w.bits(b) });
        }
        None => send::disarm(),
    }
}

fn tick(mut cx: tick::Context) {
    *cx.local.ticks += 1;
    let n = *cx.local.ticks;
    let q = &mut *cx.shared.tx;
    q.push_str(b"tick ");
    q.push_str(&[b'0' + n]);
    q.push_str(b"\n");
    if n == 5 {
        q.push_str(b"done\n");
        // SAFETY: stopping Timer1's clock; no more ticks.
        cx.local.timer.tccr1b().write(|w| unsafe { w.bits(0) });
    }
    send::arm();
}
