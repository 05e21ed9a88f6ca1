//! The executor's audited core on the ATmega328P: task dispatch, locks, start-up, gated
//! sources, driver register writes and the sleeping idle. This is the only code of the
//! crate that touches hardware.

/// Expands `$step!(index, Reg)` for every enable register, so per-register code is
/// unrolled at compile time and no loop over registers runs on the target.
macro_rules! each_reg {
    ($step:ident) => {
        $step!(0, Reg::Eimsk);
        $step!(1, Reg::Pcicr);
        $step!(2, Reg::Timsk0);
        $step!(3, Reg::Timsk1);
        $step!(4, Reg::Timsk2);
        $step!(5, Reg::Spcr);
        $step!(6, Reg::Adcsra);
        $step!(7, Reg::Twcr);
        $step!(8, Reg::Ucsr0b);
    };
}

mod cpu;
mod frame;
pub(crate) mod gates;

use core::sync::atomic::{compiler_fence, Ordering};

use crate::bits;
use crate::source::Reg;
use crate::App;

/// Runs a hardware task of priority `P` from its interrupt vector.
///
/// The AVR enters every vector with the global flag clear. Below the top level the task
/// masks the sources at its own and lower priorities, sets the flag so that higher ones
/// may preempt it, runs, clears the flag and unmasks. A top-priority task simply runs with
/// the flag clear. RETI sets the flag again after the registers are restored, so a source
/// unmasked here is taken only once the interrupted code has resumed.
///
/// # Safety
/// Called once per interrupt, from the vector of a source bound to a task of priority `P`.
#[inline(always)]
pub unsafe fn dispatch<A: App, const P: u8>(task: impl FnOnce()) {
    if P >= A::TOP {
        task();
    } else {
        // SAFETY: interrupts are disabled (vector entry); the frame is ended below.
        let f = unsafe { frame::open::<A, P, 0, true>() };
        // SAFETY: every source at or below P is masked, so only higher tasks preempt.
        unsafe { cpu::sei() };
        task();
        cpu::cli();
        // SAFETY: interrupts are disabled again; `f` is this task's entry frame.
        unsafe { frame::close::<A, P, 0, true>(f) };
    }
}

/// Runs `f` on `*ptr` with the system ceiling raised to `C`, for a task of priority `P`
/// below `C`. The top ceiling clears the global flag; below it, the sources at levels
/// `P+1..=C` are masked (those at `P` and below already are, by the task's own entry),
/// atomically when one of their registers is also written by drivers.
///
/// # Safety
/// `ptr` is a shared resource of ceiling `C`, reached through its task's handle.
#[inline(always)]
pub(crate) unsafe fn lock<A: App, const C: u8, const P: u8, T, R>(
    ptr: *mut T,
    f: impl FnOnce(&mut T) -> R,
) -> R {
    if C >= A::TOP {
        let sreg = cpu::save_cli();
        // SAFETY: no task runs until SREG is restored.
        let r = f(unsafe { &mut *ptr });
        // SAFETY: matches the save above.
        unsafe { cpu::restore(sreg) };
        r
    } else if const { crate::analysis::atomic_lock(&A::MASKS, &A::GATED, C, P) } {
        let sreg = cpu::save_cli();
        // SAFETY: interrupts are disabled; the frame is ended below at the same level.
        let fr = unsafe { frame::open::<A, C, P, false>() };
        // SAFETY: matches the save above.
        unsafe { cpu::restore(sreg) };
        // SAFETY: every user of the resource is masked until the frame ends.
        let r = f(unsafe { &mut *ptr });
        cpu::cli();
        // SAFETY: interrupts are disabled; `fr` is this level's frame.
        unsafe { frame::close::<A, C, P, false>(fr) };
        // SAFETY: the interrupt flag is back to what it was when the lock began (the
        // closure leaves it as it found it; the other SREG flags hold nothing live).
        unsafe { cpu::restore(sreg) };
        r
    } else {
        // SAFETY: only pure, ungated registers are involved, each level in one of them:
        // any task preempting the read-modify-write leaves them as it found them, so no
        // update is lost, and no level is left half masked for a task to re-enable.
        let fr = unsafe { frame::open::<A, C, P, false>() };
        compiler_fence(Ordering::SeqCst);
        // SAFETY: every user of the resource is masked until the frame ends.
        let r = f(unsafe { &mut *ptr });
        compiler_fence(Ordering::SeqCst);
        // SAFETY: as for the mask above.
        unsafe { frame::close::<A, C, P, false>(fr) };
        r
    }
}

/// Starts the application once `init` has returned and the resources are stored: enables
/// every ungated task source, selects idle sleep mode and enables interrupts.
///
/// # Safety
/// Called once, by the generated `main`, with interrupts still disabled.
#[inline(always)]
pub unsafe fn start<A: App>() {
    macro_rules! step {
        ($i:literal, $reg:expr) => {{
            let bits = const { A::START.get($i) };
            if bits != 0 {
                // SAFETY: an enable register; interrupts are off and nothing else writes it.
                unsafe { write($reg, bits::unmasked($reg, read($reg), bits)) };
            }
        }};
    }
    each_reg!(step);
    // SMCR (0x53): SE = 1, SM = 000 (idle: timers, TWI, USART and ADC keep running).
    // SAFETY: a valid SMCR value; SLEEP is only executed by idle.
    unsafe { core::ptr::write_volatile(0x53 as *mut u8, 0x01) };
    // SAFETY: the resources are initialised and every task source is configured.
    unsafe { cpu::sei() };
}

