//! The output stage: what a control tick's [`Outputs`] do to the pins. Motors (direction
//! pins and PWM), the two LEDs and the watchdog.

use drivers::pin::{Output, PORTC, PORTD};
use drivers::pwm::{Channel, Pwm};
use drivers::watchdog::{Timeout, Watchdog};
use shared::slave::{LedLevels, MotorOutput, Outputs, Watchdog as Dog};

/// M1 POS (D2).
pub type M1Pos = Output<PORTD, 2>;
/// M1 NEG (D3).
pub type M1Neg = Output<PORTD, 3>;
/// M2 POS (D4).
pub type M2Pos = Output<PORTD, 4>;
/// M2 NEG (D7).
pub type M2Neg = Output<PORTD, 7>;
/// LED1 (A2).
pub type Led1 = Output<PORTC, 2>;
/// LED2 (A3).
pub type Led2 = Output<PORTC, 3>;

/// Every output pin of the board, the PWM and the watchdog.
pub struct Stage {
    pwm: Pwm,
    m1: (M1Pos, M1Neg),
    m2: (M2Pos, M2Neg),
    leds: (Led1, Led2),
    watchdog: Watchdog,
    /// A reset was asked for: the watchdog runs out and is never fed again.
    resetting: bool,
}

impl Stage {
    /// Takes the pins (all low: both motors stopped, LEDs off) and the running PWM and
    /// watchdog.
    ///
    /// # Safety
    /// The caller must own D2, D3, D4, D7, A2 and A3.
    pub unsafe fn new(pwm: Pwm, watchdog: Watchdog) -> Stage {
        // SAFETY: pin ownership is the caller's promise.
        unsafe {
            Stage {
                pwm,
                m1: (M1Pos::take(), M1Neg::take()),
                m2: (M2Pos::take(), M2Neg::take()),
                leds: (Led1::take(), Led2::take()),
                watchdog,
                resetting: false,
            }
        }
    }

    /// Applies a tick's outputs: both duties, then the direction pins with M1 POS (D2)
    /// last, then the LEDs, so that once D2 shows a stop, the other pins do too.
    pub fn apply(&mut self, out: &Outputs) {
        let [m1, m2] = out.motors;
        self.pwm.set(Channel::M1, m1.duty());
        self.pwm.set(Channel::M2, m2.duty());
        let (pos, neg) = m2.pins();
        self.m2.0.set(pos);
        self.m2.1.set(neg);
        let (pos, neg) = m1.pins();
        self.m1.1.set(neg);
        self.m1.0.set(pos);
        self.show(out.leds);
        match out.watchdog {
            Dog::Feed if !self.resetting => self.watchdog.feed(),
            Dog::Feed => {}
            Dog::Reset => {
                if !self.resetting {
                    // The shortest period: the board resets 16 ms from now. Stopped
                    // first, so the new period starts now (the emulator re-times a
                    // running watchdog only when it is switched on).
                    self.watchdog.stop();
                    self.watchdog.start(Timeout::Ms16);
                    self.resetting = true;
                }
            }
        }
    }

    /// Sets the LEDs.
    pub fn show(&mut self, leds: LedLevels) {
        self.leds.0.set(leds.led1);
        self.leds.1.set(leds.led2);
    }

    /// The outputs at power-up, before the first tick: [`MotorOutput::BOOT`] on both
    /// motors, LEDs off. What [`Stage::apply`] does with them, less what [`Stage::new`]
    /// has done (every pin low, both duties 0): the two POS pins go high, M1 POS (D2)
    /// last, and the watchdog is fed. Written out, so that `apply` has one caller (the
    /// tick, which takes it in line) and no `Outputs` constant is kept in RAM.
    pub fn boot(&mut self) {
        const _: () = assert!(
            MotorOutput::BOOT.duty() == 0
                && matches!(MotorOutput::BOOT.pins(), (true, false))
                && !LedLevels::OFF.led1
                && !LedLevels::OFF.led2
        );
        self.m2.0.set_high();
        self.m1.0.set_high();
        self.watchdog.feed();
    }
}
