//! Attaching a Rust device model (OneWire sensors, an RC receiver) to one emulated chip
//! for exactly as long as the chip lives.
//!
//! A model registers simavr IRQ hooks and cycle timers whose parameter points at itself.
//! Those must never fire after the model is gone, and the model must never touch a core
//! that is gone, whatever order the test drops things in. So the core owns the model:
//! [`attach`] links a small simavr I/O module into the core, which
//! - calls [`Device::reset`] whenever the chip resets (simavr then has zeroed the I/O
//!   registers and dropped every cycle timer), and
//! - on `avr_terminate` (when the [`crate::Avr`] is dropped) calls [`Device::detach`], which
//!   unregisters the model's hooks and timers, unlinks itself and releases the model.
//!
//! The caller's handle shares the model through an `Rc`; a handle that outlives its chip
//! only sees the model's state, since the model forgets the core in `detach`.

use std::ffi::c_void;
use std::rc::Rc;

use simavr_ffi as ffi;

/// A device model living next to one chip.
pub(crate) trait Device: 'static {
    /// The chip was reset. simavr has zeroed the I/O registers and dropped every cycle
    /// timer; `(*avr).cycle` still holds the pre-reset count and becomes 0 right after.
    fn reset(&self, avr: *mut ffi::avr_t);
    /// The chip is being destroyed: unregister every hook, cancel every timer and forget
    /// the core.
    fn detach(&self, avr: *mut ffi::avr_t);
}

/// The I/O module linked into the core. `io` comes first, so simavr's `*mut avr_io_t`
/// is also a `*mut Module`.
#[repr(C)]
struct Module {
    io: ffi::avr_io_t,
    device: Rc<dyn Device>,
    /// The `custom.deinit` hook (and its data) that was installed before this one.
    prev_deinit: Option<unsafe extern "C" fn(*mut ffi::avr_t, *mut c_void)>,
    prev_data: *mut c_void,
}

/// Links `device` into the live core `avr` until the core is terminated.
pub(crate) fn attach(avr: *mut ffi::avr_t, device: Rc<dyn Device>) {
    let module = Box::new(Module {
        io: ffi::avr_io_t {
            next: std::ptr::null_mut(),
            avr: std::ptr::null_mut(),
            kind: c"rover-device".as_ptr(),
            irq_names: std::ptr::null_mut(),
            irq_ioctl_get: 0,
            irq_count: 0,
            irq: std::ptr::null_mut(),
            reset: Some(on_reset),
            ioctl: None,
            dealloc: None,
        },
        device,
        prev_deinit: None,
        prev_data: std::ptr::null_mut(),
    });
    let raw = Box::into_raw(module);
    // SAFETY: `avr` is a live, initialised core and `raw` a fresh heap allocation that
    // stays put until `on_deinit` takes it back; simavr only links `io` into its list and
    // calls `on_reset` with it. The previous custom hook is kept and chained.
    unsafe {
        (*raw).prev_deinit = (*avr).custom.deinit;
        (*raw).prev_data = (*avr).custom.data;
        ffi::avr_register_io(avr, std::ptr::addr_of_mut!((*raw).io));
        (*avr).custom.deinit = Some(on_deinit);
        (*avr).custom.data = raw.cast();
    }
}

/// simavr's reset callback of the module.
unsafe extern "C" fn on_reset(io: *mut ffi::avr_io_t) {
    // SAFETY: `io` is the first field of a live `Module` (it is unlinked before it is
    // freed), and `io.avr` is the core resetting it.
    let (module, avr) = unsafe { (&*io.cast::<Module>(), (*io).avr) };
    module.device.reset(avr);
}

/// `custom.deinit`: runs first in `avr_terminate`, while the core is still whole.
unsafe extern "C" fn on_deinit(avr: *mut ffi::avr_t, data: *mut c_void) {
    // SAFETY: `data` is the pointer `attach` leaked with `Box::into_raw`; `custom.data`
    // pointed at it until now and nothing else frees it.
    let module = unsafe { Box::from_raw(data.cast::<Module>()) };
    module.device.detach(avr);
    // SAFETY: the core is live; the module is removed from its I/O list before the box
    // is freed, so `avr_deallocate_ios` never sees it.
    unsafe {
        unlink(avr, std::ptr::addr_of!(module.io).cast_mut());
        (*avr).custom.deinit = module.prev_deinit;
        (*avr).custom.data = module.prev_data;
        if let Some(prev) = module.prev_deinit {
            prev(avr, module.prev_data);
        }
    }
}

/// Removes `io` from the core's list of I/O modules.
///
/// # Safety
/// `avr` must be a live core whose I/O list is well formed.
unsafe fn unlink(avr: *mut ffi::avr_t, io: *mut ffi::avr_io_t) {
    // SAFETY: per the contract, every `next` in the list is a valid module or NULL.
    unsafe {
        let mut link: *mut *mut ffi::avr_io_t = std::ptr::addr_of_mut!((*avr).io_port);
        while !(*link).is_null() {
            if *link == io {
                *link = (*io).next;
                return;
            }
            link = std::ptr::addr_of_mut!((**link).next);
        }
    }
}

/// Why a device could not be attached.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum AttachError {
    /// The pin's port does not exist on the ATmega328P (only B, C and D do).
    #[error("pin {port}{bit} does not exist on the ATmega328P; use a pin of port B, C or D")]
    NoSuchPin {
        /// The port letter asked for.
        port: char,
        /// The bit asked for.
        bit: u8,
    },
}

/// Registers `notify` with `param` on `irq`.
///
/// # Safety
/// `irq` must belong to a live core and `param` must stay valid until the hook is
/// unregistered with [`unhook`].
pub(crate) unsafe fn hook(
    irq: *mut ffi::avr_irq_t,
    notify: ffi::avr_irq_notify_t,
    param: *const c_void,
) {
    if !irq.is_null() {
        // SAFETY: per the contract.
        unsafe { ffi::avr_irq_register_notify(irq, notify, param.cast_mut()) };
    }
}

/// Unregisters a hook installed with [`hook`].
///
/// # Safety
/// `irq` must belong to a live core.
pub(crate) unsafe fn unhook(
    irq: *mut ffi::avr_irq_t,
    notify: ffi::avr_irq_notify_t,
    param: *const c_void,
) {
    if !irq.is_null() {
        // SAFETY: per the contract; unregistering a hook that is not there is a no-op.
        unsafe { ffi::avr_irq_unregister_notify(irq, notify, param.cast_mut()) };
    }
}
