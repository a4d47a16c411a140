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

geardyn_solvers::one_mode_system!(Lorenz, 3, |this, _t, y, dy| {
    dy[0] = this.sigma * (y[1] - y[0]);
    dy[1] = y[0] * (this.rho - y[2]) - y[1];
    dy[2] = y[0] * y[1] - this.beta * y[2];
});

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

/// Contact state of both clearances of [`TwoMassClearance`] (`[mesh 0, mesh 1]`).
pub type TwoContacts = [crate::ContactState; 2];

/// Two masses and two clearances: a toy gear train of two degrees of freedom, for the tests and
/// examples that show an analysis is generic over [`crate::system::GearSystem`].
///
/// State `[x1, x1', x2, x2']` (dimensionless). Mesh 0 couples mass 1 to the ground through a
/// clearance `|x1| < D0`, mesh 1 couples the masses through a clearance `|x1 - x2| < D1`; a mesh
/// in contact pushes with `k (u -+ D) + c u'` (drive `u >= D`, back `u <= -D`), a separated one
/// with nothing. Mass 1 is driven by `F0 + A cos(Omega t)`, mass 2 carries the load `-F1`:
///
/// `m1 x1'' = F0 + A cos(Omega t) - f0(x1, x1') - f1(x1 - x2, x1' - x2')`,
/// `m2 x2'' = -F1 + f1(x1 - x2, x1' - x2')`.
///
/// Loaded so that both meshes stay in drive contact, the system is linear about its static
/// deflection (the tests check it against the closed-form response and the eigenvalues).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoMassClearance {
    /// Masses `m1`, `m2`.
    pub mass: [f64; 2],
    /// Contact stiffnesses `k0`, `k1`.
    pub k: [f64; 2],
    /// Contact damping `c0`, `c1` (acting in contact only).
    pub c: [f64; 2],
    /// Half clearances `D0`, `D1` (`> 0`: a zero-width separation band has no room for the
    /// separated mode between its two contact surfaces).
    pub d: [f64; 2],
    /// Mean driving force `F0` on mass 1 and load `F1` on mass 2.
    pub load: [f64; 2],
    /// Amplitude `A` of the harmonic force on mass 1.
    pub amplitude: f64,
    /// Forcing frequency `Omega`.
    pub omega: f64,
}

impl Default for TwoMassClearance {
    /// Equal masses and meshes, 5 % damping, unit clearances, a light load and a forcing near
    /// the lower natural frequency.
    fn default() -> Self {
        TwoMassClearance {
            mass: [1.0, 1.0],
            k: [1.0, 1.0],
            c: [0.1, 0.1],
            d: [1.0, 1.0],
            load: [0.2, 0.1],
            amplitude: 0.3,
            omega: 0.7,
        }
    }
}

impl TwoMassClearance {
    /// Relative displacement and velocity of mesh `k`.
    #[inline(always)]
    fn rel(y: &[f64; 4], k: usize) -> (f64, f64) {
        if k == 0 {
            (y[0], y[1])
        } else {
            (y[0] - y[2], y[1] - y[3])
        }
    }

    /// Contact force of mesh `k` in state `s`.
    #[inline(always)]
    fn force(&self, k: usize, s: crate::ContactState, u: f64, du: f64) -> f64 {
        use crate::ContactState as C;
        match s {
            C::Drive => self.k[k] * (u - self.d[k]) + self.c[k] * du,
            C::Back => self.k[k] * (u + self.d[k]) + self.c[k] * du,
            C::Separated | C::Stuck => 0.0,
        }
    }

    fn state_of(&self, k: usize, u: f64, du: f64) -> crate::ContactState {
        use crate::ContactState as C;
        let d = self.d[k];
        if u > d || (u == d && du > 0.0) {
            C::Drive
        } else if u < -d || (u == -d && du < 0.0) {
            C::Back
        } else {
            C::Separated
        }
    }

    /// Guards mesh 0 arms in `m` (2 when separated, else 1): the guard index of mesh 1 starts
    /// there.
    fn guards_of_mesh0(m: &TwoContacts) -> usize {
        if m[0] == crate::ContactState::Separated {
            2
        } else {
            1
        }
    }

    /// Mesh and local guard (0: the drive surface `u = D`, 1: the back one) of guard `index`.
    fn which(m: &TwoContacts, index: usize) -> (usize, usize) {
        let g0 = Self::guards_of_mesh0(m);
        let (k, local) = if index < g0 {
            (0, index)
        } else {
            (1, index - g0)
        };
        // a mesh in contact arms its own surface only
        let local = match m[k] {
            crate::ContactState::Separated => local,
            crate::ContactState::Drive => 0,
            _ => 1,
        };
        (k, local)
    }

    /// Natural angular frequencies `omega_1 <= omega_2` with both meshes in contact.
    pub fn natural_frequencies(&self) -> [f64; 2] {
        // det(K - w^2 M) = 0 for K = [[k0 + k1, -k1], [-k1, k1]], M = diag(m1, m2)
        let [m1, m2] = self.mass;
        let [k0, k1] = self.k;
        let a = m1 * m2;
        let b = -((k0 + k1) * m2 + k1 * m1);
        let c = k0 * k1;
        let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
        [
            ((-b - disc) / (2.0 * a)).max(0.0).sqrt(),
            ((-b + disc) / (2.0 * a)).sqrt(),
        ]
    }
}

impl HybridSystem<4> for TwoMassClearance {
    type Mode = TwoContacts;
    type TimeTerms = f64;

