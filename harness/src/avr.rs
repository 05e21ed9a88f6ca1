//! One emulated ATmega328P: loading, running, time keeping and reset tracking.

use std::cell::{Cell, RefCell};
use std::collections::{HashMap, VecDeque};
use std::ffi::{c_void, CStr};
use std::path::{Path, PathBuf};
use std::ptr::NonNull;

use simavr_ffi as ffi;

use crate::elf;
use crate::{CpuState, HarnessError};

/// Clock of the emulated chip (the Uno's crystal).
pub const F_CPU: u64 = 16_000_000;
/// Cycles per emulated microsecond.
pub(crate) const CYCLES_PER_US: u64 = F_CPU / 1_000_000;
/// Data-space address of MCUSR.
pub(crate) const MCUSR: u16 = 0x54;
/// WDRF bit in MCUSR.
pub(crate) const WDRF: u8 = 1 << 3;
/// PORF bit in MCUSR.
pub(crate) const PORF: u8 = 1 << 0;
/// EXTRF bit in MCUSR.
pub(crate) const EXTRF: u8 = 1 << 1;
/// Flash size of the ATmega328P.
const FLASH_SIZE: usize = 32 * 1024;

extern "C" {
    /// The C library's allocator release; simavr allocates the core with `malloc`.
    fn free(ptr: *mut c_void);
}

/// Builds a simavr ioctl code from its four characters.
pub(crate) const fn ioctl_def(a: u8, b: u8, c: u8, d: u8) -> u32 {
    ((a as u32) << 24) | ((b as u32) << 16) | ((c as u32) << 8) | (d as u32)
}

/// State that simavr's callbacks (UART, timers, pin hooks) read and write.
///
/// It lives in a `Box` owned by [`Avr`], so its address is stable for the raw
/// `param` pointers handed to simavr. Callbacks only run inside `avr_run` (or
/// `avr_raise_irq`) called from `&mut Avr` methods, and every method borrows the
/// cells only briefly, never across such a call.
pub(crate) struct Shared {
    /// The emulated core.
    pub avr: *mut ffi::avr_t,
    /// Cycles that elapsed before the last reset (simavr restarts its counter at 0).
    pub base: Cell<u64>,
    /// UART0 bytes the firmware sent and nobody took yet, with the cycle they were written.
    pub uart_out: RefCell<Vec<(u64, u8)>>,
    /// Count of UART0 bytes the firmware ever sent.
    pub uart_sent: Cell<u64>,
    /// Characters queued for the firmware's UART0 receiver, as simavr's input IRQ takes
    /// them: the byte, with [`crate::uart::FRAMING_ERROR`] set for one received with a
    /// framing error.
    pub rx_queue: RefCell<VecDeque<u16>>,
    /// True while the receive pump timer is scheduled.
    pub rx_armed: Cell<bool>,
    /// Absolute cycle of the last byte handed to the receiver.
    pub rx_last: Cell<Option<u64>>,
    /// simavr's UART0 model.
    pub uart: *mut ffi::avr_uart_t,
    /// UART0's input IRQ (bytes towards the firmware).
    pub uart_in: *mut ffi::avr_irq_t,
    /// Recorded pin changes, keyed by (port letter, bit).
    pub traces: RefCell<PinTraces>,
    /// Which traced pin each hooked pin IRQ (by address) belongs to.
    pub trace_irqs: RefCell<HashMap<usize, (u8, u8)>>,
    /// The raw cycle the sleep deadline timer is queued for, if it is.
    pub deadline: Cell<Option<u64>>,
    /// Pin changes set ahead ([`Avr::set_pin_at`]), in the order they are due.
    pub pin_changes: RefCell<VecDeque<crate::pin_timer::PinChange>>,
    /// Another device holds the chip's I²C clock low: a master chip's TWINT does not rise
    /// (see [`crate::twi::port::gate_twint`]).
    pub scl_held: Cell<bool>,
}

