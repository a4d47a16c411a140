//! Gear condition indicators of a vibration signal sampled synchronously with the pinion
//! (docs/analyses.md, "Fault signatures", with the sources of every definition).
//!
//! A signal of whole revolutions is averaged over its revolutions (the time-synchronous average,
//! TSA) and split by integer orders of the revolution into
//!
//! * the **regular** signal: the mesh harmonics `k z1` (`k >= 1`) of the TSA;
//! * the **residual** signal: the TSA without the mean and the mesh harmonics
//!   ([`ResidualKind::Mesh`]) or also without the shaft orders `1 ..= shaft_orders`
//!   ([`ResidualKind::MeshAndShaft`], the default): the literature uses both;
//! * the **difference** signal: the TSA without the mean, the mesh harmonics, their first
//!   `sidebands` shaft sidebands `k z1 ± m` and the shaft orders `1 ..= shaft_orders`.
//!
//! `rms`, `peak_to_peak`, `crest_factor` and `kurtosis` are of the signal as given (every
//! sample, mean included in `rms`), the others of the TSA and its parts. The indicators are
//! ratios of amplitudes and moments: the normalised ones are dimensionless, `rms`,
//! `peak_to_peak` and `sideband_index` carry the unit of the signal.

use crate::spectrum::{band_envelope, filter_orders, line_amplitudes, setting, SettingError};
use serde::Serialize;

/// Which orders the residual signal loses besides the mean and the mesh harmonics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResidualKind {
    /// Only the mesh harmonics (Stewart's residual, as Decker and Zakrajsek computed NA4).
    Mesh,
    /// The mesh harmonics and the shaft orders `1 ..= shaft_orders` (Lebold et al. 2000;
    /// MATLAB `tsaresidual`).
    MeshAndShaft,
}

impl ResidualKind {
    /// The name used in files and options (`mesh`, `mesh_and_shaft`).
    pub fn name(self) -> &'static str {
        match self {
            ResidualKind::Mesh => "mesh",
            ResidualKind::MeshAndShaft => "mesh_and_shaft",
        }
    }

    /// From its name.
    pub fn from_name(s: &str) -> Result<Self, SettingError> {
        match s {
            "mesh" => Ok(ResidualKind::Mesh),
            "mesh_and_shaft" => Ok(ResidualKind::MeshAndShaft),
            _ => Err(setting("residual", s, "mesh or mesh_and_shaft")),
        }
    }
}

/// How the signal is read and split.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct IndicatorOptions {
    /// Samples per pinion revolution.
    pub samples_per_rev: usize,
    /// Mesh order: the pinion's tooth number `z1` (mesh cycles per pinion revolution).
    pub mesh_order: usize,
    /// Shaft sidebands `k z1 ± 1 ..= sidebands` removed from the difference signal and summed by
    /// the sideband indicators' first order (default 1).
    pub sidebands: usize,
    /// Shaft orders `1 ..= shaft_orders` removed from the difference signal (and from the
    /// residual with [`ResidualKind::MeshAndShaft`]); default 1.
    pub shaft_orders: usize,
    /// Residual definition.
    pub residual: ResidualKind,
}

impl IndicatorOptions {
    /// The defaults for `samples_per_rev` samples per revolution and mesh order `mesh_order`.
    pub fn new(samples_per_rev: usize, mesh_order: usize) -> Self {
        IndicatorOptions {
            samples_per_rev,
            mesh_order,
            sidebands: 1,
            shaft_orders: 1,
            residual: ResidualKind::MeshAndShaft,
        }
    }

    /// Largest `sidebands` and `shaft_orders` accepted.
    pub const MAX_ORDERS: usize = 1000;

