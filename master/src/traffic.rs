//! The master's own slave traffic: the schedule's actions (boot resets, ping, spreading,
//! liveness checks, temperature ticks) and the remote control's writes, performed on the
//! relay with the watchdog fed before each access. The same handles serve the PC link's
//! frames (`crate::pc`): idle builds them once.

use crate::leds::Leds;
use crate::relay::TwiRelay;
use crate::temperature::Temperatures;
use drivers::watchdog::Watchdog;
use shared::master::{Action, Outcome, RegWrite, Schedule, Service};
use shared::regs::id;

/// What performing traffic, or serving a PC frame, touches.
pub struct Traffic<'a> {
    /// The schedule of slave traffic.
    pub schedule: &'a mut Schedule,
    /// The frame logic and device 0 (the exception latch and the temperatures).
    pub service: &'a mut Service,
    /// The I2C relay.
    pub relay: &'a mut TwiRelay,
    /// Fed before every access.
    pub watchdog: &'a mut Watchdog,
}

impl Traffic<'_> {
    /// Performs the schedule's next action due at `now_ms`, if any; returns whether
    /// there was one. A temperature tick only starts here (its bus work goes on in
    /// `temps.step`); a missing sensor is raised once the tick is reported.
    pub fn schedule_step(
        &mut self,
        now_ms: u16,
        temps: &mut Temperatures,
        leds: &mut Leds,
    ) -> bool {
        let Some(action) = self.schedule.poll(u32::from(now_ms)) else {
            return false;
        };
        let mut missing = None;
        let outcome = match action {
            Action::WriteReg(w) => {
                if w.id == id::REG_PING && w.device == 1 {
                    leds.ping(now_ms);
                }
                self.watchdog.feed();
                match self.relay.write(&w) {
                    Ok(()) => Outcome::Done,
                    Err(_) => Outcome::NoAnswer,
                }
            }
            Action::ReadStatus { device } => self.read(device, id::REG_STATUS),
            Action::ReadExceptionData { device } => self.read(device, id::REG_EXCEPTIONDATA),
            Action::TemperatureTick => {
                missing = temps.start_tick();
                Outcome::Done
            }
        };
        self.schedule
            .feed(outcome, &mut self.service.local.exception);
        if let Some(e) = missing {
            self.schedule.raise(e, &mut self.service.local.exception);
        }
        true
    }

    /// Performs one write of the remote control at `now_ms`: to the master itself for
    /// device 0, else on the relay, reported to the schedule as liveness evidence.
    pub fn remote_write(&mut self, w: &RegWrite, now_ms: u16) {
        if w.device == 0 {
            self.service.local.write(w.id, w.raw());
            return;
        }
        self.watchdog.feed();
        let answered = self.relay.write(w).is_ok();
        self.schedule.observe_at(
            w.device,
            answered,
            now_ms,
            &mut self.service.local.exception,
        );
    }

    fn read(&mut self, device: u8, reg: u8) -> Outcome {
        self.watchdog.feed();
        match self.relay.read_word(device, reg) {
            Ok(v) => Outcome::Value(v),
            Err(_) => Outcome::NoAnswer,
        }
    }
}
