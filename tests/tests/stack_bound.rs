//! Each firmware image's static RAM plus a static bound on its stack
//! (`rover_tests::stack_bound`), against the goal: the original firmware's static RAM
//! alone. The emulator tests' painted high-water marks (`slave_bench`, `master_memory`)
//! show what one run reached, and are checked against the same bound there.
//!
use harness::firmware_path;
use rover_tests::stack_bound::{Bound, Program};

fn bound_of(image: &str) -> (u32, Bound) {
    let program = Program::of_elf(&firmware_path(image)).expect("the image's disassembly");
    let bound = program.bound().expect("a static stack bound");
    let statics = program.static_ram().expect("static RAM");
    let deepest: Vec<String> = bound
        .levels
        .iter()
        .map(|(level, task, bytes)| format!("level {level} {task} {bytes} B"))
        .collect();
    println!(
        "{image}: static RAM {statics} B + stack bound {} B = {} B (main {} B, {}; \
         init alone {} B)",
        bound.total,
        statics + bound.total,
        bound.main,
        deepest.join(", "),
        bound.main_with_init
    );
    (statics, bound)
}

#[test]
fn drive_steer_static_ram_plus_its_stack_bound_stays_below_the_originals_static_ram() {
    let (statics, bound) = bound_of("slave-drive");
    // The control tick, the deepest task, is what the bound is mostly made of.
    assert_eq!(bound.levels[0].0, 1);
    assert!(bound.levels[0].2 > bound.levels[1].2 + bound.levels[2].2);
    assert!(statics + bound.total < 986, "{statics} + {bound:?}");
}

#[test]
fn lift_lift_static_ram_plus_its_stack_bound_stays_below_the_originals_static_ram() {
    let (statics, bound) = bound_of("slave-lift");
    assert!(statics + bound.total < 945, "{statics} + {bound:?}");
}

#[test]
fn master_static_ram_plus_its_stack_bound_stays_below_the_originals_static_ram() {
    let (statics, bound) = bound_of("master");
    // The master's work runs in idle (its service loop), not in a task.
    assert!(bound.main > bound.levels.iter().map(|l| l.2).sum::<u32>());
    assert!(statics + bound.total < 1_269, "{statics} + {bound:?}");
}

#[test]
fn each_images_task_levels_are_read_from_the_image_as_declared() {
    // (vector, level) as `slave/src/bin/*.rs` and `master/src/main.rs` declare them:
    // PCINT2 5, TIMER0_COMPA 14, TIMER0_COMPB 15, USART_RX 18, USART_UDRE 19, ADC 21,
    // TWI 24. The bound takes them from the image; this pins that it reads them right.
    let levels = |image: &str| {
        Program::of_elf(&firmware_path(image))
            .expect("the image's disassembly")
            .levels()
            .to_vec()
    };
    // Millis and the encoder edge at 3, TWI and ADC at 2, the control tick at 1.
    let drive = [(5, 3), (14, 3), (15, 1), (21, 2), (24, 2)];
    assert_eq!(levels("slave-drive"), drive);
    // The same without the encoder.
    assert_eq!(levels("slave-lift"), drive[1..]);
    // The serial link's receive and transmit and the RC edges at 3, millis at 2.
    assert_eq!(levels("master"), [(5, 3), (14, 2), (18, 3), (19, 3)]);
}

#[test]
fn the_data_bytes_scanned_for_pointers_are_the_linkers() {
    // `harness::data_initial_bytes` against the AVR binutils' own copy of `.data`.
    for image in ["slave-drive", "slave-lift", "master"] {
        let path = firmware_path(image);
        let out = std::env::temp_dir().join(format!("data-{}-{image}.bin", std::process::id()));
        let status = std::process::Command::new("avr-objcopy")
            .args(["-O", "binary", "-j", ".data"])
            .arg(&path)
            .arg(&out)
            .status()
            .expect("avr-objcopy");
        assert!(status.success());
        let expected = std::fs::read(&out).expect("objcopy's output");
        std::fs::remove_file(&out).expect("removed");
        let elf = std::fs::read(&path).expect("the image");
        let bytes = harness::data_initial_bytes(&elf).expect(".data");
        assert!(!bytes.is_empty(), "{image}");
        assert_eq!(bytes, expected, "{image}");
    }
}
