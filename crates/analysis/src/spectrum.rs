//! Spectra in orders of the pinion revolution (docs/analyses.md, "Fault signatures").
//!
//! A signal sampled `samples_per_rev` times per pinion revolution has its spectral lines at
//! orders (cycles per revolution): order `z1` is the mesh frequency, `k z1` its harmonics and
//! `k z1 ± m` their shaft sidebands. Two spectra:
//!
//! * [`welch_orders`]: the raw record, Hann-windowed segments of a whole number of revolutions,
//!   50 % overlap, mean removed per segment, power averaged over the segments (Welch 1967) and
//!   given back as an amplitude: a sinusoid of amplitude `A` at an order on the grid reads `A`.
//! * [`line_amplitudes`]: one revolution (a time-synchronous average, periodic by construction)
//!   without window: bin `j` is order `j` exactly.
//!
//! Amplitudes carry the unit of the signal (µm, N, m/s²); orders are dimensionless.

use realfft::num_complex::Complex;
use realfft::RealFftPlanner;

/// A one-sided amplitude spectrum over orders of the pinion revolution.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Spectrum {
    /// Orders (cycles per pinion revolution), from 0 to the Nyquist order `samples_per_rev / 2`.
    pub orders: Vec<f64>,
    /// Amplitude of each order, in the unit of the signal.
    pub amplitude: Vec<f64>,
    /// Segments averaged (1: a single windowed record).
    pub segments: usize,
}

/// A setting outside its range: names the argument and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("bad {field} = {value}: allowed {allowed}")]
pub struct SettingError {
    /// The argument.
    pub field: &'static str,
    /// Its value, as given.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

pub(crate) fn setting(
    field: &'static str,
    value: impl ToString,
    allowed: impl Into<String>,
) -> SettingError {
    SettingError {
        field,
        value: value.to_string(),
        allowed: allowed.into(),
    }
}

/// The periodic ("DFT-even") Hann window of length `n`: `w_i = (1 - cos(2 pi i / n)) / 2`.
pub fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.5 * (1.0 - (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos()))
        .collect()
}

/// One-sided amplitudes of `x` (length `n`, even) with window `w` (`None`: rectangular): a
/// sinusoid of amplitude `A` on bin `j` gives `A` at `j` (the window's coherent gain divided
/// out), the mean gives itself at bin 0. `n / 2 + 1` values.
fn one_sided(
    planner: &mut RealFftPlanner<f64>,
    x: &[f64],
    w: Option<&[f64]>,
    buf: &mut Vec<f64>,
    out: &mut Vec<Complex<f64>>,
) -> Vec<f64> {
    let n = x.len();
    let fft = planner.plan_fft_forward(n);
    buf.clear();
    match w {
        Some(w) => buf.extend(x.iter().zip(w).map(|(a, b)| a * b)),
        None => buf.extend_from_slice(x),
    }
    out.clear();
    out.resize(n / 2 + 1, Complex::new(0.0, 0.0));
    // lengths are right by construction: the only error of `process` is a length mismatch
    fft.process(buf, out)
        .expect("buffer lengths match the plan");
    let gain: f64 = w.map_or(n as f64, |w| w.iter().sum());
    out.iter()
        .enumerate()
        .map(|(j, c)| {
            let edge = j == 0 || (n.is_multiple_of(2) && j == n / 2);
            c.norm() * if edge { 1.0 } else { 2.0 } / gain
        })
        .collect()
}

