//! Attaching Rust code to one chip's TWI IRQs.

use std::cell::RefCell;
use std::ffi::c_void;

use simavr_ffi as ffi;

use super::reg::{TWCR, TWINT};
use super::{TwiError, TwiMsg};
use crate::avr::{ioctl_def, Shared};
use crate::Avr;

/// Handles one message from a chip's TWI output; a returned message is raised on the same
/// chip's TWI input before the chip continues (the answer a master chip waits for).
pub(crate) type Handler = Box<dyn FnMut(TwiMsg) -> Option<TwiMsg>>;

/// The TWI input and output IRQs of one chip.
#[derive(Clone, Copy)]
pub(crate) struct TwiIrqs {
    input: *mut ffi::avr_irq_t,
    output: *mut ffi::avr_irq_t,
}

impl TwiIrqs {
    /// Looks up the TWI IRQs of a live core.
    pub fn find(avr: *mut ffi::avr_t) -> Result<TwiIrqs, TwiError> {
        // The ATmega328P's TWI has no name character: its ioctl is 't','w','i',0.
        let ctl = ioctl_def(b't', b'w', b'i', 0);
        // SAFETY: `avr` is a live, initialised core; simavr returns NULL for unknown IRQs.
        let (input, output) = unsafe {
            (
                ffi::avr_io_getirq(avr, ctl, ffi::TWI_IRQ_INPUT as i32),
                ffi::avr_io_getirq(avr, ctl, ffi::TWI_IRQ_OUTPUT as i32),
            )
        };
        if input.is_null() || output.is_null() {
            return Err(TwiError::NoTwi);
        }
        Ok(TwiIrqs { input, output })
    }

    /// Raises `msg` on the chip's TWI input.
    ///
    /// The caller must hold the chip exclusively (simavr runs the chip's TWI code inside).
    pub fn send(&self, msg: TwiMsg) {
        // SAFETY: `input` belongs to a core that outlives this value (the owner of the chip
        // keeps both together), and simavr's handler only touches that core.
        unsafe { ffi::avr_raise_irq(self.input, msg.to_raw()) };
    }
}

/// What the registered hook points at.
struct TapInner {
    irqs: TwiIrqs,
    handler: RefCell<Handler>,
}

/// A handler registered on a chip's TWI output; unregistered on drop.
///
/// It must be dropped before the chip it is attached to.
pub(crate) struct Tap {
    inner: Box<TapInner>,
}

impl Tap {
    /// Registers `handler` for every message the chip's TWI raises on its output.
    pub fn attach(irqs: TwiIrqs, handler: Handler) -> Tap {
        let inner = Box::new(TapInner {
            irqs,
            handler: RefCell::new(handler),
        });
        // SAFETY: the IRQ belongs to a live core; `param` points into the box, whose heap
        // address stays put until `drop` unregisters the hook.
        unsafe {
            ffi::avr_irq_register_notify(irqs.output, Some(on_output), inner.param());
        }
        Tap { inner }
    }
}

impl TapInner {
    fn param(&self) -> *mut c_void {
        (self as *const TapInner).cast_mut().cast()
    }
}

impl Drop for Tap {
    fn drop(&mut self) {
        // SAFETY: the same IRQ, function and parameter as registered; the core is still
        // alive (documented contract of `Tap`).
        unsafe {
            ffi::avr_irq_unregister_notify(
                self.inner.irqs.output,
                Some(on_output),
                self.inner.param(),
            );
        }
    }
}

/// simavr's notify hook for a chip's TWI output.
unsafe extern "C" fn on_output(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    // SAFETY: `param` is the `TapInner` registered in `Tap::attach`, alive until the hook is
    // unregistered; only shared references to it are made.
    let inner = unsafe { &*param.cast::<TapInner>() };
    // A handler that is already running (re-entry) is not run again: no answer means NACK.
    let reply = match inner.handler.try_borrow_mut() {
        Ok(mut handler) => handler(TwiMsg::from_raw(value)),
        Err(_) => None,
    };
    if let Some(reply) = reply {
        inner.irqs.send(reply);
    }
}

/// Makes a master chip's TWINT wait while another device holds SCL low
/// ([`Shared::scl_held`]): the firmware reads TWCR without it, as a real TWI cannot finish
/// a START, address or byte on a clock it cannot drive. simavr completes the step in zero
/// time regardless and stores what this hook returns, so a step begun while the clock was
/// held never completes: the firmware's own bounded wait must give it up.
pub(crate) fn gate_twint(avr: &mut Avr) {
    let param = (&*avr.shared as *const Shared).cast_mut().cast();
    // SAFETY: the core is live and not running; `param` is its boxed `Shared`, which
    // lives as long as the core. simavr's TWI registers no read handler on TWCR, and a
    // second call registers the same handler and parameter, which simavr accepts.
    unsafe { ffi::avr_register_io_read(avr.as_ptr(), TWCR, Some(read_twcr), param) };
}

/// simavr's read handler for a master chip's TWCR.
unsafe extern "C" fn read_twcr(avr: *mut ffi::avr_t, addr: u16, param: *mut c_void) -> u8 {
    // SAFETY: simavr calls this with its live core and the `Shared` registered in
    // `gate_twint`; `addr` is TWCR, inside the core's data space.
    let (shared, value) = unsafe {
        (
            &*param.cast::<Shared>(),
            *(*avr).data.add(usize::from(addr)),
        )
    };
    if shared.scl_held.get() {
        value & !TWINT
    } else {
        value
    }
}
