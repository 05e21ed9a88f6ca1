//! DS18S20 temperature sensors on one OneWire line, as a timing model independent of
//! the emulator: it is told when the master pulls the line low and releases it (cycle
//! stamps) and says what level the line has at any cycle. The timing rules and commands
//! are listed in the `onewire` module's documentation.

/// Cycles per µs at 16 MHz.
const CYCLES_PER_US: u64 = 16;
/// Shortest reset pulse.
const RESET_MIN: u64 = 480 * CYCLES_PER_US;
/// When devices sample a write slot, after the falling edge.
const SAMPLE: u64 = 30 * CYCLES_PER_US;
/// Longest write-1 low time of the datasheet.
const WRITE1_MAX: u64 = 15 * CYCLES_PER_US;
/// Shortest write-0 low time of the datasheet.
const WRITE0_MIN: u64 = 60 * CYCLES_PER_US;
/// Longest slot low time of the datasheet.
const SLOT_MAX: u64 = 120 * CYCLES_PER_US;
/// Delay from the end of a reset to the presence pulse, by default.
const PRESENCE_WAIT: u64 = 30 * CYCLES_PER_US;
/// Length of the presence pulse, by default.
const PRESENCE: u64 = 120 * CYCLES_PER_US;
/// How long a device holds the line low to send a 0.
const READ_HOLD: u64 = 30 * CYCLES_PER_US;
/// Longest wait from the end of CONVERT T to the strong pull-up (parasite power).
const PULLUP_MAX: u64 = 10 * CYCLES_PER_US;
/// The datasheet's maximum conversion time, the default here: 750 ms.
pub const DEFAULT_CONVERSION_US: u64 = 750_000;
/// Temperature the scratchpad holds at power-up, before any conversion: 85 °C.
pub const POWER_ON_HALF_DEGREES: i16 = 170;

/// A slot, pulse or conversion outside the datasheet's timing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TimingViolation {
    /// When it was seen (the master released the line, or the conversion lost its
    /// power), µs since the chip was loaded.
    pub at_us: u64,
    /// How long the master held the line low, µs; for a conversion's power, how long
    /// after CONVERT T the strong pull-up came or ended.
    pub low_us: u64,
    /// Which rule it broke.
    pub what: &'static str,
}

/// Counts of what happened on the line.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OneWireStats {
    /// Reset pulses.
    pub resets: u32,
    /// Resets answered by a presence pulse.
    pub presence_pulses: u32,
    /// Time slots (read or write).
    pub slots: u64,
    /// Conversions started.
    pub conversions: u32,
    /// Scratchpads read to their CRC byte.
    pub scratchpad_reads: u32,
}

/// One DS18S20.
#[derive(Debug, Clone)]
struct Sensor {
    rom: [u8; 8],
    present: bool,
    /// Temperature the next conversion measures, half degrees.
    half: i16,
    scratchpad: [u8; 9],
    /// A conversion under way: (finishes at cycle, half degrees measured).
    pending: Option<(u64, i16)>,
    /// Taking part in the current transaction.
    selected: bool,
}

/// The scratchpad of a reading: temperature, TH 75 °C, TL 70 °C, reserved, COUNT_REMAIN
/// consistent with the half degree, COUNT_PER_C 16, CRC.
fn scratchpad(half: i16) -> [u8; 9] {
    let [lo, hi] = half.to_le_bytes();
    let count_remain = if half & 1 == 0 { 0x0c } else { 0x04 };
    let mut pad = [lo, hi, 0x4b, 0x46, 0xff, 0xff, count_remain, 0x10, 0];
    pad[8] = crate::onewire::crc8(&pad[..8]);
    pad
}

/// Where a search pass stands on one bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SearchStep {
    Bit,
    Complement,
    Direction,
}

/// The devices' protocol state (the same for all that take part).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Waiting for a reset.
    Idle,
    /// Receiving a ROM command.
    Rom { bits: u8, byte: u8 },
    /// Receiving the 64 ROM bits of MATCH ROM.
    Match { bit: u8 },
    /// SEARCH ROM.
    Search { bit: u8, step: SearchStep },
    /// Sending the ROM (READ ROM).
    ReadRom { bit: u8 },
    /// Receiving a function command.
    Function { bits: u8, byte: u8 },
    /// Sending the scratchpad.
    ReadScratchpad { bit: u8 },
    /// After CONVERT T: read slots say whether the conversion is done.
    Converting,
    /// Nothing more to say until the next reset: read slots read 1.
    Done,
}