/// Welch amplitude spectrum of `x` in orders: Hann-windowed segments of `segment_revs`
/// revolutions (`segment_revs * samples_per_rev` samples), 50 % overlap, each segment's mean
/// removed, the squared amplitudes averaged over the segments and the square root taken.
/// Order resolution `1 / segment_revs`; a line on an integer order leaks into the orders
/// `± 1 / segment_revs` beside it (Hann), so with two or more revolutions per segment the
/// leakage never falls on a neighbouring integer order (a shaft sideband).
pub fn welch_orders(
    x: &[f64],
    samples_per_rev: usize,
    segment_revs: usize,
) -> Result<Spectrum, SettingError> {
    if samples_per_rev < 4 {
        return Err(setting("samples_per_rev", samples_per_rev, ">= 4"));
    }
    let seg = samples_per_rev.saturating_mul(segment_revs);
    if segment_revs == 0 || seg > x.len() {
        return Err(setting(
            "segment_revs",
            segment_revs,
            format!(
                "1 ..= {} (the revolutions in the record)",
                x.len() / samples_per_rev
            ),
        ));
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(setting(
            "signal",
            format!("{} at index {i}", x[i]),
            "finite numbers only",
        ));
    }
    let hop = (seg / 2).max(1);
    let count = (x.len() - seg) / hop + 1;
    let w = hann(seg);
    let mut planner = RealFftPlanner::<f64>::new();
    let (mut buf, mut out) = (Vec::with_capacity(seg), Vec::with_capacity(seg / 2 + 1));
    let mut centred = vec![0.0; seg];
    let mut power = vec![0.0; seg / 2 + 1];
    for s in 0..count {
        let part = &x[s * hop..s * hop + seg];
        let mean = part.iter().sum::<f64>() / seg as f64;
        for (c, v) in centred.iter_mut().zip(part) {
            *c = v - mean;
        }
        let a = one_sided(&mut planner, &centred, Some(&w), &mut buf, &mut out);
        for (p, v) in power.iter_mut().zip(&a) {
            *p += v * v;
        }
    }
    Ok(Spectrum {
        orders: (0..power.len())
            .map(|j| j as f64 / segment_revs as f64)
            .collect(),
        amplitude: power.iter().map(|p| (p / count as f64).sqrt()).collect(),
        segments: count,
    })
}

/// Amplitudes of the integer orders `0 ..= n/2` of one revolution `rev` (a time-synchronous
/// average: periodic, so no window): element `j` is the amplitude of order `j`, element 0 the
/// mean.
pub fn line_amplitudes(rev: &[f64]) -> Vec<f64> {
    let mut planner = RealFftPlanner::<f64>::new();
    let (mut buf, mut out) = (Vec::new(), Vec::new());
    one_sided(&mut planner, rev, None, &mut buf, &mut out)
}

/// Keeps the integer orders of one revolution `rev` for which `keep(order)` holds and removes
/// the others (exact: a forward FFT, bins set to zero, the inverse FFT).
pub fn filter_orders(rev: &[f64], keep: impl Fn(usize) -> bool) -> Vec<f64> {
    let n = rev.len();
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let mut buf = rev.to_vec();
    let mut spec = fwd.make_output_vec();
    fwd.process(&mut buf, &mut spec)
        .expect("buffer lengths match the plan");
    for (j, c) in spec.iter_mut().enumerate() {
        if !keep(j) {
            *c = Complex::new(0.0, 0.0);
        }
    }
    // the inverse of a real signal's spectrum: the imaginary parts of bin 0 and n/2 are zero
    spec[0].im = 0.0;
    if n.is_multiple_of(2) {
        spec[n / 2].im = 0.0;
    }
    let mut back = inv.make_output_vec();
    inv.process(&mut spec, &mut back)
        .expect("buffer lengths match the plan");
    back.iter().map(|v| v / n as f64).collect()
}

/// Envelope of the band `lo ..= hi` (integer orders) of one revolution `rev`: the modulus of the
/// analytic signal of the band-passed signal (Hilbert transform through the FFT: the band's
/// positive orders doubled, the rest zero).
pub fn band_envelope(rev: &[f64], lo: usize, hi: usize) -> Vec<f64> {
    let n = rev.len();
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let mut buf = rev.to_vec();
    let mut spec = fwd.make_output_vec();
    fwd.process(&mut buf, &mut spec)
        .expect("buffer lengths match the plan");
    // full complex spectrum of the analytic signal: 2 X_j on the band's positive orders
    let mut full = vec![Complex::new(0.0, 0.0); n];
    for (j, c) in spec.iter().enumerate() {
        if j >= lo.max(1) && j <= hi && j < n.div_ceil(2) {
            full[j] = *c * 2.0;
        }
    }
    rustfft::FftPlanner::new()
        .plan_fft_inverse(n)
        .process(&mut full);
    full.iter().map(|c| c.norm() / n as f64).collect()
}

