//! ADC inputs and reference voltages.

use simavr_ffi as ffi;

use std::ptr::NonNull;

use crate::avr::ioctl_def;
use crate::Avr;

impl Avr {
    /// Applies `mv` millivolts to ADC input `channel` (0..=7); other channels are ignored.
    /// Applying the value the input already has does nothing, so models may apply
    /// their voltages at every step without cost.
    pub fn set_adc_mv(&mut self, channel: u8, mv: u32) {
        if channel > 7 {
            return;
        }
        let Some(first) = self.adc_input_irqs() else {
            return;
        };
        // SAFETY: simavr allocates the ADC's IRQs as one array that starts at ADC0 and
        // lives as long as the core; `channel` is at most 7.
        let irq = unsafe { first.as_ptr().add(usize::from(channel)) };
        // SAFETY: live core; the ADC input IRQs take millivolts and only store them.
        unsafe {
            if (*irq).value != mv {
                ffi::avr_raise_irq(irq, mv);
            }
        }
    }

    /// The millivolts last applied to ADC input `channel` (0..=7; 0 before any).
    pub fn adc_input_mv(&mut self, channel: u8) -> Option<u32> {
        if channel > 7 {
            return None;
        }
        let first = self.adc_input_irqs()?;
        // SAFETY: as in `set_adc_mv`: one array of IRQs from ADC0, `channel` ≤ 7; a
        // plain field read.
        Some(unsafe { (*first.as_ptr().add(usize::from(channel))).value })
    }

    /// The ADC0 input IRQ, the first of eight in a row.
    fn adc_input_irqs(&mut self) -> Option<NonNull<ffi::avr_irq_t>> {
        if self.adc_inputs.is_none() {
            let ctl = ioctl_def(b'a', b'd', b'c', b'0');
            // SAFETY: live core; avr_io_getirq returns NULL for an unknown IRQ.
            let irq =
                unsafe { ffi::avr_io_getirq(self.raw.as_ptr(), ctl, ffi::ADC_IRQ_ADC0 as i32) };
            self.adc_inputs = NonNull::new(irq);
        }
        self.adc_inputs
    }

    /// Sets the AVCC and AREF voltages in millivolts (both 5000 after load).
    pub fn set_reference_mv(&mut self, avcc_mv: u32, aref_mv: u32) {
        let p = self.raw.as_ptr();
        // SAFETY: plain fields of the live core that the ADC reads at conversion time.
        unsafe {
            (*p).avcc = avcc_mv;
            (*p).aref = aref_mv;
        }
    }
}
