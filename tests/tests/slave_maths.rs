//! Emulator test of the slave's arithmetic in AVR assembly (`shared::slave::divide`,
//! `shared::slave::product` and `shared::pid::sum`) through `fixture_slave_maths`: the
//! division at its edges and on pseudo-random operands, the 16×16→32 product, and the
//! PID's saturating `I16F16` product, sum, difference, magnitude, dead zone and clamp
//! on every pair of corner values and on pseudo-random operands of every width, the
//! monitoring values' mapping (`shared::slave::scale`) by nine scales, the current
//! filter's step on every input, the clock's count of whole ms, the speed meter's
//! saturating age on every gap at a dozen ages and the power-up writer
//! (`shared::slave::image::apply_from_flash`) over a sparse image, each checked against
//! the host's own arithmetic (written out here, or the host build's). The host builds of these
//! functions are plain Rust, so only this test shows the assembly right.

use harness::Avr;

fn fixture() -> Avr {
    let mut avr = Avr::firmware("fixture_slave_maths")
        .unwrap_or_else(|e| panic!("fixture_slave_maths: {e} (build with scripts/firmware.sh)"));
    avr.uart_read_until(b"maths ready\r\n", 50_000).unwrap();
    avr
}

fn request(avr: &mut Avr, op: u8, a: u32, b: u32) -> (u32, u32) {
    let mut req = vec![op];
    req.extend_from_slice(&a.to_le_bytes());
    req.extend_from_slice(&b.to_le_bytes());
    avr.uart_send(&req);
    let reply = avr.uart_read_exact(8, 200_000).unwrap();
    let word = |i: usize| u32::from_le_bytes([reply[i], reply[i + 1], reply[i + 2], reply[i + 3]]);
    (word(0), word(4))
}

/// A fixed xorshift sequence: the same operands on every run.
fn operands(n: usize) -> impl Iterator<Item = u32> {
    let mut x: u32 = 0x1234_5678;
    std::iter::repeat_with(move || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x
    })
    .take(n)
}

const EDGES: [u32; 13] = [
    0,
    1,
    2,
    3,
    999,
    1000,
    65_535,
    65_536,
    0x7fff_ffff,
    0x8000_0000,
    0x8000_0001,
    0xffff_fffe,
    u32::MAX,
];

#[test]
fn division_matches_the_host_at_the_edges_and_on_random_operands() {
    let mut avr = fixture();
    let mut cases = 0;
    for &n in &EDGES {
        for &d in &EDGES[1..] {
            assert_eq!(request(&mut avr, 0, n, d), (n / d, n % d), "{n} / {d}");
            cases += 1;
        }
    }
    // A zero divisor: every step subtracts 0 (no test for it in the routine).
    for &n in &EDGES {
        assert_eq!(request(&mut avr, 0, n, 0), (u32::MAX, n), "{n} / 0");
        cases += 1;
    }
    let values: Vec<u32> = operands(400).collect();
    for pair in values.chunks(2) {
        let n = pair[0];
        // Divisors of every width: 1..32 significant bits.
        let d = (pair[1] >> (pair[1] % 32)).max(1);
        assert_eq!(request(&mut avr, 0, n, d), (n / d, n % d), "{n} / {d}");
        cases += 1;
    }
    assert_eq!(cases, 13 * 12 + 13 + 200);
}

#[test]
fn product_matches_the_host_on_corners_and_random_operands() {
    let mut avr = fixture();
    let corners = [
        0u16, 1, 2, 0x00ff, 0x0100, 0x7fff, 0x8000, 0xff00, 0xfffe, 0xffff,
    ];
    for &a in &corners {
        for &b in &corners {
            let want = u32::from(a) * u32::from(b);
            assert_eq!(
                request(&mut avr, 1, a.into(), b.into()),
                (want, 0),
                "{a} * {b}"
            );
        }
    }
    for x in operands(300) {
        let (a, b) = (x as u16, (x >> 16) as u16);
        let want = u32::from(a) * u32::from(b);
        assert_eq!(
            request(&mut avr, 1, a.into(), b.into()),
            (want, 0),
            "{a} * {b}"
        );
    }
}

/// Signed corners: zero, ±1, the `I16F16` unit and its neighbours, the 16-bit boundary and
/// the `i32` limits.
const SIGNED: [i32; 15] = [
    0,
    1,
    -1,
    0xffff,
    0x1_0000,
    -0x1_0000,
    0x1_0001,
    0x7fff_0000,
    0x8000,
    -0x8000,
    0x00b5_0000,
    i32::MAX,
    i32::MIN,
    i32::MIN + 1,
    i32::MAX - 1,
];

