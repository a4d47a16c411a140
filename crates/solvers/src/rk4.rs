//! The arithmetic of one RK4 step, written once: the scalar integrator's RK4 step and the lanes'
//! stages ([`crate::ensemble::rk4_lanes`]) both compute through these, in the same operation
//! order, so that a trajectory is the same to the bit whichever path integrates it.

/// The step fractions `(h/2, h/6)` of an RK4 step of length `h`, rounded as every RK4 step of
/// geardyn rounds them (`0.5 * h`, `h * (1/6)`).
#[inline(always)]
pub fn fractions(h: f64) -> (f64, f64) {
    (0.5 * h, h * (1.0 / 6.0))
}

/// One component of an RK4 stage point: `y + c k` (`c` is `h/2` or `h`).
#[inline(always)]
pub fn stage_point(y: f64, c: f64, k: f64) -> f64 {
    y + c * k
}

/// One component of the RK4 end state: `y + h6 (k1 + 2 (k2 + k3) + k4)`.
#[inline(always)]
pub fn combine(y: f64, h6: f64, k1: f64, k2: f64, k3: f64, k4: f64) -> f64 {
    y + h6 * (k1 + 2.0 * (k2 + k3) + k4)
}
