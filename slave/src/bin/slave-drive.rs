//! The drive/steer slave image (controllers 1, 2, 4, 5, 7, 8): drive motor with encoder
//! on M1, steer motor with pot on M2.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]
#![feature(asm_experimental_arch)]

slave::firmware!(DriveSteerBoard, edge, encoder);