/// Recorded (cycle, level) changes per (port letter, bit).
pub(crate) type PinTraces = HashMap<(u8, u8), Vec<(u64, bool)>>;

impl Shared {
    /// Absolute cycles since load, monotonic across resets.
    pub fn now(&self) -> u64 {
        // SAFETY: `avr` is valid for the lifetime of the owning `Avr`, and reading a
        // plain integer field does not create a reference to the struct.
        self.base.get() + unsafe { (*self.avr).cycle }
    }
}

/// What [`Avr::set_observer`] calls after every instruction.
type Observer = Box<dyn FnMut(&mut Avr)>;

/// One emulated ATmega328P at 16 MHz running a firmware image.
///
/// Time is emulated: sleeping and waiting for UART data cost no real time.
pub struct Avr {
    pub(crate) raw: NonNull<ffi::avr_t>,
    pub(crate) shared: Box<Shared>,
    pub(crate) symbols: Vec<(String, u32)>,
    last_raw_cycle: u64,
    watchdog_resets: u32,
    state: CpuState,
    /// The ADC's input IRQs (ADC0..ADC7 in a row), looked up once.
    pub(crate) adc_inputs: Option<NonNull<ffi::avr_irq_t>>,
    /// Called after every instruction of [`Avr::run_cycles`] while set (see
    /// [`Avr::set_observer`]).
    observer: Option<Observer>,
    /// Records behind the hardware-fidelity hooks ([`crate::fidelity`]); they must outlive
    /// the core, which `Drop` terminates before the fields are dropped.
    // Boxed so each record keeps its address (simavr holds it) when the Vec grows.
    #[allow(clippy::vec_box)]
    _fidelity: Vec<Box<crate::fidelity::Chained>>,
}

/// Replacement for simavr's sleep callback, which would sleep in real time to
/// keep pace with the wall clock. Emulated time simply jumps ahead instead.
unsafe extern "C" fn no_real_sleep(_avr: *mut ffi::avr_t, _how_long: ffi::avr_cycle_count_t) {}

/// A timer that does nothing; it only bounds how far a sleeping CPU jumps.
unsafe extern "C" fn deadline(
    avr: *mut ffi::avr_t,
    _when: ffi::avr_cycle_count_t,
    param: *mut c_void,
) -> ffi::avr_cycle_count_t {
    // SAFETY: `param` is the owning `Avr`'s boxed `Shared`, which outlives the core's
    // timers; `avr` is the live core running this callback.
    let (shared, avr) = unsafe { (&*param.cast::<Shared>(), &*avr) };
    // simavr runs the timers that are due and then, in the same step, lets a sleeping
    // CPU jump to the next timer. Firing while the CPU sleeps, the deadline therefore
    // re-arms itself one cycle on, so the jump ends right after it and the run stops
    // there; the next run replaces it. Otherwise it is done.
    let next = if avr.state == ffi::cpu_Sleeping as i32 {
        avr.cycle + 1
    } else {
        0
    };
    shared.deadline.set((next != 0).then_some(next));
    next
}

impl Avr {
    /// Loads an AVR ELF image into a fresh ATmega328P at 16 MHz, held at its reset vector.
    pub fn load(elf_path: &Path) -> Result<Avr, HarnessError> {
        let bytes = std::fs::read(elf_path).map_err(|source| {
            if source.kind() == std::io::ErrorKind::NotFound {
                HarnessError::FirmwareMissing {
                    path: elf_path.to_path_buf(),
                }
            } else {
                HarnessError::Read {
                    path: elf_path.to_path_buf(),
                    source,
                }
            }
        })?;
        let image = elf::parse(&bytes).map_err(|reason| HarnessError::BadElf {
            path: elf_path.to_path_buf(),
            reason,
        })?;
        if image.flash.len() > FLASH_SIZE {
            return Err(HarnessError::TooLarge {
                path: elf_path.to_path_buf(),
                size: image.flash.len(),
            });
        }
        let mut avr = Avr::blank()?;
        avr.symbols = image.symbols;
        let mut flash = image.flash;
        let len = u32::try_from(flash.len()).map_err(|_| HarnessError::TooLarge {
            path: elf_path.to_path_buf(),
            size: flash.len(),
        })?;
        // SAFETY: the core is initialised; `flash` is a live buffer of `len` bytes that
        // fits the 32 KiB flash (checked above), and simavr copies it.
        unsafe { ffi::avr_loadcode(avr.raw.as_ptr(), flash.as_mut_ptr(), len, 0) };
        for (addr, data) in &image.eeprom {
            avr.eeprom_write(*addr, data);
        }
        Ok(avr)
    }

