//! A slave chip on the bus: delivering one bus event and running its firmware until it answers.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

use super::port::{Tap, TwiIrqs};
use super::reg::{TWAR, TWCR, TWEA, TWEN, TWINT};
use super::{cond, TwiError, TwiMsg};
use crate::avr::CYCLES_PER_US;
use crate::Avr;

/// How a slave chip's TWI stands towards one address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Listen {
    /// TWI off, or TWAR holds another address.
    NotMe,
    /// TWAR matches and TWEN is set.
    Me {
        /// TWEA is set: the address (or the next byte) will be acknowledged.
        ack: bool,
    },
}

/// One emulated slave chip attached to the bus.
pub(crate) struct SlaveChip {
    /// Declared first so it is dropped (hook unregistered) before the chip can be.
    _tap: Tap,
    irqs: TwiIrqs,
    answers: Rc<RefCell<VecDeque<TwiMsg>>>,
    pub avr: Rc<RefCell<Avr>>,
}

impl SlaveChip {
    /// Attaches to the chip's TWI output, collecting what its firmware answers.
    pub fn attach(avr: Rc<RefCell<Avr>>) -> Result<SlaveChip, TwiError> {
        let raw = avr.borrow_mut().as_ptr();
        let irqs = TwiIrqs::find(raw)?;
        let answers = Rc::new(RefCell::new(VecDeque::new()));
        let sink = Rc::clone(&answers);
        let tap = Tap::attach(
            irqs,
            Box::new(move |msg| {
                if let Ok(mut queue) = sink.try_borrow_mut() {
                    queue.push_back(msg);
                }
                None
            }),
        );
        Ok(SlaveChip {
            _tap: tap,
            irqs,
            answers,
            avr,
        })
    }

    /// Whether the chip's TWI, as its firmware set it up, answers to `addr`.
    pub fn listens(&self, addr: u8) -> Listen {
        let Ok(avr) = self.avr.try_borrow() else {
            return Listen::NotMe;
        };
        let twcr = avr.read_data(TWCR);
        if twcr & TWEN == 0 || avr.read_data(TWAR) >> 1 != addr {
            return Listen::NotMe;
        }
        Listen::Me {
            ack: twcr & TWEA != 0,
        }
    }

    /// Whether TWEA is set now (the next byte will be acknowledged).
    pub fn acks(&self) -> bool {
        self.avr
            .try_borrow()
            .map(|avr| avr.read_data(TWCR) & TWEA != 0)
            .unwrap_or(false)
    }

    /// Whether the chip's TWI holds SCL low: enabled, with TWINT set (a real slave TWI
    /// stretches the clock until its firmware clears TWINT). A chip busy elsewhere counts
    /// as still holding.
    pub fn holds_scl(&self) -> bool {
        self.avr.try_borrow().map_or(true, |avr| {
            let twcr = avr.read_data(TWCR);
            twcr & TWEN != 0 && twcr & TWINT != 0
        })
    }

    /// The chip's clock in cycles.
    pub fn cycles(&self) -> u64 {
        self.avr.try_borrow().map(|avr| avr.cycles()).unwrap_or(0)
    }

    /// Raises `msg` on the chip's TWI input and runs the chip until its firmware releases the
    /// bus (clears TWINT, which simavr reports as an ADDR message), for at most `budget` cycles.
    /// Returns that message; its data byte is what the firmware left in TWDR.
    pub fn deliver(&self, msg: TwiMsg, addr: u8, budget: u64) -> Result<TwiMsg, TwiError> {
        let timeout = TwiError::Timeout {
            addr,
            waited_us: budget / CYCLES_PER_US,
        };
        let Ok(mut avr) = self.avr.try_borrow_mut() else {
            return Err(timeout);
        };
        self.answers.borrow_mut().clear();
        self.irqs.send(msg);
        let target = avr.cycles().saturating_add(budget);
        let answers = &self.answers;
        let released = |_: &mut Avr| answers.borrow().iter().any(|m| m.has(cond::ADDR));
        if !released(&mut avr) && !avr.run_to(target, released) {
            return Err(timeout);
        }
        let mut queue = self.answers.borrow_mut();
        let answer = queue.iter().rev().find(|m| m.has(cond::ADDR)).copied();
        queue.clear();
        answer.ok_or(timeout)
    }
}
