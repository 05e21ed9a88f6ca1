//! Resource storage and the proxies through which tasks reach it.
//!
//! A resource lives in a [`ResourceCell`], a plain `static` that only the code
//! [`crate::app!`] generates can open. A task reaches a shared resource only through the
//! [`Shared`] proxy in its context, and a local one only as the `&mut` in its context, so
//! there is no other path to the data: data-race freedom holds by construction. A local
//! resource declared with its value (`const_local`) lives in its own [`LocalCell`],
//! a `static` built at compile time, opened only by its task's context.

use core::cell::UnsafeCell;
use core::marker::PhantomData;
use core::mem::MaybeUninit;
use core::ops::{Deref, DerefMut};

use crate::App;

/// Storage of an application's resources: written once by the generated `main` before
/// interrupts are enabled, then reached only through task contexts.
pub struct ResourceCell<T>(UnsafeCell<MaybeUninit<T>>);

// SAFETY: the cell is only opened through task contexts. A shared resource is handed out
// by `Shared::lock`, which excludes every other user by the priority-ceiling protocol; a
// local one belongs to exactly one task (checked at compile time by
// `analysis::validate`). Values move between priority levels, hence `T: Send`.
unsafe impl<T: Send> Sync for ResourceCell<T> {}

impl<T> ResourceCell<T> {
    /// An empty cell.
    #[allow(clippy::new_without_default)]
    pub const fn uninit() -> Self {
        ResourceCell(UnsafeCell::new(MaybeUninit::uninit()))
    }

    /// Stores the initial value.
    ///
    /// # Safety
    /// Called once per cell, by the generated `main` after `init` returns and before
    /// interrupts are enabled, so nothing else can be looking at the cell.
    #[inline(always)]
    pub unsafe fn write(&self, value: T) {
        // SAFETY: exclusive access per the contract above.
        unsafe { (*self.0.get()).write(value) };
    }

    /// Pointer to the value (to a resource field of it, in generated contexts). Reading or
    /// writing through it is sound only after [`ResourceCell::write`], and only under the
    /// access rules of the resource it points to.
    #[inline(always)]
    pub fn as_mut_ptr(&self) -> *mut T {
        self.0.get().cast()
    }
}

/// Storage of one task's local resource declared with its value (`const_local`): built by
/// a constant expression, laid out by the linker (`.bss` when all zeros, else `.data`),
/// so it never passes through `init` or the stack. Only the owning task's generated
/// context opens it.
pub struct LocalCell<T>(UnsafeCell<T>);

// SAFETY: the cell is opened only by the generated context of the one task that declares
// it, and a task's runs never overlap (a task preempts only lower priorities, never
// itself), so at most one `&mut` to the value exists at a time. The value is built at
// compile time and used at the task's priority, hence `T: Send`.
unsafe impl<T: Send> Sync for LocalCell<T> {}

impl<T> LocalCell<T> {
    /// A cell holding `value`, built at compile time.
    pub const fn new(value: T) -> Self {
        LocalCell(UnsafeCell::new(value))
    }

    /// Pointer to the value. Dereferencing it is sound only in the owning task's context,
    /// which the generated code alone creates.
    #[inline(always)]
    pub fn as_mut_ptr(&self) -> *mut T {
        self.0.get()
    }
}

/// A task's handle on a shared resource with ceiling `C`, for a task of priority `P`.
///
/// [`Shared::lock`] raises the system to the ceiling for the duration of a closure. When
/// the ceiling equals the task's priority (the task is the resource's only user, or all
/// its users have the same priority), no other user can run while the task does, so the
/// handle dereferences directly to the data, with no lock at all.
pub struct Shared<'a, T, A: App, const C: u8, const P: u8> {
    ptr: *mut T,
    _life: PhantomData<(&'a mut T, A)>,
}

impl<'a, T, A: App, const C: u8, const P: u8> Shared<'a, T, A, C, P> {
    /// The handle for the resource at `ptr`.
    ///
    /// # Safety
    /// Only generated task contexts create handles: one per resource the task declares,
    /// with `C` the resource's computed ceiling and `P` the task's priority, and `ptr`
    /// pointing into the application's written `ResourceCell`.
    #[inline(always)]
    pub unsafe fn from_ptr(ptr: *mut T) -> Self {
        Shared {
            ptr,
            _life: PhantomData,
        }
    }

    /// Runs `f` on the resource with the system ceiling raised to `C`: every task that
    /// could touch the resource is held off, every task above the ceiling still runs.
    ///
    /// Taking `&mut self` keeps a task from locking the same resource twice in nested
    /// closures, which would hand out two `&mut` to one value.
    #[inline(always)]
    pub fn lock<R>(&mut self, f: impl FnOnce(&mut T) -> R) -> R {
        const {
            assert!(
                C >= P,
                "a resource's ceiling is at least each user's priority"
            )
        };
        if C == P {
            // SAFETY: no user of the resource can preempt a task at its ceiling, and
            // `&mut self` excludes a second borrow through this handle.
            f(unsafe { &mut *self.ptr })
        } else {
            // SAFETY: the handle is the only way to the value, and `port::lock` keeps
            // every other user from running until `f` returns.
            unsafe { crate::port::lock::<A, C, P, T, R>(self.ptr, f) }
        }
    }
}

impl<T, A: App, const P: u8> Deref for Shared<'_, T, A, P, P> {
    type Target = T;

    #[inline(always)]
    fn deref(&self) -> &T {
        // SAFETY: the ceiling equals the task's priority, so no other user runs while this
        // task holds the handle.
        unsafe { &*self.ptr }
    }
}

impl<T, A: App, const P: u8> DerefMut for Shared<'_, T, A, P, P> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut T {
        // SAFETY: as for `deref`, and `&mut self` makes the borrow unique.
        unsafe { &mut *self.ptr }
    }
}
