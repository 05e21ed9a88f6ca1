// Shared by the firmware crates' build scripts (`include!`d): turns `memory.x` into the
// region symbols that avr-gcc's default linker script reads, so an image that outgrows
// the ATmega328P (less the bootloader) fails to link instead of failing on the rover.

/// Reads `memory.x` at the workspace root and asks the linker to enforce its regions.
fn link_memory_x() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let path = root.join("memory.x");
    println!("cargo:rerun-if-changed={}", path.display());
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    for (region, origin_sym, length_sym) in [
        ("FLASH", "__TEXT_REGION_ORIGIN__", "__TEXT_REGION_LENGTH__"),
        ("RAM", "__DATA_REGION_ORIGIN__", "__DATA_REGION_LENGTH__"),
        ("EEPROM", "", "__EEPROM_REGION_LENGTH__"),
    ] {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with(region))
            .unwrap_or_else(|| panic!("memory.x has no {region} line"));
        let field = |key: &str| -> String {
            let at = line.find(key).unwrap_or_else(|| panic!("memory.x {region}: no {key}"));
            line[at + key.len()..]
                .trim_start_matches([' ', '='])
                .split([',', ' '])
                .next()
                .unwrap_or_default()
                .to_string()
        };
        if !origin_sym.is_empty() {
            println!("cargo:rustc-link-arg=-Wl,--defsym={origin_sym}={}", field("ORIGIN"));
        }
        println!("cargo:rustc-link-arg=-Wl,--defsym={length_sym}={}", field("LENGTH"));
    }
}
