//! Hardware fidelity: two places where simavr differs from the ATmega328P in ways the
//! project's executor depends on, put right for every emulated chip.
//!
//! - **Level-sensitive interrupts.** The ATmega328P takes an interrupt whenever its flag,
//!   its enable bit and the I flag are all set, so a flag raised while the source was
//!   masked fires as soon as the enable bit is set again; the executor's masking relies on
//!   this. simavr queues an interrupt only when the flag rises while the enable bit is
//!   already set, and drops a queued one whose enable bit is found clear. The hook below
//!   restores the hardware rule: after any write to a register holding enable bits, each
//!   vector whose enable bit and flag are both set and which is not queued is raised again.
//! - **Write-one-to-clear flags.** simavr stores TWCR verbatim, so writing a zero to TWINT
//!   clears it, where on the chip only a one does. The hook keeps such a flag set.
//! - **ADC conversion time.** simavr completes a single conversion 2 ADC clocks after ADSC
//!   is set (14 for the first after ADEN), where the chip takes 13 (25): with the /128
//!   prescaler, 16 µs instead of 104 µs. A firmware that starts the next conversion from
//!   the completion interrupt then spends most of its time in that interrupt (the slave
//!   images ran it 46 times per ms instead of about 10), which makes the emulated slaves
//!   both busier than the real ones and several times slower to emulate. The hook finds
//!   the conversion timer simavr has just armed and moves it to the chip's time.

use std::ffi::c_void;

use simavr_ffi as ffi;

/// Data-space address of the first I/O register (simavr indexes `io[]` from here).
const IO_BASE: u16 = 0x20;

/// The register's previous write handler, which the hook calls first, and the vectors whose
/// flag or enable bit live in the register.
pub(crate) struct Chained {
    write: ffi::avr_io_write_t,
    param: *mut c_void,
    // The vector lists are found once at install: the hook runs on every write to an
    // enable register (each executor lock), and looking them up there, into fresh Vecs,
    // cost the ten-chip twin about an eighth of its time.
    /// Vectors whose flag is in this register.
    raised_here: Vec<*mut ffi::avr_int_vector_t>,
    /// Vectors whose enable bit is in this register.
    enabled_here: Vec<*mut ffi::avr_int_vector_t>,
}

/// Installs the re-raise hook on every register that holds an interrupt enable bit and
/// returns the records the hooks point to, which must live as long as the core.
///
/// The hook replaces the register's write handler and calls the old one itself (simavr's
/// own chaining has room for only a few registers).
// Boxed so each record keeps its address (simavr holds it) when the Vec grows.
#[allow(clippy::vec_box)]
pub(crate) fn install(p: *mut ffi::avr_t) -> Vec<Box<Chained>> {
    let mut records = Vec::new();
    let mut regs: Vec<u16> = Vec::new();
    // SAFETY: `p` is the live core owned by `avr`; the vector table is filled by avr_init,
    // and the `io[]` slot of each register is replaced while no instruction runs.
    unsafe {
        let table = &(*p).interrupts;
        for i in 0..usize::from(table.vector_count) {
            let v = table.vector[i];
            if v.is_null() || (*v).raised.reg() == 0 {
                continue;
            }
            let reg = (*v).enable.reg() as u16;
            if reg >= IO_BASE && !regs.contains(&reg) {
                regs.push(reg);
            }
        }
        for reg in regs {
            let raised_here = vectors_at(p, reg, |v| &v.raised);
            let enabled_here = vectors_at(p, reg, |v| &v.enable);
            let slot = &mut (*p).io[usize::from(reg - IO_BASE)].w;
            let mut chained = Box::new(Chained {
                write: slot.c,
                param: slot.param,
                raised_here,
                enabled_here,
            });
            slot.c = Some(write_then_reraise);
            slot.param = (&mut *chained as *mut Chained).cast();
            records.push(chained);
        }
    }
    records
}

/// Reads bit `rb` of the data space.
///
/// # Safety
/// `avr` is a live core.
unsafe fn regbit(avr: *mut ffi::avr_t, rb: &ffi::avr_regbit_t) -> bool {
    let reg = rb.reg() as usize;
    // SAFETY: `reg` is an I/O address inside the core's data space.
    let byte = unsafe { *(*avr).data.add(reg) };
    (byte >> rb.bit()) as u32 & rb.mask() != 0
}

/// The vectors of `avr` whose `field` register is `addr`.
///
/// # Safety
/// `avr` is a live core.
unsafe fn vectors_at(
    avr: *mut ffi::avr_t,
    addr: u16,
    field: fn(&ffi::avr_int_vector_t) -> &ffi::avr_regbit_t,
) -> Vec<*mut ffi::avr_int_vector_t> {
    // SAFETY: the table and its vectors belong to the live core.
    unsafe {
        let table = &(*avr).interrupts;
        let count = usize::from(table.vector_count);
        table.vector[..count]
            .iter()
            .copied()
            .filter(|&v| !v.is_null() && (*v).raised.reg() != 0 && field(&*v).reg() as u16 == addr)
            .collect()
    }
}

