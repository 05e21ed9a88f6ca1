//! The STK500 v1 state machine: bytes from the host in, answer bytes out.
//!
//! [`Programmer::feed`] takes one byte at a time, so the caller may pass whatever a read
//! returned. A frame is executed once its last byte has arrived; answers follow the
//! STK500 v1 conventions in [`crate::stk`]. Addresses loaded with `Cmnd_STK_LOAD_ADDRESS`
//! are word addresses for both flash and EEPROM, as the Uno's bootloader and ArduinoISP
//! read them; page commands do not advance the address.
//!
//! The machine's avrdude (7.1) loads *byte* addresses for EEPROM pages, so on real hardware
//! as here an EEPROM write that starts past address 0 lands at twice its address, while
//! verify still passes. flash.sh writes only EEPROM byte 0, where both readings agree; the
//! simulator keeps the real programmers' reading so the captured image is what a board
//! would hold.

use crate::error::MemError;
use crate::isp::{self, IspOutcome};
use crate::record::{Record, Refusal, Universal, Write};
use crate::stk::*;
use crate::target::{Fuses, Memory, Target};

/// Which programmer the simulator plays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The Uno's serial bootloader (`avrdude -c arduino`): no chip erase, no serial
    /// instructions, and the boot section at the top of flash cannot be written.
    Bootloader,
    /// An ArduinoISP-style in-system programmer (`avrdude -c stk500v1` or `-c avrisp`).
    Isp,
}

impl Mode {
    /// Name used on the command line and in the log.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Bootloader => "bootloader",
            Mode::Isp => "isp",
        }
    }
}

/// First byte address of the Uno bootloader's boot section (512 bytes at the top).
pub const BOOT_SECTION: usize = 0x7e00;
/// Largest data block one page command may carry.
pub const MAX_BLOCK: usize = 256;
/// Name the ISP answers to `Cmnd_STK_GET_SIGN_ON`.
pub const SIGN_ON: &[u8] = b"AVR ISP";

/// The emulated programmer and the chip behind it.
#[derive(Debug, Clone)]
pub struct Programmer {
    mode: Mode,
    target: Target,
    frame: Vec<u8>,
    progmode: bool,
    address: u16,
    params: [u8; 256],
    record: Record,
}

impl Programmer {
    /// A programmer in `mode` attached to an erased ATmega328P.
    pub fn new(mode: Mode) -> Self {
        let mut params = [0u8; 256];
        let (hw, major, minor, lock) = match mode {
            Mode::Bootloader => (3, 8, 0, 0xcf),
            Mode::Isp => (2, 1, 18, 0xff),
        };
        params[usize::from(PARM_HW_VER)] = hw;
        params[usize::from(PARM_SW_MAJOR)] = major;
        params[usize::from(PARM_SW_MINOR)] = minor;
        params[usize::from(PARM_VTARGET)] = 50;
        params[usize::from(PARM_VADJUST)] = 50;
        params[usize::from(PARM_OSC_CMATCH)] = 1;
        params[usize::from(PARM_SCK_DURATION)] = 2;
        params[usize::from(PARM_TOPCARD_DETECT)] = 0xff;
        let fuses = Fuses {
            lock,
            ..Fuses::default()
        };
        Programmer {
            mode,
            target: Target::new(fuses),
            frame: Vec::new(),
            progmode: false,
            address: 0,
            params,
            record: Record::default(),
        }
    }

    /// The mode played.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The chip's memories as they are now.
    pub fn target(&self) -> &Target {
        &self.target
    }

    /// Everything done so far.
    pub fn record(&self) -> &Record {
        &self.record
    }

    /// Whether programming mode is on.
    pub fn in_progmode(&self) -> bool {
        self.progmode
    }

    /// Whether a frame has started but not finished.
    pub fn mid_frame(&self) -> bool {
        !self.frame.is_empty()
    }

    /// Feeds every byte of `bytes`; returns all answer bytes.
    pub fn feed_all(&mut self, bytes: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        for &b in bytes {
            self.feed(b, &mut out);
        }
        out
    }

    /// Feeds one byte from the host, appending any answer to `out`.
    pub fn feed(&mut self, byte: u8, out: &mut Vec<u8>) {
        self.frame.push(byte);
        loop {
            match frame_len(&self.frame) {
                FrameLen::NeedMore => return,
                FrameLen::Total(n) if self.frame.len() < n => return,
                FrameLen::Total(_) => {
                    let frame = core::mem::take(&mut self.frame);
                    if frame.last() == Some(&SYNC_CRC_EOP) {
                        self.execute(&frame, out);
                    } else {
                        self.record.nosyncs += 1;
                        out.push(RESP_NOSYNC);
                    }
                    return;
                }
                FrameLen::Unknown => {
                    let second = match self.frame.as_slice() {
                        [SYNC_CRC_EOP] => {
                            // A stray end-of-packet byte: the host is out of step.
                            self.frame.clear();
                            self.record.nosyncs += 1;
                            out.push(RESP_NOSYNC);
                            return;
                        }
                        [_] => return,
                        [_, second, ..] => *second,
                        [] => return,
                    };
                    self.frame.clear();
                    if second == SYNC_CRC_EOP {
                        self.record.unknown += 1;
                        out.extend_from_slice(&[RESP_INSYNC, RESP_UNKNOWN]);
                        return;
                    }
                    // Not a frame: the second byte may start the next one.
                    self.record.nosyncs += 1;
                    out.push(RESP_NOSYNC);
                    self.frame.push(second);
                }
            }
        }
    }

