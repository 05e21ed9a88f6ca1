//! UART0: bytes from the firmware are collected with their cycle stamps; bytes
//! for the firmware are queued and handed to the receiver one per character
//! time, the pace of a real line.

use std::ffi::c_void;

use simavr_ffi as ffi;

use crate::avr::{c_str, ioctl_def, Shared, CYCLES_PER_US};
use crate::{Avr, HarnessError};

/// Data-space address of UCSR0B.
const UCSR0B: usize = 0xC1;
/// RXEN0 bit in UCSR0B.
const RXEN0: u8 = 1 << 4;
/// simavr's mark on a received character that had a framing error (`UART_INPUT_FE`): the
/// firmware reads FE0 set in UCSR0A while that character is the next in its buffer.
pub(crate) const FRAMING_ERROR: u16 = 0x8000;
/// Cycles to wait before retrying while the receiver is still disabled.
const RX_RETRY_CYCLES: u64 = 1600;

/// Finds simavr's model of UART0 in the core's peripheral list (NULL if absent).
pub(crate) fn find_uart0(avr: *mut ffi::avr_t) -> *mut ffi::avr_uart_t {
    // SAFETY: `avr` is an initialised core; its io_port list is a NULL-terminated
    // linked list of peripherals whose `kind` strings are static. A peripheral of
    // kind "uart" is an `avr_uart_t`, whose first member is its `avr_io_t`.
    unsafe {
        let mut io = (*avr).io_port;
        while !io.is_null() {
            if c_str((*io).kind).is_some_and(|k| k.to_bytes() == b"uart") {
                let uart = io.cast::<ffi::avr_uart_t>();
                if (*uart).name as u8 == b'0' {
                    return uart;
                }
            }
            io = (*io).next;
        }
    }
    std::ptr::null_mut()
}

/// UART0's IRQ number `irq` (UART_IRQ_*), NULL if absent.
fn uart_irq(avr: *mut ffi::avr_t, irq: u32) -> *mut ffi::avr_irq_t {
    // SAFETY: `avr` is an initialised core; avr_io_getirq returns NULL for unknown ioctls.
    unsafe { ffi::avr_io_getirq(avr, ioctl_def(b'u', b'a', b'r', b'0'), irq as i32) }
}

/// UART0's input IRQ: a value raised on it is a received character.
pub(crate) fn input_irq(avr: *mut ffi::avr_t) -> *mut ffi::avr_irq_t {
    uart_irq(avr, ffi::UART_IRQ_INPUT)
}

/// Called by simavr for every byte the firmware writes to UDR0 while TX is enabled.
unsafe extern "C" fn on_uart_output(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    // SAFETY: `param` is the `Shared` box registered in `install_uart_hooks`, alive as
    // long as the core; no other borrow of `uart_out` is held while simavr runs.
    let shared = unsafe { &*param.cast::<Shared>() };
    let stamp = shared.now();
    shared.uart_out.borrow_mut().push((stamp, value as u8));
    shared.uart_sent.set(shared.uart_sent.get() + 1);
}

/// Cycle timer: hands the next queued byte to the receiver, then re-arms one
/// character time later while bytes remain.
unsafe extern "C" fn rx_pump(
    avr: *mut ffi::avr_t,
    when: ffi::avr_cycle_count_t,
    param: *mut c_void,
) -> ffi::avr_cycle_count_t {
    // SAFETY: `param` is the `Shared` box registered in `arm_rx_pump`, alive as long
    // as the core.
    let shared = unsafe { &*param.cast::<Shared>() };
    // SAFETY: `uart` points into the live core; `avr` is that core, running this
    // timer, and its data array covers UCSR0B.
    let (cpb, rx_enabled) = unsafe {
        (
            (*shared.uart).cycles_per_byte.max(1),
            *(*avr).data.add(UCSR0B) & RXEN0 != 0,
        )
    };
    if !rx_enabled {
        // A real line would lose these bytes; the harness holds them until the
        // firmware has enabled its receiver, so tests may queue input before boot.
        return when + RX_RETRY_CYCLES;
    }
    let character = shared.rx_queue.borrow_mut().pop_front();
    let Some(character) = character else {
        shared.rx_armed.set(false);
        return 0;
    };
    shared.rx_last.set(Some(shared.now()));
    // SAFETY: `uart_in` is UART0's input IRQ of this live core.
    unsafe { ffi::avr_raise_irq(shared.uart_in, u32::from(character)) };
    if shared.rx_queue.borrow().is_empty() {
        shared.rx_armed.set(false);
        0
    } else {
        when + cpb
    }
}

impl Avr {
    /// Hooks UART0's output and turns off simavr's real-time polling sleep and its
    /// console echo.
    pub(crate) fn install_uart_hooks(&mut self) {
        let p = self.raw.as_ptr();
        let param = std::ptr::from_ref::<Shared>(&self.shared).cast_mut().cast();
        // SAFETY: `uart` points into the live core (found in `blank`); the output IRQ
        // belongs to it; `param` is the boxed `Shared`, which outlives the core's use.
        unsafe {
            let uart = self.shared.uart;
            (*uart).flags &= !(ffi::AVR_UART_FLAG_POLL_SLEEP | ffi::AVR_UART_FLAG_STDIO);
            ffi::avr_irq_register_notify(
                uart_irq(p, ffi::UART_IRQ_OUTPUT),
                Some(on_uart_output),
                param,
            );
        }
    }

