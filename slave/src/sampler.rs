//! The ADC task's body: the round robin of reference §7.2 (ch0, ch1, ch6, ch7), each
//! conversion started as soon as the previous one is stored.

use drivers::adc::Adc;
use shared::slave::{next_mux, AdcChannel, AdcCollector};

/// The ADC and the multiplexer number of the channel being converted.
pub struct Sampler {
    adc: Adc,
    mux: u8,
}

impl Sampler {
    /// Starts the first conversion (ch0).
    pub fn start(mut adc: Adc) -> Sampler {
        let mux = AdcChannel::ORDER[0].mux();
        adc.start(mux);
        Sampler { adc, mux }
    }

    /// A conversion finished: stores it and starts the next channel's.
    #[inline(always)]
    pub fn on_complete(&mut self, collector: &mut AdcCollector) {
        let value = self.adc.result();
        let done = self.mux;
        self.mux = next_mux(done);
        self.adc.start(self.mux);
        collector.record_mux(done, value);
    }
}
