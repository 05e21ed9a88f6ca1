//! The master's two LEDs (reference §6.5).
//!
//! - **D13** (status): lit from power-up until `Ready`, then at each ping (the ping's
//!   first write) for [`PING_LIT_MS`]. The original counted 100 loop passes; a fixed
//!   time gives the same brief flash whatever the loop's speed.
//! - **D7** (blue, under the chassis): lit while the remote control's link is up.
//!   Once the master has raised an exception (boot excluded), it flashes the type code
//!   of the last one raised instead, link or not, until the next reboot, as the
//!   original did (a master reset does not stop it): [`FLASH_PERIOD_MS`] per pulse,
//!   lit for the first [`FLASH_ON_MS`], as many pulses as the code, in a cycle of
//!   [`FLASH_CYCLE_MS`]. The original's cycle held at most 10 pulses (in 80,001 passes
//!   of 8,000 each); this one holds 16, so the new type 11 (slave silent) shows as 11,
//!   distinct from 10. All three are powers of two, so the pattern needs no division.

use drivers::pin::{Output, PORTB, PORTD};
use shared::exception::{ExceptionType, MasterLatch};

/// The Uno's LED on D13 (PB5).
pub type StatusLed = Output<PORTB, 5>;
/// The blue LED on D7 (PD7).
pub type BlueLed = Output<PORTD, 7>;

/// How long D13 stays lit after a ping starts, ms.
pub const PING_LIT_MS: u16 = 100;
/// One pulse of the type code, ms.
pub const FLASH_PERIOD_MS: u16 = 512;
/// The lit part of a pulse, ms (the original's 30 %, rounded to a power of two).
pub const FLASH_ON_MS: u16 = 128;
/// One cycle of the type code: room for 16 pulses, ms. It divides 2¹⁶, so the pattern
/// runs on the clock's low 16 bits without a seam at their wrap.
pub const FLASH_CYCLE_MS: u16 = 16 * FLASH_PERIOD_MS;
const _: () = assert!(65_536 % FLASH_CYCLE_MS as u32 == 0);

/// Both LEDs and what they show.
pub struct Leds {
    status: StatusLed,
    blue: BlueLed,
    /// When the last ping lit D13 (the clock's low 16 bits), while it is lit.
    ping_at: Option<u16>,
    /// Type code of the last exception raised (0: none yet).
    code: u8,
}

impl Leds {
    /// D13 lit (boot), D7 dark.
    pub fn new(status: StatusLed, blue: BlueLed) -> Self {
        status.set_high();
        blue.set_low();
        Leds {
            status,
            blue,
            ping_at: None,
            code: 0,
        }
    }

    /// Boot is over: D13 goes dark.
    pub fn ready(&mut self) {
        self.status.set_low();
    }

    /// A ping starts at `now_ms`.
    // Out of line: measured 6 B smaller than in the schedule step.
    #[inline(never)]
    pub fn ping(&mut self, now_ms: u16) {
        self.status.set_high();
        self.ping_at = Some(now_ms);
    }

    /// Notes the exception latched in `latch`, if it is one the master raised.
    pub fn note(&mut self, latch: &MasterLatch) {
        match latch.current() {
            Some(e) if e.kind != ExceptionType::Boot => self.code = e.kind.code(),
            _ => {}
        }
    }

    /// Sets both LEDs for `now_ms`, with the remote control's link `rc_up` or not.
    #[inline(never)]
    pub fn update(&mut self, now_ms: u16, rc_up: bool) {
        let now = now_ms;
        if let Some(at) = self.ping_at {
            if now.wrapping_sub(at) >= PING_LIT_MS {
                self.status.set_low();
                self.ping_at = None;
            }
        }
        // The type code, once one was raised, takes the place of the link's light.
        self.blue.set(if self.code == 0 {
            rc_up
        } else {
            flash_lit(self.code, now)
        });
    }
}

/// Whether the type-code pattern of `code` is lit at `now_ms` (the clock's low 16 bits;
/// never for code 0).
fn flash_lit(code: u8, now_ms: u16) -> bool {
    let t = now_ms % FLASH_CYCLE_MS;
    t / FLASH_PERIOD_MS < u16::from(code) && t % FLASH_PERIOD_MS < FLASH_ON_MS
}
