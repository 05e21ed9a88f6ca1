//! Host test of `app!`: the declaration expands, the ceilings and masks it computes are the
//! analysis results, and each context reaches exactly the resources its task declared.

use executor::analysis::{ceiling, level_masks};
use executor::{App, Reg, Source};

/// A record of which task touched it, for checking the context wiring.
#[derive(Default)]
pub struct Log {
    seen: Vec<&'static str>,
}

executor::app! {
    #[shared]
    struct Shared {
        log: Log,
        count: u16,
        own: u8,
    }

    #[local]
    struct Local {
        steps: u8,
        idle_runs: u32,
    }

    #[init]
    fn init;

    #[idle(shared = [count], local = [idle_runs], const_local = [banner: [u8; 2] = *b"hi"])]
    fn idle;

    #[task(binds = ADC, priority = 1, shared = [log, count], local = [steps],
           const_local = [total: u16 = 1000, last: Option<u8> = None])]
    fn adc;

    #[task(binds = TWI, priority = 2, shared = [log, own])]
    fn twi;

    #[task(binds = USART_UDRE, priority = 2, shared = [log], gated = true)]
    fn udre;

    #[task(binds = PCINT2, priority = 3, shared = [log])]
    fn encoder;
}

fn init(_cx: init::Context) -> (Shared, Local) {
    (
        Shared {
            log: Log::default(),
            count: 0,
            own: 0,
        },
        Local {
            steps: 0,
            idle_runs: 0,
        },
    )
}

#[allow(dead_code)]
fn idle(mut cx: idle::Context) -> ! {
    loop {
        *cx.local.idle_runs += 1;
        let c = cx.shared.count.lock(|c| *c);
        cx.sleep.sleep_unless(|| c > 0);
    }
}

fn adc(mut cx: adc::Context) {
    *cx.local.steps += 1;
    *cx.local.total += 1;
    *cx.local.last = Some(*cx.local.steps);
    cx.shared.log.lock(|l| l.seen.push("adc"));
    cx.shared.count.lock(|c| *c += 1);
}

fn twi(mut cx: twi::Context) {
    // `own` is used by this task only: its ceiling is the task's priority, no lock.
    *cx.shared.own += 1;
    cx.shared.log.lock(|l| l.seen.push("twi"));
}

fn udre(mut cx: udre::Context) {
    cx.shared.log.lock(|l| l.seen.push("udre"));
    udre::disarm();
}

fn encoder(mut cx: encoder::Context) {
    // The top task is the highest user of `log`: direct access.
    cx.shared.log.seen.push("encoder");
}

#[test]
fn ceilings_are_the_highest_user_priority() {
    assert_eq!(__exec_ceil::log, 3);
    assert_eq!(__exec_ceil::count, 1);
    assert_eq!(__exec_ceil::own, 2);
    assert_eq!(__exec_ceil::log, ceiling(__EXEC_TASKS, 0));
}

#[test]
fn priorities_and_top_come_from_the_declaration() {
    assert_eq!(adc::PRIORITY, 1);
    assert_eq!(twi::PRIORITY, 2);
    assert_eq!(encoder::PRIORITY, 3);
    assert_eq!(idle::PRIORITY, 0);
    assert_eq!(<__ExecApp as App>::TOP, 3);
}

#[test]
fn masks_gates_and_start_bits_follow_the_tasks() {
    let masks = <__ExecApp as App>::MASKS;
    assert_eq!(masks, level_masks(__EXEC_TASKS));
    let l1 = masks.level(1);
    let l2 = masks.level(2);
    assert_eq!(l1.get(Reg::Adcsra.index()), Source::ADC.bit());
    assert_eq!(l1.get(Reg::Twcr.index()), 0);
    assert_eq!(l2.get(Reg::Twcr.index()), Source::TWI.bit());
    assert_eq!(l2.get(Reg::Ucsr0b.index()), Source::USART_UDRE.bit());
    assert_eq!(
        l2.get(Reg::Pcicr.index()),
        0,
        "the top task is never masked"
    );
    let gated = <__ExecApp as App>::GATED;
    let start = <__ExecApp as App>::START;
    assert!(gated.contains(Source::USART_UDRE));
    assert!(!start.contains(Source::USART_UDRE));
    assert!(start.contains(Source::ADC) && start.contains(Source::TWI));
    assert!(start.contains(Source::PCINT2));
    // A lock at ceiling 2 rewrites TWCR/UCSR0B, which drivers also write: atomic.
    assert!(executor::analysis::atomic_lock(&masks, &gated, 2, 0));
}

#[test]
fn contexts_reach_the_declared_resources() {
    // Const locals are built at compile time: their values are in place before `init`.
    // SAFETY: no context exists yet (the one test that creates contexts is this one).
    unsafe {
        assert_eq!(*idle::__const_local::banner.as_mut_ptr(), *b"hi");
        assert_eq!(*adc::__const_local::total.as_mut_ptr(), 1000);
        assert_eq!(*adc::__const_local::last.as_mut_ptr(), None);
    }
    // SAFETY: what the generated `main` does, on one thread, before any context exists.
    unsafe { __EXEC_RESOURCES.write(init(init::Context::new())) };
    // SAFETY: one run at a time, as the vectors run them.
    unsafe {
        adc::__run();
        twi::__run();
        udre::__run();
        encoder::__run();
        adc::__run();
    }
    // SAFETY: no context is alive any more.
    let (shared, local) = unsafe { &*__EXEC_RESOURCES.as_mut_ptr() };
    assert_eq!(shared.log.seen, ["adc", "twi", "udre", "encoder", "adc"]);
    assert_eq!(shared.count, 2);
    assert_eq!(shared.own, 1);
    assert_eq!(local.steps, 2);
    assert_eq!(local.idle_runs, 0);
    // The task's const locals kept their state across its two runs.
    // SAFETY: no context is alive any more.
    unsafe {
        assert_eq!(*adc::__const_local::total.as_mut_ptr(), 1002);
        assert_eq!(*adc::__const_local::last.as_mut_ptr(), Some(2));
    }
}