    /// Loads `<workspace>/target/firmware/<name>.elf`, where `scripts/firmware.sh` puts images.
    pub fn firmware(name: &str) -> Result<Avr, HarnessError> {
        Avr::load(&firmware_path(name))
    }

    /// Creates and initialises an empty core with the harness's hooks installed.
    pub(crate) fn blank() -> Result<Avr, HarnessError> {
        // SAFETY: the name is a NUL-terminated string; simavr returns NULL for unknown cores.
        let raw = unsafe { ffi::avr_make_mcu_by_name(c"atmega328p".as_ptr()) };
        let raw = NonNull::new(raw).ok_or(HarnessError::CoreUnavailable)?;
        let p = raw.as_ptr();
        // SAFETY: `p` is a freshly allocated core; avr_init sets up its memories and
        // peripherals. The fields written are plain data that simavr reads later.
        unsafe {
            (*p).frequency = F_CPU as u32;
            if ffi::avr_init(p) != 0 {
                free(p.cast());
                return Err(HarnessError::CoreUnavailable);
            }
            (*p).frequency = F_CPU as u32;
            (*p).vcc = 5000;
            (*p).avcc = 5000;
            (*p).aref = 5000;
            (*p).sleep = Some(no_real_sleep);
        }
        let uart = crate::uart::find_uart0(p);
        let uart_in = crate::uart::input_irq(p);
        if uart.is_null() || uart_in.is_null() {
            // SAFETY: `p` was initialised by avr_init and is not used after this.
            unsafe {
                ffi::avr_terminate(p);
                free(p.cast());
            }
            return Err(HarnessError::CoreUnavailable);
        }
        let shared = Box::new(Shared {
            avr: p,
            base: Cell::new(0),
            uart_out: RefCell::new(Vec::new()),
            uart_sent: Cell::new(0),
            rx_queue: RefCell::new(VecDeque::new()),
            rx_armed: Cell::new(false),
            rx_last: Cell::new(None),
            uart,
            uart_in,
            traces: RefCell::new(HashMap::new()),
            trace_irqs: RefCell::new(HashMap::new()),
            deadline: Cell::new(None),
            pin_changes: RefCell::new(VecDeque::new()),
            scl_held: Cell::new(false),
        });
        let mut avr = Avr {
            raw,
            shared,
            symbols: Vec::new(),
            last_raw_cycle: 0,
            watchdog_resets: 0,
            state: CpuState::Running,
            adc_inputs: None,
            observer: None,
            _fidelity: Vec::new(),
        };
        avr._fidelity = crate::fidelity::install(avr.raw.as_ptr());
        avr.install_uart_hooks();
        // A power-on reset: MCUSR.PORF set, as the chip reports after power-up.
        avr.write_data(MCUSR, PORF);
        Ok(avr)
    }

    /// The underlying simavr core, for modules that attach further peripherals (TWI bus).
    pub fn as_ptr(&mut self) -> *mut ffi::avr_t {
        self.raw.as_ptr()
    }