    /// Refuses a setting, or a signal of `len` samples, that the indicators cannot be read from,
    /// naming the argument and its allowed range.
    pub fn check(&self, len: usize) -> Result<(), SettingError> {
        let spr = self.samples_per_rev;
        if spr < 8 {
            return Err(setting("samples_per_rev", spr, ">= 8"));
        }
        if len < spr || !len.is_multiple_of(spr) {
            return Err(setting(
                "samples_per_rev",
                spr,
                format!("a divisor of the signal length {len} that leaves at least one revolution"),
            ));
        }
        if self.sidebands > Self::MAX_ORDERS {
            return Err(setting(
                "sidebands",
                self.sidebands,
                format!("0 ..= {}", Self::MAX_ORDERS),
            ));
        }
        if self.shaft_orders > Self::MAX_ORDERS {
            return Err(setting(
                "shaft_orders",
                self.shaft_orders,
                format!("0 ..= {}", Self::MAX_ORDERS),
            ));
        }
        let (lo, hi) = self.mesh_range();
        if self.mesh_order < lo || self.mesh_order > hi {
            return Err(setting(
                "mesh_order",
                self.mesh_order,
                if lo > hi {
                    format!(
                        "none: samples_per_rev = {spr} leaves no mesh order with {} sideband(s) below the Nyquist order {}",
                        self.sidebands,
                        spr / 2
                    )
                } else {
                    format!(
                        "{lo} ..= {hi} (the mesh order and its {} sideband(s) between order 1 and below the Nyquist order samples_per_rev / 2 = {})",
                        self.sidebands,
                        spr / 2
                    )
                },
            ));
        }
        Ok(())
    }

    /// The mesh orders accepted: the first sidebands above order 0 and below the Nyquist order.
    pub fn mesh_range(&self) -> (usize, usize) {
        // the sideband indicators read the first sidebands whatever `sidebands` says
        let s = self.sidebands.max(1);
        let below_nyquist = self.samples_per_rev.saturating_sub(1) / 2;
        (s + 1, below_nyquist.saturating_sub(s))
    }

    fn nyquist(&self) -> usize {
        self.samples_per_rev / 2
    }

    fn is_mesh(&self, j: usize) -> bool {
        j > 0 && j.is_multiple_of(self.mesh_order)
    }

    fn is_sideband(&self, j: usize) -> bool {
        let z = self.mesh_order;
        let k = (j + z / 2) / z;
        k >= 1 && {
            let m = j.abs_diff(k * z);
            m >= 1 && m <= self.sidebands
        }
    }

    fn is_shaft(&self, j: usize) -> bool {
        j >= 1 && j <= self.shaft_orders
    }

    /// The orders of the regular signal, and those the difference and residual signals lose.
    pub fn orders(&self) -> RemovedOrders {
        let all = 0..=self.nyquist();
        let regular: Vec<usize> = all.clone().filter(|&j| self.is_mesh(j)).collect();
        let difference = all
            .clone()
            .filter(|&j| j == 0 || self.is_mesh(j) || self.is_sideband(j) || self.is_shaft(j))
            .collect();
        let residual = all
            .filter(|&j| {
                j == 0
                    || self.is_mesh(j)
                    || (self.residual == ResidualKind::MeshAndShaft && self.is_shaft(j))
            })
            .collect();
        RemovedOrders {
            regular,
            difference,
            residual,
            residual_kind: self.residual,
            nb4_band: self.nb4_band(),
        }
    }

    /// NB4's band around the mesh order: `z1 ± z1 / 2`, below the Nyquist order.
    fn nb4_band(&self) -> [usize; 2] {
        let z = self.mesh_order;
        [
            (z - z / 2).max(1),
            (z + z / 2).min((self.samples_per_rev - 1) / 2),
        ]
    }
}

/// The orders of each part of the TSA (recorded with every result).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RemovedOrders {
    /// Orders the regular signal keeps (the mesh harmonics up to the Nyquist order).
    pub regular: Vec<usize>,
    /// Orders removed from the TSA to give the difference signal.
    pub difference: Vec<usize>,
    /// Orders removed from the TSA to give the residual signal.
    pub residual: Vec<usize>,
    /// The residual definition used.
    pub residual_kind: ResidualKind,
    /// The band (orders, inclusive) whose envelope NB4 reads.
    pub nb4_band: [usize; 2],
}

