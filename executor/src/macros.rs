//! [`app!`](crate::app): the one place where an application states its resources, its
//! tasks, their vectors and priorities, and what each task uses.

/// Declares an application, RTIC style, in one place and up front.
///
/// ```text
/// executor::app! {
///     #[shared]
///     struct Shared {
///         trace: Trace,
///         ticks: u16,
///     }
///
///     #[local]
///     struct Local {
///         steps: u8,
///     }
///
///     #[init]
///     fn init;
///
///     #[idle(shared = [ticks])]
///     fn idle;
///
///     #[task(binds = TIMER1_COMPA, priority = 1, shared = [trace, ticks], local = [steps])]
///     fn tick;
///
///     #[task(binds = USART_UDRE, priority = 2, shared = [trace], gated = true)]
///     fn send;
/// }
///
/// fn init(cx: init::Context) -> (Shared, Local) { /* configure cx.device */ }
/// fn idle(mut cx: idle::Context) -> ! { loop { cx.sleep.sleep() } }
/// fn tick(mut cx: tick::Context) { cx.shared.ticks.lock(|t| *t += 1); *cx.local.steps += 1; }
/// fn send(mut cx: send::Context) { /* ... */ send::disarm(); }
/// ```
///
/// - `#[shared]` lists the resources that tasks share, `#[local]` those that one task owns
///   (task-local state). `init` returns their initial values, runs with interrupts off and
///   gets the device peripherals as `cx.device`.
/// - A task (or idle) may also own local resources declared with a constant value in its
///   attribute, `const_local = [name: Type = expr, ...]`: each is a `static` built at
///   compile time ([`LocalCell`](crate::LocalCell)), never returned by `init`, handed to
///   the task as `cx.local.name: &mut Type`.
/// - `#[idle]` is optional: idle runs at priority 0 and sleeps with `cx.sleep`. Without
///   it, the executor's idle sleeps between interrupts.
/// - Each `#[task]` binds a vector (the ATmega328P vector names of [`Source`](crate::Source))
///   at a priority 1..=[`MAX_PRIORITY`](crate::MAX_PRIORITY), in this order: `binds`,
///   `priority`, then optionally `shared`, `local`, `const_local` and `gated = true` (see
///   [`gate`](crate::gate)).
///
/// Each task `t` gets a module `t` with `t::Context`: `cx.shared.r` is a handle with
/// `lock` (or direct access when the resource's ceiling equals the task's priority),
/// `cx.local.r` is `&mut`. The macro computes every ceiling and mask at compile time and
/// rejects inconsistent declarations (a local used twice, a vector bound twice, a priority
/// out of range) with a compile error. The firmware crate needs `avr-device` as a direct
/// dependency and `#![feature(abi_avr_interrupt)]`, as for any AVR interrupt handler.
///
/// A task's context lives for one run. Its `&mut` to a local resource cannot be kept for
/// the next run (which gets a new one to the same value), so a task that claims a context
/// for ever does not compile:
///
/// ```compile_fail,E0597
/// executor::app! {
///     #[shared]
///     struct Shared { count: u8 }
///
///     #[local]
///     struct Local { steps: u8 }
///
///     #[init]
///     fn init;
///
///     #[task(binds = ADC, priority = 1, local = [steps])]
///     fn adc;
/// }
///
/// fn init(_cx: init::Context) -> (Shared, Local) {
///     (Shared { count: 0 }, Local { steps: 0 })
/// }
///
/// fn adc(cx: adc::Context<'static>) {
///     let kept: &'static mut u8 = cx.local.steps;
///     *kept += 1;
/// }
/// # fn main() {}
/// ```
///
/// The same task with the context's lifetime left to the compiler:
///
/// ```
/// # executor::app! {
/// #     #[shared]
/// #     struct Shared { count: u8 }
/// #
/// #     #[local]
/// #     struct Local { steps: u8 }
/// #
/// #     #[init]
/// #     fn init;
/// #
/// #     #[task(binds = ADC, priority = 1, local = [steps])]
/// #     fn adc;
/// # }
/// #
/// # fn init(_cx: init::Context) -> (Shared, Local) {
/// #     (Shared { count: 0 }, Local { steps: 0 })
/// # }
/// #
/// fn adc(cx: adc::Context) {
///     let this_run: &mut u8 = cx.local.steps;
///     *this_run += 1;
/// }
/// # fn main() {}
/// ```
#[macro_export]
macro_rules! app {
    (
        #[shared]
        struct Shared {
            $($sname:ident : $sty:ty),* $(,)?
        }

        #[local]
        struct Local {
            $($lname:ident : $lty:ty),* $(,)?
        }

        #[init]
        fn $init:ident;

        $(
            #[idle( $(shared = [$($ishared:ident),* $(,)?])? $(,)?
                    $(local = [$($ilocal:ident),* $(,)?])? $(,)?
                    $(const_local = [$($iclocal:ident : $iclty:ty = $iclinit:expr),* $(,)?])? )]
            fn $idle:ident;
        )?

        $(
            #[task(binds = $vector:ident, priority = $prio:literal
                $(, shared = [$($tshared:ident),* $(,)?])?
                $(, local = [$($tlocal:ident),* $(,)?])?
                $(, const_local = [$($tclocal:ident : $tclty:ty = $tclinit:expr),* $(,)?])?
                $(, gated = $gated:tt)? $(,)?)]
            fn $task:ident;
        )*
    ) => {
        /// Initial values of the shared resources, returned by `init`.
        pub struct Shared {
            $(
                #[allow(missing_docs)]
                pub $sname: $sty,
            )*
        }

        /// Initial values of the local resources, returned by `init`.
        pub struct Local {
            $(
                #[allow(missing_docs)]
                pub $lname: $lty,
            )*
        }

        #[doc(hidden)]
        #[allow(non_camel_case_types, dead_code)]
        enum __ExecSharedId {
            $($sname,)*
        }

        #[doc(hidden)]
        #[allow(non_camel_case_types, dead_code)]
        enum __ExecLocalId {
            $($lname,)*
        }

        #[doc(hidden)]
        #[allow(non_camel_case_types, unused_imports)]
        mod __exec_stypes {
            use super::*;
            $(pub type $sname = $sty;)*
        }

        #[doc(hidden)]
        #[allow(non_camel_case_types, unused_imports)]
        mod __exec_ltypes {
            use super::*;
            $(pub type $lname = $lty;)*
        }

        /// Every resource, in one cell that `main` fills with `init`'s result in place.
        #[doc(hidden)]
        static __EXEC_RESOURCES: $crate::ResourceCell<(Shared, Local)> =
            $crate::ResourceCell::uninit();

        /// The task table the analysis runs on (hardware tasks, then idle).
        #[doc(hidden)]
        const __EXEC_TASKS: &[$crate::analysis::Task] = &[
            $(
                $crate::analysis::Task {
                    binds: ::core::option::Option::Some($crate::Source::$vector),
                    priority: $prio,
                    shared: &[$($(__ExecSharedId::$tshared as u8,)*)?],
                    local: &[$($(__ExecLocalId::$tlocal as u8,)*)?],
                    gated: $crate::__exec_flag!($($gated)?),
                },
            )*
            $(
                $crate::__exec_idle_entry!(
                    $idle,
                    [$($(__ExecSharedId::$ishared as u8,)*)?],
                    [$($(__ExecLocalId::$ilocal as u8,)*)?]
                ),
            )?
        ];

        const _: () = $crate::analysis::assert_valid(
            __EXEC_TASKS,
            <[&str]>::len(&[$(stringify!($sname)),*]),
            <[&str]>::len(&[$(stringify!($lname)),*]),
        );

        /// The application's constants, computed from the task table at compile time.
        #[doc(hidden)]
        pub struct __ExecApp;

        impl $crate::App for __ExecApp {
            const TOP: u8 = $crate::analysis::top(__EXEC_TASKS);
            const MASKS: $crate::LevelMasks = $crate::analysis::level_masks(__EXEC_TASKS);
            const GATED: $crate::RegBits = $crate::analysis::gated_bits(__EXEC_TASKS);
            const START: $crate::RegBits = $crate::analysis::start_bits(__EXEC_TASKS);
            const EXACT: [bool; $crate::source::REG_COUNT] =
                $crate::analysis::exact_restore(&$crate::analysis::gated_bits(__EXEC_TASKS));
        }

        /// The ceiling of each shared resource.
        #[doc(hidden)]
        #[allow(non_upper_case_globals)]
        mod __exec_ceil {
            $(
                pub const $sname: u8 = $crate::analysis::ceiling(
                    super::__EXEC_TASKS,
                    super::__ExecSharedId::$sname as u8,
                );
            )*
        }

        /// `init`'s context.
        pub mod $init {
            /// What `init` gets: the device peripherals, before any task can run.
            pub struct Context {
                /// The peripherals, to configure and to move into resources.
                pub device: $crate::Device,
            }

            impl Context {
                /// Created once, by the generated `main`.
                ///
                /// # Safety
                /// Called once, before anything else uses the peripherals.
                #[doc(hidden)]
                #[inline(always)]
                pub unsafe fn new() -> Self {
                    Context {
                        // SAFETY: per this function's contract.
                        device: unsafe { $crate::__private::take_device() },
                    }
                }
            }
        }

        $(
            $crate::__exec_context!(
                $idle, 0,
                [$($($ishared),*)?],
                [$($($ilocal),*)?],
                [$($($iclocal : $iclty = $iclinit),*)?],
                {
                    /// Idle's right to sleep the CPU.
                    pub sleep: $crate::Sleep,
                },
                {
                    // SAFETY: this is idle's context, created once by `main`.
                    sleep: unsafe { $crate::Sleep::new() },
                },
                {}
            );
        )?

        $(
            $crate::__exec_context!(
                $task, $prio,
                [$($($tshared),*)?],
                [$($($tlocal),*)?],
                [$($($tclocal : $tclty = $tclinit),*)?],
                {},
                {},
                {
                    $crate::__exec_gate_fns!($vector $(, $gated)?);

                    /// Runs the task once, with a context that lives for this run only.
                    ///
                    /// # Safety
                    /// Called only by the task's vector (or a host test standing in for
                    /// it), after the resources were stored, one run at a time.
                    #[doc(hidden)]
                    #[inline(always)]
                    pub unsafe fn __run() {
                        let run = ();
                        // SAFETY: per this function's contract.
                        super::$task(unsafe { Context::new(&run) })
                    }
                }
            );

            // The task's level, as an absolute symbol `__exec_level_<vector>` (no flash):
            // the static stack bound reads the levels from the image, not from a copy.
            #[cfg(target_arch = "avr")]
            ::core::arch::global_asm!(
                ".global __exec_level_{vector}",
                ".set __exec_level_{vector}, {level}",
                vector = const $crate::Source::$vector.vector(),
                level = const $task::PRIORITY,
            );

            #[cfg(target_arch = "avr")]
            #[avr_device::interrupt(atmega328p)]
            fn $vector() {
                // SAFETY: this is the vector of the source bound to the task, entered with
                // interrupts disabled; the context is created once for this run.
                unsafe { $crate::__private::dispatch::<__ExecApp, { $task::PRIORITY }>(|| $task::__run()) }
            }
        )*

        /// Runs `init` and stores its result. Not inlined, so that the stack space the
        /// result may pass through is given back before idle runs on the same stack.
        ///
        /// # Safety
        /// Called once, by `main`, with interrupts off.
        #[cfg(target_arch = "avr")]
        #[inline(never)]
        unsafe fn __exec_setup() {
            // SAFETY: interrupts have been off since reset and stay off until `start`
            // enables them: `init` runs once, with the only context it will ever get,
            // and its result is stored once, before anyone can read it.
            unsafe { __EXEC_RESOURCES.write($init($init::Context::new())) };
        }

        #[cfg(target_arch = "avr")]
        #[avr_device::entry]
        fn main() -> ! {
            // SAFETY: `main` runs once, with interrupts off since reset; `start` enables
            // them only after the resources are stored.
            unsafe {
                __exec_setup();
                $crate::__private::start::<__ExecApp>();
            }
            $crate::__exec_run_idle!($($idle)?)
        }
    };
}