    /// Sends the CPU to `address` (a byte address in flash, as [`Avr::symbol`] gives it)
    /// between two instructions, stepping it awake first if it sleeps: a fault injected
    /// into the firmware, e.g. a jump to its panic handler. The interrupted code's state is
    /// never returned to, so the target must not return either.
    pub fn jump_to(&mut self, address: u32) {
        while self.state() == CpuState::Sleeping {
            self.step();
        }
        // SAFETY: a plain field write to the live core between two instructions.
        unsafe { (*self.raw.as_ptr()).pc = address };
    }

    /// Hangs the CPU, as firmware stuck in a loop with interrupts off: the I flag is cleared
    /// and the CPU sent to a one-instruction loop (`rjmp .`) put in the last flash word,
    /// which is the bootloader's and holds nothing of the images here. Peripherals run on
    /// (a TWI that takes its address holds SCL low); only a reset ends it, the watchdog's
    /// if the firmware runs one.
    pub fn hang(&mut self) {
        const LOOP_AT: u32 = 0x7FFE;
        const RJMP_SELF: [u8; 2] = 0xCFFFu16.to_le_bytes();
        // Awake first: a sleeping CPU with its I flag clear would never wake.
        self.jump_to(LOOP_AT);
        // SAFETY: plain writes to the live core between two instructions: two bytes inside
        // its 32-KB flash, and its I flag (simavr keeps SREG as one byte per bit).
        unsafe {
            let p = self.raw.as_ptr();
            let at = LOOP_AT as usize;
            *(*p).flash.add(at) = RJMP_SELF[0];
            *(*p).flash.add(at + 1) = RJMP_SELF[1];
            (*p).sreg[ffi::S_I as usize] = 0;
        }
    }

    /// Emulated clock cycles since load (monotonic across watchdog resets).
    pub fn cycles(&self) -> u64 {
        self.shared.now()
    }

    /// Emulated microseconds since load.
    pub fn micros(&self) -> u64 {
        self.cycles() / CYCLES_PER_US
    }

    /// The CPU state after the last step.
    pub fn state(&self) -> CpuState {
        self.state
    }

    /// Resets the firmware survived that were caused by the watchdog.
    pub fn watchdog_resets(&self) -> u32 {
        self.watchdog_resets
    }

    /// Runs one emulator step (one instruction, or one sleep jump to the next timer).
    pub fn step(&mut self) -> CpuState {
        let p = self.raw.as_ptr();
        if self.shared.deadline.take().is_some() {
            // A single step has no deadline: a sleeping CPU jumps to its next event,
            // not to the end of an earlier run.
            // SAFETY: timers are owned by the live core; cancelling matches the
            // callback and param registered by `arm_deadline`.
            unsafe { ffi::avr_cycle_timer_cancel(p, Some(deadline), self.shared_param()) };
        }
        self.step_raw()
    }

    /// One emulator step, keeping an armed deadline.
    fn step_raw(&mut self) -> CpuState {
        let p = self.raw.as_ptr();
        // SAFETY: the core is initialised and owned by `self`; no Rust reference into
        // it or into `shared`'s cells is alive across this call.
        let raw_state = unsafe { ffi::avr_run(p) };
        // SAFETY: plain field read of a live core.
        let raw_cycle = unsafe { (*p).cycle };
        if raw_cycle < self.last_raw_cycle {
            self.after_reset();
        }
        self.last_raw_cycle = raw_cycle;
        self.state = CpuState::from_raw(raw_state);
        self.state
    }

    /// Bookkeeping after simavr reset the core (it restarts its cycle counter at 0
    /// and drops every cycle timer). Every reset simavr makes by itself comes from
    /// the watchdog, and leaves MCUSR.WDRF set.
    fn after_reset(&mut self) {
        if self.read_data(MCUSR) & WDRF != 0 {
            self.watchdog_resets += 1;
        }
        self.resync_after_reset(self.last_raw_cycle + 1);
    }