    fn initial_mode(&self, t: f64, y: &mut [f64; 4]) -> TwoContacts {
        let (u0, v0) = Self::rel(y, 0);
        let (u1, v1) = Self::rel(y, 1);
        let mut m = [self.state_of(0, u0, v0), self.state_of(1, u1, v1)];
        // a mesh at rest exactly on a contact surface is in contact when the free motion presses
        // it in (no crossing follows that an event could see)
        for k in 0..2 {
            let (u, du) = Self::rel(y, k);
            let d = self.d[k];
            if m[k] != crate::ContactState::Separated || du != 0.0 || (u != d && u != -d) {
                continue;
            }
            let mut dy = [0.0; 4];
            self.rhs(t, &self.time_terms(t), y, &m, &mut dy);
            let a = if k == 0 { dy[1] } else { dy[1] - dy[3] };
            if u == d && a > 0.0 {
                m[k] = crate::ContactState::Drive;
            } else if u == -d && a < 0.0 {
                m[k] = crate::ContactState::Back;
            }
        }
        m
    }
    fn time_terms(&self, t: f64) -> f64 {
        (self.omega * t).cos()
    }
    fn rhs(&self, _t: f64, c: &f64, y: &[f64; 4], m: &TwoContacts, dy: &mut [f64; 4]) {
        let (u0, v0) = Self::rel(y, 0);
        let (u1, v1) = Self::rel(y, 1);
        let f0 = self.force(0, m[0], u0, v0);
        let f1 = self.force(1, m[1], u1, v1);
        dy[0] = y[1];
        dy[1] = (self.load[0] + self.amplitude * c - f0 - f1) / self.mass[0];
        dy[2] = y[3];
        dy[3] = (-self.load[1] + f1) / self.mass[1];
    }
    fn guards(&self, _t: f64, y: &[f64; 4], m: &TwoContacts, g: &mut Guards) {
        use crate::ContactState as C;
        for (k, state) in m.iter().enumerate() {
            let (u, _) = Self::rel(y, k);
            let d = self.d[k];
            match state {
                C::Drive => g.push(u - d, Direction::Falling),
                C::Back | C::Stuck => g.push(u + d, Direction::Rising),
                C::Separated => {
                    g.push(u - d, Direction::Rising);
                    g.push(u + d, Direction::Falling);
                }
            }
        }
    }
    fn on_event(
        &self,
        _t: f64,
        _y: &mut [f64; 4],
        m: &mut TwoContacts,
        index: usize,
    ) -> EventAction {
        use crate::ContactState as C;
        let (k, local) = Self::which(m, index);
        m[k] = match (m[k], local) {
            (C::Separated, 0) => C::Drive,
            (C::Separated, _) => C::Back,
            _ => C::Separated,
        };
        EventAction::Continue
    }
}

impl Variational<4> for TwoMassClearance {
    fn jacobian(&self, _t: f64, _c: &f64, _y: &[f64; 4], m: &TwoContacts, j: &mut [[f64; 4]; 4]) {
        let on = |k: usize| {
            if matches!(m[k], crate::ContactState::Drive | crate::ContactState::Back) {
                (self.k[k], self.c[k])
            } else {
                (0.0, 0.0)
            }
        };
        let (k0, c0) = on(0);
        let (k1, c1) = on(1);
        let [m1, m2] = self.mass;
        *j = [
            [0.0, 1.0, 0.0, 0.0],
            [-(k0 + k1) / m1, -(c0 + c1) / m1, k1 / m1, c1 / m1],
            [0.0, 0.0, 0.0, 1.0],
            [k1 / m2, c1 / m2, -k1 / m2, -c1 / m2],
        ];
    }
    fn guard_gradient(
        &self,
        _t: f64,
        _y: &[f64; 4],
        m: &TwoContacts,
        index: usize,
    ) -> ([f64; 4], f64) {
        let (k, _) = Self::which(m, index);
        if k == 0 {
            ([1.0, 0.0, 0.0, 0.0], 0.0)
        } else {
            ([1.0, 0.0, -1.0, 0.0], 0.0)
        }
    }
}

impl crate::system::GearSystem<4> for TwoMassClearance {
    fn mesh_count(&self) -> usize {
        2
    }
    fn excitation_period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }
    fn natural_period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.natural_frequencies()[1]
    }
    #[inline(always)]
    fn mesh_state(&self, _t: f64, y: &[f64; 4], k: usize) -> [f64; 2] {
        let (u, v) = Self::rel(y, k);
        [u, v]
    }
    #[inline(always)]
    fn mesh_force(&self, _t: f64, y: &[f64; 4], m: &TwoContacts, k: usize) -> f64 {
        let (u, v) = Self::rel(y, k);
        self.force(k, m[k], u, v)
    }
    fn contact(&self, m: &TwoContacts, k: usize) -> crate::ContactState {
        m[k]
    }
    fn backlash_levels(&self, k: usize) -> (f64, f64) {
        (self.d[k], self.d[k])
    }
    fn event(
        &self,
        before: &TwoContacts,
        _after: &TwoContacts,
        index: usize,
    ) -> (usize, crate::EventKind) {
        use crate::{ContactState as C, EventKind as E};
        let (k, local) = Self::which(before, index);
        let kind = match (before[k], local) {
            (C::Separated, 0) => E::DriveEnter,
            (C::Separated, _) => E::BackEnter,
            (C::Drive, _) => E::DriveExit,
            _ => E::BackExit,
        };
        (k, kind)
    }
}
