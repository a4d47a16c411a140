//! Enables the AVX-512 copy of the lockstep ensemble engine (`cfg(geardyn_avx512)`) when the
//! compiler accepts the AVX-512 target features on stable (Rust 1.89 or newer); older compilers
//! (the crate builds from 1.87) keep the AVX2/FMA and baseline copies.

use std::process::Command;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(geardyn_avx512)");
    println!("cargo::rerun-if-env-changed=RUSTC");
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let minor = Command::new(rustc)
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|v| {
            // "rustc 1.95.0 (59807616e 2026-04-14)"
            let ver = v.split_whitespace().nth(1)?.to_string();
            let mut it = ver.split('.');
            let major: u32 = it.next()?.parse().ok()?;
            let minor: u32 = it.next()?.parse().ok()?;
            Some(if major > 1 { u32::MAX } else { minor })
        });
    if minor.is_some_and(|m| m >= 89) {
        println!("cargo::rustc-cfg=geardyn_avx512");
    }
}
