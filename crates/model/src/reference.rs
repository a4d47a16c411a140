//! Reference hybrid systems that live beside the gear model: for tests, benchmarks of the
//! integrators against closed forms, and as templates a user can copy to implement
//! [`HybridSystem`] for a system of their own.

use geardyn_solvers::{Direction, EventAction, Guards, HybridSystem, Variational};

/// Forced Duffing oscillator `x'' + delta x' + alpha x + beta x^3 = gamma cos(omega t)`
/// (smooth; no events). State `[x, x']`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Duffing {
    /// Damping `delta`.
    pub delta: f64,
    /// Linear stiffness `alpha`.
    pub alpha: f64,
    /// Cubic stiffness `beta`.
    pub beta: f64,
    /// Forcing amplitude `gamma`.
    pub gamma: f64,
    /// Forcing frequency `omega`.
    pub omega: f64,
}

impl HybridSystem<2> for Duffing {
    type Mode = ();
    type TimeTerms = f64;
    fn initial_mode(&self, _t: f64, _y: &mut [f64; 2]) {}
    fn time_terms(&self, t: f64) -> f64 {
        (self.omega * t).cos()
    }
    fn rhs(&self, _t: f64, c: &f64, y: &[f64; 2], _m: &(), dy: &mut [f64; 2]) {
        let x = y[0];
        dy[0] = y[1];
        dy[1] = self.gamma * c - self.delta * y[1] - self.alpha * x - self.beta * x * x * x;
    }
}

/// The Lorenz system `x' = s(y-x)`, `y' = x(r-z) - y`, `z' = xy - bz` (smooth; no events).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lorenz {
    /// Prandtl number `sigma`.
    pub sigma: f64,
    /// Rayleigh number `rho`.
    pub rho: f64,
    /// Geometric factor `beta`.
    pub beta: f64,
}

impl Default for Lorenz {
    /// The classical chaotic parameters `sigma = 10, rho = 28, beta = 8/3`.
    fn default() -> Self {
        Lorenz {
            sigma: 10.0,
            rho: 28.0,
            beta: 8.0 / 3.0,
        }
    }
}

impl HybridSystem<3> for Lorenz {
    type Mode = ();
    type TimeTerms = ();
    fn initial_mode(&self, _t: f64, _y: &mut [f64; 3]) {}
    fn time_terms(&self, _t: f64) {}
    fn rhs(&self, _t: f64, _tt: &(), y: &[f64; 3], _m: &(), dy: &mut [f64; 3]) {
        dy[0] = self.sigma * (y[1] - y[0]);
        dy[1] = y[0] * (self.rho - y[2]) - y[1];
        dy[2] = y[0] * y[1] - self.beta * y[2];
    }
}

/// Harmonically forced linear oscillator with a rigid stop at `x = -gap` and restitution `r`:
/// `x'' + 2 zeta x' + x = a cos(omega t)` for `x > -gap`, `x'+ = -r x'-` at the stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactOscillator {
    /// Damping ratio.
    pub zeta: f64,
    /// Forcing amplitude.
    pub a: f64,
    /// Forcing frequency.
    pub omega: f64,
    /// Distance of the stop below the origin.
    pub gap: f64,
    /// Restitution coefficient.
    pub r: f64,
}

impl HybridSystem<2> for ImpactOscillator {
    type Mode = ();
    type TimeTerms = f64;
    fn initial_mode(&self, _t: f64, y: &mut [f64; 2]) {
        if y[0] < -self.gap {
            y[0] = -self.gap;
        }
    }
    fn time_terms(&self, t: f64) -> f64 {
        (self.omega * t).cos()
    }
    fn rhs(&self, _t: f64, c: &f64, y: &[f64; 2], _m: &(), dy: &mut [f64; 2]) {
        dy[0] = y[1];
        dy[1] = self.a * c - 2.0 * self.zeta * y[1] - y[0];
    }
    fn guards(&self, _t: f64, y: &[f64; 2], _m: &(), g: &mut Guards) {
        g.push(y[0] + self.gap, Direction::Falling);
    }
    fn on_event(&self, _t: f64, y: &mut [f64; 2], _m: &mut (), _i: usize) -> EventAction {
        y[0] = -self.gap;
        y[1] *= -self.r;
        EventAction::Continue
    }
}

impl Variational<2> for Duffing {
    fn jacobian(&self, _t: f64, _c: &f64, y: &[f64; 2], _m: &(), jac: &mut [[f64; 2]; 2]) {
        *jac = [
            [0.0, 1.0],
            [-self.alpha - 3.0 * self.beta * y[0] * y[0], -self.delta],
        ];
    }
    fn guard_gradient(&self, _t: f64, _y: &[f64; 2], _m: &(), _i: usize) -> ([f64; 2], f64) {
        ([0.0; 2], 0.0)
    }
}

impl Variational<3> for Lorenz {
    fn jacobian(&self, _t: f64, _tt: &(), y: &[f64; 3], _m: &(), jac: &mut [[f64; 3]; 3]) {
        *jac = [
            [-self.sigma, self.sigma, 0.0],
            [self.rho - y[2], -1.0, -y[0]],
            [y[1], y[0], -self.beta],
        ];
    }
    fn guard_gradient(&self, _t: f64, _y: &[f64; 3], _m: &(), _i: usize) -> ([f64; 3], f64) {
        ([0.0; 3], 0.0)
    }
}

impl Variational<2> for ImpactOscillator {
    fn jacobian(&self, _t: f64, _c: &f64, _y: &[f64; 2], _m: &(), jac: &mut [[f64; 2]; 2]) {
        *jac = [[0.0, 1.0], [-1.0, -2.0 * self.zeta]];
    }
    fn guard_gradient(&self, _t: f64, _y: &[f64; 2], _m: &(), _i: usize) -> ([f64; 2], f64) {
        ([1.0, 0.0], 0.0)
    }
    fn reset_jacobian(&self, _t: f64, _y: &[f64; 2], _m: &(), _i: usize) -> [[f64; 2]; 2] {
        [[1.0, 0.0], [0.0, -self.r]]
    }
}