/// `gated = true` → `true`; absent or `false` → `false`.
#[doc(hidden)]
#[macro_export]
macro_rules! __exec_flag {
    () => {
        false
    };
    (true) => {
        true
    };
    (false) => {
        false
    };
}

/// Idle's row of the task table.
#[doc(hidden)]
#[macro_export]
macro_rules! __exec_idle_entry {
    ($idle:ident, [$($shared:expr,)*], [$($local:expr,)*]) => {
        $crate::analysis::Task {
            binds: ::core::option::Option::None,
            priority: 0,
            shared: &[$($shared,)*],
            local: &[$($local,)*],
            gated: false,
        }
    };
}

/// `arm`/`disarm` for a gated task's module.
#[doc(hidden)]
#[macro_export]
macro_rules! __exec_gate_fns {
    ($vector:ident) => {};
    ($vector:ident, false) => {};
    ($vector:ident, true) => {
        /// Arms the task's interrupt source: the driver has work for it.
        #[inline(always)]
        pub fn arm() {
            $crate::gate::arm::<
                super::__ExecApp,
                { $crate::Source::$vector.reg().index() },
                { $crate::Source::$vector.bit() },
            >();
        }

        /// Disarms the task's interrupt source until it is armed again.
        #[inline(always)]
        pub fn disarm() {
            $crate::gate::disarm::<
                super::__ExecApp,
                { $crate::Source::$vector.reg().index() },
                { $crate::Source::$vector.bit() },
            >();
        }
    };
}

