//! Hostile input, generated: random `--set` values (NaN, inf, huge, tiny, negative, ordinary)
//! for every parameter name, and random mutations of a valid config file. Every case must end
//! within a time bound with either a result free of NaN/inf or a one-line error, never a panic.
//!
//! A few hundred cases run in the normal suite; `GEARDYN_FUZZ_CASES=N` runs N.

mod common;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const NAMES: &[&str] = &[
    "omega",
    "F",
    "xi",
    "c",
    "D",
    "D_d",
    "D_s",
    "eps",
    "kappa",
    "R",
    "v_stick",
    "k_c",
    "mu",
    "exponent",
    "restitution",
    "x0",
    "v0",
    "tau0",
    "rtol",
    "atol",
    "steps_per_cycle",
    // given by a flag of every case too (--periods, --transient): refused as given twice
    "record_periods",
    "transient_periods",
    "decision_periods",
    "decision_budget",
    "max_work",
    "pair.z1",
    "pair.mu",
    "pair.module_mm",
    "pair.x1",
    "pair.face_width_mm",
    "pair.breakage.removed_height_mm",
    "pair.operating.speed_rpm",
    "pair.operating.torque_nm",
    "pair.damping_ratio",
    "pair.characteristic_length_um",
];

const VALUES: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e300",
    "-1e300",
    "1e-308",
    "5e-324",
    "0",
    "-0",
    "-1",
    "1e6",
    "4294967304",
    "0.5",
    "1.3",
    "2",
    "0.05",
    "1e-9",
    "abc",
    "",
];

/// Per-case limit: a case that takes longer hangs.
const LIMIT: Duration = Duration::from_secs(30);

fn run(args: &[String]) -> (Option<i32>, String, String, Duration) {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_geardyn"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    loop {
        if let Some(_status) = child.try_wait().unwrap() {
            let out = child.wait_with_output().unwrap();
            return (
                out.status.code(),
                String::from_utf8_lossy(&out.stdout).into_owned(),
                String::from_utf8_lossy(&out.stderr).into_owned(),
                start.elapsed(),
            );
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return (None, String::new(), String::new(), start.elapsed());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn check(args: &[String], out_dir: &std::path::Path) {
    let (code, _out, err, _) = run(args);
    let Some(code) = code else {
        panic!("no end within {LIMIT:?}: {args:?}");
    };
    assert!(!err.contains("panicked"), "panic for {args:?}: {err}");
    if code == 0 {
        if let Ok(s) = std::fs::read_to_string(out_dir.join("summary.json")) {
            // JSON has no NaN/inf: serde writes them as null, so the numbers must be numbers
            let v: serde_json::Value = serde_json::from_str(&s).unwrap();
            for k in ["p_id", "max_force", "min_force", "max_impact_force"] {
                assert!(v[k].is_number(), "{k} not finite for {args:?}: {s}");
            }
        }
    } else {
        assert_eq!(code, 2, "exit code {code} for {args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        // numbers are printed as numbers (1e300 was written out with 301 digits)
        let longest = err
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest < 25, "a {longest}-digit number in {args:?}: {err}");
    }
}

fn cases() -> usize {
    std::env::var("GEARDYN_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300)
}

#[test]
fn random_overrides_end_with_a_result_or_one_line_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(20261122);
    let dir = std::env::temp_dir().join(format!("geardyn-fuzz-{}", std::process::id()));
    for _ in 0..cases() {
        let _ = std::fs::remove_dir_all(&dir);
        let preset = ["classic", "breakage", "internal"][rng.gen_range(0..3)];
        let mut args: Vec<String> = vec![
            "simulate".into(),
            "--preset".into(),
            preset.into(),
            "--periods".into(),
            "2".into(),
            "--transient".into(),
            "2".into(),
            "--trajectory-periods".into(),
            "1".into(),
            "--out".into(),
            dir.to_string_lossy().into_owned(),
        ];
        for _ in 0..rng.gen_range(1..=3) {
            let name = NAMES[rng.gen_range(0..NAMES.len())];
            let value = if rng.gen_bool(0.6) {
                VALUES[rng.gen_range(0..VALUES.len())].to_string()
            } else {
                // a random magnitude over the whole double range, either sign
                let e: i32 = rng.gen_range(-320..=308);
                let m: f64 = rng.gen_range(-9.9..9.9);
                format!("{m}e{e}")
            };
            args.push("--set".into());
            args.push(format!("{name}={value}"));
        }
        check(&args, &dir);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn random_config_mutations_end_with_a_result_or_one_line_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let dir = std::env::temp_dir().join(format!("geardyn-fuzzcfg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base: Vec<String> = ["classic", "breakage", "internal"]
        .iter()
        .map(|p| {
            let (code, out, err, _) = run(&["show".into(), "--preset".into(), (*p).into()]);
            assert_eq!(code, Some(0), "{err}");
            out
        })
        .collect();
    let out = dir.join("out");
    for _ in 0..cases() / 2 {
        let _ = std::fs::remove_dir_all(&out);
        let text = &base[rng.gen_range(0..base.len())];
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        for _ in 0..rng.gen_range(1..=3) {
            let i = rng.gen_range(0..lines.len());
            match rng.gen_range(0..5) {
                // replace a value
                0 => {
                    if let Some((k, _)) = lines[i].split_once(" = ") {
                        let v = VALUES[rng.gen_range(0..VALUES.len())];
                        lines[i] = format!("{k} = {v}");
                    }
                }
                // delete a line
                1 => {
                    lines.remove(i);
                }
                // duplicate a line
                2 => {
                    let l = lines[i].clone();
                    lines.insert(i, l);
                }
                // a typo in a key
                3 => lines[i] = lines[i].replacen('_', "__", 1),
                // garbage
                _ => lines[i] = "[[[ = =".into(),
            }
        }
        let cfg = dir.join("c.toml");
        std::fs::write(&cfg, lines.join("\n")).unwrap();
        let args = common::strs(&[
            "simulate",
            "--config",
            cfg.to_str().unwrap(),
            "--periods",
            "2",
            "--transient",
            "2",
            "--trajectory-periods",
            "1",
            "--out",
            out.to_str().unwrap(),
        ]);
        check(&args, &out);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A positive exponent where the lanes do not step the contact law (the internal preset's
/// Johnson-type law): the escape test does not apply, and the decision follows the run to its
/// horizon once — it once asked for the test again after every follow, for ever.
#[test]
fn a_chaotic_run_without_the_escape_test_ends() {
    let out = std::env::temp_dir().join(format!("geardyn-noescape-{}", std::process::id()));
    let args: Vec<String> = [
        "bifurcation",
        "--preset",
        "internal",
        "--transient",
        "100",
        "--periods",
        "30",
        "--mode",
        "sweep",
        "--param",
        "omega",
        "--range",
        "1.4:1.8:6",
        "--out",
        out.to_str().unwrap(),
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let (code, _, err, _) = run(&args);
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(code, Some(0), "{err}");
}
