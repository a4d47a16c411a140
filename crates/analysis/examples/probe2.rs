use geardyn_analysis::simulate::*;
use geardyn_model::*;
fn main() {
    for om in [0.8, 0.95, 1.3] {
        let mut p = presets::classic();
        p.omega = om;
        let m = MeshModel::new(&p).unwrap();
        for y0 in [[1.1, 0.0], [1.0, 0.0], [0.0, 0.0], [1.5, 0.3], [-1.0, 0.0], [1.3,-0.2]] {
            let opts = SimOptions { transient_periods: 1000, record_periods: 64, ..Default::default() };
            let r = simulate(&m, y0, &opts).unwrap();
            let s = summarize(&m, &r, &opts);
            println!("om={om} y0={y0:?} label {} pid {:.3} strobe {:?}", s.label, s.p_id, &r.strobe.last().unwrap()[1..]);
        }
    }
}