/// The label of integer order `order` when it is a mesh harmonic (`mesh1`, `mesh2`, ...) or a
/// shaft sideband of one within `sidebands` orders (`mesh1-1`, `mesh2+3`, ...); `None` else.
pub fn order_label(order: usize, mesh_order: usize, sidebands: usize) -> Option<String> {
    if mesh_order == 0 || order == 0 {
        return None;
    }
    let k = (order + mesh_order / 2) / mesh_order;
    if k == 0 {
        return None;
    }
    let centre = k * mesh_order;
    let m = order.abs_diff(centre);
    if m == 0 {
        Some(format!("mesh{k}"))
    } else if m <= sidebands {
        Some(format!(
            "mesh{k}{}{m}",
            if order > centre { '+' } else { '-' }
        ))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn a_line_at_a_known_order_has_its_amplitude() {
        // 8 revolutions of 256 samples: 2.5 at order 40 (the mesh order of a 40-tooth pinion),
        // 0.3 at order 7, and a mean of 4 (removed per segment)
        let spr = 256;
        let x: Vec<f64> = (0..8 * spr)
            .map(|i| {
                let th = 2.0 * PI * i as f64 / spr as f64;
                4.0 + 2.5 * (40.0 * th + 0.3).cos() + 0.3 * (7.0 * th).sin()
            })
            .collect();
        let s = welch_orders(&x, spr, 4).unwrap();
        assert_eq!(s.segments, 3);
        let at = |o: f64| {
            let j = s.orders.iter().position(|&v| v == o).unwrap();
            s.amplitude[j]
        };
        assert!((at(40.0) - 2.5).abs() < 1e-9, "{}", at(40.0));
        assert!((at(7.0) - 0.3).abs() < 1e-9);
        // Hann leakage: half the amplitude on the neighbouring bins (orders 39.75, 40.25), none
        // on the integer orders beside the line
        assert!((at(40.25) - 1.25).abs() < 1e-9);
        assert!(at(39.0) < 1e-9 && at(41.0) < 1e-9 && at(0.0) < 1e-9);
        let lines = line_amplitudes(&x[..spr]);
        assert!((lines[40] - 2.5).abs() < 1e-12 && (lines[0] - 4.0).abs() < 1e-12);
        assert!((lines[7] - 0.3).abs() < 1e-12 && lines[8] < 1e-12);
    }

    #[test]
    fn an_odd_number_of_samples_per_revolution_reads_the_same_line() {
        let spr = 255;
        let x: Vec<f64> = (0..4 * spr)
            .map(|i| 2.5 * (2.0 * PI * 40.0 * i as f64 / spr as f64).cos())
            .collect();
        let s = welch_orders(&x, spr, 2).unwrap();
        let j = s.orders.iter().position(|&o| o == 40.0).unwrap();
        assert!((s.amplitude[j] - 2.5).abs() < 1e-9, "{}", s.amplitude[j]);
        assert!((line_amplitudes(&x[..spr])[40] - 2.5).abs() < 1e-12);
    }

    #[test]
    fn filtering_and_envelope_are_exact_on_lines() {
        let n = 128;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let th = 2.0 * PI * i as f64 / n as f64;
                // a carrier at order 20, amplitude-modulated at order 1 (sidebands 19, 21)
                (1.0 + 0.5 * th.cos()) * (20.0 * th).cos() + 0.7 * (3.0 * th).cos()
            })
            .collect();
        let kept = filter_orders(&x, |j| j == 3);
        for (i, v) in kept.iter().enumerate() {
            let th = 2.0 * PI * i as f64 / n as f64;
            assert!((v - 0.7 * (3.0 * th).cos()).abs() < 1e-12);
        }
        let env = band_envelope(&x, 18, 22);
        for (i, v) in env.iter().enumerate() {
            let th = 2.0 * PI * i as f64 / n as f64;
            assert!((v - (1.0 + 0.5 * th.cos())).abs() < 1e-12, "{i}: {v}");
        }
    }

    #[test]
    fn labels_name_mesh_harmonics_and_sidebands() {
        assert_eq!(order_label(40, 40, 2).as_deref(), Some("mesh1"));
        assert_eq!(order_label(39, 40, 2).as_deref(), Some("mesh1-1"));
        assert_eq!(order_label(82, 40, 2).as_deref(), Some("mesh2+2"));
        assert_eq!(order_label(83, 40, 2), None);
        assert_eq!(order_label(3, 40, 2), None);
    }

    #[test]
    fn bad_settings_are_named() {
        let e = welch_orders(&[0.0; 100], 10, 20).unwrap_err();
        assert_eq!(e.field, "segment_revs");
        let e = welch_orders(&[0.0; 100], 3, 1).unwrap_err();
        assert_eq!(e.field, "samples_per_rev");
        let e = welch_orders(&[f64::NAN; 100], 10, 1).unwrap_err();
        assert_eq!(e.field, "signal");
    }
}