    /// Schedules the receive pump if bytes are queued and it is not running,
    /// keeping one character time between successive bytes.
    pub(crate) fn arm_rx_pump(&mut self) {
        let shared = &self.shared;
        if shared.rx_armed.get() || shared.rx_queue.borrow().is_empty() {
            return;
        }
        let cpb = self.uart_cycles_per_byte();
        let now = shared.now();
        let earliest = shared.rx_last.get().map_or(now, |last| last + cpb);
        let delay = earliest.saturating_sub(now).max(1);
        let param = std::ptr::from_ref::<Shared>(shared).cast_mut().cast();
        // SAFETY: the live core owns the timer list; `param` is the boxed `Shared`.
        unsafe { ffi::avr_cycle_timer_register(self.raw.as_ptr(), delay, Some(rx_pump), param) };
        shared.rx_armed.set(true);
    }

    /// Cycles one UART0 character takes at the configured baud rate (simavr counts
    /// start, 8 data, a parity slot and stop: 11 bit times, 1496 cycles at 115200).
    pub fn uart_cycles_per_byte(&self) -> u64 {
        // SAFETY: `uart` points into the live core; plain field read.
        unsafe { (*self.shared.uart).cycles_per_byte }.max(1)
    }

    /// Queues bytes for the firmware's UART0 receiver; they arrive one per
    /// character time while the emulation runs.
    pub fn uart_send(&mut self, bytes: &[u8]) {
        self.queue_rx(bytes.iter().map(|&b| u16::from(b)));
    }

    /// Like [`Avr::uart_send`], but each byte arrives with a framing error (a wrong baud
    /// rate or noise on the line): the firmware finds FE0 set in UCSR0A before it reads
    /// the byte from UDR0.
    pub fn uart_send_framing_error(&mut self, bytes: &[u8]) {
        self.queue_rx(bytes.iter().map(|&b| u16::from(b) | FRAMING_ERROR));
    }

    fn queue_rx(&mut self, characters: impl Iterator<Item = u16>) {
        self.shared.rx_queue.borrow_mut().extend(characters);
        self.arm_rx_pump();
    }

    /// Drops the bytes queued by [`Avr::uart_send`] that the receiver has not been handed
    /// yet: a line whose sender was cut off mid-stream, or a chip reset whose UART, as on
    /// the real chip, keeps nothing of what was on its way. Returns how many.
    pub fn uart_discard_input(&mut self) -> usize {
        let mut queue = self.shared.rx_queue.borrow_mut();
        let n = queue.len();
        queue.clear();
        n
    }

    /// Bytes queued by [`Avr::uart_send`] that the receiver has not been handed yet.
    pub fn uart_pending_input(&self) -> usize {
        self.shared.rx_queue.borrow().len()
    }

    /// Count of bytes the firmware sent on UART0 that were not taken yet.
    pub fn uart_available(&self) -> usize {
        self.shared.uart_out.borrow().len()
    }

    /// Takes every byte the firmware sent on UART0 since the last take.
    pub fn uart_take(&mut self) -> Vec<u8> {
        self.uart_take_timed().into_iter().map(|(_, b)| b).collect()
    }

    /// Like [`Avr::uart_take`], with the cycle (see [`Avr::cycles`]) at which the
    /// firmware wrote each byte to UDR0.
    pub fn uart_take_timed(&mut self) -> Vec<(u64, u8)> {
        std::mem::take(&mut *self.shared.uart_out.borrow_mut())
    }

    /// Runs until the firmware's untaken UART output contains `needle`, then takes
    /// and returns everything up to and including it (later bytes stay queued).
    pub fn uart_read_until(&mut self, needle: &[u8], max_us: u64) -> Result<Vec<u8>, HarnessError> {
        let what = format!("UART bytes {:?}", String::from_utf8_lossy(needle));
        self.uart_wait(&what, max_us, |out| {
            if needle.is_empty() {
                return Some(0);
            }
            out.windows(needle.len())
                .position(|w| w == needle)
                .map(|i| i + needle.len())
        })
    }

    /// Runs until the firmware has sent `n` untaken UART bytes and takes exactly `n`.
    pub fn uart_read_exact(&mut self, n: usize, max_us: u64) -> Result<Vec<u8>, HarnessError> {
        let what = format!("{n} UART bytes");
        self.uart_wait(&what, max_us, |out| (out.len() >= n).then_some(n))
    }

    /// Runs until `split` finds an end index in the untaken output; takes that prefix.
    fn uart_wait(
        &mut self,
        what: &str,
        max_us: u64,
        mut split: impl FnMut(&[u8]) -> Option<usize>,
    ) -> Result<Vec<u8>, HarnessError> {
        let start = self.cycles();
        let target = start.saturating_add(max_us.saturating_mul(CYCLES_PER_US));
        let mut seen = u64::MAX;
        let mut found = None;
        let mut check = |avr: &mut Avr| {
            let sent = avr.shared.uart_sent.get();
            if sent == seen {
                return false;
            }
            seen = sent;
            let out: Vec<u8> = avr
                .shared
                .uart_out
                .borrow()
                .iter()
                .map(|&(_, b)| b)
                .collect();
            found = split(&out);
            found.is_some()
        };
        if !check(self) {
            self.run_to(target, &mut check);
        }
        match found {
            Some(end) => {
                let mut out = self.shared.uart_out.borrow_mut();
                Ok(out.drain(..end).map(|(_, b)| b).collect())
            }
            None => {
                self.check_running(what)?;
                Err(HarnessError::Timeout {
                    what: what.to_string(),
                    waited_us: (self.cycles() - start) / CYCLES_PER_US,
                    got: self
                        .shared
                        .uart_out
                        .borrow()
                        .iter()
                        .map(|&(_, b)| b)
                        .collect(),
                })
            }
        }
    }
}
