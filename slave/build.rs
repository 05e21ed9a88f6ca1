include!("../build-support/memory_x.rs");

fn main() {
    link_memory_x();
    // Linker relaxation: calls and jumps within reach become RCALL/RJMP (2 B and a
    // cycle less each): about 100 B per image. The master links without it (an RC
    // pulse measured 1 µs longer there); the slave's timings are benchmarked with it.
    println!("cargo:rustc-link-arg-bins=-Wl,--relax");
    // Functions in the order of their section names (`.text.<symbol>`), not the
    // compiler's: the mangled names put the core's methods first, then the shared
    // routines (the PID's product, sum and difference, the state machine, the rate), then
    // the interrupt handlers with the tick, so most calls to the shared routines are
    // within an RCALL's 4 KB (measured: 31 → 16 long calls; drive/lift −30 / −20 B).
    println!("cargo:rustc-link-arg-bins=-Wl,--sort-section=name");
}
