//! Human-readable derived quantities of a configuration (printed by `geardyn show` as TOML
//! comments, so the output stays a valid config file).

use crate::config::ConfigError;
use geardyn_physics::pair::Dimensionless;
use geardyn_scenario::Scenario;
use std::fmt::Write;

/// The operating point that is integrated, in one line:
/// `omega = .., F = .., xi = .., c = .., D_d = .., D_s = ..` (dimensionless).
pub fn operating_point(sc: &Scenario) -> String {
    let p = sc.params();
    format!(
        "omega = {}, F = {}, xi = {}, c = {}, D_d = {}, D_s = {}",
        p.omega, p.load, p.xi, p.c, p.d_double, p.d_single
    )
}

/// [`operating_point`] for a figure's title, without the parameter `param` (a swept one: its
/// value is the axis of a figure, not a fixed setting), each value to four significant digits
/// as the figures' ticks write it (a pair's speed in rpm gives omega = 1.2345678...).
pub fn operating_point_without(sc: &Scenario, param: &str) -> String {
    let p = sc.params();
    [
        ("omega", p.omega),
        ("F", p.load),
        ("xi", p.xi),
        ("c", p.c),
        ("D_d", p.d_double),
        ("D_s", p.d_single),
    ]
    .iter()
    .filter(|(name, _)| *name != param)
    .map(|(name, v)| format!("{name} = {}", crate::figure::tick(*v)))
    .collect::<Vec<_>>()
    .join(", ")
}

/// Derived quantities as `# ` comment lines.
pub fn describe(sc: &Scenario) -> Result<String, ConfigError> {
    let mut s = String::new();
    let p = sc.params();
    let model = sc.model();
    let _ = writeln!(s, "# --- derived quantities (comments; not read back) ---");
    let _ = writeln!(
        s,
        "# contact ratio eps = {:.4}{}; excitation period = {} mesh cycle(s) = {:.6} (dimensionless time)",
        p.eps,
        p.breakage.map_or(String::new(), |b| format!(", broken tooth eps_b = {:.4} (cycle {})", b.eps_b, b.broken_cycle)),
        model.cycles_per_period(),
        model.excitation_period()
    );
    let _ = writeln!(
        s,
        "# integrated (dimensionless): {}{}",
        operating_point(sc),
        if sc.spec().overrides.is_empty() {
            String::new()
        } else {
            format!(
                " ({} set explicitly over the pair's physical operating point)",
                sc.spec()
                    .overrides
                    .keys()
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    );
    if let Some(pm) = sc.pair_model() {
        let g = &pm.geom;
        let _ = writeln!(
            s,
            "# geometry: centre distance {:.4} mm, operating pressure angle {:.4} deg, base pitch {:.4} mm, path of contact {:.4} mm",
            g.a_w * 1e3,
            g.alpha_w.to_degrees(),
            g.pb * 1e3,
            (g.s_d - g.s_a) * 1e3
        );
        let _ = writeln!(
            s,
            "# radii (mm): pinion base {:.4} tip {:.4} root {:.4}; gear base {:.4} tip {:.4} root {:.4}",
            g.rb1 * 1e3,
            g.ra1 * 1e3,
            g.rf1 * 1e3,
            g.rb2 * 1e3,
            g.ra2 * 1e3,
            g.rf2 * 1e3
        );
        let kmin = pm
            .rows
            .iter()
            .map(|r| r.k_mesh)
            .fold(f64::INFINITY, f64::min);
        let kmax = pm.rows.iter().map(|r| r.k_mesh).fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "# mesh stiffness: k_av = {:.4e} N/m (range {:.4e} .. {:.4e}); m_e = {:.4e} kg (I_p = {:.4e}, I_g = {:.4e} kg m^2)",
            pm.k_av, kmin, kmax, pm.m_e, pm.i_p, pm.i_g
        );
        let _ = writeln!(
            s,
            "# omega_n = sqrt(k_av/m_e) = {:.4e} rad/s ({:.2} Hz); b_c = {:.3} um",
            pm.omega_n,
            pm.omega_n / (2.0 * std::f64::consts::PI),
            pm.b_c * 1e6
        );
        let op = pm.to_physical(&Dimensionless {
            omega: p.omega,
            load: p.load,
            xi: p.xi,
            d: p.d_single,
        });
        let _ = writeln!(
            s,
            "# operating point of omega = {}, F = {}, xi = {}, D = {}: pinion {:.2} rpm, torque {:.4} N m, E_a = {:.4} um, half backlash b = {:.4} um",
            p.omega, p.load, p.xi, p.d_single, op.speed_rpm, op.torque_nm, op.error_amplitude_um, op.half_backlash_um
        );
        if let Some((dd, ds)) = pm.backlash {
            let _ = writeln!(
                s,
                "# physical half backlash at the operating point: D_d = {:.5}, D_s = {:.5} (static + load deformation - thermal growth - oil film; used unless D_d/D_s are set explicitly)",
                dd, ds
            );
        }
        if pm.spec.lubrication.is_some() {
            let mu = pm.rows.iter().map(|r| r.mu1);
            let (mlo, mhi) = mu.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
            let (llo, lhi) = pm
                .rows
                .iter()
                .map(|r| r.lambda1)
                .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
            let count = |c: i8| {
                pm.rows.iter().filter(|r| r.regime1 == c).count() as f64 / pm.rows.len() as f64
            };
            let _ = writeln!(
                s,
                "# lubrication: mu {:.4} .. {:.4}, film parameter Lambda {:.3} .. {:.3}; EHL {:.0}%, mixed {:.0}%, boundary {:.0}% of the path",
                mlo, mhi, llo, lhi, 100.0 * count(0), 100.0 * count(1), 100.0 * count(2)
            );
        }
        let per = pm.to_physical(&Dimensionless {
            omega: 1.0,
            load: 1.0,
            xi: 1.0,
            d: 1.0,
        });
        let _ = writeln!(
            s,
            "# scales: omega = 1 <-> {:.2} rpm; F = 1 <-> {:.4} N m; xi = 1 <-> {:.4} um",
            per.speed_rpm, per.torque_nm, per.error_amplitude_um
        );
    }
    Ok(s)
}