impl Phase {
    /// Whether the devices send in this phase (so every slot is a read slot).
    fn sends(self) -> bool {
        matches!(
            self,
            Phase::Search {
                step: SearchStep::Bit | SearchStep::Complement,
                ..
            } | Phase::ReadRom { .. }
                | Phase::ReadScratchpad { .. }
                | Phase::Converting
                | Phase::Done
        )
    }
}

/// A parasite-powered conversion's supply: the master must drive the line high within
/// 10 µs of CONVERT T and hold it there until the conversion is done.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Power {
    /// No conversion needs it.
    Idle,
    /// CONVERT T ended at `since`; the conversion runs until `until`.
    Due { since: u64, until: u64 },
    /// Driven high in time after CONVERT T, which ended at `since`; the conversion runs
    /// until `until`.
    Held { since: u64, until: u64 },
}

/// The line and the devices on it.
#[derive(Debug, Clone)]
pub(crate) struct Wire {
    sensors: Vec<Sensor>,
    conversion_cycles: u64,
    /// The presence pulse: (delay after the reset's release, length), cycles.
    presence: (u64, u64),
    /// Whether the devices draw their power from the line (the rover's sensors do).
    parasite: bool,
    power: Power,
    /// The master drives the line high (a strong pull-up) since this cycle.
    master_high_since: Option<u64>,
    /// The master has pulled the line low since this cycle.
    master_low_since: Option<u64>,
    /// A device pulls the line low over [start, end).
    hold: Option<(u64, u64)>,
    phase: Phase,
    stats: OneWireStats,
    violations: Vec<TimingViolation>,
}

impl Wire {
    /// An empty line: no devices, released.
    pub fn new() -> Wire {
        Wire {
            sensors: Vec::new(),
            conversion_cycles: DEFAULT_CONVERSION_US * CYCLES_PER_US,
            presence: (PRESENCE_WAIT, PRESENCE),
            parasite: false,
            power: Power::Idle,
            master_high_since: None,
            master_low_since: None,
            hold: None,
            phase: Phase::Idle,
            stats: OneWireStats::default(),
            violations: Vec::new(),
        }
    }

    /// Adds a present device measuring `half` half degrees; returns its index.
    pub fn add(&mut self, rom: [u8; 8], half: i16) -> usize {
        self.sensors.push(Sensor {
            rom,
            present: true,
            half,
            scratchpad: scratchpad(POWER_ON_HALF_DEGREES),
            pending: None,
            selected: false,
        });
        self.sensors.len() - 1
    }

    pub fn len(&self) -> usize {
        self.sensors.len()
    }

    pub fn rom(&self, i: usize) -> Option<[u8; 8]> {
        self.sensors.get(i).map(|s| s.rom)
    }

    /// Sets the temperature device `i` measures from its next conversion on (clamped to
    /// the DS18S20's −55..125 °C).
    pub fn set_half_degrees(&mut self, i: usize, half: i16) -> bool {
        let Some(s) = self.sensors.get_mut(i) else {
            return false;
        };
        s.half = half.clamp(-110, 250);
        true
    }

    /// The temperature device `i` measures, in 0.5 °C units.
    pub fn half_degrees(&self, i: usize) -> Option<i16> {
        self.sensors.get(i).map(|s| s.half)
    }

    /// Puts device `i` on the line or takes it off (it then answers nothing).
    pub fn set_present(&mut self, i: usize, present: bool) -> bool {
        let Some(s) = self.sensors.get_mut(i) else {
            return false;
        };
        s.present = present;
        s.selected &= present;
        true
    }

    pub fn set_conversion_cycles(&mut self, cycles: u64) {
        self.conversion_cycles = cycles;
    }

    /// Sets the presence pulse's delay after a reset and its length, cycles.
    pub fn set_presence(&mut self, wait: u64, length: u64) {
        self.presence = (wait, length);
    }

    /// Makes the devices parasite-powered (`true`) or externally powered.
    pub fn set_parasite(&mut self, parasite: bool) {
        self.parasite = parasite;
    }

    /// Device `i`'s scratchpad at cycle `now`.
    pub fn scratchpad(&mut self, i: usize, now: u64) -> Option<[u8; 9]> {
        self.settle(now);
        self.sensors.get(i).map(|s| s.scratchpad)
    }

    pub fn stats(&self) -> OneWireStats {
        self.stats
    }