    /// Keeps time monotonic and restarts the harness's timers after a reset that
    /// happened `elapsed` raw cycles into the previous run.
    fn resync_after_reset(&mut self, elapsed: u64) {
        let shared = &self.shared;
        shared.base.set(shared.base.get() + elapsed);
        shared.rx_armed.set(false);
        self.last_raw_cycle = 0;
        // simavr dropped every cycle timer.
        self.shared.deadline.set(None);
        self.arm_rx_pump();
        self.arm_pin_timer();
    }

    /// An external reset (the RESET pin, or the Uno's DTR auto-reset): the firmware
    /// restarts from its reset vector with MCUSR.EXTRF set; EEPROM, queued UART
    /// input and untaken UART output are kept, and emulated time runs on.
    pub fn reset(&mut self) {
        let p = self.raw.as_ptr();
        // SAFETY: plain field read of the live core.
        let elapsed = unsafe { (*p).cycle };
        // SAFETY: the core is live and not running (we hold `&mut self`); avr_reset
        // reinitialises registers, peripherals and timers in place.
        unsafe { ffi::avr_reset(p) };
        let mcusr = self.read_data(MCUSR);
        self.write_data(MCUSR, mcusr | EXTRF);
        self.state = CpuState::Running;
        self.resync_after_reset(elapsed);
    }

    /// Runs until `n` more cycles have elapsed, the CPU halts, or forever if it never does.
    /// Sleep is fast-forwarded: a sleeping CPU jumps to its next timer event.
    pub fn run_cycles(&mut self, n: u64) {
        let target = self.cycles().saturating_add(n);
        if self.observer.is_some() {
            self.run_to(target, |_| false);
        } else {
            self.run_to_target(target);
        }
    }

    /// Calls `observe` after every instruction (or sleep jump) that [`Avr::run_cycles`],
    /// [`Avr::run_until`] or a bus delivering an I2C event run from now on, also when a
    /// bus or a plant runs this chip: for cycle profiles of code that only runs under bus
    /// traffic. The runs take the slower stepping path while
    /// it is set. [`Avr::clear_observer`] removes it.
    pub fn set_observer(&mut self, observe: impl FnMut(&mut Avr) + 'static) {
        self.observer = Some(Box::new(observe));
    }

    /// Whether an observer is set ([`Avr::set_observer`]).
    pub(crate) fn has_observer(&self) -> bool {
        self.observer.is_some()
    }

    /// Removes the observer set by [`Avr::set_observer`].
    pub fn clear_observer(&mut self) {
        self.observer = None;
    }

    /// Runs for `us` emulated microseconds (see [`Avr::run_cycles`]).
    pub fn run_us(&mut self, us: u64) {
        self.run_cycles(us.saturating_mul(CYCLES_PER_US));
    }

    /// Runs until `pred` returns true (checked after every step) or `max_us` of emulated
    /// time pass or the CPU halts. Returns whether `pred` became true.
    pub fn run_until(&mut self, max_us: u64, mut pred: impl FnMut(&mut Avr) -> bool) -> bool {
        if pred(self) {
            return true;
        }
        let target = self
            .cycles()
            .saturating_add(max_us.saturating_mul(CYCLES_PER_US));
        self.run_to(target, |avr| pred(avr))
    }

    /// Steps until `cycles() >= target`, the CPU halts or `stop` says so. Returns
    /// whether `stop` ended the run.
    pub(crate) fn run_to(&mut self, target: u64, mut stop: impl FnMut(&mut Avr) -> bool) -> bool {
        let mut observer = self.observer.take();
        let stopped = loop {
            let now = self.cycles();
            if now >= target || self.state.is_halted() {
                break false;
            }
            self.arm_deadline(now, target);
            self.step_raw();
            if let Some(observe) = observer.as_mut() {
                observe(self);
            }
            if stop(self) {
                break true;
            }
        };
        if self.observer.is_none() {
            self.observer = observer;
        }
        stopped
    }

