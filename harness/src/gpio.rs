//! GPIO: driving inputs, reading outputs, recording pin changes and reading a
//! PWM duty cycle back from the timer registers.

use std::ffi::c_void;

use simavr_ffi as ffi;

use crate::avr::{ioctl_def, Shared};
use crate::{Avr, Pin};

/// Called by simavr whenever a traced pin's level is raised.
unsafe extern "C" fn on_pin_change(irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    // SAFETY: `param` is the `Avr`'s boxed `Shared`, which outlives the core.
    let shared = unsafe { &*param.cast::<Shared>() };
    let Some(key) = shared.trace_irqs.borrow().get(&(irq as usize)).copied() else {
        return;
    };
    let level = value & 1 != 0;
    let now = shared.now();
    let mut traces = shared.traces.borrow_mut();
    let trace = traces.entry(key).or_default();
    if trace.last().map(|&(_, l)| l) != Some(level) {
        trace.push((now, level));
    }
}

/// The timer output a PWM-capable pin carries.
#[derive(Clone, Copy)]
struct OcPin {
    /// Timer 0, 1 or 2.
    timer: u8,
    /// Channel A (false) or B (true).
    channel_b: bool,
}

fn oc_pin(pin: Pin) -> Option<OcPin> {
    let (timer, channel_b) = match (pin.port_name(), pin.bit) {
        (b'D', 6) => (0, false),
        (b'D', 5) => (0, true),
        (b'B', 1) => (1, false),
        (b'B', 2) => (1, true),
        (b'B', 3) => (2, false),
        (b'D', 3) => (2, true),
        _ => return None,
    };
    Some(OcPin { timer, channel_b })
}

/// Waveform shape of a timer mode.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    Fast,
    PhaseCorrect,
}

/// Where a timer mode takes its TOP from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Top {
    Fixed(u16),
    OcrA,
    Icr,
}

/// (shape, top) for a timer/WGM combination, None when the mode is not PWM.
fn pwm_mode(timer: u8, wgm: u8) -> Option<(Shape, Top)> {
    use Shape::*;
    use Top::*;
    if timer == 1 {
        Some(match wgm {
            1 => (PhaseCorrect, Fixed(0xFF)),
            2 => (PhaseCorrect, Fixed(0x1FF)),
            3 => (PhaseCorrect, Fixed(0x3FF)),
            5 => (Fast, Fixed(0xFF)),
            6 => (Fast, Fixed(0x1FF)),
            7 => (Fast, Fixed(0x3FF)),
            8 | 10 => (PhaseCorrect, Icr),
            9 | 11 => (PhaseCorrect, OcrA),
            14 => (Fast, Icr),
            15 => (Fast, OcrA),
            _ => return None,
        })
    } else {
        Some(match wgm {
            1 => (PhaseCorrect, Fixed(0xFF)),
            3 => (Fast, Fixed(0xFF)),
            5 => (PhaseCorrect, OcrA),
            7 => (Fast, OcrA),
            _ => return None,
        })
    }
}

/// Duty cycle of a PWM output from its mode, COM bits, compare value and TOP.
fn duty(shape: Shape, com: u8, ocr: u16, top: u16) -> Option<f32> {
    if top == 0 {
        return None;
    }
    let high = match shape {
        Shape::Fast => (f32::from(ocr) + 1.0) / (f32::from(top) + 1.0),
        Shape::PhaseCorrect => f32::from(ocr) / f32::from(top),
    }
    .clamp(0.0, 1.0);
    match com {
        2 => Some(high),
        3 => Some(1.0 - high),
        _ => None,
    }
}

/// simavr's index of a timer's first compare-output IRQ (`TIMER_IRQ_OUT_COMP`).
const TIMER_IRQ_OUT_COMP: i32 = 4;

impl Avr {
    /// Stops simavr from drawing the PWM waveforms on the output-compare pins (OC0A/B,
    /// OC1A/B, OC2A/B): the pins then follow their PORT bits only, while the timers,
    /// their interrupts and [`Avr::pwm_duty`] (read from the timer registers) work as
    /// before. A model that takes the duty from [`Avr::pwm_duty`] loses nothing, and at
    /// 31 kHz the waveform costs the emulator about a tenth of its time per board.
    pub fn detach_pwm_waveforms(&mut self) {
        let oc_pins = [
            (b'0', [Pin::d(6), Pin::d(5)]),
            (b'1', [Pin::d(9), Pin::d(10)]),
            (b'2', [Pin::d(11), Pin::d(3)]),
        ];
        for (timer, pins) in oc_pins {
            let ctl = ioctl_def(b't', b'm', b'r', timer);
            for (comp, pin) in (0..).zip(pins) {
                // SAFETY: live core; avr_io_getirq returns NULL for an unknown IRQ.
                let from = unsafe {
                    ffi::avr_io_getirq(self.raw.as_ptr(), ctl, TIMER_IRQ_OUT_COMP + comp)
                };
                let to = self.pin_irq(pin);
                if !from.is_null() && !to.is_null() {
                    // SAFETY: both IRQs belong to this live core; unconnecting a pair
                    // that is not connected does nothing.
                    unsafe { ffi::avr_unconnect_irq(from, to) };
                }
            }
        }
    }

    /// The ioport IRQ of one pin, NULL for a port the chip lacks.
    pub(crate) fn pin_irq(&self, pin: Pin) -> *mut ffi::avr_irq_t {
        if pin.registers().is_none() {
            return std::ptr::null_mut();
        }
        let ctl = ioctl_def(b'i', b'o', b'g', pin.port_name());
        // SAFETY: live core; avr_io_getirq returns NULL for unknown ports.
        unsafe { ffi::avr_io_getirq(self.raw.as_ptr(), ctl, i32::from(pin.bit)) }
    }

