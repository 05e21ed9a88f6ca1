//! Register values to fixed point and back, without floats or fixed-point division.
//!
//! A mapped register with range [a, b] and size n stands for raw·(b − a)/F + a, with
//! F = 65534 (2 bytes) or 254 (1 byte) (reference §3). Every range in the tables has
//! integer ends, so a [`Scale`] holds them as integers, taken from the generated table
//! when the crate is compiled: no second copy, and no float at run time.
//!
//! - [`Scale::unmap`] is exact (the true value, truncated to 1/65536) using two `u32`
//!   divisions; it runs only when a register is written.
//! - [`Scale::unmap_int`] truncates to an integer, as the original does for thresholds
//!   (the integer part of `unmap`'s result); it equals the original's float32 result for
//!   every raw value (tested exhaustively).
//! - [`Scale::map`] (value → raw, clamped) runs for every monitoring value, so it uses a
//!   reciprocal computed at compile time and four 16×16-bit products; on the AVR one
//!   routine in assembly (12 byte products, 144 B where the Rust took 262 B), checked on
//!   the chip against the host's form (`slave_maths`).
//!
//! A range must span less than 2^15 (the span's top bit marks a one-byte register:
//! [`Scale::of`] fails to compile otherwise); the widest in the tables is 8000.
//!
//! The crate denies `unsafe`; this module allows it for the AVR's mapping routine in
//! assembly, as [`super::product`] does.
#![allow(unsafe_code)]

use super::divide::div_rem;
use super::product::wide;
#[cfg(target_arch = "avr")]
use super::words::halves;
use crate::pid::Fix;
use crate::regs::Register;

/// An integer mapping range and register size. Small and `Copy`: its methods are
/// inlined wrappers, so a constant scale reaches the arithmetic as immediate operands,
/// not as a table in RAM.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Scale {
    /// a, the value of raw 0.
    min: i16,
    /// b − a.
    span: u16,
    /// F: 65534 or 254.
    full: u16,
    /// ⌈F·65536 / (b − a)⌉, for [`Scale::map`].
    reciprocal: u32,
}

/// What [`Scale::unmap`] reads of a [`Scale`], in 4 bytes on the AVR: the entry type
/// of a table of scales chosen at run time, which costs less code than choosing the
/// constants by a `match` (each arm loads its own immediates); 4 bytes, so an entry's
/// offset is two shifts, not a product.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Unmapping {
    /// a, the value of raw 0.
    min: i16,
    /// b − a (below 2^15: [`Scale::of`] checks), with [`ONE_BYTE`] set for a one-byte
    /// register (F = 254; else 65534).
    span: u16,
}

/// [`Unmapping`]'s mark of a one-byte register in its span's free top bit.
const ONE_BYTE: u16 = 0x8000;

impl Unmapping {
    /// [`Scale::unmap`] of the scale this came from.
    #[inline(always)]
    pub fn unmap(self, raw: u16) -> Fix {
        let full = if self.span & ONE_BYTE != 0 {
            254
        } else {
            65_534
        };
        unmap(raw, self.min, self.span & !ONE_BYTE, full)
    }
}

/// What [`Scale::map`] reads of a [`Scale`], as a `static` for the firmware: the one
/// mapping routine then takes a pointer to it (one register pair) where each call would
/// load seven bytes of immediates.
///
/// Only for a scale whose reciprocal is below 2^24 (a two-byte register's range
/// spanning 256 or more, or any one-byte register's: every monitoring register and
/// CHASSIS), held in 3 bytes: [`Scale::mapping`] fails to compile otherwise, and the
/// AVR's routine multiplies by three bytes, not four.
///
/// `repr(C)`: the AVR's mapping routine reads the fields at fixed offsets (0, 2, 3, 5).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(C)]
pub struct Mapping {
    /// ⌈F·65536 / (b − a)⌉'s low 16 bits.
    reciprocal_low: u16,
    /// ⌈F·65536 / (b − a)⌉'s top 8 bits (bits 16..23).
    reciprocal_high: u8,
    /// a, the value of raw 0.
    min: i16,
    /// b − a.
    span: u16,
}

// The AVR routine's offsets (every field 1-aligned there).
#[cfg(target_arch = "avr")]
const _: () = {
    use core::mem::{offset_of, size_of};
    assert!(offset_of!(Mapping, reciprocal_low) == 0 && offset_of!(Mapping, reciprocal_high) == 2);
    assert!(offset_of!(Mapping, min) == 3 && offset_of!(Mapping, span) == 5);
    assert!(size_of::<Mapping>() == 7);
};

