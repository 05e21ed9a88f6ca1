//! STK500 v1 wire constants and frame lengths.
//!
//! Every command is one command byte, a fixed or length-prefixed argument block, and the
//! end-of-packet byte [`SYNC_CRC_EOP`]. The programmer answers [`RESP_INSYNC`], any
//! payload, then a status byte ([`RESP_OK`], [`RESP_FAILED`] or [`RESP_UNKNOWN`]), or a
//! lone [`RESP_NOSYNC`] when the frame did not end with the end-of-packet byte.

/// Response: the frame was well formed.
pub const RESP_INSYNC: u8 = 0x14;
/// Response: the frame did not end with [`SYNC_CRC_EOP`].
pub const RESP_NOSYNC: u8 = 0x15;
/// Status: command done.
pub const RESP_OK: u8 = 0x10;
/// Status: command understood but refused or failed.
pub const RESP_FAILED: u8 = 0x11;
/// Status: command byte not known.
pub const RESP_UNKNOWN: u8 = 0x12;
/// End of every command frame (an ASCII space).
pub const SYNC_CRC_EOP: u8 = 0x20;

/// `Cmnd_STK_GET_SYNC`: no arguments.
pub const CMD_GET_SYNC: u8 = 0x30;
/// `Cmnd_STK_GET_SIGN_ON`: no arguments; answers the programmer's name.
pub const CMD_GET_SIGN_ON: u8 = 0x31;
/// `Cmnd_STK_SET_PARAMETER`: parameter, value.
pub const CMD_SET_PARAMETER: u8 = 0x40;
/// `Cmnd_STK_GET_PARAMETER`: parameter; answers one value byte.
pub const CMD_GET_PARAMETER: u8 = 0x41;
/// `Cmnd_STK_SET_DEVICE`: 20 bytes of device description.
pub const CMD_SET_DEVICE: u8 = 0x42;
/// `Cmnd_STK_SET_DEVICE_EXT`: a size byte (counting itself), then size − 1 bytes.
pub const CMD_SET_DEVICE_EXT: u8 = 0x45;
/// `Cmnd_STK_ENTER_PROGMODE`: no arguments.
pub const CMD_ENTER_PROGMODE: u8 = 0x50;
/// `Cmnd_STK_LEAVE_PROGMODE`: no arguments.
pub const CMD_LEAVE_PROGMODE: u8 = 0x51;
/// `Cmnd_STK_CHIP_ERASE`: no arguments.
pub const CMD_CHIP_ERASE: u8 = 0x52;
/// `Cmnd_STK_CHECK_AUTOINC`: no arguments.
pub const CMD_CHECK_AUTOINC: u8 = 0x53;
/// `Cmnd_STK_LOAD_ADDRESS`: word address, low byte first.
pub const CMD_LOAD_ADDRESS: u8 = 0x55;
/// `Cmnd_STK_UNIVERSAL`: four bytes of serial-programming instruction; answers one byte.
pub const CMD_UNIVERSAL: u8 = 0x56;
/// `Cmnd_STK_PROG_PAGE`: size (high byte first), memory type, size data bytes.
pub const CMD_PROG_PAGE: u8 = 0x64;
/// `Cmnd_STK_READ_PAGE`: size (high byte first), memory type; answers size bytes.
pub const CMD_READ_PAGE: u8 = 0x74;
/// `Cmnd_STK_READ_SIGN`: no arguments; answers the three signature bytes.
pub const CMD_READ_SIGN: u8 = 0x75;

/// Memory type byte of a page command: flash.
pub const MEMTYPE_FLASH: u8 = b'F';
/// Memory type byte of a page command: EEPROM.
pub const MEMTYPE_EEPROM: u8 = b'E';