/// A signal split into its time-synchronous average and the parts of the TSA.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Decomposition {
    /// Revolutions averaged.
    pub revolutions: usize,
    /// Time-synchronous average: one revolution, `samples_per_rev` samples.
    pub tsa: Vec<f64>,
    /// Regular signal (mesh harmonics of the TSA).
    pub regular: Vec<f64>,
    /// Difference signal.
    pub difference: Vec<f64>,
    /// Residual signal.
    pub residual: Vec<f64>,
    /// Envelope of the TSA's band around the mesh order (NB4).
    pub envelope: Vec<f64>,
    /// Amplitudes of the TSA's integer orders `0 ..= samples_per_rev / 2`.
    pub lines: Vec<f64>,
    /// The orders of each part.
    pub orders: RemovedOrders,
}

/// Below this RMS, relative to the TSA's standard deviation, a difference or residual signal is
/// the integration's noise, not content: a healthy pair on a motion of one mesh cycle has no
/// order but the mesh harmonics, and its normalised moments are then those of round-off.
pub const NOISE_FLOOR: f64 = 1e-6;

impl Decomposition {
    /// RMS of the difference signal over the TSA's standard deviation.
    pub fn difference_fraction(&self) -> f64 {
        rms(&self.difference) / central(&self.tsa).std()
    }
    /// RMS of the residual signal over the TSA's standard deviation.
    pub fn residual_fraction(&self) -> f64 {
        rms(&self.residual) / central(&self.tsa).std()
    }
    /// Whether the difference signal is at the integration's noise floor ([`NOISE_FLOOR`]).
    pub fn difference_is_noise(&self) -> bool {
        !exceeds(self.difference_fraction(), NOISE_FLOOR)
    }
    /// Whether the residual signal is at the integration's noise floor ([`NOISE_FLOOR`]).
    pub fn residual_is_noise(&self) -> bool {
        !exceeds(self.residual_fraction(), NOISE_FLOOR)
    }
    /// Whether the envelope of NB4's band is constant to the integration's noise floor (a band
    /// holding the mesh order alone: no modulation).
    pub fn envelope_is_noise(&self) -> bool {
        self.envelope_below(NOISE_FLOOR)
    }
    fn envelope_below(&self, floor: f64) -> bool {
        !exceeds(central(&self.envelope).std(), floor * rms(&self.envelope))
    }
    /// Whether the first sidebands of the mesh order `z` are at the noise floor, relative to the
    /// TSA's standard deviation.
    pub fn sidebands_are_noise(&self, z: usize) -> bool {
        self.sidebands_below(z, NOISE_FLOOR)
    }
    fn sidebands_below(&self, z: usize, floor: f64) -> bool {
        let sb = self.lines.get(z - 1).copied().unwrap_or(0.0)
            + self.lines.get(z + 1).copied().unwrap_or(0.0);
        !exceeds(sb, floor * central(&self.tsa).std())
    }
    /// Whether indicator `name` of this record reads only the integration's noise (the
    /// normalised moments of a difference, residual or envelope signal that has no content, the
    /// energy ratio and sideband indicators without any non-mesh order).
    pub fn indicator_is_noise(&self, name: &str, z: usize) -> bool {
        self.indicator_below(name, z, NOISE_FLOOR)
    }
    /// Whether the content indicator `name` reads (difference, residual, envelope modulation or
    /// first sidebands) is below `floor` relative to the TSA's standard deviation (the envelope:
    /// relative to its RMS). [`Decomposition::indicator_is_noise`] at [`NOISE_FLOOR`]; a higher
    /// floor stands for a measurement's noise. Indicators of the raw signal and FM0: never.
    pub fn indicator_below(&self, name: &str, z: usize, floor: f64) -> bool {
        let tsa_std = central(&self.tsa).std();
        match name {
            "fm4" | "m6a" | "m8a" | "er" => !exceeds(rms(&self.difference), floor * tsa_std),
            "na4" => !exceeds(rms(&self.residual), floor * tsa_std),
            "nb4" => self.envelope_below(floor),
            "sideband_index" | "sideband_level_factor" => self.sidebands_below(z, floor),
            _ => false,
        }
    }
}

/// `a > b`, false when either is NaN (a NaN content is no content).
fn exceeds(a: f64, b: f64) -> bool {
    a > b
}

