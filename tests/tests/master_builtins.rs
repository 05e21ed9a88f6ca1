//! Emulator test of the images' runtime routines (`drivers/src/runtime.rs`) through
//! `fixture_builtins`, which links them as the master does: 32-bit unsigned and signed
//! division with edge values, and `memcpy`/`memset` of lengths 0 to 32 (both sides of the
//! 16-byte mark) at four offsets, each checked against the host's own result.

use harness::Avr;

fn fixture() -> Avr {
    let mut avr = Avr::firmware("fixture_builtins")
        .unwrap_or_else(|e| panic!("fixture_builtins: {e} (build with scripts/firmware.sh)"));
    avr.uart_read_until(b"builtins ready\r\n", 50_000).unwrap();
    avr
}

fn request(avr: &mut Avr, op: u8, a: u32, b: u32, reply: usize) -> Vec<u8> {
    let mut req = vec![op];
    req.extend_from_slice(&a.to_le_bytes());
    req.extend_from_slice(&b.to_le_bytes());
    avr.uart_send(&req);
    avr.uart_read_exact(reply, 200_000).unwrap()
}

fn pair(bytes: &[u8]) -> (u32, u32) {
    let q = u32::from_le_bytes(bytes[..4].try_into().unwrap());
    let r = u32::from_le_bytes(bytes[4..].try_into().unwrap());
    (q, r)
}

#[test]
fn unsigned_division_matches_the_host_at_the_edges() {
    let mut avr = fixture();
    let values = [
        0,
        1,
        2,
        3,
        7,
        10,
        255,
        256,
        1000,
        65_535,
        65_536,
        0x7fff_ffff,
        0x8000_0000,
    ];
    let edges = [u32::MAX, u32::MAX - 1, 0x8000_0001, 123_456_789];
    for &n in values.iter().chain(&edges) {
        for &d in values.iter().chain(&edges).filter(|&&d| d != 0) {
            let got = pair(&request(&mut avr, 0, n, d, 8));
            assert_eq!(got, (n / d, n % d), "{n} / {d}");
        }
    }
}

#[test]
fn signed_division_truncates_toward_zero_like_the_host() {
    let mut avr = fixture();
    let values: [i32; 12] = [
        0,
        1,
        -1,
        2,
        -2,
        7,
        -7,
        1000,
        -65_536,
        i32::MAX,
        i32::MIN,
        i32::MIN + 1,
    ];
    for &n in &values {
        for &d in values
            .iter()
            .filter(|&&d| d != 0 && !(n == i32::MIN && d == -1))
        {
            let (q, r) = pair(&request(&mut avr, 1, n as u32, d as u32, 8));
            assert_eq!((q as i32, r as i32), (n / d, n % d), "{n} / {d}");
        }
    }
}

#[test]
fn memcpy_and_memset_touch_exactly_their_bytes() {
    let mut avr = fixture();
    for len in [0usize, 1, 2, 3, 15, 16, 31, 32] {
        for at in [0usize, 1, 7, 8] {
            let mut want = vec![0xeeu8; 40];
            for i in 0..len {
                want[at + i] = i as u8 + 1;
            }
            let got = request(&mut avr, 2, len as u32, at as u32, 40);
            assert_eq!(got, want, "memcpy of {len} at {at}");

            let mut want = vec![0xeeu8; 40];
            want[at..at + len].fill(0x5a);
            let got = request(&mut avr, 3, len as u32, (0x5a << 8) | at as u32, 40);
            assert_eq!(got, want, "memset of {len} at {at}");
        }
    }
}