/// The context module of a task or of idle.
#[doc(hidden)]
#[macro_export]
macro_rules! __exec_context {
    (
        $name:ident, $prio:expr,
        [$($shared:ident),*],
        [$($local:ident),*],
        [$($clocal:ident : $clty:ty = $clinit:expr),*],
        { $($extra_field:tt)* },
        { $($extra_init:tt)* },
        { $($items:tt)* }
    ) => {
        /// The context and priority of this task.
        pub mod $name {
            /// The task's static priority.
            pub const PRIORITY: u8 = $prio;

            /// The shared resources the task declared.
            pub struct SharedResources<'a> {
                $(
                    #[allow(missing_docs)]
                    pub $shared: $crate::Shared<
                        'a,
                        super::__exec_stypes::$shared,
                        super::__ExecApp,
                        { super::__exec_ceil::$shared },
                        { PRIORITY },
                    >,
                )*
                #[doc(hidden)]
                pub __life: ::core::marker::PhantomData<&'a ()>,
            }

            /// The task's local resources declared with their values (`const_local`):
            /// each a static built at compile time, its type under the same name.
            #[doc(hidden)]
            #[allow(non_camel_case_types, non_upper_case_globals)]
            pub mod __const_local {
                #[allow(unused_imports)]
                use super::super::*;
                $(
                    pub type $clocal = $clty;
                    pub static $clocal: $crate::LocalCell<$clty> = $crate::LocalCell::new($clinit);
                )*
            }

            /// The local resources the task owns.
            pub struct LocalResources<'a> {
                $(
                    #[allow(missing_docs)]
                    pub $local: &'a mut super::__exec_ltypes::$local,
                )*
                $(
                    #[allow(missing_docs)]
                    pub $clocal: &'a mut __const_local::$clocal,
                )*
                #[doc(hidden)]
                pub __life: ::core::marker::PhantomData<&'a ()>,
            }

            /// What the task gets each time it runs.
            pub struct Context<'a> {
                /// Handles on the shared resources.
                pub shared: SharedResources<'a>,
                /// The task's own resources.
                pub local: LocalResources<'a>,
                $($extra_field)*
            }

            impl<'a> Context<'a> {
                /// Created by the generated vector (or `main` for idle), once per run.
                /// Its lifetime is that of `_run`, a local of the caller: a task's
                /// context (and every `&mut` it hands out) cannot outlive the run, so
                /// a task declared with `Context<'static>` does not compile.
                ///
                /// # Safety
                /// Called only there, after the resources were stored.
                #[doc(hidden)]
                #[inline(always)]
                pub unsafe fn new(_run: &'a ()) -> Self {
                    Context {
                        shared: SharedResources {
                            $(
                                // SAFETY: per this function's contract; the handle
                                // carries the resource's ceiling and this priority.
                                $shared: unsafe {
                                    $crate::Shared::from_ptr(::core::ptr::addr_of_mut!(
                                        (*super::__EXEC_RESOURCES.as_mut_ptr()).0.$shared
                                    ))
                                },
                            )*
                            __life: ::core::marker::PhantomData,
                        },
                        local: LocalResources {
                            $(
                                // SAFETY: this task is the resource's only owner
                                // (checked at compile time) and runs one at a time.
                                $local: unsafe {
                                    &mut *::core::ptr::addr_of_mut!(
                                        (*super::__EXEC_RESOURCES.as_mut_ptr()).1.$local
                                    )
                                },
                            )*
                            $(
                                // SAFETY: the cell is declared in this task's attribute,
                                // so this context is its only user, and the task runs one
                                // at a time.
                                $clocal: unsafe { &mut *__const_local::$clocal.as_mut_ptr() },
                            )*
                            __life: ::core::marker::PhantomData,
                        },
                        $($extra_init)*
                    }
                }
            }

            $($items)*
        }
    };
}

/// Runs the declared idle, or the executor's sleeping one.
#[doc(hidden)]
#[macro_export]
macro_rules! __exec_run_idle {
    () => {
        // SAFETY: this is `main` running idle, after start.
        unsafe { $crate::__private::default_idle() }
    };
    ($idle:ident) => {{
        let run = ();
        // SAFETY: idle's only context, created after start.
        $idle(unsafe { $idle::Context::new(&run) })
    }};
}