/// Averages `signal` over its revolutions and splits the average (validated by
/// [`IndicatorOptions::check`]).
pub fn decompose(signal: &[f64], o: &IndicatorOptions) -> Result<Decomposition, SettingError> {
    o.check(signal.len())?;
    if let Some(i) = signal.iter().position(|v| !v.is_finite()) {
        return Err(setting(
            "signal",
            format!("{} at index {i}", signal[i]),
            "finite numbers only",
        ));
    }
    let spr = o.samples_per_rev;
    let revs = signal.len() / spr;
    let mut tsa = vec![0.0; spr];
    for rev in signal.chunks_exact(spr) {
        for (a, v) in tsa.iter_mut().zip(rev) {
            *a += v;
        }
    }
    for a in &mut tsa {
        *a /= revs as f64;
    }
    let orders = o.orders();
    let regular = filter_orders(&tsa, |j| o.is_mesh(j) && j <= o.nyquist());
    let difference = filter_orders(&tsa, |j| {
        !(j == 0 || o.is_mesh(j) || o.is_sideband(j) || o.is_shaft(j))
    });
    let residual = filter_orders(&tsa, |j| {
        !(j == 0 || o.is_mesh(j) || (o.residual == ResidualKind::MeshAndShaft && o.is_shaft(j)))
    });
    let [lo, hi] = orders.nb4_band;
    let envelope = band_envelope(&tsa, lo, hi);
    let lines = line_amplitudes(&tsa);
    Ok(Decomposition {
        revolutions: revs,
        tsa,
        regular,
        difference,
        residual,
        envelope,
        lines,
        orders,
    })
}

/// Central moments of a signal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moments {
    /// Samples.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Second to eighth central moments `(1/n) sum (x - mean)^k`, `k = 2, 4, 6, 8`.
    pub m: [f64; 4],
}

impl Moments {
    /// Standard deviation (population: `1/n`).
    pub fn std(&self) -> f64 {
        self.m[0].sqrt()
    }
    /// `m4 / m2^2` (3 for Gaussian noise, 1.5 for a sine); NaN for a constant signal.
    pub fn kurtosis(&self) -> f64 {
        self.m[1] / (self.m[0] * self.m[0])
    }
}

/// Central moments of `x` (two passes: the mean first).
pub fn central(x: &[f64]) -> Moments {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n.max(1) as f64;
    let mut m = [0.0; 4];
    for v in x {
        let d = v - mean;
        let d2 = d * d;
        let d4 = d2 * d2;
        m[0] += d2;
        m[1] += d4;
        m[2] += d4 * d2;
        m[3] += d4 * d4;
    }
    for s in &mut m {
        *s /= n.max(1) as f64;
    }
    Moments { n, mean, m }
}

/// Root mean square `sqrt(mean(x^2))` (mean included).
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// Names of the indicators, in the order of [`Indicators::named`].
pub const INDICATOR_NAMES: [&str; 13] = [
    "rms",
    "peak_to_peak",
    "crest_factor",
    "kurtosis",
    "fm0",
    "fm4",
    "m6a",
    "m8a",
    "na4",
    "nb4",
    "er",
    "sideband_index",
    "sideband_level_factor",
];

/// The value of normalised indicator `name` for Gaussian noise (FM4, NA4, NB4: 3; M6A: 15;
/// M8A: 105, the standardised moments of a normal distribution): the reference of a healthy
/// signal whose difference, residual or envelope holds nothing but noise. `None` for the others.
pub fn gaussian_reference(name: &str) -> Option<f64> {
    match name {
        "fm4" | "na4" | "nb4" => Some(3.0),
        "m6a" => Some(15.0),
        "m8a" => Some(105.0),
        _ => None,
    }
}

