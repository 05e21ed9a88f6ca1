//! Blodwen master board firmware (ATmega328P on an Arduino Uno).
//!
//! It links the PC to the nine motor controllers: it answers the PC-master protocol of
//! `docs/protocol.md` on the USART, serves its own registers (device 0) and relays the
//! others over I2C; it pings the slaves, spreads their exceptions and notices a slave
//! that goes silent; it reads the ten temperature sensors on the OneWire bus; it lets an
//! RC receiver drive the rover; and, when the PC arms it, it stops every motor once the PC
//! goes silent (REGMASTER_PCTIMEOUT). Every decision is in `shared::master` and tested on
//! the host; this crate moves bytes and bits between the hardware and that logic.
//!
//! Tasks (priorities are static; higher preempts lower):
//!
//! | Task | Vector | Priority | Touches |
//! |---|---|---|---|
//! | `receive` | USART_RX | 3 | `usart`, `rx` |
//! | `transmit` | USART_UDRE (gated) | 3 | `usart`, `tx` |
//! | `rc_edge` | PCINT2 (D2..D4) | 3 | `edges`: Timer1's count and the pin levels |
//! | `tick` | TIMER0_COMPA, 1 kHz | 2 | `clock` |
//! | idle | — | 0 | `rx`, `tx`, `clock`, `edges`; frames, schedule, OneWire, RC, LEDs |
//!
//! The RC edges run at the top priority so their time stamps wait for nothing but the
//! other top tasks (a few µs) and the OneWire slots' interrupt-free windows (at most
//! ~13 µs, see `drivers::onewire`): a pulse width is off by at most that much.
//!
//! Idle boots (banner line 1, OneWire discovery, the slaves' hard resets under the 1-s
//! watchdog, then the rest of the banner and the 125-ms watchdog), then loops: take the
//! RC edges, drain the PC link, then one piece of work in turn (the remote control's
//! next write or pass, one OneWire step of a temperature tick, the schedule's next
//! action), the LEDs; it sleeps when there was nothing to do.
//!
//! Functions marked `#[inline(never)]` wrap a large piece of the shared logic or are
//! called from more than one place: kept out of line, each exists once in flash.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod banner;
mod leds;
mod link;
mod panic;
mod pc;
mod relay;
mod remote;
mod temperature;
mod traffic;

// The compiler's runtime routines (32-bit division, memcpy, memset), small (drivers::runtime).
drivers::division_routines!();
drivers::mem_routines!();

use drivers::onewire::OneWire;
use drivers::pcint::PortDChanges;
use drivers::tick::Tick;
use drivers::timer1::FreeRunning;
use drivers::twi::TwiMaster;
use drivers::usart::Usart0;
use drivers::watchdog::{Timeout, Watchdog};
use leds::{BlueLed, Leds, StatusLed};
use link::{Clock, Replies, RxEvent, RxQueue, TxQueue};
use pc::PcLink;
use relay::TwiRelay;
use remote::{EdgeQueue, RcEdges, RemoteControl};
use shared::master::{Schedule, Service};
use temperature::Temperatures;
use traffic::Traffic;

/// PD2..PD4 in PCMSK2: the RC channels raise PCINT2.
const RC_PIN_MASK: u8 = 0b0001_1100;

executor::app! {
    #[shared]
    struct Shared {
        usart: Usart0,
        rx: RxQueue,
        tx: TxQueue,
        clock: Clock,
        edges: EdgeQueue,
    }

    #[local]
    struct Local {
        watchdog: Watchdog,
        relay: TwiRelay,
        wire: OneWire,
        leds: Leds,
        rc_edges: RcEdges,
        _tick: Tick,
        _changes: PortDChanges,
    }

    #[init]
    fn init;

    // Idle's state that needs no hardware is built at compile time, straight into
    // static memory (`.bss` or `.data`), instead of passing through init and the stack:
    // the PC link (parser, inter-byte timeout, read sets), the sensors, the remote
    // control, the frame logic with device 0 and the schedule of slave traffic.
    #[idle(shared = [rx, tx, clock, edges],
           local = [watchdog, relay, wire, leds],
           const_local = [
               pc: PcLink = PcLink::new(),
               temps: Temperatures = Temperatures::new(),
               remote: RemoteControl = RemoteControl::new(),
               service: Service = Service::new(),
               schedule: Schedule = Schedule::new(),
           ])]
    fn idle;

    #[task(binds = USART_RX, priority = 3, shared = [usart, rx])]
    fn receive;

    #[task(binds = USART_UDRE, priority = 3, shared = [usart, tx], gated = true)]
    fn transmit;

    #[task(binds = PCINT2, priority = 3, shared = [edges], local = [rc_edges])]
    fn rc_edge;

    #[task(binds = TIMER0_COMPA, priority = 2, shared = [clock])]
    fn tick;
}