impl Mapping {
    /// [`Scale::map`] of the scale this came from.
    #[inline(always)]
    pub fn map(&self, value: Fix) -> u16 {
        map(value, self)
    }

    /// [`Scale::map_int`] of the scale this came from.
    #[inline(always)]
    pub fn map_int(&self, value: u16) -> u16 {
        self.map(Fix::from_bits(i32::from(value) << 16))
    }
}

impl Scale {
    /// The part of the scale [`Scale::map`] uses, for a `static`. Panics (fails to
    /// compile, in a `static`) unless the reciprocal is below 2^24 (see [`Mapping`]).
    pub const fn mapping(self) -> Mapping {
        assert!(
            self.reciprocal < 1 << 24,
            "a reciprocal of more than 3 bytes"
        );
        Mapping {
            reciprocal_low: self.reciprocal as u16,
            reciprocal_high: (self.reciprocal >> 16) as u8,
            min: self.min,
            span: self.span,
        }
    }

    /// Whether `other` maps every value to the same raw value ([`Scale::map`]): the same
    /// [`Mapping`]. For compile-time checks of a shared `static`.
    pub const fn maps_as(self, other: Scale) -> bool {
        self.min == other.min && self.span == other.span && self.reciprocal == other.reciprocal
    }

    /// The part of the scale [`Scale::unmap`] uses, for a table.
    pub const fn unmapping(self) -> Unmapping {
        Unmapping {
            min: self.min,
            span: self.span | if self.full == 254 { ONE_BYTE } else { 0 },
        }
    }

    /// The scale of register `id` of `table`, evaluated at compile time. Fails to compile
    /// (a const panic) if the register is unmapped or its range has ends that are not
    /// integers within ±32767.
    pub const fn of(table: &[Register], id: u8) -> Scale {
        let reg = &table[id as usize];
        let Some(range) = reg.range else {
            panic!("register is unmapped");
        };
        let min = range.min as i32;
        let max = range.max as i32;
        assert!(min as f32 == range.min && max as f32 == range.max && min < max);
        assert!(min >= -32767 && max <= 32767 && max - min < ONE_BYTE as i32);
        let full: u32 = if reg.size == 1 { 254 } else { 65534 };
        let span = (max - min) as u32;
        let reciprocal = ((full as u64) << 16).div_ceil(span as u64);
        Scale {
            min: min as i16,
            span: span as u16,
            full: full as u16,
            reciprocal: reciprocal as u32,
        }
    }

    /// The value a raw register holds: raw·(b − a)/F + a, truncated toward −∞ to 1/65536.
    #[inline(always)]
    pub fn unmap(self, raw: u16) -> Fix {
        unmap(raw, self.min, self.span, self.full)
    }

    /// The value a raw register holds, truncated toward zero to an integer (as the
    /// original does for OVERCURRENTTHRESH and STALLCHECK). Only for ranges starting at
    /// 0, which all integer parameters have: then it is [`Scale::unmap`]'s integer part,
    /// ⌊raw·(b − a)/F⌋, the quotient of the same division (no second routine).
    #[inline(always)]
    pub fn unmap_int(self, raw: u16) -> u16 {
        Scale::whole(self.unmap(raw))
    }

    /// The integer part of a non-negative [`Scale::unmap`] result of a range from 0
    /// (below 2^16): what [`Scale::unmap_int`] gives for the same raw value.
    #[inline(always)]
    pub fn whole(value: Fix) -> u16 {
        (value.to_bits() >> 16) as u16
    }

    /// The raw value for `value`: trunc((clamp(v, a, b) − a)·F/(b − a)). Within one count
    /// of the exact result, and exact at the ends and wherever the exact result is a whole
    /// number (0 ↔ 0x7fff in symmetric ranges).
    #[inline(always)]
    pub fn map(self, value: Fix) -> u16 {
        map_wide(value, self.min, self.span, self.reciprocal)
    }

    /// The raw value for an integer (e.g. an ADC reading), as [`Scale::map`].
    #[inline(always)]
    pub fn map_int(self, value: u16) -> u16 {
        self.map(Fix::from_bits(i32::from(value) << 16))
    }
}