/// The condition indicators of one signal (definitions in docs/analyses.md).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Indicators {
    /// `sqrt(mean(x^2))` of the signal as given (unit of the signal).
    pub rms: f64,
    /// `max(x) - min(x)` of the signal as given (unit of the signal).
    pub peak_to_peak: f64,
    /// `max|x| / rms` of the signal as given.
    pub crest_factor: f64,
    /// `m4 / m2^2` of the signal as given (central moments).
    pub kurtosis: f64,
    /// Peak-to-peak of the TSA over the sum of its mesh-harmonic amplitudes.
    pub fm0: f64,
    /// Kurtosis of the difference signal.
    pub fm4: f64,
    /// `m6 / m2^3` of the difference signal.
    pub m6a: f64,
    /// `m8 / m2^4` of the difference signal.
    pub m8a: f64,
    /// Fourth moment of the residual over the square of its variance averaged over the run.
    pub na4: f64,
    /// As NA4, of the envelope of the TSA's band around the mesh order.
    pub nb4: f64,
    /// Energy ratio: RMS of the difference signal over RMS of the regular signal.
    pub er: f64,
    /// Mean amplitude of the first shaft sidebands of the mesh order, `(A(z1-1) + A(z1+1)) / 2`
    /// (unit of the signal).
    pub sideband_index: f64,
    /// `(A(z1-1) + A(z1+1))` over the standard deviation of the TSA.
    pub sideband_level_factor: f64,
}

impl Indicators {
    /// `(name, value)` in the order of [`INDICATOR_NAMES`].
    pub fn named(&self) -> [(&'static str, f64); 13] {
        let v = [
            self.rms,
            self.peak_to_peak,
            self.crest_factor,
            self.kurtosis,
            self.fm0,
            self.fm4,
            self.m6a,
            self.m8a,
            self.na4,
            self.nb4,
            self.er,
            self.sideband_index,
            self.sideband_level_factor,
        ];
        let mut out = [("", 0.0); 13];
        for (k, o) in out.iter_mut().enumerate() {
            *o = (INDICATOR_NAMES[k], v[k]);
        }
        out
    }

    /// The value of indicator `name`.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.named()
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| *v)
    }
}

/// The indicators of `signal` (the samples as given) with its decomposition `dec`; `run` holds
/// the decompositions of the records before it in the same run (for NA4 and NB4, whose
/// denominator is the variance averaged over the run including this record; empty: this record's
/// own variance, i.e. the kurtosis of its residual).
pub fn indicators(
    signal: &[f64],
    dec: &Decomposition,
    o: &IndicatorOptions,
    run: &[&Decomposition],
) -> Indicators {
    let raw = central(signal);
    let r = rms(signal);
    let (lo, hi) = signal
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let peak = lo.abs().max(hi.abs());
    let tsa = central(&dec.tsa);
    let (tlo, thi) = dec
        .tsa
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let mesh_sum: f64 = dec.orders.regular.iter().map(|&j| dec.lines[j]).sum();
    let d = central(&dec.difference);
    let res = central(&dec.residual);
    let env = central(&dec.envelope);
    let run_var = |own: f64, of: fn(&Decomposition) -> f64| {
        (run.iter().map(|p| of(p)).sum::<f64>() + own) / (run.len() + 1) as f64
    };
    let res_var = run_var(res.m[0], |p| central(&p.residual).m[0]);
    let env_var = run_var(env.m[0], |p| central(&p.envelope).m[0]);
    let z = o.mesh_order;
    let sb = dec.lines[z - 1] + dec.lines[z + 1];
    Indicators {
        rms: r,
        peak_to_peak: hi - lo,
        crest_factor: peak / r,
        kurtosis: raw.kurtosis(),
        fm0: (thi - tlo) / mesh_sum,
        fm4: d.kurtosis(),
        m6a: d.m[2] / d.m[0].powi(3),
        m8a: d.m[3] / d.m[0].powi(4),
        na4: res.m[1] / (res_var * res_var),
        nb4: env.m[1] / (env_var * env_var),
        er: rms(&dec.difference) / rms(&dec.regular),
        sideband_index: sb / 2.0,
        sideband_level_factor: sb / tsa.std(),
    }
}

/// The indicators of one signal on its own (validated; NA4 and NB4 with the signal's own
/// variance).
///
/// ```
/// use geardyn_analysis::indicators::{indicators_of, IndicatorOptions};
/// let x: Vec<f64> = (0..512).map(|i| (2.0 * std::f64::consts::PI * 20.0 * i as f64 / 256.0).sin()).collect();
/// let ind = indicators_of(&x, &IndicatorOptions::new(256, 20)).unwrap();
/// assert!((ind.kurtosis - 1.5).abs() < 1e-9 && (ind.crest_factor - 2f64.sqrt()).abs() < 1e-9);
/// ```
pub fn indicators_of(signal: &[f64], o: &IndicatorOptions) -> Result<Indicators, SettingError> {
    let dec = decompose(signal, o)?;
    Ok(indicators(signal, &dec, o, &[]))
}

