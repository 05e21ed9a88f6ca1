//! Each firmware image's static RAM plus a static bound on its stack
//! (`rover_tests::stack_bound`), against the goal: the original firmware's static RAM
//! alone. The emulator tests' painted high-water marks (`slave_bench`, `master_memory`)
//! show what one run reached, and are checked against the same bound there.
//!
use harness::firmware_path;
use rover_tests::stack_bound::{
    Bound, Program, DRIVE_STEER_LEVELS, LIFT_LIFT_LEVELS, MASTER_LEVELS,
};

fn bound_of(image: &str, levels: &[(u8, u8)]) -> (u32, Bound) {
    let program = Program::of_elf(&firmware_path(image)).expect("the image's disassembly");
    let bound = program.bound(levels).expect("a static stack bound");
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
    let (statics, bound) = bound_of("slave-drive", DRIVE_STEER_LEVELS);
    // The control tick, the deepest task, is what the bound is mostly made of.
    assert_eq!(bound.levels[0].0, 1);
    assert!(bound.levels[0].2 > bound.levels[1].2 + bound.levels[2].2);
    assert!(statics + bound.total < 986, "{statics} + {bound:?}");
}

#[test]
fn lift_lift_static_ram_plus_its_stack_bound_stays_below_the_originals_static_ram() {
    let (statics, bound) = bound_of("slave-lift", LIFT_LIFT_LEVELS);
    assert!(statics + bound.total < 945, "{statics} + {bound:?}");
}

#[test]
fn master_static_ram_plus_its_stack_bound_stays_below_the_originals_static_ram() {
    let (statics, bound) = bound_of("master", MASTER_LEVELS);
    // The master's work runs in idle (its service loop), not in a task.
    assert!(bound.main > bound.levels.iter().map(|l| l.2).sum::<u32>());
    assert!(statics + bound.total < 1_269, "{statics} + {bound:?}");
}

#[test]
fn a_level_list_that_misses_a_task_is_refused() {
    let program = Program::of_elf(&firmware_path("slave-drive")).expect("disassembly");
    let err = program.bound(LIFT_LIFT_LEVELS).unwrap_err();
    assert!(err.contains("update the list"), "{err}");
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
