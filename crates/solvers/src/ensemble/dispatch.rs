//! Run-time dispatch of the lockstep engine to a copy compiled for the CPU's vector features
//! (AVX-512, AVX2/FMA, baseline); the copies run the same IEEE operations in the same order.

use super::engine::drive;
use super::{LaneDriver, Lockstep};

/// A copy of the engine loop [`drive`] under the given attributes (target features).
macro_rules! engine_copy {
    ($(#[$attr:meta])* $name:ident) => {
        $(#[$attr])*
        fn $name<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
        where
            B: Lockstep<N, L>,
            B::Sys: 's,
            D: LaneDriver<'s, B, N, L>,
        {
            drive(batch, drv)
        }
    };
}

engine_copy!(
    #[cfg(all(target_arch = "x86_64", geardyn_avx512))]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx2,fma")]
    drive_avx512
);
engine_copy!(
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    drive_avx2
);
engine_copy!(
    #[inline(never)]
    drive_base
);

/// The copies of the engine [`run_lanes_on`] can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dispatch {
    /// The best copy this CPU runs (AVX-512, else AVX2/FMA, else baseline).
    Auto,
    /// The AVX2/FMA copy when the CPU has those features, else the baseline.
    Avx2,
    /// The baseline copy (x86-64 SSE2 on x86_64).
    Baseline,
}

/// Which copy of the engine [`run_lanes`] uses on this CPU: `"avx512"`, `"avx2+fma"` or
/// `"baseline"`.
pub fn dispatch_path() -> &'static str {
    if has_avx512() {
        "avx512"
    } else if has_avx2() {
        "avx2+fma"
    } else {
        "baseline"
    }
}

fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

fn has_avx512() -> bool {
    #[cfg(all(target_arch = "x86_64", geardyn_avx512))]
    {
        has_avx2()
            && std::is_x86_feature_detected!("avx512f")
            && std::is_x86_feature_detected!("avx512vl")
            && std::is_x86_feature_detected!("avx512dq")
    }
    #[cfg(not(all(target_arch = "x86_64", geardyn_avx512)))]
    {
        false
    }
}

/// Runs every item the driver supplies through `L` lockstep lanes until its queue is empty.
/// Dispatches to the AVX-512 or AVX2/FMA copy of the engine when the CPU has those features (the
/// results are identical: the same IEEE operations in the same order, no fused multiply-add).
pub fn run_lanes<'s, B, D, const N: usize, const L: usize>(batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    run_lanes_on(Dispatch::Auto, batch, drv)
}

/// As [`run_lanes`], on the copy `how` selects (when the CPU runs it; for tests and benchmarks).
pub fn run_lanes_on<'s, B, D, const N: usize, const L: usize>(how: Dispatch, batch: &B, drv: &mut D)
where
    B: Lockstep<N, L>,
    B::Sys: 's,
    D: LaneDriver<'s, B, N, L>,
{
    #[cfg(all(target_arch = "x86_64", geardyn_avx512))]
    {
        if how == Dispatch::Auto && has_avx512() {
            // SAFETY: the CPU supports the features the function was compiled for.
            unsafe { drive_avx512(batch, drv) };
            return;
        }
    }
    #[cfg(target_arch = "x86_64")]
    {
        if how != Dispatch::Baseline && has_avx2() {
            // SAFETY: the CPU supports the features the function was compiled for.
            unsafe { drive_avx2(batch, drv) };
            return;
        }
    }
    drive_base(batch, drv)
}
