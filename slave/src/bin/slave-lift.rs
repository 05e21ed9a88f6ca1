//! The lift/lift slave image (controllers 3, 6, 9): lift motors ONE (M1) and TWO (M2),
//! each with a pot.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

slave::firmware!(LiftLiftBoard);