    /// Drives an input pin from outside (a switch, a sensor, another chip).
    pub fn set_pin(&mut self, pin: Pin, high: bool) {
        let irq = self.pin_irq(pin);
        if !irq.is_null() {
            // SAFETY: `irq` is this core's pin IRQ; hooks may run and record changes.
            unsafe { ffi::avr_raise_irq(irq, u32::from(high)) };
        }
    }

    /// The pin's level: what the firmware drives if it is an output (DDR bit set),
    /// else the level its input sees.
    pub fn pin(&self, pin: Pin) -> bool {
        let Some((pin_reg, ddr, port)) = pin.registers() else {
            return false;
        };
        let mask = 1 << pin.bit;
        if self.read_data(ddr) & mask != 0 {
            self.read_data(port) & mask != 0
        } else {
            self.read_data(pin_reg) & mask != 0
        }
    }

    /// Starts recording (cycle, level) changes of `pin`, starting with its level now.
    pub fn trace_pin(&mut self, pin: Pin) {
        let key = (pin.port_name(), pin.bit);
        let irq = self.pin_irq(pin);
        if irq.is_null() || self.shared.traces.borrow().contains_key(&key) {
            return;
        }
        let now = self.cycles();
        let level = self.pin(pin);
        self.shared
            .traces
            .borrow_mut()
            .insert(key, vec![(now, level)]);
        self.shared
            .trace_irqs
            .borrow_mut()
            .insert(irq as usize, key);
        let param = std::ptr::from_ref::<Shared>(&self.shared).cast_mut().cast();
        // SAFETY: `irq` belongs to the live core; `param` is the boxed `Shared`, which
        // is dropped only after the core.
        unsafe { ffi::avr_irq_register_notify(irq, Some(on_pin_change), param) };
    }

    /// The recorded (cycle, level) changes of a traced pin (empty if not traced).
    pub fn pin_trace(&self, pin: Pin) -> Vec<(u64, bool)> {
        self.shared
            .traces
            .borrow()
            .get(&(pin.port_name(), pin.bit))
            .cloned()
            .unwrap_or_default()
    }

    /// The duty cycle (0.0..=1.0, fraction of time high) of a Timer0/1/2 PWM pin,
    /// computed from the timer registers; None if the pin is not a running PWM output.
    pub fn pwm_duty(&self, pin: Pin) -> Option<f32> {
        let oc = oc_pin(pin)?;
        let (_, ddr, _) = pin.registers()?;
        if self.read_data(ddr) & (1 << pin.bit) == 0 {
            return None;
        }
        let (tccra, tccrb, ocra, ocrb, icr) = match oc.timer {
            0 => (0x44, 0x45, 0x47, 0x48, 0),
            1 => (0x80, 0x81, 0x88, 0x8A, 0x86),
            _ => (0xB0, 0xB1, 0xB3, 0xB4, 0),
        };
        let a = self.read_data(tccra);
        let b = self.read_data(tccrb);
        if b & 0x07 == 0 {
            return None; // clock stopped
        }
        let wgm_hi_mask = if oc.timer == 1 { 0x03 } else { 0x01 };
        let wgm = (a & 0x03) | (((b >> 3) & wgm_hi_mask) << 2);
        let (shape, top) = pwm_mode(oc.timer, wgm)?;
        let read16 = |addr: u16| {
            if oc.timer == 1 {
                u16::from_le_bytes([self.read_data(addr), self.read_data(addr + 1)])
            } else {
                u16::from(self.read_data(addr))
            }
        };
        let top = match top {
            Top::Fixed(t) => t,
            Top::OcrA => read16(ocra),
            Top::Icr => read16(icr),
        };
        let (com, ocr) = if oc.channel_b {
            ((a >> 4) & 3, read16(ocrb))
        } else {
            ((a >> 6) & 3, read16(ocra))
        };
        if com == 1 && !oc.channel_b && matches!(pwm_mode(oc.timer, wgm), Some((_, Top::OcrA))) {
            return Some(0.5); // OCnA toggles on every compare match at TOP
        }
        duty(shape, com, ocr, top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duty_fast_and_phase_correct() {
        assert_eq!(duty(Shape::Fast, 2, 63, 255), Some(0.25));
        assert_eq!(duty(Shape::Fast, 3, 63, 255), Some(0.75));
        assert_eq!(duty(Shape::Fast, 2, 255, 255), Some(1.0));
        assert_eq!(duty(Shape::PhaseCorrect, 2, 64, 256), Some(0.25));
        assert_eq!(duty(Shape::PhaseCorrect, 0, 64, 256), None);
        assert_eq!(duty(Shape::Fast, 2, 1, 0), None);
    }

    #[test]
    fn modes() {
        assert_eq!(pwm_mode(1, 14), Some((Shape::Fast, Top::Icr)));
        assert_eq!(pwm_mode(1, 5), Some((Shape::Fast, Top::Fixed(0xFF))));
        assert_eq!(pwm_mode(0, 3), Some((Shape::Fast, Top::Fixed(0xFF))));
        assert_eq!(pwm_mode(2, 5), Some((Shape::PhaseCorrect, Top::OcrA)));
        assert_eq!(pwm_mode(0, 0), None);
        assert_eq!(pwm_mode(1, 4), None);
    }

    #[test]
    fn oc_pins() {
        assert!(oc_pin(Pin::d(9)).is_some_and(|o| o.timer == 1 && !o.channel_b));
        assert!(oc_pin(Pin::d(3)).is_some_and(|o| o.timer == 2 && o.channel_b));
        assert!(oc_pin(Pin::d(13)).is_none());
    }
}