fn init(cx: init::Context) -> (Shared, Local) {
    // First, so the emulator can read the stack's high-water mark later.
    drivers::stack::paint();
    let dp = cx.device;
    let (mut watchdog, _cause) = Watchdog::new(dp.WDT, &dp.CPU);
    // Boot runs under the 1 s watchdog, as the original's boot resets did.
    watchdog.start(Timeout::S1);
    // SAFETY: D13 and D7 are used by nothing else in this firmware.
    let leds = Leds::new(unsafe { StatusLed::take() }, unsafe { BlueLed::take() });
    // SAFETY: D6 is the OneWire line and nothing else.
    let wire = unsafe { OneWire::take() };
    // SAFETY: D2..D4 are the RC inputs and nothing else.
    let rc_pins = unsafe { drivers::rc_pins::RcPins::take() };
    let usart = Usart0::new(dp.USART0);
    let twi = TwiMaster::new(dp.TWI, relay::BUS_KHZ);
    let timer1 = FreeRunning::start(dp.TC1);
    let tick = Tick::start(dp.TC0);
    let changes = PortDChanges::new(dp.EXINT, RC_PIN_MASK);
    (
        Shared {
            usart,
            // The fill is never read; all-zero slots cost init a clear instead of a
            // store loop.
            rx: RxQueue::new(RxEvent::Byte(0)),
            tx: TxQueue::new(0),
            clock: Clock::new(),
            edges: EdgeQueue::new((0, 0)),
        },
        Local {
            watchdog,
            relay: TwiRelay::new(twi),
            wire,
            leds,
            rc_edges: RcEdges::new(timer1, rc_pins),
            _tick: tick,
            _changes: changes,
        },
    )
}

fn idle(mut cx: idle::Context) -> ! {
    let l = cx.local;
    banner::starting(&mut Replies::new(&mut cx.shared.tx));
    // Boot work, under the 1-s watchdog: the sensors, then the slaves' hard resets
    // (REG_RESET = 2), after which each reboots into its boot exception with defaults.
    l.temps.discover(l.wire, l.watchdog, &mut l.service.local);
    // The handles of all slave traffic and PC frames, built once for boot and the loop.
    let mut traffic = Traffic {
        schedule: l.schedule,
        service: l.service,
        relay: l.relay,
        watchdog: l.watchdog,
    };
    while !traffic.schedule.booted() {
        let now = link::now_ms(&mut cx.shared.clock);
        traffic.schedule_step(now, l.temps, l.leds);
    }
    traffic.watchdog.start(Timeout::Ms125);
    banner::finish(&mut Replies::new(&mut cx.shared.tx));
    l.leds.ready();

    let mut turn = 0u8;
    loop {
        traffic.watchdog.feed();
        let now = link::now_ms(&mut cx.shared.clock);
        // The remote control counts from when the slaves are back from the boot resets
        // (pings start then too): a link-up write (REG_RESET = 1) sent while they reboot
        // is lost, and the link-up comes once per boot, so a transmitter on at power-up
        // would never drive. Until then its edges are dropped.
        let started = traffic.schedule.started();
        while let Some(edge) = cx.shared.edges.lock(|q| q.pop_front()) {
            if started {
                l.remote.edge(edge, now);
            }
        }
        let rc_up = l.remote.link_up(now);

        let mut busy = l.pc.drain(
            &mut cx.shared.rx,
            &mut cx.shared.tx,
            &mut cx.shared.clock,
            rc_up,
            &mut traffic,
        );

        // Then one piece of work: the PC link is drained between any two.
        let now = link::now_ms(&mut cx.shared.clock);
        busy |= one_piece_of_work(
            &mut turn,
            now,
            &mut traffic,
            l.remote,
            l.temps,
            l.wire,
            l.leds,
        );

        l.leds.note(&traffic.service.local.exception);
        l.leds.update(now, rc_up);
        if !busy {
            cx.sleep
                .sleep_unless(|| cx.shared.rx.lock(|q| !q.is_empty()));
        }
    }
}

/// Performs the next piece of work that has something to do, taking turns from the one
/// after `turn`: the remote control's next write or pass, one OneWire step of a
/// temperature tick, the schedule's next action. Returns whether there was one.
// In line: its one call site (measured 2 B smaller).
#[inline(always)]
fn one_piece_of_work(
    turn: &mut u8,
    now: u16,
    traffic: &mut Traffic<'_>,
    remote: &mut RemoteControl,
    temps: &mut Temperatures,
    wire: &mut OneWire,
    leds: &mut Leds,
) -> bool {
    for _ in 0..3u8 {
        // The next of 0, 1, 2 (a comparison, where `% 3` would call a division).
        *turn = if *turn >= 2 { 0 } else { *turn + 1 };
        let worked = match *turn {
            0 => remote.next(now, |w| traffic.remote_write(&w, now)),
            1 => {
                let ticking = temps.busy();
                temps.step(wire, &mut traffic.service.local);
                ticking
            }
            _ => traffic.schedule_step(now, temps, leds),
        };
        if worked {
            return true;
        }
    }
    false
}

fn receive(mut cx: receive::Context) {
    let event = match cx.shared.usart.on_receive() {
        Ok(b) => RxEvent::Byte(b),
        Err(drivers::usart::RxError::Framing) => RxEvent::Framing,
        Err(drivers::usart::RxError::Overrun) => RxEvent::Overrun,
    };
    // When idle is behind by a whole queue, the byte is lost like an overrun, and the
    // newest entry says so.
    cx.shared.rx.push_or_replace(event, RxEvent::Overrun);
}

fn transmit(mut cx: transmit::Context) {
    match cx.shared.tx.pop_front() {
        Some(b) => cx.shared.usart.send(b),
        None => transmit::disarm(),
    }
}

fn rc_edge(mut cx: rc_edge::Context) {
    cx.local.rc_edges.on_change(&mut cx.shared.edges);
}

fn tick(mut cx: tick::Context) {
    cx.shared.clock.advance();
}
