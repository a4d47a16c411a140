//! Geometry and mesh phasing of a planetary stage: sun, `N` planets on a carrier, ring; the
//! checks a stage must pass (tooth counts that close, equally spaced planets, planets that clear
//! each other), the planet positions, the speed ratio, and the relative phases of the sun–planet
//! and of the ring–planet meshes (Parker & Lin 2004, "Mesh phasing relationships in planetary and
//! epicyclic gears", J. Mech. Des. 126:365–370).
//!
//! Conventions: standard (unshifted) spur gears of one module `m` with addendum `m`, all meshes
//! at the same pressure angle, so the ring closes with `Z_r = Z_s + 2 Z_p` and the centre distance
//! of every planet is `a = m (Z_s + Z_p) / 2`. Planet `n` (`n = 0 .. N-1`) sits at the carrier
//! angle `psi_n = 2 pi n / N`, counted in the direction the carrier turns. A **phase** is a
//! fraction of one mesh cycle in `[0, 1)`: mesh `n` goes through the state of mesh 0 that much
//! of a mesh period later. For a sun–planet mesh it is `frac(Z_s psi_n / 2 pi)`, for a
//! ring–planet mesh `frac(-Z_r psi_n / 2 pi)` (the ring's teeth pass the planets the other way
//! in the carrier's frame; Parker & Lin 2004, eqs. 9 and 10 for equally spaced planets).
//! The phase between the sun and ring meshes of one planet depends on the tooth thicknesses and
//! is not computed here.

use crate::error::PhysicsError;
use std::f64::consts::PI;

/// Teeth and planets of a stage, and the module.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanetaryStage {
    /// Sun teeth `Z_s`.
    pub sun: u32,
    /// Planet teeth `Z_p`.
    pub planet: u32,
    /// Ring teeth `Z_r` (internal gear).
    pub ring: u32,
    /// Planets `N`.
    pub planets: u32,
    /// Module (m).
    pub module: f64,
}

/// Fewest teeth a gear of a stage may have (below it a standard 20° involute undercuts).
pub const MIN_TEETH: u32 = 12;
/// Planets a stage may have.
pub const PLANETS: std::ops::RangeInclusive<u32> = 2..=12;

fn invalid(field: &str, value: f64, allowed: String) -> PhysicsError {
    PhysicsError::Invalid {
        field: format!("stage.{field}"),
        value,
        allowed,
    }
}

impl PlanetaryStage {
    /// A checked stage: every gear has at least [`MIN_TEETH`] teeth, `N` in [`PLANETS`], the
    /// module positive and finite, the ring closes (`Z_r = Z_s + 2 Z_p`), the planets can be
    /// equally spaced (`(Z_s + Z_r) / N` whole) and adjacent planets clear each other (their
    /// centres farther apart than a planet's tip diameter `m (Z_p + 2)`). Each error names the
    /// field and what it may be.
    ///
    /// ```
    /// use geardyn_physics::planetary::PlanetaryStage;
    /// let s = PlanetaryStage::new(24, 36, 96, 4, 0.004).unwrap();
    /// assert_eq!(s.ratio(), 5.0);
    /// // 3 planets can be equally spaced: (24 + 96) / 3 = 40 is whole; 7 cannot
    /// assert!(PlanetaryStage::new(24, 36, 96, 3, 0.004).is_ok());
    /// let e = PlanetaryStage::new(24, 36, 96, 7, 0.004).unwrap_err().to_string();
    /// assert!(e.contains("stage.planets = 7"), "{e}");
    /// ```
    pub fn new(
        sun: u32,
        planet: u32,
        ring: u32,
        planets: u32,
        module: f64,
    ) -> Result<Self, PhysicsError> {
        for (field, z) in [("sun_teeth", sun), ("planet_teeth", planet)] {
            if z < MIN_TEETH {
                return Err(invalid(
                    field,
                    z as f64,
                    format!("a whole number >= {MIN_TEETH}"),
                ));
            }
        }
        if !(module > 0.0 && module.is_finite()) {
            return Err(invalid("module", module, "a finite length > 0 (m)".into()));
        }
        if !PLANETS.contains(&planets) {
            return Err(invalid(
                "planets",
                planets as f64,
                format!("{} ..= {}", PLANETS.start(), PLANETS.end()),
            ));
        }
        let closes = sun + 2 * planet;
        if ring != closes {
            return Err(invalid(
                "ring_teeth",
                ring as f64,
                format!("sun_teeth + 2 planet_teeth = {closes} (the ring must close around sun and planets)"),
            ));
        }
        if !(sun + ring).is_multiple_of(planets) {
            let fits: Vec<String> = PLANETS
                .filter(|n| (sun + ring).is_multiple_of(*n))
                .map(|n| n.to_string())
                .collect();
            return Err(invalid(
                "planets",
                planets as f64,
                format!(
                    "a divisor of sun_teeth + ring_teeth = {} for equal spacing ({})",
                    sun + ring,
                    fits.join(", ")
                ),
            ));
        }
        let s = PlanetaryStage {
            sun,
            planet,
            ring,
            planets,
            module,
        };
        let gap = s.planet_gap();
        if gap <= 0.0 {
            return Err(PhysicsError::Geometry(format!(
                "{planets} planets of {planet} teeth interfere: adjacent planet centres are {:.4} mm apart, less than a planet's tip diameter {:.4} mm (fewer or smaller planets)",
                1e3 * s.adjacent_planet_distance(),
                1e3 * s.planet_tip_diameter()
            )));
        }
        Ok(s)
    }

