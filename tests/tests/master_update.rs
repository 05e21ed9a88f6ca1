//! The PC library's `Rover::update()` against the master in the emulator, with register
//! models at all nine slave addresses: read sets 0, 1 and 2 configured as the library
//! does (reference §4.3), then ten rounds of the ten update frames, timed in emulated
//! time while the master also pings, checks liveness and runs temperature ticks.

mod master_support;

use master_support::{Rig, BYTE_US};

/// The library's read-set frames: set 0 via each DS board, set 1 via each LL board,
/// set 2 via the master.
fn configure(rig: &mut Rig) {
    let set0 = [
        0x17, 0x04, 0x00, 0x01, 0x02, 0x03, 0x05, 0x2c, 0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16,
        0x17, 0x21, 0x22, 0x23, 0x24, 0x25, 0x26, 0x27,
    ];
    let set1 = [
        0x15, 0x04, 0x01, 0x01, 0x02, 0x03, 0x05, 0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x22,
        0x23, 0x24, 0x25, 0x26, 0x27, 0x28,
    ];
    let set2 = [0x0e, 0x04, 0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11];
    for pair in 0..3u8 {
        for (dev, frame) in [
            (3 * pair + 1, &set0[..]),
            (3 * pair + 2, &set0[..]),
            (3 * pair + 3, &set1[..]),
        ] {
            let mut f = frame.to_vec();
            f[1] = dev << 4 | 0x04;
            assert_eq!(rig.exchange(&f, 1), [(f.len() - 3) as u8]);
        }
    }
    assert_eq!(rig.exchange(&set2, 1), [0x0b]);
}

/// One update: the ten frames in the library's order, each with its reply length.
const UPDATE: [([u8; 3], usize); 10] = [
    ([0x03, 0x13, 0x00], 40),
    ([0x03, 0x23, 0x00], 40),
    ([0x03, 0x33, 0x01], 36),
    ([0x03, 0x43, 0x00], 40),
    ([0x03, 0x53, 0x00], 40),
    ([0x03, 0x63, 0x01], 36),
    ([0x03, 0x73, 0x00], 40),
    ([0x03, 0x83, 0x00], 40),
    ([0x03, 0x93, 0x01], 36),
    ([0x03, 0x03, 0x02], 22),
];

#[test]
fn ten_updates_run_at_wire_speed() {
    let mut rig = Rig::new();
    configure(&mut rig);
    // Steady state: pings, liveness checks and temperature ticks are all running.
    rig.run_to(6_000_000);
    let start = rig.micros();
    for _ in 0..10 {
        for (frame, n) in UPDATE {
            rig.bus.uart_send(0, &frame);
            let reply = rig.read_exact(n, 200_000);
            assert_eq!(reply.len(), n);
        }
    }
    let took = (rig.micros() - start) as f64;
    let bytes: usize = UPDATE.iter().map(|(f, n)| f.len() + n).sum();
    let wire = 10.0 * bytes as f64 * BYTE_US;
    let rate = 10.0 / (took / 1e6);
    println!(
        "10 updates: {took:.0} us, wire time {wire:.0} us, ratio {:.3}, {rate:.1} updates/s",
        took / wire
    );
    assert!(rate >= 25.0, "{rate} updates/s");
    assert!(took <= 1.07 * wire, "ratio {}", took / wire);
}
