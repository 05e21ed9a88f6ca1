//! Executor example: a TWI event that arrives while the TWI task is masked survives the
//! lock, and runs the task as soon as the lock ends (the TWINT trap).
//!
//! TWINT, the TWI's event flag, is cleared by writing a one to it, so masking TWIE by
//! reading TWCR and writing it back with TWIE cleared silently drops a pending event. Idle
//! shows both ways. First, inside a lock of `bus` (ceiling 2, the TWI task's priority) it
//! requests a START, waits for the hardware to raise TWINT, and locks again (nested) so
//! that TWCR is masked and unmasked once more with the event pending; the TWI task must
//! not run inside, and must run once, with status 0x08 (START sent), right after. Then it
//! repeats the START and masks TWIE the naive way; the event is gone and the task never
//! runs. Idle prints
//! `twimask pending_in_lock=1 ran_inside=0 ran_after=1 status=8 naive_twint=0 naive_ran=0`.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

mod exec_support;

use avr_device::atmega328p::TWI;
use executor::hw::{self, DriverReg};

use exec_support::{busy, Uart};

const TWINT: u8 = 1 << 7;
const TWSTA: u8 = 1 << 5;
const TWSTO: u8 = 1 << 4;
const TWEN: u8 = 1 << 2;
const TWIE: u8 = 1 << 0;

/// What the TWI task saw.
pub struct Bus {
    runs: u8,
    status: u8,
}

executor::app! {
    #[shared]
    struct Shared {
        bus: Bus,
        other: u8,
    }

    #[local]
    struct Local {
        uart: Uart,
        twi_regs: TWI,
    }

    #[init]
    fn init;

    #[idle(shared = [bus, other], local = [uart])]
    fn idle;

    #[task(binds = TWI, priority = 2, shared = [bus, other], local = [twi_regs])]
    fn twi;

    #[task(binds = PCINT2, priority = 3)]
    fn top_unused;
}

fn init(cx: init::Context) -> (Shared, Local) {
    let dp = cx.device;
    let uart = Uart::new(dp.USART0);
    // 100 kHz (TWBR 72, prescaler 1) and the TWI on; the executor owns TWIE.
    // SAFETY: documented TWBR value.
    dp.TWI.twbr().write(|w| unsafe { w.bits(72) });
    hw::write(DriverReg::Twcr, TWEN);
    (
        Shared {
            bus: Bus { runs: 0, status: 0 },
            other: 0,
        },
        Local {
            uart,
            twi_regs: dp.TWI,
        },
    )
}

/// Waits until the hardware raises TWINT (bounded); returns whether it did.
fn wait_twint() -> bool {
    for _ in 0..100 {
        if hw::read(DriverReg::Twcr) & TWINT != 0 {
            return true;
        }
        busy(4);
    }
    false
}

fn idle(mut cx: idle::Context) -> ! {
    cx.local.uart.put_str(b"exec_twi_mask ready\n");
    let idle::SharedResources { bus, other, .. } = &mut cx.shared;

    // The executor's way.
    let (pending_in_lock, ran_inside) = bus.lock(|b| {
        let runs = b.runs;
        // START: TWSTA with TWINT written as one to hand the bus to the hardware.
        hw::write(DriverReg::Twcr, TWINT | TWSTA | TWEN);
        let pending = wait_twint();
        // Mask and unmask TWCR again while the event is pending.
        other.lock(|o| *o += 1);
        busy(20);
        let still = hw::read(DriverReg::Twcr) & TWINT != 0;
        (pending && still, b.runs != runs)
    });
    busy(20);
    let (ran_after, status) = bus.lock(|b| (b.runs, b.status));

    // The naive way, for contrast: read TWCR, clear TWIE, write it back.
    let naive_twint = bus.lock(|b| {
        let runs = b.runs;
        hw::write(DriverReg::Twcr, TWINT | TWSTA | TWEN);
        wait_twint();
        // SAFETY: TWCR (0xBC) is an I/O register; this write is the trap being shown.
        unsafe {
            let twcr = core::ptr::read_volatile(0xBC as *const u8);
            core::ptr::write_volatile(0xBC as *mut u8, twcr & !TWIE);
        }
        let flag = hw::read(DriverReg::Twcr) & TWINT != 0;
        b.runs = runs;
        flag
    });
    busy(20);
    let naive_ran = bus.lock(|b| b.runs) != ran_after;

    let uart = &mut *cx.local.uart;
    uart.put_str(b"twimask ");
    uart.field(b"pending_in_lock", u32::from(pending_in_lock));
    uart.field(b"ran_inside", u32::from(ran_inside));
    uart.field(b"ran_after", u32::from(ran_after));
    uart.field(b"status", u32::from(status));
    uart.field(b"naive_twint", u32::from(naive_twint));
    uart.field(b"naive_ran", u32::from(naive_ran));
    uart.put(b'\n');
    loop {
        cx.sleep.sleep();
    }
}

fn twi(mut cx: twi::Context) {
    let status = cx.local.twi_regs.twsr().read().bits() & 0xF8;
    let bus = &mut *cx.shared.bus;
    bus.runs += 1;
    bus.status = status;
    // Release the bus with a STOP (this also clears TWINT).
    hw::write(DriverReg::Twcr, TWINT | TWSTO | TWEN);
}

fn top_unused(_cx: top_unused::Context) {}
