//! The H-bridge input of one motor: PWM duty and the two direction pins.
//!
//! The slave drives each motor through one half of an L298 bridge: an enable pin carrying
//! the PWM (D9 or D10, 31.4 kHz) and two direction pins POS and NEG (reference §7.4):
//!
//! | POS | NEG | Duty | Bridge |
//! |---|---|---|---|
//! | high | low | d > 0 | forward: mean terminal voltage +d·12 V |
//! | low | high | d > 0 | reverse: mean terminal voltage −d·12 V |
//! | equal | equal | d > 0 | brake: terminals shorted for a fraction d of the time |
//! | any | any | 0 | off: bridge disabled, the motor coasts |
//!
//! The PWM period (32 µs) is far shorter than any time constant of the motors, so the
//! models see the mean voltage (continuous conduction); the bridge's decay mode during
//! the off part of each period is not modelled.

use crate::constants::SUPPLY_V;

/// What the bridge does with its motor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BridgeMode {
    /// POS high, NEG low: positive voltage; the motor turns forward.
    Forward,
    /// POS low, NEG high: negative voltage; the motor turns in reverse.
    Reverse,
    /// POS and NEG equal with a non-zero duty: the terminals are shorted while enabled.
    Brake,
    /// Duty 0: the bridge is disabled and the motor coasts.
    Off,
}

/// One motor's bridge input: duty 0..=1 and mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bridge {
    duty: f64,
    mode: BridgeMode,
}

impl Default for Bridge {
    fn default() -> Self {
        Bridge::off()
    }
}

impl Bridge {
    /// The bridge as the pins set it: `duty` is the enable pin's PWM duty (clamped to
    /// 0..=1, NaN counts as 0), `pos`/`neg` the direction pins' levels.
    pub fn from_pins(duty: f64, pos: bool, neg: bool) -> Bridge {
        let duty = if duty.is_nan() {
            0.0
        } else {
            duty.clamp(0.0, 1.0)
        };
        let mode = if duty == 0.0 {
            BridgeMode::Off
        } else {
            match (pos, neg) {
                (true, false) => BridgeMode::Forward,
                (false, true) => BridgeMode::Reverse,
                _ => BridgeMode::Brake,
            }
        };
        Bridge { duty, mode }
    }

    /// Forward at `duty` (0..=1).
    pub fn forward(duty: f64) -> Bridge {
        Bridge::from_pins(duty, true, false)
    }

    /// Reverse at `duty` (0..=1).
    pub fn reverse(duty: f64) -> Bridge {
        Bridge::from_pins(duty, false, true)
    }

    /// Forward for a positive `signed_duty`, reverse for a negative one (magnitude clamped to 1).
    pub fn signed(signed_duty: f64) -> Bridge {
        if signed_duty < 0.0 {
            Bridge::reverse(-signed_duty)
        } else {
            Bridge::forward(signed_duty)
        }
    }

    /// Disabled: the motor coasts.
    pub fn off() -> Bridge {
        Bridge {
            duty: 0.0,
            mode: BridgeMode::Off,
        }
    }

    /// The duty, 0..=1 (0 when off).
    pub fn duty(&self) -> f64 {
        self.duty
    }

    /// The mode.
    pub fn mode(&self) -> BridgeMode {
        self.mode
    }

    /// (mean terminal voltage while conducting, fraction of time conducting). The motor
    /// current is `fraction · (volts − back-EMF) / R`.
    pub(crate) fn drive(&self) -> (f64, f64) {
        match self.mode {
            BridgeMode::Forward => (self.duty * SUPPLY_V, 1.0),
            BridgeMode::Reverse => (-self.duty * SUPPLY_V, 1.0),
            BridgeMode::Brake => (0.0, self.duty),
            BridgeMode::Off => (0.0, 0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pins_select_the_mode() {
        assert_eq!(
            Bridge::from_pins(0.5, true, false).mode(),
            BridgeMode::Forward
        );
        assert_eq!(
            Bridge::from_pins(0.5, false, true).mode(),
            BridgeMode::Reverse
        );
        assert_eq!(
            Bridge::from_pins(0.5, false, false).mode(),
            BridgeMode::Brake
        );
        assert_eq!(Bridge::from_pins(0.5, true, true).mode(), BridgeMode::Brake);
        assert_eq!(Bridge::from_pins(0.0, true, false).mode(), BridgeMode::Off);
    }

    #[test]
    fn duty_is_clamped_and_nan_is_off() {
        assert_eq!(Bridge::forward(1.7).duty(), 1.0);
        assert_eq!(Bridge::forward(-0.2).mode(), BridgeMode::Off);
        assert_eq!(
            Bridge::from_pins(f64::NAN, true, false).mode(),
            BridgeMode::Off
        );
    }

    #[test]
    fn mean_voltage_follows_duty_and_direction() {
        assert_eq!(Bridge::forward(0.5).drive(), (6.0, 1.0));
        assert_eq!(Bridge::reverse(0.25).drive(), (-3.0, 1.0));
        assert_eq!(Bridge::signed(-0.25), Bridge::reverse(0.25));
        assert_eq!(Bridge::from_pins(0.4, false, false).drive(), (0.0, 0.4));
        assert_eq!(Bridge::off().drive(), (0.0, 0.0));
    }
}
