//! Reads an AVR ELF image: the flash bytes to load and the symbol table.
//!
//! Only what the harness needs is parsed: 32-bit little-endian ELF, `PT_LOAD`
//! program headers (placed by physical address, as the linker lays out flash)
//! and `SHT_SYMTAB` entries.

/// Offset the GNU AVR linker adds to data-space addresses.
pub(crate) const DATA_OFFSET: u32 = 0x0080_0000;
/// Offset the GNU AVR linker adds to EEPROM addresses.
pub(crate) const EEPROM_OFFSET: u32 = 0x0081_0000;
/// First address past the EEPROM region (fuses, lock bits and `.mmcu` follow).
const EEPROM_END: u32 = 0x0082_0000;

const PT_LOAD: u32 = 1;
const SHT_SYMTAB: u32 = 2;
const EM_AVR: u16 = 83;

/// The parts of an ELF image the harness loads.
#[derive(Debug, Default)]
pub(crate) struct Image {
    /// Flash contents from address 0, padded with 0xFF between segments.
    pub flash: Vec<u8>,
    /// (EEPROM address, bytes) for `.eeprom` segments.
    pub eeprom: Vec<(u16, Vec<u8>)>,
    /// Symbol name and value (data symbols keep the linker's 0x800000 offset).
    pub symbols: Vec<(String, u32)>,
}

fn u16_at(b: &[u8], off: usize) -> Result<u16, String> {
    b.get(off..off + 2)
        .map(|s| u16::from_le_bytes([s[0], s[1]]))
        .ok_or_else(|| format!("truncated at byte {off}"))
}

fn u32_at(b: &[u8], off: usize) -> Result<u32, String> {
    b.get(off..off + 4)
        .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .ok_or_else(|| format!("truncated at byte {off}"))
}

fn slice(b: &[u8], off: u32, len: u32) -> Result<&[u8], String> {
    let start = off as usize;
    let end = start
        .checked_add(len as usize)
        .ok_or_else(|| "segment size overflows".to_string())?;
    b.get(start..end)
        .ok_or_else(|| format!("segment {start:#x}..{end:#x} lies past the end of the file"))
}

/// Parses `bytes` as an AVR ELF file. The error string says what is wrong.
pub(crate) fn parse(bytes: &[u8]) -> Result<Image, String> {
    if bytes.get(0..4) != Some(b"\x7fELF".as_slice()) {
        return Err("not an ELF file (bad magic)".into());
    }
    if bytes.get(4) != Some(&1) || bytes.get(5) != Some(&1) {
        return Err("not a 32-bit little-endian ELF file".into());
    }
    if u16_at(bytes, 18)? != EM_AVR {
        return Err("not an AVR ELF file (e_machine is not EM_AVR)".into());
    }
    let mut image = Image::default();
    load_segments(bytes, &mut image)?;
    load_symbols(bytes, &mut image)?;
    Ok(image)
}

/// The initial bytes of an image's `.data`, as flash holds them for the startup code to
/// copy: `__data_end − __data_start` bytes from `__data_load_start`.
pub fn data_initial_bytes(elf: &[u8]) -> Result<Vec<u8>, String> {
    let image = parse(elf)?;
    let symbol = |name: &str| {
        image
            .symbols
            .iter()
            .find(|(n, _)| n == name)
            .map(|&(_, v)| v)
            .ok_or_else(|| format!("no {name} in the symbol table"))
    };
    let (start, end) = (symbol("__data_start")?, symbol("__data_end")?);
    let load = symbol("__data_load_start")? as usize;
    let len = end
        .checked_sub(start)
        .ok_or("__data_end lies below __data_start")? as usize;
    image
        .flash
        .get(load..load + len)
        .map(<[u8]>::to_vec)
        .ok_or_else(|| format!("`.data`'s {len} bytes at {load:#x} lie past the flash image"))
}

/// The flash an image takes: its code and the initial `.data` stored after it (`.text`
/// plus `.data`, as `avr-size` counts flash), from address 0 to the last byte loaded.
pub fn flash_bytes(elf: &[u8]) -> Result<usize, String> {
    Ok(parse(elf)?.flash.len())
}

fn load_segments(bytes: &[u8], image: &mut Image) -> Result<(), String> {
    let phoff = u32_at(bytes, 28)? as usize;
    let phentsize = usize::from(u16_at(bytes, 42)?);
    let phnum = usize::from(u16_at(bytes, 44)?);
    for i in 0..phnum {
        let ph = phoff + i * phentsize;
        if u32_at(bytes, ph)? != PT_LOAD {
            continue;
        }
        let offset = u32_at(bytes, ph + 4)?;
        let paddr = u32_at(bytes, ph + 12)?;
        let filesz = u32_at(bytes, ph + 16)?;
        if filesz == 0 {
            continue;
        }
        let data = slice(bytes, offset, filesz)?;
        if paddr < DATA_OFFSET {
            let start = paddr as usize;
            let end = start + data.len();
            if image.flash.len() < end {
                image.flash.resize(end, 0xFF);
            }
            image.flash[start..end].copy_from_slice(data);
        } else if (EEPROM_OFFSET..EEPROM_END).contains(&paddr) {
            let addr = u16::try_from(paddr - EEPROM_OFFSET)
                .map_err(|_| format!("EEPROM segment at {paddr:#x} is out of range"))?;
            image.eeprom.push((addr, data.to_vec()));
        }
    }
    if image.flash.is_empty() {
        return Err("the file holds no flash segment".into());
    }
    Ok(())
}

fn load_symbols(bytes: &[u8], image: &mut Image) -> Result<(), String> {
    let shoff = u32_at(bytes, 32)? as usize;
    let shentsize = usize::from(u16_at(bytes, 46)?);
    let shnum = usize::from(u16_at(bytes, 48)?);
    for i in 0..shnum {
        let sh = shoff + i * shentsize;
        if u32_at(bytes, sh + 4)? != SHT_SYMTAB {
            continue;
        }
        let offset = u32_at(bytes, sh + 16)?;
        let size = u32_at(bytes, sh + 20)?;
        let link = u32_at(bytes, sh + 24)? as usize;
        let entsize = u32_at(bytes, sh + 36)?.max(16) as usize;
        let strtab_sh = shoff + link * shentsize;
        let str_off = u32_at(bytes, strtab_sh + 16)?;
        let str_size = u32_at(bytes, strtab_sh + 20)?;
        let strtab = slice(bytes, str_off, str_size)?;
        let table = slice(bytes, offset, size)?;
        for entry in table.chunks_exact(entsize) {
            let name_off = u32_at(entry, 0)? as usize;
            let value = u32_at(entry, 4)?;
            let Some(rest) = strtab.get(name_off..) else {
                continue;
            };
            let len = rest.iter().position(|&c| c == 0).unwrap_or(rest.len());
            if len == 0 {
                continue;
            }
            let name = String::from_utf8_lossy(&rest[..len]).into_owned();
            image.symbols.push((name, value));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_non_elf() {
        assert_eq!(
            parse(b"hello world, not an elf").map(|_| ()),
            Err("not an ELF file (bad magic)".to_string())
        );
    }

    #[test]
    fn rejects_truncated_header() {
        let mut b = b"\x7fELF\x01\x01\x01".to_vec();
        b.resize(12, 0);
        assert_eq!(
            parse(&b).map(|_| ()),
            Err("truncated at byte 18".to_string())
        );
    }
}
