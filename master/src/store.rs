//! Idle's state that needs no hardware to build, in static memory from the start.
//!
//! Everything a task owns normally comes from `init`'s result, which passes through the
//! stack on its way into the executor's resources. For the master's ~700 bytes of
//! frame buffer, read sets, schedule, sensors and remote-control state that transient
//! was larger than the stack left free (2 KB of RAM in all). Built by `const fn`s, this
//! state is instead laid out by the linker (zeros in `.bss`, the rest in `.data`), and
//! `init` only hands idle a reference to it.

use core::cell::UnsafeCell;

/// A value in static memory, handed out once as `&'static mut`.
pub struct Store<T>(UnsafeCell<T>);

// SAFETY: the value is reached only through `Store::take`, whose contract lets it be
// called once, so at most one reference to the value ever exists, held by one task.
unsafe impl<T: Send> Sync for Store<T> {}

impl<T> Store<T> {
    /// A store holding `value`, built at compile time.
    pub const fn new(value: T) -> Self {
        Store(UnsafeCell::new(value))
    }

    /// The value, for its one owner.
    ///
    /// # Safety
    /// Called at most once per store for the program's whole run (from `init`, which
    /// runs once), so the reference returned is the only one.
    // A `&mut` from `&self` is the point of the store; the contract above is what makes
    // it unique, as a `static mut` would need the same promise.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn take(&'static self) -> &'static mut T {
        // SAFETY: per the contract, no other reference to the value exists or will.
        unsafe { &mut *self.0.get() }
    }
}