/// Data-space address of ADCSRA on the ATmega328P.
const ADCSRA: u16 = 0x7A;
/// ADSC (start conversion) in ADCSRA.
const ADSC: u8 = 1 << 6;
/// Most timers simavr keeps armed at once for one core.
const MAX_TIMERS: usize = 64;

/// The (callback, parameter) of every cycle timer armed on `avr`, at most [`MAX_TIMERS`].
///
/// # Safety
/// `avr` is a live core and no timer is being added or removed meanwhile.
unsafe fn armed_timers(avr: *mut ffi::avr_t) -> ([(usize, usize); MAX_TIMERS], usize) {
    let mut out = [(0usize, 0usize); MAX_TIMERS];
    let mut n = 0;
    // SAFETY: the list belongs to the live core; each slot is valid while linked.
    unsafe {
        let mut slot = (*avr).cycle_timers.timer;
        while !slot.is_null() && n < MAX_TIMERS {
            out[n] = (
                (*slot).timer.map_or(0, |f| f as usize),
                (*slot).param as usize,
            );
            n += 1;
            slot = (*slot).next;
        }
    }
    (out, n)
}

/// After a write to ADCSRA that started a conversion: re-arms the conversion timer simavr
/// armed at 2 (or 14) ADC clocks to the chip's 13 (or 25). `before` lists the timers
/// armed before the write.
///
/// # Safety
/// `avr` is a live core, inside the ADCSRA write hook.
unsafe fn stretch_conversion(avr: *mut ffi::avr_t, v: u8, before: &[(usize, usize)]) {
    // ADPS2..0: the ADC clock is the CPU clock / 2^ADPS (0 means 2).
    let prescale = 1u64 << (v & 0x07).max(1);
    // SAFETY: as for `armed_timers`; the slot's fields are read before it is cancelled,
    // and the callback is re-armed with its own parameter.
    unsafe {
        let now = (*avr).cycle;
        let mut slot = (*avr).cycle_timers.timer;
        while !slot.is_null() {
            let (timer, param, when) = ((*slot).timer, (*slot).param, (*slot).when);
            slot = (*slot).next;
            let key = (timer.map_or(0, |f| f as usize), param as usize);
            if before.contains(&key) {
                continue;
            }
            let clocks = match when.saturating_sub(now) / prescale {
                2 => 13,
                14 => 25,
                _ => continue,
            };
            ffi::avr_cycle_timer_cancel(avr, timer, param);
            ffi::avr_cycle_timer_register(avr, clocks * prescale, timer, param);
            return;
        }
    }
}

unsafe extern "C" fn write_then_reraise(avr: *mut ffi::avr_t, addr: u16, v: u8, p: *mut c_void) {
    // SAFETY: simavr calls this with its live core and the `Chained` record installed for
    // this register; the vectors belong to the core's peripherals.
    unsafe {
        let chained = &*p.cast::<Chained>();
        let starts_conversion =
            addr == ADCSRA && v & ADSC != 0 && *(*avr).data.add(usize::from(addr)) & ADSC == 0;
        let before = if starts_conversion {
            Some(armed_timers(avr))
        } else {
            None
        };
        // Flags that live in this very register (TWINT in TWCR, ADIF in ADCSRA), set
        // before the write and written as zero: on the chip, writing zero leaves them set.
        // (At most a few vectors share a register; a bit mask over the list is enough.)
        let mut keep = 0u32;
        for (i, &vec) in chained.raised_here.iter().enumerate().take(32) {
            if regbit(avr, &(*vec).raised) && (v >> (*vec).raised.bit()) & 1 == 0 {
                keep |= 1 << i;
            }
        }
        match chained.write {
            // The peripheral's handler stores the value itself.
            Some(write) => write(avr, addr, v, chained.param),
            // Nobody watched the register: store it as the core would have.
            None => ffi::avr_core_watch_write(avr, addr, v),
        }
        if let Some((timers, n)) = before {
            stretch_conversion(avr, v, &timers[..n]);
        }
        // simavr's TWI handler stores TWCR verbatim, which drops TWINT on a zero.
        for (i, &vec) in chained.raised_here.iter().enumerate().take(32) {
            if keep & (1 << i) != 0 {
                let rb = &(*vec).raised;
                *(*avr).data.add(rb.reg() as usize) |= 1 << rb.bit();
            }
        }
        for &vec in &chained.enabled_here {
            if regbit(avr, &(*vec).enable) && regbit(avr, &(*vec).raised) && (*vec).pending() == 0 {
                ffi::avr_raise_interrupt(avr, vec);
            }
        }
    }
}
