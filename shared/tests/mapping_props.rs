//! Properties of the value mapping over every mapped register of every board.

use proptest::prelude::*;
use shared::mapping::{full_scale, map, unmap};
use shared::regs::{BoardKind, Range, Register};

fn mapped() -> Vec<&'static Register> {
    [
        BoardKind::Master,
        BoardKind::DriveSteer,
        BoardKind::LiftLift,
    ]
    .iter()
    .flat_map(|k| k.table().iter())
    .filter(|r| r.range.is_some())
    .collect()
}

fn range(reg: &Register) -> Range {
    reg.range.unwrap()
}

fn any_mapped() -> impl Strategy<Value = &'static Register> {
    proptest::sample::select(mapped())
}

/// A register and a fraction in [0, 1] of its range.
fn reg_and_value() -> impl Strategy<Value = (&'static Register, f32)> {
    (any_mapped(), 0.0f32..=1.0).prop_map(|(r, t)| {
        let Range { min, max } = range(r);
        let v = (min + t * (max - min)).clamp(min, max);
        (r, v)
    })
}

#[test]
fn max_maps_to_full_scale_and_min_to_zero() {
    for r in mapped() {
        let Range { min, max } = range(r);
        assert_eq!(u32::from(map(max, r)), full_scale(r.size), "{}", r.name);
        assert_eq!(map(min, r), 0, "{}", r.name);
        assert_eq!(unmap(0, r), min, "{}", r.name);
        assert_eq!(unmap(full_scale(r.size) as u16, r), max, "{}", r.name);
    }
}

#[test]
fn symmetric_ranges_put_zero_at_half_scale_exactly() {
    let mut seen = 0;
    for r in mapped() {
        let Range { min, max } = range(r);
        if min != -max {
            continue;
        }
        seen += 1;
        let half: u16 = if r.size == 2 { 0x7fff } else { 0x7f };
        assert_eq!(map(0.0, r), half, "{}", r.name);
        assert_eq!(unmap(half, r), 0.0, "{}", r.name);
    }
    assert!(seen > 20, "only {seen} symmetric registers");
}

proptest! {
    #[test]
    fn round_trip_within_one_lsb((r, v) in reg_and_value()) {
        let Range { min, max } = range(r);
        let lsb = (max - min) / full_scale(r.size) as f32;
        let back = unmap(map(v, r), r);
        // Truncation loses less than one step; allow float rounding on top.
        let slack = lsb * 1e-3 + f32::EPSILON * max.abs().max(min.abs()) * 4.0;
        prop_assert!((v - back).abs() <= lsb + slack, "{} v={} back={} lsb={}", r.name, v, back, lsb);
    }

    #[test]
    fn map_clamps_outside_the_range(r in any_mapped(), beyond in 0.0f32..1.0e6) {
        let Range { min, max } = range(r);
        prop_assert_eq!(map(min - beyond, r), 0);
        prop_assert_eq!(u32::from(map(max + beyond, r)), full_scale(r.size));
    }

    #[test]
    fn map_is_monotonic(r in any_mapped(), a in -5000.0f32..5000.0, b in -5000.0f32..5000.0) {
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        prop_assert!(map(lo, r) <= map(hi, r), "{}: map({})={} > map({})={}", r.name, lo, map(lo, r), hi, map(hi, r));
    }

    #[test]
    fn raw_stays_within_full_scale(r in any_mapped(), v in proptest::num::f32::ANY) {
        prop_assert!(u32::from(map(v, r)) <= full_scale(r.size));
    }

    #[test]
    fn unmapped_registers_truncate(v in 0.0f32..65535.0, raw in any::<u16>()) {
        let reset = BoardKind::DriveSteer.register(0).unwrap();
        prop_assert_eq!(map(v, reset), v.trunc() as u16);
        prop_assert_eq!(unmap(raw, reset), f32::from(raw));
    }
}
