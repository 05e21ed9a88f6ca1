//! Blodwen master board firmware (ATmega328P on an Arduino Uno).
//!
//! It links the PC to the nine motor controllers: it answers the PC-master protocol of
//! `docs/protocol.md` on the USART, serves its own registers (device 0) and relays the
//! others over I2C. Every decision is in `shared::master` and tested on the host; this
//! crate moves bytes between the hardware and that logic.
//!
//! Tasks (priorities are static; higher preempts lower):
//!
//! | Task | Vector | Priority | Touches |
//! |---|---|---|---|
//! | `receive` | USART_RX | 3 | `usart`, `rx` |
//! | `transmit` | USART_UDRE (gated) | 3 | `usart`, `tx` |
//! | `tick` | TIMER0_COMPA, 1 kHz | 2 | `clock` |
//! | idle | — | 0 | `rx`, `tx`, `clock`; frames, relay, watchdog |
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

mod banner;
mod link;
mod panic;
mod relay;

use drivers::pin::{Output, PORTB};
use drivers::tick::Tick;
use drivers::usart::Usart0;
use drivers::watchdog::{Timeout, Watchdog};
use drivers::twi::TwiMaster;
use link::{Clock, RxEvent, RxQueue, TxQueue};
use relay::TwiRelay;
use shared::master::SlaveBus;
use shared::regs::id::REG_RESET;
use shared::master::Service;
use shared::protocol::Parser;

/// The Uno's LED on D13 (PB5): lit during boot.
type StatusLed = Output<PORTB, 5>;

executor::app! {
    #[shared]
    struct Shared {
        usart: Usart0,
        rx: RxQueue,
        tx: TxQueue,
        clock: Clock,
    }

    #[local]
    struct Local {
        parser: Parser,
        service: Service,
        watchdog: Watchdog,
        status_led: StatusLed,
        relay: TwiRelay,
        _tick: Tick,
    }

    #[init]
    fn init;

    #[idle(shared = [rx, tx, clock], local = [parser, service, watchdog, status_led, relay])]
    fn idle;

    #[task(binds = USART_RX, priority = 3, shared = [usart, rx])]
    fn receive;

    #[task(binds = USART_UDRE, priority = 3, shared = [usart, tx], gated = true)]
    fn transmit;

    #[task(binds = TIMER0_COMPA, priority = 2, shared = [clock])]
    fn tick;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    let (mut watchdog, _cause) = Watchdog::new(dp.WDT, &dp.CPU);
    // Boot runs under the 1 s watchdog, as the original's boot resets did.
    watchdog.start(Timeout::S1);
    // SAFETY: D13 is used by nothing else in this firmware.
    let status_led = unsafe { StatusLed::take() };
    status_led.set_high();
    (
        Shared {
            usart: Usart0::new(dp.USART0),
            rx: RxQueue::new(),
            tx: TxQueue::new(),
            clock: Clock::new(),
        },
        Local {
            parser: Parser::new(),
            service: Service::new(),
            watchdog,
            status_led,
            relay: TwiRelay::new(TwiMaster::new(dp.TWI, relay::BUS_KHZ)),
            _tick: Tick::start(dp.TC0),
        },
    )
}

fn idle(mut cx: idle::Context) -> ! {
    banner::starting(&mut link::Replies::new(&mut cx.shared.tx));
    // Hard-reset every slave (REG_RESET = 2): each reboots into its boot exception with
    // its defaults, as after the original master's boot.
    for device in 1..=9 {
        let _ = cx.local.relay.write_register(device, REG_RESET, &[2]);
        cx.local.watchdog.feed();
    }
    cx.local.watchdog.start(Timeout::Ms125);
    banner::finish(&mut link::Replies::new(&mut cx.shared.tx));
    cx.local.status_led.set_low();

    let bus = &mut *cx.local.relay;
    let mut last_byte_ms = 0u32;
    loop {
        cx.local.watchdog.feed();
        let now = cx.shared.clock.lock(|c| c.ms());
        while let Some(event) = cx.shared.rx.lock(|q| q.pop_front()) {
            last_byte_ms = now;
            match event {
                RxEvent::Byte(b) => {
                    if let Some(frame) = cx.local.parser.push_frame(b) {
                        let mut out = link::Replies::new(&mut cx.shared.tx);
                        cx.local
                            .service
                            .execute(frame, bus, &mut |r| out.send(r));
                    }
                }
                RxEvent::Error(e) => {
                    cx.local.parser.abort();
                    cx.local.service.link_error(e);
                }
            }
        }
        if link::frame_stalled(now, last_byte_ms) && cx.local.parser.abort() {
            cx.local.service.link_error(shared::master::LinkError::Frame(
                shared::protocol::FrameError::Truncated,
            ));
        }
        cx.sleep.sleep_unless(|| cx.shared.rx.lock(|q| !q.is_empty()));
    }
}

fn receive(mut cx: receive::Context) {
    let event = match cx.shared.usart.on_receive() {
        Ok(b) => RxEvent::Byte(b),
        Err(drivers::usart::RxError::Framing) => RxEvent::Error(shared::master::LinkError::Framing),
        Err(drivers::usart::RxError::Overrun) => RxEvent::Error(shared::master::LinkError::Overrun),
    };
    if cx.shared.rx.push_back(event).is_err() {
        // Idle is behind by a whole queue: the byte is lost like an overrun, and says so.
        let _ = cx.shared.rx.pop_back();
        let _ = cx
            .shared
            .rx
            .push_back(RxEvent::Error(shared::master::LinkError::Overrun));
    }
}

fn transmit(mut cx: transmit::Context) {
    match cx.shared.tx.pop_front() {
        Some(b) => cx.shared.usart.send(b),
        None => transmit::disarm(),
    }
}

fn tick(mut cx: tick::Context) {
    cx.shared.clock.advance();
}
