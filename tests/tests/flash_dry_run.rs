//! `flash.sh --dry-run` end to end: the script builds the real images, runs the real
//! avrdude command against `programmer-sim`, and the images the simulated chip ended up
//! with are compared byte for byte with the ELF files and the controller number.
//! Also checks that bad controller numbers and role mismatches are refused before any
//! build, and that `--force` overrides a mismatch.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const FLASH_SIZE: usize = 32 * 1024;
const EEPROM_SIZE: usize = 1024;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Fails (never skips) when the AVR tools are missing.
fn require_tools() {
    for tool in ["avrdude", "avr-objcopy"] {
        let found = Command::new("sh")
            .args(["-c", &format!("command -v {tool}")])
            .output()
            .map(|o| o.status.success())
            .unwrap_or(false);
        assert!(
            found,
            "{tool} is not installed: run scripts/setup.sh to install the AVR tools"
        );
    }
}

fn flash_sh(args: &[&str]) -> Output {
    Command::new(root().join("flash.sh"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn le16(b: &[u8], at: usize) -> usize {
    usize::from(u16::from_le_bytes([b[at], b[at + 1]]))
}

fn le32(b: &[u8], at: usize) -> usize {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]) as usize
}

/// The 32 KB flash image an ELF file loads: every PT_LOAD segment's file bytes at its
/// physical (load) address, the rest erased.
fn flash_image_of_elf(elf: &[u8]) -> Vec<u8> {
    assert_eq!(&elf[..4], b"\x7fELF", "not an ELF file");
    assert_eq!(elf[4], 1, "expected a 32-bit ELF");
    assert_eq!(elf[5], 1, "expected a little-endian ELF");
    assert_eq!(le16(elf, 0x12), 83, "expected an AVR ELF (e_machine 83)");
    let phoff = le32(elf, 0x1c);
    let phentsize = le16(elf, 0x2a);
    let phnum = le16(elf, 0x2c);
    let mut image = vec![0xff; FLASH_SIZE];
    let mut loaded = 0;
    for i in 0..phnum {
        let ph = phoff + i * phentsize;
        let (p_type, offset, paddr, filesz) = (
            le32(elf, ph),
            le32(elf, ph + 4),
            le32(elf, ph + 12),
            le32(elf, ph + 16),
        );
        if p_type != 1 || filesz == 0 {
            continue;
        }
        assert!(
            paddr + filesz <= FLASH_SIZE,
            "segment at {paddr:#x} is not in flash"
        );
        image[paddr..paddr + filesz].copy_from_slice(&elf[offset..offset + filesz]);
        loaded += filesz;
    }
    assert!(loaded > 0, "the ELF loads no bytes");
    image
}

/// The same image by a second route: avr-objcopy's raw binary of .text and .data.
fn flash_image_by_objcopy(elf: &Path, dir: &Path) -> Vec<u8> {
    let bin = dir.join("objcopy-check.bin");
    let status = Command::new("avr-objcopy")
        .args(["-O", "binary", "-j", ".text", "-j", ".data"])
        .arg(elf)
        .arg(&bin)
        .status()
        .unwrap();
    assert!(status.success());
    let raw = std::fs::read(&bin).unwrap();
    let mut image = vec![0xff; FLASH_SIZE];
    image[..raw.len()].copy_from_slice(&raw);
    image
}

/// Runs one dry run, checks everything it captured, and returns flash.sh's stderr.
fn check_dry_run(args: &[&str], role: &str, addr: Option<u8>, expected_cmd: &str) -> String {
    let out = flash_sh(args);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(
        out.status.success(),
        "flash.sh {args:?} failed\nstdout:\n{stdout}\nstderr:\n{stderr}"
    );
    let name = match addr {
        Some(n) => format!("{role}-{n}"),
        None => role.to_string(),
    };
    let dir = root().join("target/flash-dry-run").join(&name);
    let rel = format!("target/flash-dry-run/{name}");
    // The command that a board would get, with the real default port.
    let expected = expected_cmd.replace("DIR", &rel);
    assert!(
        stderr.contains(&format!("on a board this runs: {expected}\n")),
        "expected command {expected:?} in:\n{stderr}"
    );
    assert!(stdout.contains(&format!("{rel}/flash.bin")), "{stdout}");
    assert!(stderr.contains("bytes of flash verified"), "{stderr}");

    let elf_path = dir.join("image.elf");
    let elf = std::fs::read(&elf_path).unwrap();
    let expected_flash = flash_image_of_elf(&elf);
    assert_eq!(expected_flash, flash_image_by_objcopy(&elf_path, &dir));
    // The copy flash.sh worked from is the role's image.
    let built = std::fs::read(harness::firmware_path(role)).unwrap();
    assert_eq!(
        flash_image_of_elf(&built),
        expected_flash,
        "{name}: not {role}.elf"
    );

    let flash = std::fs::read(dir.join("flash.bin")).unwrap();
    assert_eq!(flash.len(), FLASH_SIZE);
    let first_diff = flash.iter().zip(&expected_flash).position(|(a, b)| a != b);
    assert_eq!(
        first_diff, None,
        "{name}: captured flash differs from the ELF"
    );

    let eeprom = std::fs::read(dir.join("eeprom.bin")).unwrap();
    assert_eq!(eeprom.len(), EEPROM_SIZE);
    match addr {
        Some(n) => {
            assert_eq!(eeprom[0], n, "{name}: EEPROM byte 0");
            assert!(
                eeprom[1..].iter().all(|&b| b == 0xff),
                "{name}: EEPROM tail"
            );
        }
        None => assert!(eeprom.iter().all(|&b| b == 0xff), "master EEPROM touched"),
    }

    let log = std::fs::read_to_string(dir.join("log.json")).unwrap();
    assert!(log.contains("\"end\": \"port-closed\""), "{log}");
    assert!(log.contains("\"refusals\": []"), "{log}");
    let (mode, erases) = match addr {
        Some(_) => ("isp", 1),
        None => ("bootloader", 0),
    };
    assert!(log.contains(&format!("\"mode\": \"{mode}\"")), "{log}");
    assert!(
        log.contains(&format!("\"chip_erases\": {erases},")),
        "{log}"
    );
    stderr
}

#[test]
fn dry_runs_capture_the_images_each_board_would_get() {
    require_tools();
    let slave = "avrdude -p m328p -c stk500v1 -P /dev/ttyACM0 -b 19200 \
                 -U flash:w:DIR/flash.hex:i -U eeprom:w:DIR/eeprom.hex:i";
    // One after another: each run rebuilds target/firmware.
    check_dry_run(
        &["--dry-run", "slave-lift", "3"],
        "slave-lift",
        Some(3),
        slave,
    );
    check_dry_run(
        &["--dry-run", "slave-drive", "4"],
        "slave-drive",
        Some(4),
        slave,
    );
    check_dry_run(
        &["--dry-run", "master"],
        "master",
        None,
        "avrdude -p m328p -c arduino -P /dev/ttyACM0 -b 115200 -D -U flash:w:DIR/flash.hex:i",
    );
    // A mismatch is accepted with --force, and says so.
    let stderr = check_dry_run(
        &["--dry-run", "--force", "slave-drive", "3"],
        "slave-drive",
        Some(3),
        slave,
    );
    assert!(
        stderr.contains("warning: controller 3 is a slave-lift board; writing slave-drive anyway"),
        "{stderr}"
    );
}

#[test]
fn bad_numbers_and_role_mismatches_are_refused_before_building() {
    let cases: [(&[&str], &str); 6] = [
        (&["--dry-run", "slave-drive", "0"], "out of range"),
        (&["--dry-run", "slave-lift", "10"], "out of range"),
        (
            &["--dry-run", "slave-drive", "3"],
            "controller 3 is a slave-lift board",
        ),
        (
            &["--dry-run", "slave-lift", "4"],
            "controller 4 is a slave-drive board",
        ),
        (
            &["--dry-run", "--force", "slave-drive", "0"],
            "out of range",
        ),
        (
            &["--dry-run", "master", "2"],
            "the master has no I2C address",
        ),
    ];
    for (args, message) in cases {
        let out = flash_sh(args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("building firmware"),
            "{args:?} built: {stderr}"
        );
    }
    // The mismatch message says how to fix it.
    let stderr = text(&flash_sh(&["slave-drive", "3"]).stderr);
    assert!(stderr.contains("./flash.sh slave-lift 3"), "{stderr}");
    assert!(stderr.contains("--force"), "{stderr}");
}
