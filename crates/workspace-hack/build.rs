//! Empty: present only so that the `[build-dependencies]` of `Cargo.toml` (host features of
//! syn, shared with the proc-macro crates) take part in every build.

fn main() {}
