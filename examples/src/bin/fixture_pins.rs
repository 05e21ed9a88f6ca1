//! Fixture: mirrors input D2 (PD2) onto output D13 (PB5) and drives a Timer1
//! fast 8-bit PWM on D9 (OC1A) at OCR1A = 63 of 255, a duty of 64/256 = 25 %.
//! Used by the harness's GPIO tests.
#![no_std]
#![no_main]

#[avr_device::entry]
fn main() -> ! {
    let dp = firmware_examples::peripherals();
    // D13 = PB5 and D9 = PB1 are outputs; D2 = PD2 stays an input, no pull-up.
    // SAFETY: any DDRB value is valid.
    dp.PORTB
        .ddrb()
        .write(|w| unsafe { w.bits((1 << 5) | (1 << 1)) });
    // Timer1 mode 5 (fast PWM, 8-bit): WGM10 in TCCR1A, WGM12 in TCCR1B; COM1A = 10
    // (clear on match, set at BOTTOM); clock/8.
    // SAFETY: these are documented TCCR1A/TCCR1B/OCR1A values.
    dp.TC1.ocr1a().write(|w| unsafe { w.bits(63) });
    dp.TC1.tccr1a().write(|w| unsafe { w.bits(0b1000_0001) });
    dp.TC1.tccr1b().write(|w| unsafe { w.bits(0b0000_1010) });
    loop {
        let high = dp.PORTD.pind().read().bits() & (1 << 2) != 0;
        dp.PORTB.portb().modify(|r, w| {
            let v = if high {
                r.bits() | (1 << 5)
            } else {
                r.bits() & !(1 << 5)
            };
            // SAFETY: any PORTB value is valid.
            unsafe { w.bits(v) }
        });
    }
}

firmware_examples::spin_on_panic!();