    pub fn violations(&self) -> &[TimingViolation] {
        &self.violations
    }

    /// The chip was reset at cycle `now`: its pin is an input again and the transaction
    /// is lost. Conversions under way go on, but a parasite-powered conversion under way loses its strong pull-up.
    pub fn chip_reset(&mut self, now: u64) {
        self.drive_high(false, now);
        self.master_low_since = None;
        self.hold = None;
        self.phase = Phase::Idle;
    }

    /// Whether the line is high at cycle `now` (pulled up, nobody pulling it low).
    pub fn line_high(&self, now: u64) -> bool {
        let held = self.hold.is_some_and(|(a, b)| (a..b).contains(&now));
        self.master_low_since.is_none() && !held
    }

    /// The master pulls the line low (`low`) or releases it, at cycle `now`.
    pub fn master(&mut self, low: bool, now: u64) {
        match (self.master_low_since, low) {
            (None, true) => {
                self.settle(now);
                self.master_low_since = Some(now);
                self.slot_start(now);
            }
            (Some(start), false) => {
                self.master_low_since = None;
                self.slot_end(now.saturating_sub(start), now);
            }
            _ => {}
        }
    }

    /// The master drives the line high (`high`: DDR and PORT set, a strong pull-up) or
    /// stops, at cycle `now`.
    pub fn drive_high(&mut self, high: bool, now: u64) {
        match (self.master_high_since, high) {
            (None, true) => {
                self.master_high_since = Some(now);
                if let Power::Due { since, until } = self.power {
                    if now - since > PULLUP_MAX {
                        self.brown_out(
                            now - since,
                            now,
                            "strong pull-up more than 10 µs after CONVERT T",
                        );
                    } else {
                        self.power = Power::Held { since, until };
                    }
                }
                self.settle(now);
            }
            (Some(_), false) => {
                self.master_high_since = None;
                self.settle(now);
                if let Power::Held { since, .. } = self.power {
                    self.brown_out(
                        now - since,
                        now,
                        "strong pull-up ended before the conversion was done",
                    );
                }
            }
            _ => {}
        }
    }

    /// A parasite-powered conversion lost its supply: the devices converting reset, so
    /// their scratchpads hold the power-up 85 °C.
    fn brown_out(&mut self, after: u64, now: u64, what: &'static str) {
        self.violation(after, now, what);
        self.power = Power::Idle;
        for s in self.sensors.iter_mut().filter(|s| s.pending.is_some()) {
            s.pending = None;
            s.scratchpad = scratchpad(POWER_ON_HALF_DEGREES);
        }
    }

    /// Applies conversions that have finished by `now`, and checks their power.
    fn settle(&mut self, now: u64) {
        match self.power {
            Power::Due { since, .. } if now - since > PULLUP_MAX => {
                self.brown_out(
                    now - since,
                    now,
                    "no strong pull-up within 10 µs of CONVERT T",
                );
            }
            Power::Held { until, .. } if now >= until => self.power = Power::Idle,
            _ => {}
        }
        for s in &mut self.sensors {
            if let Some((until, half)) = s.pending {
                if now >= until {
                    s.scratchpad = scratchpad(half);
                    s.pending = None;
                }
            }
        }
    }

    fn selected(&self) -> impl Iterator<Item = &Sensor> {
        self.sensors.iter().filter(|s| s.present && s.selected)
    }

    /// The wired-AND of what the taking-part devices send in this slot.
    fn sent_bit(&mut self, now: u64) -> bool {
        self.settle(now);
        let bit = |bytes: &[u8], i: u8| bytes[usize::from(i / 8)] & (1 << (i % 8)) != 0;
        match self.phase {
            Phase::Search {
                bit: i,
                step: SearchStep::Bit,
            } => self.selected().all(|s| bit(&s.rom, i)),
            Phase::Search {
                bit: i,
                step: SearchStep::Complement,
            } => self.selected().all(|s| !bit(&s.rom, i)),
            Phase::ReadRom { bit: i } => self.selected().all(|s| bit(&s.rom, i)),
            Phase::ReadScratchpad { bit: i } => self.selected().all(|s| bit(&s.scratchpad, i)),
            Phase::Converting => self.selected().all(|s| s.pending.is_none()),
            _ => true,
        }
    }

    fn slot_start(&mut self, now: u64) {
        if self.phase.sends() && !self.sent_bit(now) {
            self.hold = Some((now, now + READ_HOLD));
        }
    }

