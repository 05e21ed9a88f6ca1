//! An RC receiver on three input pins of an emulated chip: the master's D2 (drive), D3
//! (steer) and D4 (mode).
//!
//! While on, it sends a frame every 20 ms: channel 0's pulse, then channel 1's starting
//! as channel 0's ends, then channel 2's, as receivers that decode a pulse train do; then
//! the pins stay low until the next frame. Widths are set per channel (µs, 500..=2500,
//! default 1500) and take effect from the next frame. It is off (pins low, no edges)
//! until [`RcReceiver::turn_on`]. Edges are raised on the pins from simavr cycle timers,
//! so they wake a sleeping CPU and raise pin-change interrupts. They are scheduled on
//! exact cycles, without drift; simavr applies each at the first instruction boundary at
//! or after its cycle, so an edge may land up to a few cycles late. A chip reset
//! restarts the frame.
//!
//! # Example
//! ```no_run
//! use harness::rc::RcReceiver;
//! use harness::Avr;
//!
//! let mut avr = Avr::firmware("fixture_rc")?;
//! let rc = RcReceiver::attach(&mut avr);
//! rc.set_width(0, 1000);
//! rc.turn_on();
//! avr.run_us(100_000);
//! # Ok::<(), harness::HarnessError>(())
//! ```

use std::cell::{Cell, RefCell};
use std::ffi::c_void;
use std::rc::Rc;

use simavr_ffi as ffi;

use crate::avr::{ioctl_def, CYCLES_PER_US};
use crate::onewire::hook;
use crate::{uno, Avr, Pin};

/// The receiver's channel pins: D2, D3, D4 (PD2..PD4, PCINT18..20).
pub const RC_PINS: [Pin; 3] = [uno::D2, uno::D3, uno::D4];
/// Frame period, µs.
pub const FRAME_US: u64 = 20_000;
/// The widths the channels start with, µs: the sticks at rest on the rover's transmitter
/// (reference §9.2's ranges): drive and steer centred, (1940 + 1000) / 2 and
/// (1738 + 940) / 2, and the mode switch at normal steering (not crab). A receiver turned
/// on without settings then moves nothing (servo neutral, 1500 µs, would steer the rover
/// to full lock: on the steer channel it is outside the dead band).
pub const DEFAULT_WIDTHS_US: [u16; 3] = [1470, 1339, 910];
/// Shortest and longest width the receiver sends, µs.
pub const WIDTH_RANGE_US: (u16, u16) = (500, 2500);

/// Pin levels after each edge event of a frame, bit c for channel c.
const FRAME_LEVELS: [u8; 4] = [0b001, 0b010, 0b100, 0b000];

/// The receiver's state.
#[derive(Debug)]
struct State {
    on: bool,
    widths: [u16; 3],
    /// The widths of the frame being sent.
    frame: [u16; 3],
    /// The next edge event of the frame, 0..4.
    step: usize,
    /// Raw cycle the current frame started at.
    frame_start: u64,
    frames: u64,
}

/// The model shared by the chip's timer and the caller's handle.
struct Model {
    state: RefCell<State>,
    /// The chip's core; NULL once the chip is gone.
    core: Cell<*mut ffi::avr_t>,
    /// The three pins' IRQs.
    irqs: [*mut ffi::avr_irq_t; 3],
}

impl Model {
    fn param(&self) -> *mut c_void {
        std::ptr::from_ref(self).cast_mut().cast()
    }

    /// Sets the pins to `levels` (bit c for channel c): falls first, then rises.
    fn drive(&self, levels: u8) {
        for want_high in [false, true] {
            for (c, &irq) in self.irqs.iter().enumerate() {
                let high = levels & (1 << c) != 0;
                if high == want_high && !irq.is_null() {
                    // SAFETY: the IRQ belongs to the live core (only called while
                    // attached); unchanged levels are filtered by simavr.
                    unsafe { ffi::avr_raise_irq(irq, u32::from(high)) };
                }
            }
        }
    }

    /// Schedules the frame timer `delay` cycles from the core's current raw cycle.
    fn arm(&self, core: *mut ffi::avr_t, delay: u64) {
        // SAFETY: a live core; the parameter is this model, which the core keeps alive
        // and whose timer `detach` cancels.
        unsafe {
            ffi::avr_cycle_timer_register(core, delay, Some(on_timer), self.param());
        }
    }

    /// One edge event at raw cycle `when`; returns the raw cycle of the next (0: none).
    fn fire(&self, when: u64) -> u64 {
        let Ok(mut st) = self.state.try_borrow_mut() else {
            return 0;
        };
        if !st.on {
            return 0;
        }
        if st.step == 0 {
            st.frame_start = when;
            st.frame = st.widths;
            st.frames += 1;
        }
        let levels = FRAME_LEVELS[st.step];
        st.step = (st.step + 1) % FRAME_LEVELS.len();
        let offset_us: u64 = match st.step {
            0 => FRAME_US,
            n => st.frame[..n].iter().map(|&w| u64::from(w)).sum(),
        };
        let next = st.frame_start + offset_us * CYCLES_PER_US;
        drop(st);
        self.drive(levels);
        next
    }
}