/// In line: the firmware unmaps in one place, [`super::motor::Params::set`] (58 B and
/// 24 B smaller in the two images than a call).
#[inline(always)]
fn unmap(raw: u16, min: i16, span: u16, full: u16) -> Fix {
    // `max(1)` proves the divisor is not zero (F is 254 or 65534).
    let full = u32::from(full.max(1));
    // raw·span ≤ 65535·65535 < 2^32; the result is at most 65535·span/full ≤ span + 1.
    // A 16×16-bit product: the AVR's 32-bit multiplication is a library routine.
    let product = wide(raw, span);
    let (whole, rem) = div_rem(product, full);
    let fraction = div_rem(rem << 16, full).0;
    let bits = (whole << 16 | fraction) as i32;
    Fix::from_bits(bits.wrapping_add(i32::from(min) << 16))
}

/// On the AVR: one routine in assembly on the operands where the calling convention
/// has them (the value's bits in r25..r22, the mapping's address in r21:r20, the raw
/// value returned in r25:r24), using only registers a call may clobber, so it saves
/// none. The clamp works on the value's high half h (the integer part, ⌊v⌋): v < a
/// exactly when h < a (a's fraction bits are 0), and the offset's whole part is h − a,
/// clamped to the span with the fraction cleared when h − a ≥ b − a. Then bytes 4 and 5
/// of the 48-bit product of the offset o (f0, f1, w0, w1) and the 3-byte reciprocal r
/// (r0..r2), column by column (the bytes o_i·r_j with i + j = k) into three rotating
/// bytes as in [`super::product::fixed`]; bytes 0..3 only carry, a carry into byte 6 is
/// dropped (o·r < 2^48: the raw value is below 2^16). 12 products; [`map`] in Rust took
/// 262 B.
#[cfg(target_arch = "avr")]
#[inline(never)]
fn map(value: Fix, mapping: &Mapping) -> u16 {
    let (low, high) = halves(value.to_bits() as u32);
    let raw: u16;
    // SAFETY: reads the 7 bytes of `*mapping` (a valid reference) and otherwise only
    // registers: the operands and clobbers named here, r0 (the scratch register) and
    // r1 (the zero register, which `mul` overwrites and which is cleared again before
    // the block ends, as the AVR ABI requires); SREG is not preserved.
    unsafe {
        core::arch::asm!(
            // a (min) into X, b − a (span) into r19:r18.
            "ldd r26, Z+3",
            "ldd r27, Z+4",
            "ldd r18, Z+5",
            "ldd r19, Z+6",
            // h < a: the offset 0 (h := a, the fraction 0).
            "cp r24, r26",
            "cpc r25, r27",
            "brge 0f",
            "movw r24, r26",
            "clr r22",
            "clr r23",
            // w = h − a; w ≥ b − a: the span, the fraction 0.
            "0: sub r24, r26",
            "sbc r25, r27",
            "cp r24, r18",
            "cpc r25, r19",
            "brlo 1f",
            "movw r24, r18",
            "clr r22",
            "clr r23",
            // The reciprocal r0..r2 into r18..r20; then Z is free.
            "1: ldd r18, Z+0",
            "ldd r19, Z+1",
            "ldd r20, Z+2",
            "clr r31",
            // Column 0: f0·r0, only its carry (into r26 for column 1).
            "mul r22, r18",
            "mov r26, r1",
            "clr r27",
            "clr r30",
            // Column 1 into r26, r27, r30: f0·r1, f1·r0.
            "mul r22, r19",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            "mul r23, r18",
            "add r26, r0",
            "adc r27, r1",
            "adc r30, r31",
            // Column 2 into r27, r30, r26: f0·r2, f1·r1, w0·r0.
            "clr r26",
            "mul r22, r20",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            "mul r23, r19",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            "mul r24, r18",
            "add r27, r0",
            "adc r30, r1",
            "adc r26, r31",
            // Column 3 into r30, r26, r27: f1·r2, w0·r1, w1·r0.
            "clr r27",
            "mul r23, r20",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            "mul r24, r19",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            "mul r25, r18",
            "add r30, r0",
            "adc r26, r1",
            "adc r27, r31",
            // Column 4 into r26, r27 (byte 4, the raw value's low byte): w0·r2, w1·r1.
            "mul r24, r20",
            "add r26, r0",
            "adc r27, r1",
            "mul r25, r19",
            "add r26, r0",
            "adc r27, r1",
            // Column 5 into r27 (byte 5, the high byte): w1·r2.
            "mul r25, r20",
            "add r27, r0",
            "clr r1",
            "movw r24, r26",
            inout("r23r22") low => _,
            inout("r25r24") high => raw,
            inout("Z") mapping as *const Mapping => _,
            out("r19r18") _,
            out("r20") _,
            out("X") _,
            options(pure, readonly, nostack),
        );
    }
    raw
}