/// `Parm_STK_HW_VER`.
pub const PARM_HW_VER: u8 = 0x80;
/// `Parm_STK_SW_MAJOR`.
pub const PARM_SW_MAJOR: u8 = 0x81;
/// `Parm_STK_SW_MINOR`.
pub const PARM_SW_MINOR: u8 = 0x82;
/// `Parm_STK_VTARGET`, in tenths of a volt.
pub const PARM_VTARGET: u8 = 0x84;
/// `Parm_STK_VADJUST` (reference voltage), in tenths of a volt.
pub const PARM_VADJUST: u8 = 0x85;
/// `Parm_STK_OSC_PSCALE`.
pub const PARM_OSC_PSCALE: u8 = 0x86;
/// `Parm_STK_OSC_CMATCH`.
pub const PARM_OSC_CMATCH: u8 = 0x87;
/// `Parm_STK_SCK_DURATION`.
pub const PARM_SCK_DURATION: u8 = 0x89;
/// `Parm_STK_TOPCARD_DETECT`: 0xff means no top card.
pub const PARM_TOPCARD_DETECT: u8 = 0x98;

/// How far a frame that starts with `buf[0]` has been understood.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameLen {
    /// The frame is this many bytes long, end-of-packet byte included.
    Total(usize),
    /// The length depends on header bytes that have not arrived yet.
    NeedMore,
    /// `buf[0]` is not a command this programmer knows.
    Unknown,
}

/// The total length of the frame whose first bytes are `buf` (an empty `buf` needs more).
pub fn frame_len(buf: &[u8]) -> FrameLen {
    let Some(&cmd) = buf.first() else {
        return FrameLen::NeedMore;
    };
    let fixed_args = match cmd {
        CMD_GET_SYNC | CMD_GET_SIGN_ON | CMD_ENTER_PROGMODE | CMD_LEAVE_PROGMODE
        | CMD_CHIP_ERASE | CMD_CHECK_AUTOINC | CMD_READ_SIGN => 0,
        CMD_GET_PARAMETER => 1,
        CMD_SET_PARAMETER | CMD_LOAD_ADDRESS => 2,
        CMD_READ_PAGE => 3,
        CMD_UNIVERSAL => 4,
        CMD_SET_DEVICE => 20,
        CMD_SET_DEVICE_EXT => {
            return match buf.get(1) {
                // The size byte counts itself: size − 1 parameter bytes follow it.
                Some(&size) => FrameLen::Total(2 + usize::from(size.saturating_sub(1)) + 1),
                None => FrameLen::NeedMore,
            };
        }
        CMD_PROG_PAGE => {
            return match (buf.get(1), buf.get(2)) {
                (Some(&hi), Some(&lo)) => {
                    // command, size hi, size lo, memory type, data, end of packet
                    FrameLen::Total(4 + usize::from(u16::from_be_bytes([hi, lo])) + 1)
                }
                _ => FrameLen::NeedMore,
            };
        }
        _ => return FrameLen::Unknown,
    };
    FrameLen::Total(1 + fixed_args + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_frames_have_their_documented_lengths() {
        assert_eq!(frame_len(&[CMD_GET_SYNC]), FrameLen::Total(2));
        assert_eq!(frame_len(&[CMD_GET_PARAMETER]), FrameLen::Total(3));
        assert_eq!(frame_len(&[CMD_LOAD_ADDRESS]), FrameLen::Total(4));
        assert_eq!(frame_len(&[CMD_READ_PAGE]), FrameLen::Total(5));
        assert_eq!(frame_len(&[CMD_UNIVERSAL]), FrameLen::Total(6));
        assert_eq!(frame_len(&[CMD_SET_DEVICE]), FrameLen::Total(22));
    }

    #[test]
    fn length_prefixed_frames_wait_for_their_header() {
        assert_eq!(frame_len(&[CMD_SET_DEVICE_EXT]), FrameLen::NeedMore);
        assert_eq!(frame_len(&[CMD_SET_DEVICE_EXT, 5]), FrameLen::Total(7));
        assert_eq!(frame_len(&[CMD_PROG_PAGE, 0x00]), FrameLen::NeedMore);
        assert_eq!(
            frame_len(&[CMD_PROG_PAGE, 0x00, 0x80]),
            FrameLen::Total(133)
        );
        assert_eq!(
            frame_len(&[CMD_PROG_PAGE, 0x01, 0x00]),
            FrameLen::Total(261)
        );
    }

    #[test]
    fn other_bytes_are_unknown() {
        assert_eq!(frame_len(&[SYNC_CRC_EOP]), FrameLen::Unknown);
        assert_eq!(frame_len(&[0x57]), FrameLen::Unknown);
        assert_eq!(frame_len(&[]), FrameLen::NeedMore);
    }
}