    fn violation(&mut self, low: u64, now: u64, what: &'static str) {
        self.violations.push(TimingViolation {
            at_us: now / CYCLES_PER_US,
            low_us: low / CYCLES_PER_US,
            what,
        });
    }

    fn slot_end(&mut self, low: u64, now: u64) {
        if low >= RESET_MIN {
            self.reset_pulse(now);
            return;
        }
        self.stats.slots += 1;
        if low > SLOT_MAX {
            self.violation(
                low,
                now,
                "slot low for 120..480 µs: neither a slot nor a reset",
            );
        }
        if self.phase.sends() {
            if low >= WRITE1_MAX {
                self.violation(
                    low,
                    now,
                    "read slot held low by the master for 15 µs or more",
                );
            }
            self.sent(now);
        } else if self.phase != Phase::Idle {
            if (WRITE1_MAX..WRITE0_MIN).contains(&low) {
                self.violation(low, now, "write slot low for 15..60 µs: ambiguous");
            }
            self.received(low < SAMPLE, now);
        }
    }

    fn reset_pulse(&mut self, now: u64) {
        self.stats.resets += 1;
        let mut any = false;
        for s in &mut self.sensors {
            s.selected = s.present;
            any |= s.present;
        }
        if any {
            self.stats.presence_pulses += 1;
            let (wait, length) = self.presence;
            self.hold = Some((now + wait, now + wait + length));
            self.phase = Phase::Rom { bits: 0, byte: 0 };
        } else {
            self.phase = Phase::Idle;
        }
    }

    /// The devices sent a bit: move on.
    fn sent(&mut self, _now: u64) {
        self.phase = match self.phase {
            Phase::Search {
                bit,
                step: SearchStep::Bit,
            } => Phase::Search {
                bit,
                step: SearchStep::Complement,
            },
            Phase::Search {
                bit,
                step: SearchStep::Complement,
            } => Phase::Search {
                bit,
                step: SearchStep::Direction,
            },
            Phase::ReadRom { bit: 63 } => Phase::Function { bits: 0, byte: 0 },
            Phase::ReadRom { bit } => Phase::ReadRom { bit: bit + 1 },
            Phase::ReadScratchpad { bit: 71 } => {
                self.stats.scratchpad_reads += 1;
                Phase::Done
            }
            Phase::ReadScratchpad { bit } => Phase::ReadScratchpad { bit: bit + 1 },
            other => other,
        };
    }

    /// Drops the taking-part devices whose ROM bit `i` is not `value`; returns whether any
    /// is left.
    fn keep_matching(&mut self, i: u8, value: bool) -> bool {
        let mut any = false;
        for s in &mut self.sensors {
            let b = s.rom[usize::from(i / 8)] & (1 << (i % 8)) != 0;
            s.selected &= s.present && b == value;
            any |= s.selected;
        }
        any
    }

    /// The devices received a bit from the master.
    fn received(&mut self, value: bool, now: u64) {
        let v = u8::from(value);
        self.phase = match self.phase {
            Phase::Rom { bits: 7, byte } => match byte | (v << 7) {
                0xf0 => Phase::Search {
                    bit: 0,
                    step: SearchStep::Bit,
                },
                0x55 => Phase::Match { bit: 0 },
                0xcc => Phase::Function { bits: 0, byte: 0 },
                0x33 => Phase::ReadRom { bit: 0 },
                _ => Phase::Idle,
            },
            Phase::Rom { bits, byte } => Phase::Rom {
                bits: bits + 1,
                byte: byte | (v << bits),
            },
            Phase::Match { bit } => match (self.keep_matching(bit, value), bit) {
                (false, _) => Phase::Idle,
                (true, 63) => Phase::Function { bits: 0, byte: 0 },
                (true, _) => Phase::Match { bit: bit + 1 },
            },
            Phase::Search {
                bit,
                step: SearchStep::Direction,
            } => match (self.keep_matching(bit, value), bit) {
                (false, _) => Phase::Idle,
                (true, 63) => Phase::Function { bits: 0, byte: 0 },
                (true, _) => Phase::Search {
                    bit: bit + 1,
                    step: SearchStep::Bit,
                },
            },
            Phase::Function { bits: 7, byte } => self.function(byte | (v << 7), now),
            Phase::Function { bits, byte } => Phase::Function {
                bits: bits + 1,
                byte: byte | (v << bits),
            },
            other => other,
        };
    }