/// Pseudo-random signed operands of every width (1..32 significant bits, both signs).
fn signed_operands(n: usize) -> impl Iterator<Item = i32> {
    operands(n).map(|x| ((x >> (x % 32)) as i32).wrapping_mul(if x & 1 == 0 { 1 } else { -1 }))
}

/// Every pair of corners, then `random` pseudo-random pairs, through `op` on the chip,
/// against `want` on the host; returns how many pairs were checked.
fn check_pairs(op: u8, random: usize, want: impl Fn(i32, i32) -> Option<i32>) -> usize {
    let mut avr = fixture();
    let mut pairs: Vec<(i32, i32)> = SIGNED
        .iter()
        .flat_map(|&a| SIGNED.iter().map(move |&b| (a, b)))
        .collect();
    let random: Vec<i32> = signed_operands(2 * random).collect();
    pairs.extend(random.chunks(2).map(|p| (p[0], p[1])));
    let mut checked = 0;
    for (a, b) in pairs {
        let Some(expected) = want(a, b) else { continue };
        let got = request(&mut avr, op, a as u32, b as u32);
        assert_eq!(got, (expected as u32, 0), "op {op}: a {a:#x}, b {b:#x}");
        checked += 1;
    }
    checked
}

#[test]
fn fixed_product_truncates_toward_zero_and_saturates_as_the_host_does() {
    let checked = check_pairs(2, 400, |a, b| {
        // The exact product in 64 bits, ÷ 2^16 toward zero, then the i32 limits.
        let exact = i64::from(a) * i64::from(b) / 65_536;
        Some(exact.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
    });
    assert_eq!(checked, 15 * 15 + 400);
}

/// The product's short form (both magnitudes below 2^24, their top bytes 0: 9 byte
/// products instead of 16) and its edges: the largest operands, the boundary of the
/// saturation (181.0193…², 2^31 − 1 and 2^31 bits of result), one top byte 0 and the
/// other not, then pseudo-random operands of 1..24 significant bits.
#[test]
fn fixed_product_short_form_matches_the_host() {
    let mut avr = fixture();
    let edges = [
        0x00ff_ffff,
        0x00ff_fffe,
        0x0080_0000,
        0x00b5_04f3,
        0x00b5_04f4,
        0x00b5_0000,
        0x0001_0000,
        0x0000_0001,
        0x0100_0000,
        0x0000_ffff,
    ];
    let edges: Vec<i32> = edges.iter().flat_map(|&x: &i32| [x, -x]).collect();
    let mut pairs: Vec<(i32, i32)> = edges
        .iter()
        .flat_map(|&a| edges.iter().map(move |&b| (a, b)))
        .collect();
    let random: Vec<i32> = operands(600)
        .map(|x| {
            let bits = (x >> (8 + x % 24)) as i32 & 0x00ff_ffff;
            if x & 1 == 0 {
                bits
            } else {
                -bits
            }
        })
        .collect();
    pairs.extend(random.chunks(2).map(|p| (p[0], p[1])));
    let (mut short, mut saturated) = (0, 0);
    for &(a, b) in &pairs {
        let exact = i64::from(a) * i64::from(b) / 65_536;
        let want = exact.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32;
        let got = request(&mut avr, 2, a as u32, b as u32);
        assert_eq!(got, (want as u32, 0), "a {a:#x}, b {b:#x}");
        if a.unsigned_abs() < 1 << 24 && b.unsigned_abs() < 1 << 24 && a != 0 && b != 0 {
            short += 1;
            saturated += usize::from(i64::from(want) != exact);
        }
    }
    assert_eq!(pairs.len(), 400 + 300);
    // Both forms are reached, and the short form's saturation too.
    assert!(short > 500 && short < pairs.len(), "{short}");
    assert!(saturated >= 20, "{saturated}");
}

#[test]
fn saturating_sum_and_difference_match_the_host() {
    assert_eq!(check_pairs(3, 300, |a, b| Some(a.saturating_add(b))), 525);
    assert_eq!(check_pairs(4, 300, |a, b| Some(a.saturating_sub(b))), 525);
}

#[test]
fn magnitude_dead_zone_and_clamp_match_the_host() {
    assert_eq!(
        check_pairs(5, 100, |a, _| Some(a.unsigned_abs() as i32)),
        325
    );
    let dead_zone = |a: i32, b: i32| Some(if a.unsigned_abs() < b as u32 { 0 } else { a });
    assert_eq!(check_pairs(6, 300, dead_zone), 525);
    // The clamp is defined for cap ≥ 0 only: about half of the pairs.
    let clamp = |a: i32, b: i32| (b >= 0).then(|| a.clamp(-b, b));
    let checked = check_pairs(7, 300, clamp);
    assert!(checked > 250, "only {checked} pairs with a cap ≥ 0");
}

/// The fixture's op 8 scales, in its order (`MAPPINGS` in `fixture_slave_maths`).
const MAPPED: [u8; 9] = [
    shared::regs::id::REGDS_DRIVE_ACTUALSPEED,
    shared::regs::id::REGDS_DRIVE_ERROR,
    shared::regs::id::REGDS_STEER_ACTUALPOS,
    shared::regs::id::REGDS_DRIVE_CONTROL,
    shared::regs::id::REGDS_DRIVE_INTERVALCTRL,
    shared::regs::id::REGDS_CHASSIS,
    shared::regs::id::REGDS_STEER_CALIBMIN,
    shared::regs::id::REGDS_DRIVE_DEADZONE,
    shared::regs::id::REGDS_DRIVE_STALLCHECK,
];

#[test]
fn monitoring_map_matches_the_host_at_the_clamps_and_on_random_values() {
    use shared::pid::Fix;
    use shared::slave::scale::Scale;
    let mut avr = fixture();
    let random: Vec<i32> = signed_operands(120).collect();
    let mut checked = 0;
    let mut inside = 0;
    for (index, &id) in MAPPED.iter().enumerate() {
        let scale = Scale::of(&shared::regs::DS, id);
        let range = shared::regs::DS[usize::from(id)].range.unwrap();
        let (a, b) = ((range.min as i32) << 16, (range.max as i32) << 16);
        // Each end and one bit either side of it, the middle, whole values near the
        // ends, every corner, then the random values (most beyond the small ranges:
        // scaled into the range too).
        let mut values = vec![a - 1, a, a + 1, b - 1, b, b + 1, (a + b) / 2, a + 0x1_0000];
        values.extend([b - 0x1_0000, b - 0x8000, a + 0xffff]);
        values.extend(SIGNED.iter().copied());
        for &x in &random {
            values.push(x);
            values.push(a.wrapping_add((x as u32 % (b - a) as u32) as i32));
        }
        for v in values {
            let want = scale.map(Fix::from_bits(v));
            let got = request(&mut avr, 8, v as u32, index as u32);
            assert_eq!(got, (u32::from(want), 0), "register {id}: {v:#x}");
            checked += 1;
            inside += usize::from(want != 0 && want != 65_534 && want != 254);
        }
    }
    assert_eq!(checked, 9 * (11 + SIGNED.len() + 240));
    assert!(inside > 9 * 150, "{inside} values inside the ranges");
}

#[test]
fn current_filter_step_matches_the_formula_on_every_input() {
    // Every sample byte c and every raw value f (2^24 steps): the chip's results, in
    // order, hashed and summed there, against the host's formula. The hash changes with
    // any single wrong result (each step of it is a bijection).
    let mut avr = fixture();
    let mut reached = [0usize; 2];
    for c in 0..=u8::MAX {
        avr.uart_send(&[10, c, 0, 0, 0, 0, 0, 0, 0]);
        let reply = avr.uart_read_exact(8, 30_000_000).unwrap();
        let word =
            |i: usize| u32::from_le_bytes([reply[i], reply[i + 1], reply[i + 2], reply[i + 3]]);
        let (mut hash, mut sum) = (0u32, 0u32);
        let q = u32::from(c) << 8;
        for f in 0..=u32::from(u16::MAX) {
            let rising = q > f;
            let p = if rising { 25 } else { 2 };
            let want = (256 - p) * f / 256 + q * p / 256;
            hash = hash.rotate_left(5) ^ want;
            sum = sum.wrapping_add(want);
            reached[usize::from(rising)] += 1;
        }
        assert_eq!((word(0), word(4)), (hash, sum), "sample {c}: hash, sum");
    }
    // Both branches, each on more than a quarter of the inputs.
    assert_eq!(reached[0] + reached[1], 1 << 24);
    assert!(reached[0] > 1 << 22 && reached[1] > 1 << 22, "{reached:?}");
}

#[test]
fn clock_count_of_whole_ms_matches_the_host() {
    // Gaps at and around each distance to the next ms, around whole ms and 2^16, a
    // pseudo-random set below 2^22 µs and the longest; ms counts at 0, at a 16-bit
    // carry and at the 32-bit wrap.
    use shared::slave::clock::count_ms;
    let mut avr = fixture();
    let mut cases = 0;
    let mut wrapped = 0;
    for to_next in [1u16, 2, 500, 999, 1000] {
        let t = u32::from(to_next);
        let mut gaps = vec![0, 1, t - 1, t, t + 1, 999, 1000, 1001, 1999, 2000, 2001];
        gaps.extend([65_535, 65_536, 123_456, (1 << 20) + 7]);
        gaps.extend(operands(12).map(|x| x >> 10));
        for gap in gaps {
            for high in [0u32, 1, 0x1234, 0xffff] {
                let ms = high * 0x1_0001;
                let (want_next, want_ms) = count_ms(gap, to_next, ms);
                let got = request(&mut avr, 9, gap, high << 16 | t);
                assert_eq!(
                    got,
                    (u32::from(want_next), want_ms),
                    "{gap} µs, {to_next}, {ms}"
                );
                cases += 1;
                wrapped += usize::from(want_ms < ms);
            }
        }
    }
    // The longest gap: 4,294,968 passes.
    avr.uart_send(&[9, 0xff, 0xff, 0xff, 0xff, 0x01, 0, 0, 0]);
    let reply = avr.uart_read_exact(8, 20_000_000).unwrap();
    let word = |i: usize| u32::from_le_bytes([reply[i], reply[i + 1], reply[i + 2], reply[i + 3]]);
    let (want_next, want_ms) = count_ms(u32::MAX, 1, 0);
    assert_eq!((word(0), word(4)), (u32::from(want_next), want_ms));
    assert_eq!((want_next, want_ms), (706, 4_294_968));
    assert_eq!(cases, 5 * 27 * 4);
    assert!(wrapped > 50, "{wrapped}");
}

#[test]
fn the_saturating_age_matches_the_host_for_every_gap() {
    // Every gap at ages from 0 to the largest: op 11 hashes the 65,536 results in order.
    let mut avr = fixture();
    let mut saturated = 0;
    let ages = [
        0u16,
        1,
        2,
        249,
        2_500,
        0x7fff,
        0x8000,
        37_501,
        0xfffe,
        u16::MAX,
    ];
    for age in ages.into_iter().chain(operands(4).map(|x| x as u16)) {
        let (mut hash, mut sum) = (0u32, 0u32);
        for gap in 0..=u16::MAX {
            let want = age.saturating_add(gap);
            hash = hash.rotate_left(5) ^ u32::from(want);
            sum = sum.wrapping_add(u32::from(want));
            saturated += usize::from(want == u16::MAX);
        }
        let reply = {
            let mut req = vec![11u8];
            req.extend_from_slice(&u32::from(age).to_le_bytes());
            req.extend_from_slice(&[0; 4]);
            avr.uart_send(&req);
            avr.uart_read_exact(8, 50_000_000).unwrap()
        };
        let word =
            |i: usize| u32::from_le_bytes([reply[i], reply[i + 1], reply[i + 2], reply[i + 3]]);
        assert_eq!((word(0), word(4)), (hash, sum), "age {age}");
    }
    assert!(saturated > 200_000, "{saturated}");
}

/// The fixture's op-20 image, byte `i` (as `fixture_slave_maths` has it).
fn sample_byte(i: usize) -> u8 {
    if (i < 120 && i.is_multiple_of(3)) || i == 400 || i == 599 {
        (i * 37 % 255 + 1) as u8
    } else {
        0
    }
}

#[test]
fn power_up_writer_matches_the_host_over_a_sparse_image() {
    use shared::slave::image::{apply, Image};
    let want: Vec<u8> = (0..600).map(sample_byte).collect();
    let image = Image::<600>::ZERO.bytes_at(0, &want);
    let mut pairs = vec![[0u8; 2]; image.len()];
    image.fill(&mut pairs);
    // 40 + 2 bytes, and one pair that stores a zero on the way to byte 400.
    assert_eq!(pairs.len(), 43);
    assert_eq!(pairs[0], [0, 1]);
    assert_eq!(pairs[40], [255, 0]);
    let mut host = vec![0u8; 600];
    apply(&pairs, &mut host);
    assert_eq!(host, want);
    let mut avr = fixture();
    let mut got = Vec::new();
    for at in (0..600).step_by(8) {
        let (x, y) = request(&mut avr, 20, at, 0);
        got.extend(x.to_le_bytes());
        got.extend(y.to_le_bytes());
    }
    assert_eq!(got, want);
}
