//! Value mapping between engineering values and raw register values.
//!
//! A mapped register with range [a, b] and size n carries
//! raw = trunc(((clamp(v, a, b) - a) * F) / (b - a)), F = 2^(8n) - 2, and unmaps as
//! ((raw * (b - a)) / F) + a. All arithmetic is `f32`, step by step in that order, so
//! the results match the original PC library and firmware bit for bit. An unmapped
//! register carries trunc(v) as an integer.

use crate::regs::{Range, Register, Shape};

/// F for a register size: 65534 for 2 bytes, 254 for 1 byte (any other size is treated
/// as 2 bytes).
pub fn full_scale(size: u8) -> u32 {
    if size == 1 {
        254
    } else {
        65534
    }
}

/// Maps a value onto a register's raw value (clamping to the range first).
pub fn map(value: f32, reg: &Register) -> u16 {
    map_shape(value, &reg.shape())
}

/// Unmaps a raw value into the value it stands for.
pub fn unmap(raw: u16, reg: &Register) -> f32 {
    unmap_shape(raw, &reg.shape())
}

/// The original PC library's check before a write: a ≤ v ≤ b for a mapped register,
/// 0 ≤ v ≤ 65535 for an unmapped one. NaN is never in range.
pub fn in_range(value: f32, reg: &Register) -> bool {
    in_range_shape(value, &reg.shape())
}

/// [`map`] for a compact [`Shape`].
pub fn map_shape(value: f32, shape: &Shape) -> u16 {
    match shape.range {
        // `as` truncates toward zero and saturates (NaN gives 0).
        None => value as u16,
        Some(Range { min, max }) => {
            let clamped = if value < min {
                min
            } else if value > max {
                max
            } else {
                value
            };
            let f = full_scale(shape.size) as f32;
            (((clamped - min) * f) / (max - min)) as u16
        }
    }
}

/// [`unmap`] for a compact [`Shape`].
pub fn unmap_shape(raw: u16, shape: &Shape) -> f32 {
    match shape.range {
        None => f32::from(raw),
        Some(Range { min, max }) => {
            let f = full_scale(shape.size) as f32;
            ((f32::from(raw) * (max - min)) / f) + min
        }
    }
}

/// [`in_range`] for a compact [`Shape`].
pub fn in_range_shape(value: f32, shape: &Shape) -> bool {
    match shape.range {
        None => (0.0..=65535.0).contains(&value),
        Some(Range { min, max }) => (min..=max).contains(&value),
    }
}