    /// A complete function command.
    fn function(&mut self, command: u8, now: u64) -> Phase {
        match command {
            0x44 => {
                let until = now + self.conversion_cycles;
                for s in self.sensors.iter_mut().filter(|s| s.present && s.selected) {
                    s.pending = Some((until, s.half));
                    self.stats.conversions += 1;
                }
                if self.parasite {
                    self.power = Power::Due { since: now, until };
                }
                Phase::Converting
            }
            0xbe => Phase::ReadScratchpad { bit: 0 },
            _ => Phase::Idle,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::onewire::ROVER_SENSOR_ROMS;

    const US: u64 = CYCLES_PER_US;

    /// Drives a wire with textbook timings and a µs clock.
    struct Master {
        wire: Wire,
        now: u64,
    }

    impl Master {
        fn new(wire: Wire) -> Master {
            Master {
                wire,
                now: 1000 * US,
            }
        }

        fn low_for(&mut self, us: u64) {
            self.wire.master(true, self.now);
            self.now += us * US;
            self.wire.master(false, self.now);
        }

        fn reset(&mut self) -> bool {
            self.low_for(480);
            self.now += 70 * US;
            let presence = !self.wire.line_high(self.now);
            self.now += 410 * US;
            presence
        }

        fn write_bit(&mut self, bit: bool) {
            self.low_for(if bit { 6 } else { 60 });
            self.now += if bit { 64 } else { 10 } * US;
        }

        fn read_bit(&mut self) -> bool {
            self.wire.master(true, self.now);
            self.now += 6 * US;
            self.wire.master(false, self.now);
            self.now += 9 * US;
            let bit = self.wire.line_high(self.now);
            self.now += 55 * US;
            bit
        }

        fn write_byte(&mut self, byte: u8) {
            for i in 0..8 {
                self.write_bit(byte & (1 << i) != 0);
            }
        }

        fn read_byte(&mut self) -> u8 {
            (0..8).fold(0, |b, i| b | (u8::from(self.read_bit()) << i))
        }
    }

    fn rover_wire() -> Wire {
        let mut w = Wire::new();
        for (i, rom) in ROVER_SENSOR_ROMS.iter().enumerate() {
            w.add(*rom, 40 + i as i16);
        }
        w
    }

    #[test]
    fn presence_only_with_a_present_device() {
        let mut m = Master::new(Wire::new());
        assert!(!m.reset());
        let mut w = Wire::new();
        w.add(ROVER_SENSOR_ROMS[0], 0);
        let mut m = Master::new(w);
        assert!(m.reset());
        m.wire.set_present(0, false);
        assert!(!m.reset());
        assert_eq!(m.wire.stats().resets, 2);
        assert_eq!(m.wire.stats().presence_pulses, 1);
    }

    #[test]
    fn read_rom_of_a_single_device() {
        let mut w = Wire::new();
        w.add(ROVER_SENSOR_ROMS[3], 0);
        let mut m = Master::new(w);
        assert!(m.reset());
        m.write_byte(0x33);
        let rom: Vec<u8> = (0..8).map(|_| m.read_byte()).collect();
        assert_eq!(rom, ROVER_SENSOR_ROMS[3]);
        assert!(m.wire.violations().is_empty(), "{:?}", m.wire.violations());
    }

    #[test]
    fn match_rom_convert_and_read_the_scratchpad() {
        let mut m = Master::new(rover_wire());
        assert!(m.reset());
        m.write_byte(0x55);
        for b in ROVER_SENSOR_ROMS[5] {
            m.write_byte(b);
        }
        m.write_byte(0xbe);
        let pad: Vec<u8> = (0..9).map(|_| m.read_byte()).collect();
        assert_eq!(pad[..2], [0xaa, 0x00], "85 °C before any conversion");
        assert_eq!(crate::onewire::crc8(&pad), 0);
        // SKIP ROM + CONVERT T converts all; read slots say busy until 750 ms have passed.
        assert!(m.reset());
        m.write_byte(0xcc);
        m.write_byte(0x44);
        assert!(!m.read_bit(), "busy");
        m.now += 750_000 * US;
        assert!(m.read_bit(), "done");
        assert!(m.reset());
        m.write_byte(0x55);
        for b in ROVER_SENSOR_ROMS[5] {
            m.write_byte(b);
        }
        m.write_byte(0xbe);
        let pad: Vec<u8> = (0..9).map(|_| m.read_byte()).collect();
        assert_eq!(pad, scratchpad(45));
        assert_eq!(pad[..8], [45, 0, 0x4b, 0x46, 0xff, 0xff, 0x04, 0x10]);
        assert_eq!(m.wire.stats().conversions, 10);
        assert_eq!(m.wire.stats().scratchpad_reads, 2);
        assert!(m.wire.violations().is_empty(), "{:?}", m.wire.violations());
    }

    /// SKIP ROM, CONVERT T on a parasite-powered rover wire, with the strong pull-up
    /// `gap_us` after the last slot's release (None: the last slot ends driving high).
    fn parasite_convert(gap_us: Option<u64>) -> Master {
        let mut w = rover_wire();
        w.set_parasite(true);
        let mut m = Master::new(w);
        assert!(m.reset());
        m.write_byte(0xcc);
        for i in 0..7 {
            m.write_bit(0x44 & (1 << i) != 0);
        }
        // The last bit, a 0: 60 µs low, then either released or driven high at once.
        m.wire.master(true, m.now);
        m.now += 60 * US;
        match gap_us {
            None => {
                m.wire.master(false, m.now);
                m.wire.drive_high(true, m.now);
            }
            Some(gap) => {
                m.wire.master(false, m.now);
                m.now += gap * US;
                m.wire.drive_high(true, m.now);
            }
        }
        m
    }

    fn reading(m: &mut Master, sensor: usize) -> [u8; 2] {
        let pad = m.wire.scratchpad(sensor, m.now).unwrap_or_default();
        [pad[0], pad[1]]
    }

    #[test]
    fn a_parasite_conversion_powered_at_once_measures() {
        let mut m = parasite_convert(None);
        m.now += 750_000 * US;
        m.wire.drive_high(false, m.now);
        assert_eq!(reading(&mut m, 5), [45, 0]);
        assert!(m.wire.violations().is_empty(), "{:?}", m.wire.violations());
        // 10 µs late is still in time.
        let mut m = parasite_convert(Some(10));
        m.now += 750_000 * US;
        assert_eq!(reading(&mut m, 5), [45, 0]);
        assert!(m.wire.violations().is_empty(), "{:?}", m.wire.violations());
    }

    #[test]
    fn a_parasite_conversion_powered_late_browns_out_to_85_degrees() {
        let mut m = parasite_convert(Some(11));
        m.now += 750_000 * US;
        assert_eq!(reading(&mut m, 5), [0xaa, 0x00]);
        let v = m.wire.violations();
        assert_eq!(v.len(), 1, "{v:?}");
        assert_eq!(v[0].low_us, 11);
        assert_eq!(v[0].what, "strong pull-up more than 10 µs after CONVERT T");
    }

    #[test]
    fn a_parasite_conversion_without_its_pull_up_to_the_end_browns_out() {
        // Released after 500 ms of the 750.
        let mut m = parasite_convert(None);
        m.now += 500_000 * US;
        m.wire.drive_high(false, m.now);
        m.now += 250_000 * US;
        assert_eq!(reading(&mut m, 5), [0xaa, 0x00]);
        assert_eq!(
            m.wire.violations()[0].what,
            "strong pull-up ended before the conversion was done"
        );
        // Never powered: seen at the next look at the line.
        let mut w = rover_wire();
        w.set_parasite(true);
        let mut m = Master::new(w);
        assert!(m.reset());
        m.write_byte(0xcc);
        m.write_byte(0x44);
        m.now += 750_000 * US;
        assert_eq!(reading(&mut m, 2), [0xaa, 0x00]);
        assert_eq!(
            m.wire.violations()[0].what,
            "no strong pull-up within 10 µs of CONVERT T"
        );
    }

    #[test]
    fn negative_temperatures_are_twos_complement_half_degrees() {
        assert_eq!(scratchpad(-50)[..2], [0xce, 0xff]);
        assert_eq!(scratchpad(-51)[6], 0x04);
        assert_eq!(scratchpad(50)[6], 0x0c);
    }

    #[test]
    fn bad_timings_are_recorded() {
        let mut m = Master::new(rover_wire());
        m.low_for(300);
        assert!(m.reset());
        m.low_for(40);
        let v = m.wire.violations();
        assert_eq!(v.len(), 2, "{v:?}");
        assert_eq!(v[0].low_us, 300);
        assert_eq!(v[1].low_us, 40);
    }
}