    fn execute(&mut self, frame: &[u8], out: &mut Vec<u8>) {
        let Some(&cmd) = frame.first() else {
            return;
        };
        let arg = |i: usize| frame.get(i).copied().unwrap_or(0);
        out.push(RESP_INSYNC);
        match cmd {
            CMD_GET_SYNC => self.record.syncs += 1,
            CMD_GET_SIGN_ON => {
                if self.mode == Mode::Isp {
                    out.extend_from_slice(SIGN_ON);
                }
            }
            CMD_SET_PARAMETER => self.params[usize::from(arg(1))] = arg(2),
            CMD_GET_PARAMETER => out.push(self.params[usize::from(arg(1))]),
            CMD_SET_DEVICE | CMD_SET_DEVICE_EXT | CMD_CHECK_AUTOINC => {}
            CMD_ENTER_PROGMODE => {
                self.progmode = true;
                self.record.progmode_entries += 1;
            }
            CMD_LEAVE_PROGMODE => self.progmode = false,
            CMD_CHIP_ERASE => {
                if !self.progmode {
                    return self.refuse(cmd, MemError::NotInProgMode, out);
                }
                if self.mode == Mode::Isp {
                    self.target.chip_erase();
                    self.record.chip_erases += 1;
                }
            }
            CMD_LOAD_ADDRESS => self.address = u16::from_le_bytes([arg(1), arg(2)]),
            CMD_UNIVERSAL => {
                let instr = [arg(1), arg(2), arg(3), arg(4)];
                if !self.progmode {
                    out.push(0x00);
                    return self.refuse(cmd, MemError::NotInProgMode, out);
                }
                let (answer, outcome) = match self.mode {
                    Mode::Isp => isp::execute(&mut self.target, instr),
                    Mode::Bootloader => (0x00, IspOutcome::Ignored),
                };
                if outcome == IspOutcome::ChipErase {
                    self.record.chip_erases += 1;
                }
                self.record.universal.push(Universal {
                    instr,
                    answer,
                    outcome,
                });
                out.push(answer);
            }
            CMD_PROG_PAGE => {
                let len = usize::from(u16::from_be_bytes([arg(1), arg(2)]));
                let data = frame.get(4..4 + len).unwrap_or(&[]);
                match self.prog_page(arg(3), data) {
                    Ok(()) => {}
                    Err(e) => return self.refuse(cmd, e, out),
                }
            }
            CMD_READ_PAGE => {
                let len = usize::from(u16::from_be_bytes([arg(1), arg(2)]));
                match self.read_page(arg(3), len) {
                    Ok(data) => out.extend_from_slice(&data),
                    Err(e) => return self.refuse(cmd, e, out),
                }
            }
            CMD_READ_SIGN => out.extend_from_slice(&crate::target::SIGNATURE),
            _ => {
                // frame_len only completes frames of known commands.
                out.push(RESP_UNKNOWN);
                self.record.unknown += 1;
                return;
            }
        }
        out.push(RESP_OK);
    }

    fn refuse(&mut self, command: u8, err: MemError, out: &mut Vec<u8>) {
        self.record.refusals.push(Refusal {
            command,
            reason: err.to_string(),
        });
        out.push(RESP_FAILED);
    }

    /// Checks a page command and returns the memory and first byte address it addresses.
    fn page_access(&self, memtype: u8, len: usize) -> Result<(Memory, usize), MemError> {
        if !self.progmode {
            return Err(MemError::NotInProgMode);
        }
        let memory = match memtype {
            MEMTYPE_FLASH => Memory::Flash,
            MEMTYPE_EEPROM => Memory::Eeprom,
            other => return Err(MemError::MemoryType(other)),
        };
        let addr = usize::from(self.address) * 2;
        if len > MAX_BLOCK {
            return Err(MemError::OutOfRange {
                memory: memory.name(),
                addr,
                len,
                size: MAX_BLOCK,
            });
        }
        Ok((memory, addr))
    }

    fn prog_page(&mut self, memtype: u8, data: &[u8]) -> Result<(), MemError> {
        let (memory, addr) = self.page_access(memtype, data.len())?;
        if self.mode == Mode::Bootloader
            && memory == Memory::Flash
            && addr + data.len() > BOOT_SECTION
        {
            return Err(MemError::BootSection {
                addr,
                len: data.len(),
                boot: BOOT_SECTION,
            });
        }
        self.target.write(memory, addr, data)?;
        self.record.writes.push(Write {
            memory,
            addr,
            len: data.len(),
        });
        Ok(())
    }

    fn read_page(&mut self, memtype: u8, len: usize) -> Result<Vec<u8>, MemError> {
        let (memory, addr) = self.page_access(memtype, len)?;
        let data = self.target.read(memory, addr, len)?.to_vec();
        self.record.count_read(memory);
        Ok(data)
    }
}

#[cfg(test)]
#[path = "session_tests.rs"]
mod tests;