/// The idle loop used when the application declares none: sleep until an interrupt,
/// forever.
///
/// # Safety
/// Called only by the generated `main`, as idle (priority 0), after [`start`].
pub unsafe fn default_idle() -> ! {
    loop {
        // SAFETY: this is idle (priority 0), and `start` set SMCR.SE.
        unsafe { cpu::sei_sleep() };
    }
}

/// The global interrupt flag in SREG.
const SREG_I: u8 = 1 << 7;

/// Idle's right to put the CPU to sleep, in its context as `cx.sleep`.
pub struct Sleep {
    _private: (),
}

impl Sleep {
    /// The token.
    ///
    /// # Safety
    /// Only the generated idle context creates it.
    #[doc(hidden)]
    pub unsafe fn new() -> Sleep {
        Sleep { _private: () }
    }

    /// Sleeps until the next interrupt unless `busy` reports work. `busy` runs with
    /// interrupts disabled and the SLEEP follows SEI directly, so work that an interrupt
    /// creates after the check always wakes the CPU: no wake-up is lost.
    ///
    /// Called with interrupts disabled (from inside a top-ceiling lock), it returns at once
    /// without sleeping: sleeping would have to enable interrupts inside the lock. Inside a
    /// lock of a lower ceiling it sleeps, and only a source above the ceiling can wake it:
    /// call it outside locks.
    #[inline(always)]
    pub fn sleep_unless(&mut self, busy: impl FnOnce() -> bool) {
        let sreg = cpu::save_cli();
        if sreg & SREG_I == 0 || busy() {
            // SAFETY: puts back the state saved above.
            unsafe { cpu::restore(sreg) };
        } else {
            // SAFETY: `Sleep` exists only in idle's context, which runs with interrupts
            // enabled (checked above); SMCR.SE was set at start.
            unsafe { cpu::sei_sleep() };
        }
    }

    /// Sleeps until the next interrupt.
    #[inline(always)]
    pub fn sleep(&mut self) {
        self.sleep_unless(|| false);
    }
}

#[inline(always)]
unsafe fn read(reg: Reg) -> u8 {
    // SAFETY: an I/O register of the ATmega328P.
    unsafe { core::ptr::read_volatile(reg.addr() as *const u8) }
}

#[inline(always)]
unsafe fn write(reg: Reg, v: u8) {
    // SAFETY: an I/O register of the ATmega328P; callers compute `v` with `bits`.
    unsafe { core::ptr::write_volatile(reg.addr() as *mut u8, v) };
}

/// Arms gated source bit `bit` of register index `r`: the driver wants its interrupt. The
/// bit goes on now unless a masking frame holds it, in which case that frame turns it on
/// when it ends.
#[inline(always)]
pub(crate) fn arm(reg: Reg, bit: u8) {
    let sreg = cpu::save_cli();
    let r = reg.index();
    // SAFETY: interrupts are disabled for the whole update.
    unsafe {
        gates::WANT.set(r, gates::WANT.get(r) | bit);
        if gates::HELD.get(r) & bit == 0 {
            write(reg, bits::unmasked(reg, read(reg), bit));
        }
        cpu::restore(sreg);
    }
}

/// Disarms gated source bit `bit` of register `reg`: its interrupt is off until armed.
#[inline(always)]
pub(crate) fn disarm(reg: Reg, bit: u8) {
    let sreg = cpu::save_cli();
    let r = reg.index();
    // SAFETY: interrupts are disabled for the whole update.
    unsafe {
        gates::WANT.set(r, gates::WANT.get(r) & !bit);
        write(reg, bits::masked(reg, read(reg), bit));
        cpu::restore(sreg);
    }
}

/// A driver's write to a register that also holds enable bits (see [`crate::hw`]).
#[inline(always)]
pub(crate) fn driver_write(reg: Reg, value: u8) {
    let sreg = cpu::save_cli();
    // SAFETY: interrupts are disabled between the read and the write, so no enable bit
    // changes in between; `bits::driver_write` keeps the enable bits as they are.
    unsafe {
        write(reg, bits::driver_write(reg, read(reg), value));
        cpu::restore(sreg);
    }
}

/// A driver's read-modify-write of such a register; `f` sees the value with the
/// write-one-to-act bits cleared, so returning it unchanged changes nothing.
#[inline(always)]
pub(crate) fn driver_modify(reg: Reg, f: impl FnOnce(u8) -> u8) {
    let sreg = cpu::save_cli();
    // SAFETY: as for `driver_write`.
    unsafe {
        let now = read(reg);
        let v = f(now & !reg.write_zero_bits());
        write(reg, bits::driver_write(reg, now, v));
        cpu::restore(sreg);
    }
}

/// Reads a register that holds enable bits.
#[inline(always)]
pub(crate) fn driver_read(reg: Reg) -> u8 {
    // SAFETY: reading an enable register has no side effect.
    unsafe { read(reg) }
}

/// Disables interrupts for good, for a panic handler: no task runs after this, so the
/// handler can stop the motors undisturbed.
#[inline(always)]
pub fn freeze() {
    cpu::cli();
}

/// The device peripherals, handed to `init`.
pub type Device = avr_device::atmega328p::Peripherals;

/// Takes the device peripherals for `init`.
///
/// # Safety
/// Called once, by the generated `main`, before anything else uses peripherals.
#[inline(always)]
pub unsafe fn take_device() -> Device {
    // SAFETY: per the contract, this is the only instance.
    unsafe { avr_device::atmega328p::Peripherals::steal() }
}