    /// [`Avr::run_to`] with nothing to check between steps: the lock-stepped bus's inner
    /// loop, where the harness's own work per instruction is most of what it costs
    /// beyond simavr. Between resets only simavr's raw cycle counter needs reading.
    pub(crate) fn run_to_target(&mut self, target: u64) {
        let p = self.raw.as_ptr();
        // The inner loop leaves `self.state` stale until it ends; nothing reads it
        // meanwhile (hooks see only simavr's core).
        loop {
            let now = self.cycles();
            if now >= target || self.state.is_halted() {
                return;
            }
            self.arm_deadline(now, target);
            let raw_target = target - self.shared.base.get();
            let running = [ffi::cpu_Running as i32, ffi::cpu_Sleeping as i32];
            loop {
                // SAFETY: the core is initialised and owned by `self`; no Rust reference
                // into it or into `shared`'s cells is alive across this call.
                let raw_state = unsafe { ffi::avr_run(p) };
                // SAFETY: plain field read of a live core.
                let raw_cycle = unsafe { (*p).cycle };
                let reset = raw_cycle < self.last_raw_cycle;
                if reset || !running.contains(&raw_state) || raw_cycle >= raw_target {
                    // A reset, a halt or the end: the outer loop does the bookkeeping.
                    if reset {
                        self.after_reset();
                    } else {
                        self.last_raw_cycle = raw_cycle;
                    }
                    self.state = CpuState::from_raw(raw_state);
                    break;
                }
                self.last_raw_cycle = raw_cycle;
            }
        }
    }

    /// Makes sure a sleeping CPU does not jump past the absolute cycle `target`.
    fn arm_deadline(&mut self, now: u64, target: u64) {
        let raw_target = target - self.shared.base.get();
        if self.shared.deadline.get() == Some(raw_target) {
            return;
        }
        let p = self.raw.as_ptr();
        // SAFETY: timers are owned by the live core; registering cancels the one this
        // callback and param had queued; `deadline` reads its param as the boxed `Shared`.
        unsafe {
            ffi::avr_cycle_timer_register(p, target - now, Some(deadline), self.shared_param());
        }
        self.shared.deadline.set(Some(raw_target));
    }

    /// The boxed `Shared` as a hook parameter.
    fn shared_param(&self) -> *mut c_void {
        std::ptr::from_ref::<Shared>(&self.shared).cast_mut().cast()
    }

    /// Fails with [`HarnessError::Halted`] if the CPU has halted.
    pub(crate) fn check_running(&self, what: &str) -> Result<(), HarnessError> {
        if self.state.is_halted() {
            Err(HarnessError::Halted {
                state: self.state,
                what: what.to_string(),
                at_us: self.micros(),
            })
        } else {
            Ok(())
        }
    }
}

impl Drop for Avr {
    fn drop(&mut self) {
        let p = self.raw.as_ptr();
        // SAFETY: the core was allocated by simavr with malloc and initialised; after
        // avr_terminate releases its memories nothing uses it again, and the hook
        // parameter (`shared`) is dropped only after this.
        unsafe {
            ffi::avr_terminate(p);
            free(p.cast());
        }
    }
}

/// `<workspace>/target/firmware/<name>.elf`, or `$BLODWEN_FIRMWARE_DIR/<name>.elf` when
/// that is set (as `scripts/firmware.sh` honours it), so that two work trees or two
/// builds in progress do not test each other's images.
pub fn firmware_path(name: &str) -> PathBuf {
    let dir = match std::env::var_os("BLODWEN_FIRMWARE_DIR") {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
            .join("target")
            .join("firmware"),
    };
    dir.join(format!("{name}.elf"))
}

/// Reads a C string simavr owns, if it is not NULL.
pub(crate) fn c_str(p: *const std::os::raw::c_char) -> Option<&'static CStr> {
    // SAFETY: simavr's kind and name strings are static literals; NULL is checked.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) })
}
