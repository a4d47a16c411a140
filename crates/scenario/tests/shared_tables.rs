//! The zoned tables of a physical pair hold each distinct piece once, and every piece still reads
//! its own samples.

use geardyn_model::params::StiffnessForm;
use geardyn_scenario::ScenarioSpec;

#[test]
fn equal_pieces_share_one_table_and_read_their_own_samples() {
    for name in ["breakage", "internal"] {
        let s = ScenarioSpec::preset(name).unwrap().resolve().unwrap();
        let m = s.model();
        let StiffnessForm::Zoned { pieces } = &s.params().stiffness else {
            panic!("{name}: a physical pair has zoned tables");
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let mut distinct: Vec<(Vec<u64>, Vec<u64>, Vec<u64>)> = Vec::new();
        for pc in pieces {
            let key = (bits(&pc.k), bits(&pc.h_drive), bits(&pc.h_back));
            if !distinct.contains(&key) {
                distinct.push(key);
            }
        }
        let held: usize = distinct.iter().map(|d| 3 * d.0.len()).sum();
        assert_eq!(m.table_samples(), held, "{name}");
        // the broken pair's 40 cycles repeat a few pieces: the tables shrink tenfold or more
        if name == "breakage" {
            let all: usize = pieces.iter().map(|pc| 3 * pc.k.len()).sum();
            assert!(pieces.len() > 100 && held * 10 < all, "{held} of {all}");
        }
        // every piece reads its own samples (interior sample points, away from the borders)
        for pc in pieces {
            let n = pc.k.len();
            for i in [1, n / 2, n - 2] {
                let u = pc.start + (pc.end - pc.start) * i as f64 / (n - 1) as f64;
                let k = m.stiffness_at(u);
                let (hd, hb) = m.friction_factors_at(u);
                for (got, want) in [(k, pc.k[i]), (hd, pc.h_drive[i]), (hb, pc.h_back[i])] {
                    assert!(
                        (got - want).abs() <= 1e-12 * want.abs(),
                        "{name} u={u}: {got} vs {want}"
                    );
                }
            }
        }
    }
}