/// The indicators of `signal` with NA4 and NB4 over a run: `run` holds the earlier records of
/// the same run, each as long as `signal` and read with the same options (empty: the signal's
/// own variance). Every input is validated: an error names the argument (`signal`, `run[i]`,
/// `samples_per_rev`, `mesh_order`, ...) and its allowed range.
pub fn indicators_with_run(
    signal: &[f64],
    o: &IndicatorOptions,
    run: &[&[f64]],
) -> Result<Indicators, SettingError> {
    let dec = decompose(signal, o)?;
    let mut prior = Vec::with_capacity(run.len());
    for (i, r) in run.iter().enumerate() {
        if r.len() != signal.len() {
            return Err(setting(
                "run",
                format!("record {i} of {} samples", r.len()),
                format!("records as long as the signal ({} samples)", signal.len()),
            ));
        }
        prior.push(decompose(r, o).map_err(|e| SettingError {
            field: "run",
            value: format!("record {i}: {} = {}", e.field, e.value),
            allowed: e.allowed,
        })?);
    }
    let refs: Vec<&Decomposition> = prior.iter().collect();
    Ok(indicators(signal, &dec, o, &refs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use std::f64::consts::PI;

    fn gaussian(n: usize, seed: u64) -> Vec<f64> {
        // Box–Muller on a seeded stream: deterministic
        use rand::Rng;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                let u1: f64 = rng.gen_range(f64::EPSILON..1.0);
                let u2: f64 = rng.gen();
                (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
            })
            .collect()
    }

    #[test]
    fn pure_sine_has_kurtosis_1_5_and_crest_sqrt_2() {
        let spr = 256;
        let x: Vec<f64> = (0..4 * spr)
            .map(|i| 3.0 * (2.0 * PI * 20.0 * i as f64 / spr as f64).sin())
            .collect();
        let ind = indicators_of(&x, &IndicatorOptions::new(spr, 20)).unwrap();
        assert!((ind.kurtosis - 1.5).abs() < 1e-12, "{}", ind.kurtosis);
        assert!(
            (ind.crest_factor - 2f64.sqrt()).abs() < 1e-12,
            "{}",
            ind.crest_factor
        );
        assert!((ind.rms - 3.0 / 2f64.sqrt()).abs() < 1e-12);
        assert!((ind.peak_to_peak - 6.0).abs() < 1e-12);
        // all of it is the mesh order: FM0 = p2p / A(z1) = 2, no sidebands, no difference
        assert!((ind.fm0 - 2.0).abs() < 1e-12, "{}", ind.fm0);
        assert!(ind.sideband_index < 1e-12 && ind.er < 1e-12);
    }

    #[test]
    fn gaussian_noise_has_kurtosis_3() {
        let x = gaussian(1 << 16, 7);
        let m = central(&x);
        assert!((m.kurtosis() - 3.0).abs() < 0.1, "{}", m.kurtosis());
        // (standard error of the sample kurtosis sqrt(24 / n) = 0.019)
        // sixth and eighth standardised moments of a Gaussian: 15 and 105
        let ind = indicators_of(&x, &IndicatorOptions::new(1 << 12, 100)).unwrap();
        assert!((ind.kurtosis - 3.0).abs() < 0.1);
        // the TSA of 16 revolutions of noise is noise again: FM4 of its difference near 3
        assert!((ind.fm4 - 3.0).abs() < 0.3, "{}", ind.fm4);
        assert!((ind.m6a - 15.0).abs() < 4.0, "{}", ind.m6a);
        assert!((ind.m8a - 105.0).abs() < 50.0, "{}", ind.m8a);
    }

    #[test]
    fn a_periodic_impulse_train_has_fm4_far_above_3() {
        // a mesh tone plus one impulse per revolution (a broken tooth)
        let spr = 512;
        let x: Vec<f64> = (0..8 * spr)
            .map(|i| {
                let k = i % spr;
                (2.0 * PI * 16.0 * k as f64 / spr as f64).cos() + if k == 100 { 5.0 } else { 0.0 }
            })
            .collect();
        let o = IndicatorOptions::new(spr, 16);
        let ind = indicators_of(&x, &o).unwrap();
        assert!(ind.fm4 > 50.0, "{}", ind.fm4);
        assert!(ind.m6a > ind.fm4 && ind.m8a > ind.m6a);
        assert!(ind.na4 > 50.0 && ind.er > 0.1 && ind.sideband_index > 0.0);
        // without the impulse: nothing but the mesh order
        let clean: Vec<f64> = (0..8 * spr)
            .map(|i| (2.0 * PI * 16.0 * (i % spr) as f64 / spr as f64).cos())
            .collect();
        let dec = decompose(&clean, &o).unwrap();
        assert!(dec.difference_is_noise() && dec.residual_is_noise());
        assert!(dec.envelope_is_noise() && dec.sidebands_are_noise(16));
        assert!(["fm4", "na4", "nb4", "er", "sideband_index"]
            .iter()
            .all(|n| dec.indicator_is_noise(n, 16)));
        assert!(!dec.indicator_is_noise("kurtosis", 16));
        let dec = decompose(&x, &o).unwrap();
        assert!(!dec.difference_is_noise() && !dec.envelope_is_noise());
        assert!(!dec.sidebands_are_noise(16));
    }

    #[test]
    fn na4_over_a_run_uses_the_mean_variance() {
        let spr = 64;
        let o = IndicatorOptions::new(spr, 8);
        let base: Vec<f64> = gaussian(spr, 1);
        let grown: Vec<f64> = base.iter().map(|v| 2.0 * v).collect();
        let d1 = decompose(&base, &o).unwrap();
        let d2 = decompose(&grown, &o).unwrap();
        let own = indicators(&grown, &d2, &o, &[]);
        let run = indicators(&grown, &d2, &o, &[&d1]);
        // variance 4 s against the run's mean (s + 4 s) / 2: NA4 grows by (4 / 2.5)^2
        assert!((run.na4 / own.na4 - (4.0f64 / 2.5).powi(2)).abs() < 1e-9);
    }

    #[test]
    fn removed_orders_follow_the_options() {
        let mut o = IndicatorOptions::new(32, 5);
        let r = o.orders();
        assert_eq!(r.regular, vec![5, 10, 15]);
        assert_eq!(r.difference, vec![0, 1, 4, 5, 6, 9, 10, 11, 14, 15, 16]);
        assert_eq!(r.residual, vec![0, 1, 5, 10, 15]);
        o.residual = ResidualKind::Mesh;
        assert_eq!(o.orders().residual, vec![0, 5, 10, 15]);
    }

    #[test]
    fn bad_input_is_named_never_a_panic() {
        let x = vec![1.0; 100];
        let e = indicators_of(&x, &IndicatorOptions::new(30, 5)).unwrap_err();
        assert_eq!(e.field, "samples_per_rev");
        let e = indicators_of(&x, &IndicatorOptions::new(4, 1)).unwrap_err();
        assert_eq!(e.field, "samples_per_rev");
        let e = indicators_of(&x, &IndicatorOptions::new(50, 24)).unwrap_err();
        assert_eq!(e.field, "mesh_order");
        assert!(e.allowed.contains("2 ..= 23"), "{}", e.allowed);
        let e = indicators_of(&x, &IndicatorOptions::new(50, 1)).unwrap_err();
        assert_eq!(e.field, "mesh_order");
        let mut y = vec![0.5; 100];
        y[17] = f64::NAN;
        let e = indicators_of(&y, &IndicatorOptions::new(50, 5)).unwrap_err();
        assert_eq!(e.field, "signal");
        assert!(indicators_of(&[], &IndicatorOptions::new(8, 2)).is_err());
        // a constant signal has no kurtosis: NaN, not a panic
        let c = indicators_of(&x, &IndicatorOptions::new(50, 5)).unwrap();
        assert!(c.kurtosis.is_nan() && (c.rms - 1.0).abs() < 1e-15);
    }
}
