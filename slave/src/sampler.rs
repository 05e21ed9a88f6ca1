//! The ADC task's body: the round robin of reference §7.2 (ch0, ch1, ch6, ch7), each
//! conversion started as soon as the previous one is stored.

use drivers::adc::Adc;
use shared::slave::{AdcChannel, AdcCollector};

/// The ADC and the channel being converted.
pub struct Sampler {
    adc: Adc,
    channel: AdcChannel,
}

impl Sampler {
    /// Starts the first conversion (ch0).
    pub fn start(mut adc: Adc) -> Sampler {
        let channel = AdcChannel::ORDER[0];
        adc.start(channel.mux());
        Sampler { adc, channel }
    }

    /// A conversion finished: stores it and starts the next channel's.
    #[inline(always)]
    pub fn on_complete(&mut self, collector: &mut AdcCollector) {
        let value = self.adc.result();
        let done = self.channel;
        self.channel = done.next();
        self.adc.start(self.channel.mux());
        collector.record(done, value);
    }
}