    /// Centre distance of every planet from the stage axis (m).
    pub fn centre_distance(&self) -> f64 {
        self.module * (self.sun + self.planet) as f64 / 2.0
    }

    /// Tip diameter of a planet (m): `m (Z_p + 2)`.
    pub fn planet_tip_diameter(&self) -> f64 {
        self.module * (self.planet + 2) as f64
    }

    /// Distance between the centres of adjacent planets (m): `2 a sin(pi / N)`.
    pub fn adjacent_planet_distance(&self) -> f64 {
        2.0 * self.centre_distance() * (PI / self.planets as f64).sin()
    }

    /// Clearance between the tip circles of adjacent planets (m); negative when they overlap.
    pub fn planet_gap(&self) -> f64 {
        self.adjacent_planet_distance() - self.planet_tip_diameter()
    }

    /// Carrier angle of planet `n` (rad), `2 pi n / N`.
    pub fn planet_angle(&self, n: u32) -> f64 {
        2.0 * PI * (n % self.planets) as f64 / self.planets as f64
    }

    /// Speed ratio sun to carrier with the ring fixed: `1 + Z_r / Z_s`.
    pub fn ratio(&self) -> f64 {
        1.0 + self.ring as f64 / self.sun as f64
    }

    /// Mesh cycles per carrier revolution with the ring fixed: `Z_r` (the ring's teeth pass each
    /// planet once per carrier turn; equally `Z_s` times the sun's turns relative to the carrier).
    pub fn mesh_cycles_per_carrier_turn(&self) -> f64 {
        self.ring as f64
    }

    /// Phase of the sun–planet mesh of planet `n` relative to planet 0, in mesh cycles, in
    /// `[0, 1)`: `frac(Z_s psi_n / 2 pi)`.
    pub fn sun_planet_phase(&self, n: u32) -> f64 {
        frac(self.sun as f64 * self.planet_angle(n) / (2.0 * PI))
    }

    /// Phase of the ring–planet mesh of planet `n` relative to planet 0, in mesh cycles, in
    /// `[0, 1)`: `frac(-Z_r psi_n / 2 pi)`.
    pub fn ring_planet_phase(&self, n: u32) -> f64 {
        frac(-(self.ring as f64) * self.planet_angle(n) / (2.0 * PI))
    }

    /// Whether every sun–planet mesh is in phase (`Z_s / N` whole); otherwise the meshes are
    /// sequentially phased.
    pub fn in_phase(&self) -> bool {
        self.sun.is_multiple_of(self.planets)
    }
}