unsafe extern "C" fn on_timer(
    _avr: *mut ffi::avr_t,
    when: ffi::avr_cycle_count_t,
    param: *mut c_void,
) -> ffi::avr_cycle_count_t {
    // SAFETY: `param` is the `Model` the core owns (see `hook`); `detach` cancels the
    // timer before the model can go.
    let model = unsafe { &*param.cast::<Model>() };
    model.fire(when)
}

impl hook::Device for Model {
    fn reset(&self, avr: *mut ffi::avr_t) {
        // The reset zeroed the PIN register but not the pins' IRQs, which only notify on
        // change: make them agree, or the next rising edge would go unseen.
        for &irq in &self.irqs {
            if !irq.is_null() {
                // SAFETY: the IRQ belongs to the live core being reset.
                unsafe { (*irq).value = 0 };
            }
        }
        let Ok(mut st) = self.state.try_borrow_mut() else {
            return;
        };
        st.step = 0;
        if st.on {
            drop(st);
            // simavr dropped every timer and is about to restart its cycle count at 0;
            // register against the new count.
            // SAFETY: the live core being reset; its cycle is set to 0 right after the
            // peripherals' reset callbacks anyway, and restored here until then.
            unsafe {
                let saved = (*avr).cycle;
                (*avr).cycle = 0;
                self.arm(avr, CYCLES_PER_US);
                (*avr).cycle = saved;
            }
        }
    }

    fn detach(&self, avr: *mut ffi::avr_t) {
        // SAFETY: the core is still whole during `custom.deinit`.
        unsafe { ffi::avr_cycle_timer_cancel(avr, Some(on_timer), self.param()) };
        self.core.set(std::ptr::null_mut());
    }
}

/// An RC receiver on D2, D3 and D4 of an emulated chip.
pub struct RcReceiver {
    model: Rc<Model>,
}

impl RcReceiver {
    /// Attaches a receiver, off, to `avr`'s D2, D3 and D4.
    pub fn attach(avr: &mut Avr) -> RcReceiver {
        let core = avr.as_ptr();
        let irqs = RC_PINS.map(|pin| {
            let ctl = ioctl_def(b'i', b'o', b'g', pin.port_name());
            // SAFETY: a live core; avr_io_getirq returns NULL for an unknown IRQ.
            unsafe { ffi::avr_io_getirq(core, ctl, i32::from(pin.bit)) }
        });
        let model = Rc::new(Model {
            state: RefCell::new(State {
                on: false,
                widths: DEFAULT_WIDTHS_US,
                frame: DEFAULT_WIDTHS_US,
                step: 0,
                frame_start: 0,
                frames: 0,
            }),
            core: Cell::new(core),
            irqs,
        });
        hook::attach(core, Rc::clone(&model) as Rc<dyn hook::Device>);
        RcReceiver { model }
    }

    /// Sets channel `channel`'s pulse width (µs, clamped to 500..=2500) from the next
    /// frame on.
    ///
    /// # Panics
    /// If `channel` is not 0, 1 or 2 (a mistake in the calling test).
    pub fn set_width(&self, channel: usize, us: u16) {
        let mut st = self.model.state.borrow_mut();
        let Some(w) = st.widths.get_mut(channel) else {
            panic!("the RC receiver has channels 0, 1 and 2, not {channel}");
        };
        *w = us.clamp(WIDTH_RANGE_US.0, WIDTH_RANGE_US.1);
    }

    /// The widths the next frame will carry, µs.
    pub fn widths(&self) -> [u16; 3] {
        self.model.state.borrow().widths
    }

    /// Starts sending frames; the first starts 1 µs from now.
    pub fn turn_on(&self) {
        let core = self.model.core.get();
        let mut st = self.model.state.borrow_mut();
        if st.on || core.is_null() {
            return;
        }
        st.on = true;
        st.step = 0;
        drop(st);
        self.model.arm(core, CYCLES_PER_US);
    }

    /// Stops sending: the pins go low and stay low.
    pub fn turn_off(&self) {
        let core = self.model.core.get();
        let mut st = self.model.state.borrow_mut();
        st.on = false;
        st.step = 0;
        drop(st);
        if !core.is_null() {
            // SAFETY: the live core; cancelling a timer that is not armed is a no-op.
            unsafe { ffi::avr_cycle_timer_cancel(core, Some(on_timer), self.model.param()) };
            self.model.drive(0);
        }
    }

    /// Whether the receiver is sending.
    pub fn is_on(&self) -> bool {
        self.model.state.borrow().on
    }

    /// Frames started since attached.
    pub fn frames(&self) -> u64 {
        self.model.state.borrow().frames
    }
}
