//! Emulator test of the slave's arithmetic in AVR assembly (`shared::slave::divide` and
//! `shared::slave::product`) through `fixture_slave_maths`: the division at its edges and
//! on pseudo-random operands, and the 16×16→32 product on every corner and on
//! pseudo-random operands, each checked against the host's own arithmetic. The host
//! builds of both functions are plain Rust, so only this test shows the assembly right.

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
    let values: Vec<u32> = operands(400).collect();
    for pair in values.chunks(2) {
        let n = pair[0];
        // Divisors of every width: 1..32 significant bits.
        let d = (pair[1] >> (pair[1] % 32)).max(1);
        assert_eq!(request(&mut avr, 0, n, d), (n / d, n % d), "{n} / {d}");
        cases += 1;
    }
    assert_eq!(cases, 13 * 12 + 200);
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
