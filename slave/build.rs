include!("../build-support/memory_x.rs");

fn main() {
    link_memory_x();
}