/// [`Mapping::map`] on the host: [`map_wide`], the reference the chip's routine is
/// checked against.
#[cfg(not(target_arch = "avr"))]
#[inline(never)]
fn map(value: Fix, mapping: &Mapping) -> u16 {
    let reciprocal = u32::from(mapping.reciprocal_high) << 16 | u32::from(mapping.reciprocal_low);
    map_wide(value, mapping.min, mapping.span, reciprocal)
}

/// [`Scale::map`] of any scale: the clamp, then ⌊offset·r/2^32⌋ by four 16×16-bit
/// products. (Out of line: on the AVR only a scale that has no [`Mapping`] would use it.)
#[inline(never)]
fn map_wide(value: Fix, min: i16, span: u16, reciprocal: u32) -> u16 {
    // |a|, |b| ≤ 32767, so a and b fit an I16F16's bits.
    let min = i32::from(min) << 16;
    let max = min.wrapping_add(i32::from(span) << 16);
    let clamped = value.to_bits().max(min).min(max);
    // 0 ≤ offset ≤ span·65536 < 2^32.
    let offset = clamped.wrapping_sub(min) as u32;
    let whole = (offset >> 16) as u16;
    let fraction = offset as u16;
    let (r_high, r_low) = ((reciprocal >> 16) as u16, reciprocal as u16);
    // whole·r ≤ F·65536 + span < 2^32, and the fraction terms add less than r. Four
    // 16×16-bit products (see [`wide`]) instead of three 32-bit ones.
    let scaled = (wide(whole, r_high) << 16)
        .wrapping_add(wide(whole, r_low))
        .wrapping_add(wide(fraction, r_high))
        .wrapping_add(wide(fraction, r_low) >> 16);
    u16::try_from(scaled >> 16).unwrap_or(u16::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::regs::{id, DS};

    #[test]
    fn mappings_hold_their_scales_3_byte_reciprocals() {
        // The mapping itself is the scale's arithmetic on the host: the AVR routine is
        // checked against it on the chip (`tests/tests/slave_maths.rs`, op 8).
        let ids = [
            id::REGDS_DRIVE_ACTUALSPEED,
            id::REGDS_STEER_ACTUALPOS,
            id::REGDS_DRIVE_CONTROL,
            id::REGDS_CHASSIS,
            id::REGDS_STEER_CALIBMIN,
        ];
        for id in ids {
            let scale = Scale::of(&DS, id);
            let mapping = scale.mapping();
            let r = u32::from(mapping.reciprocal_high) << 16 | u32::from(mapping.reciprocal_low);
            assert_eq!(r, scale.reciprocal, "{id}");
        }
        // ±200's is the largest a mapped register has: 24 bits.
        assert!(Scale::of(&DS, id::REGDS_STEER_ACTUALPOS).reciprocal >= 1 << 23);
    }

    #[test]
    fn a_monitoring_value_is_within_one_count_of_the_originals_float32() {
        // docs/protocol.md ("How the slaves compute"): the slave unmaps a demand and maps
        // a monitoring value in fixed point, the original in float32. Over every raw
        // REQSPEED, the error of a held wheel (demand − 0) read back through ERROR.
        let (req, err) = (id::REGDS_DRIVE_REQSPEED, id::REGDS_DRIVE_ERROR);
        let (req_reg, err_reg) = (&DS[usize::from(req)], &DS[usize::from(err)]);
        let (req_scale, err_scale) = (Scale::of(&DS, req), Scale::of(&DS, err));
        let mut differ = 0;
        for raw in 0..=65534u16 {
            let here = err_scale.map(req_scale.unmap(raw));
            let original = crate::mapping::map(crate::mapping::unmap(raw, req_reg), err_reg);
            assert!(
                here.abs_diff(original) <= 1,
                "{raw:#06x}: {here} {original}"
            );
            differ += usize::from(here != original);
        }
        assert!(differ > 0, "the fixed point is not float32");
        // The example the docs give: a demand of 1000 (0x9ffe) on a held wheel.
        let here = err_scale.map(req_scale.unmap(0x9ffe));
        let original = crate::mapping::map(crate::mapping::unmap(0x9ffe, req_reg), err_reg);
        assert_eq!((here, original), (0xfffb, 0xfffa));
    }

    #[test]
    #[should_panic(expected = "a reciprocal of more than 3 bytes")]
    fn a_scale_spanning_less_than_256_has_no_mapping() {
        // INTEGRALDECAY spans 0..1: its reciprocal needs 32 bits.
        let _ = Scale::of(&DS, id::REGDS_DRIVE_INTEGRALDECAY).mapping();
    }
}
