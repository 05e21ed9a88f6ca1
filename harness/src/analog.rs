//! ADC inputs and reference voltages.

use simavr_ffi as ffi;

use crate::avr::ioctl_def;
use crate::Avr;

impl Avr {
    /// Applies `mv` millivolts to ADC input `channel` (0..=7); other channels are ignored.
    pub fn set_adc_mv(&mut self, channel: u8, mv: u32) {
        if channel > 7 {
            return;
        }
        let ctl = ioctl_def(b'a', b'd', b'c', b'0');
        let irq_no = ffi::ADC_IRQ_ADC0 as i32 + i32::from(channel);
        // SAFETY: live core; the ADC input IRQs take millivolts and only store them.
        unsafe {
            let irq = ffi::avr_io_getirq(self.raw.as_ptr(), ctl, irq_no);
            if !irq.is_null() {
                ffi::avr_raise_irq(irq, mv);
            }
        }
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
