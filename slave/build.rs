include!("../build-support/memory_x.rs");

fn main() {
    link_memory_x();
    // Linker relaxation: calls and jumps within reach become RCALL/RJMP (2 B and a
    // cycle less each): about 100 B per image. The master links without it (an RC
    // pulse measured 1 µs longer there); the slave's timings are benchmarked with it.
    println!("cargo:rustc-link-arg-bins=-Wl,--relax");
}
