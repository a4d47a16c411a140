//! Helpers shared by the integration tests.

/// `f` run on a rayon pool of `threads` threads (the thread-count invariance tests).
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}
