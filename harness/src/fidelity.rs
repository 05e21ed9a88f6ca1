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

use std::ffi::c_void;

use simavr_ffi as ffi;

/// Data-space address of the first I/O register (simavr indexes `io[]` from here).
const IO_BASE: u16 = 0x20;

/// The register's previous write handler, which the hook calls first.
pub(crate) struct Chained {
    write: ffi::avr_io_write_t,
    param: *mut c_void,
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
            let slot = &mut (*p).io[usize::from(reg - IO_BASE)].w;
            let mut chained = Box::new(Chained {
                write: slot.c,
                param: slot.param,
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

unsafe extern "C" fn write_then_reraise(avr: *mut ffi::avr_t, addr: u16, v: u8, p: *mut c_void) {
    // SAFETY: simavr calls this with its live core and the `Chained` record installed for
    // this register; the vectors belong to the core's peripherals.
    unsafe {
        // Flags that live in this very register (TWINT in TWCR, ADIF in ADCSRA), set
        // before the write and written as zero: on the chip, writing zero leaves them set.
        let keep: Vec<_> = vectors_at(avr, addr, |v| &v.raised)
            .into_iter()
            .filter(|&vec| regbit(avr, &(*vec).raised) && (v >> (*vec).raised.bit()) & 1 == 0)
            .collect();
        let chained = &*p.cast::<Chained>();
        match chained.write {
            // The peripheral's handler stores the value itself.
            Some(write) => write(avr, addr, v, chained.param),
            // Nobody watched the register: store it as the core would have.
            None => ffi::avr_core_watch_write(avr, addr, v),
        }
        // simavr's TWI handler stores TWCR verbatim, which drops TWINT on a zero.
        for vec in keep {
            let rb = &(*vec).raised;
            *(*avr).data.add(rb.reg() as usize) |= 1 << rb.bit();
        }
        for vec in vectors_at(avr, addr, |v| &v.enable) {
            if regbit(avr, &(*vec).enable) && regbit(avr, &(*vec).raised) && (*vec).pending() == 0 {
                ffi::avr_raise_interrupt(avr, vec);
            }
        }
    }
}
