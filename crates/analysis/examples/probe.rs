use geardyn_analysis::simulate::*;
use geardyn_model::*;
fn main() {
    for name in ["classic", "breakage", "internal"] {
        for om in [0.8, 0.95, 1.3] {
            let mut p = presets::by_name(name).unwrap();
            p.omega = om;
            let m = MeshModel::new(&p).unwrap();
            for method in [Method::default(), Method::Rk4 { steps_per_cycle: 512 }] {
                let opts = SimOptions { method, transient_periods: if name=="breakage" {20} else {300}, record_periods: if name=="breakage" {10} else {64}, ..Default::default() };
                let t = std::time::Instant::now();
                let r = simulate(&m, [1.1, 0.0], &opts);
                match r {
                    Ok(r) => { let s = summarize(&m, &r, &opts); println!("{name} om={om} {:?} {:.3}s steps={} last strobe {:?} label {} pid {:.3} fmax {:.3} fmin {:.3} imp {}", method, t.elapsed().as_secs_f64(), r.steps, r.strobe.last().unwrap(), s.label, s.p_id, s.max_force, s.min_force, s.impacts); }
                    Err(e) => println!("{name} om={om} ERR {e}"),
                }
            }
        }
    }
}