/// `x` modulo 1, in `[0, 1)`, with the rounding of whole numbers cleaned (`2.9999999999999996`
/// is 0, not 0.9999999999999996).
fn frac(x: f64) -> f64 {
    let f = x - x.floor();
    if (f - 1.0).abs() < 1e-12 || f.abs() < 1e-12 {
        0.0
    } else {
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sum over the planets of `exp(2 pi i k gamma_n)` for the `k`-th mesh harmonic: what
    /// reaches the carrier from the sun–planet meshes.
    fn phasor_sum(s: &PlanetaryStage, k: u32, phase: impl Fn(u32) -> f64) -> f64 {
        let (mut re, mut im) = (0.0, 0.0);
        for n in 0..s.planets {
            let a = 2.0 * PI * k as f64 * phase(n);
            re += a.cos();
            im += a.sin();
        }
        re.hypot(im)
    }

    /// Parker's rule (Parker 2000, "A physical explanation for the effectiveness of planet
    /// phasing to suppress planetary gear vibration", J. Sound Vib. 236:561–573): the k-th
    /// harmonic of the sun–planet mesh forces sums to N over the planets when `k Z_s / N` is whole
    /// and cancels otherwise; likewise for the ring with `Z_r`.
    #[test]
    fn mesh_harmonics_cancel_over_the_planets_unless_k_z_over_n_is_whole() {
        // 25 sun teeth, 5 planets? (25 + 75) / 5 = 20: equal spacing; 25 / 5 whole: in phase
        let s = PlanetaryStage::new(25, 25, 75, 5, 0.003).unwrap();
        assert!(s.in_phase());
        let s = PlanetaryStage::new(26, 25, 76, 3, 0.003).unwrap();
        assert!(!s.in_phase());
        for k in 1..=12 {
            let sun = phasor_sum(&s, k, |n| s.sun_planet_phase(n));
            let ring = phasor_sum(&s, k, |n| s.ring_planet_phase(n));
            let whole = |z: u32| (k * z).is_multiple_of(s.planets);
            let want = |z: u32| if whole(z) { s.planets as f64 } else { 0.0 };
            assert!((sun - want(s.sun)).abs() < 1e-9, "k {k}: sun {sun}");
            assert!((ring - want(s.ring)).abs() < 1e-9, "k {k}: ring {ring}");
        }
    }

    /// Sequential phasing of 26/25/76 with 3 planets: planet 1 at 120 degrees meets the sun
    /// 26/3 = 8.667 teeth later, a phase of 2/3; the ring's -76/3 = -25.333 teeth, a phase of 2/3.
    #[test]
    fn phases_of_a_sequentially_phased_stage() {
        let s = PlanetaryStage::new(26, 25, 76, 3, 0.003).unwrap();
        assert_eq!(s.sun_planet_phase(0), 0.0);
        assert!((s.sun_planet_phase(1) - 2.0 / 3.0).abs() < 1e-12);
        assert!((s.sun_planet_phase(2) - 1.0 / 3.0).abs() < 1e-12);
        assert!((s.ring_planet_phase(1) - 2.0 / 3.0).abs() < 1e-12);
        // equally spaced planets ((Z_s + Z_r) / N whole): each planet's sun and ring meshes are
        // shifted alike against planet 0's (Parker & Lin 2004)
        for n in 0..3 {
            assert!((s.sun_planet_phase(n) - s.ring_planet_phase(n)).abs() < 1e-12);
        }
    }

    /// Kinematics with the ring fixed: the sun turns `1 + Z_r / Z_s` times per carrier turn, and
    /// the mesh frequency seen from the carrier is `Z_s (w_s - w_c) = Z_r w_c`.
    #[test]
    fn ratio_and_mesh_frequency_agree() {
        let s = PlanetaryStage::new(24, 36, 96, 4, 0.004).unwrap();
        let (wc, ws) = (1.0, s.ratio());
        assert_eq!(ws, 5.0);
        assert_eq!(
            s.sun as f64 * (ws - wc),
            s.mesh_cycles_per_carrier_turn() * wc
        );
        assert!((s.centre_distance() - 0.12).abs() < 1e-15);
    }

    /// Each defect is refused with its field and what it may be.
    #[test]
    fn impossible_stages_are_refused_by_name() {
        let err = |r: Result<PlanetaryStage, PhysicsError>| r.unwrap_err().to_string();
        let e = err(PlanetaryStage::new(24, 36, 95, 4, 0.004));
        assert!(
            e.contains("stage.ring_teeth = 95") && e.contains("96"),
            "{e}"
        );
        let e = err(PlanetaryStage::new(24, 36, 96, 7, 0.004));
        assert!(e.contains("stage.planets = 7") && e.contains("120"), "{e}");
        let e = err(PlanetaryStage::new(10, 36, 82, 4, 0.004));
        assert!(e.contains("stage.sun_teeth = 10"), "{e}");
        let e = err(PlanetaryStage::new(24, 36, 96, 4, f64::NAN));
        assert!(e.contains("stage.module = NaN"), "{e}");
        let e = err(PlanetaryStage::new(24, 36, 96, 1, 0.004));
        assert!(e.contains("stage.planets = 1"), "{e}");
        // 6 planets of 36 teeth on a 120-tooth sum: 2 a sin(30 deg) = a = 0.12 m < tip 0.152 m
        let e = err(PlanetaryStage::new(24, 36, 96, 6, 0.004));
        assert!(e.contains("interfere"), "{e}");
        let s = PlanetaryStage::new(24, 36, 96, 4, 0.004).unwrap();
        assert!(s.planet_gap() > 0.0);
    }
}
