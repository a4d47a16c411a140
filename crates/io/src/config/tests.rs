#[test]
fn long_numbers_in_parser_messages_are_shortened() {
    let m = format!(
        "invalid type: floating point `{}.0`, expected u32 at line 3",
        "1".to_string() + &"0".repeat(300)
    );
    assert_eq!(
        super::short_numbers(&m),
        "invalid type: floating point `1e300`, expected u32 at line 3"
    );
    assert_eq!(
        super::short_numbers("omega = 1.25 at 12"),
        "omega = 1.25 at 12"
    );
}

use super::*;

/// The error of a classic configuration file whose simulation settings `edit` changed.
fn file_error(edit: impl FnOnce(&mut SimulationConfig)) -> String {
    let mut f = Config::preset("classic").unwrap();
    edit(&mut f.simulation);
    Config::from_toml(&f.to_toml())
        .and_then(|c| c.sim_options())
        .unwrap_err()
        .to_string()
}

#[test]
fn the_decision_knobs_take_their_own_ranges_from_set_and_from_a_file() {
    let mut c = Config::preset("classic").unwrap();
    // decision_budget counts right-hand-side evaluations up to MAX_DECISION_BUDGET, far above
    // MAX_PERIODS
    c.set("decision_budget", 2e10).unwrap();
    assert_eq!(c.sim_options().unwrap().decision_budget, 20_000_000_000);
    let e = c.set("decision_budget", 1.1e12).unwrap_err().to_string();
    assert!(
        e.contains("decision_budget") && e.contains("right-hand-side"),
        "{e}"
    );
    let e = c.set("decision_budget", 1.5).unwrap_err().to_string();
    assert!(e.contains("[0, 1000000000000]"), "{e}");
    c.set("decision_periods", 2e4).unwrap();
    assert_eq!(c.sim_options().unwrap().decision_periods, 20_000);
    let e = c.set("decision_periods", 1e8).unwrap_err().to_string();
    assert!(e.contains("decision_periods"), "{e}");
    // the same bound from a file
    let e = file_error(|s| s.decision_budget = 2_000_000_000_000);
    assert!(e.contains("decision_budget"), "{e}");
    // the escape test: 0 copies (off) or 2 to 4096; its span 0 (the default) or 100 and more
    assert_eq!(c.sim_options().unwrap().escape.copies, 16);
    c.set("escape_copies", 0.0).unwrap();
    assert!(!c.sim_options().unwrap().escape.on());
    c.set("escape_copies", 64.0).unwrap();
    c.set("escape_periods", 3000.0).unwrap();
    let esc = c.sim_options().unwrap().escape;
    assert_eq!((esc.copies, esc.periods), (64, 3000));
    for (name, bad, range) in [
        ("escape_copies", 1.0, "[2, 4096]"),
        ("escape_copies", 2.5, "[2, 4096]"),
        ("escape_copies", f64::NAN, "[2, 4096]"),
        ("escape_periods", 50.0, "[100, 1000000]"),
        ("escape_periods", -1.0, "[100, 1000000]"),
    ] {
        let e = c.set(name, bad).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(range), "{e}");
    }
    // follow_steps: 0 (the requested integrator) or 16 and more steps per natural period
    c.set("follow_steps", 0.0).unwrap();
    assert_eq!(c.sim_options().unwrap().follow_steps, 0);
    c.set("follow_steps", 128.0).unwrap();
    assert_eq!(c.sim_options().unwrap().follow_steps, 128);
    for bad in [8.0, 64.5, -1.0, f64::NAN] {
        let e = c.set("follow_steps", bad).unwrap_err().to_string();
        assert!(
            e.contains("follow_steps") && e.contains("[16, 1000000]"),
            "{e}"
        );
    }
    let e = file_error(|s| s.follow_steps = 4);
    assert!(e.contains("follow_steps"), "{e}");
    // the option --follow-steps (Python: follow_steps=) sets it, checked the same way
    let mut c = Config::preset("classic").unwrap();
    let o = SimOverrides {
        follow_steps: Some(0.0),
        ..Default::default()
    };
    o.apply(&mut c, &[], Face::Cli).unwrap();
    assert_eq!(c.sim_options().unwrap().follow_steps, 0);
    let bad = SimOverrides {
        follow_steps: Some(3.0),
        ..Default::default()
    };
    let e = bad.apply(&mut c, &[], Face::Cli).unwrap_err().to_string();
    assert!(
        e.contains("--follow-steps 3") && e.contains("[16, 1000000]"),
        "{e}"
    );
}

#[test]
fn presets_round_trip_through_toml() {
    for (name, _) in presets::PRESETS {
        let c = Config::preset(name).unwrap();
        let back = Config::from_toml(&c.to_toml()).unwrap();
        assert_eq!(c, back, "{name}");
        back.resolve().unwrap();
    }
}

#[test]
fn a_partial_simulation_table_takes_the_defaults_of_the_missing_keys() {
    let mut c = Config::preset("classic").unwrap();
    c.simulation = SimulationConfig::default();
    let text = c.to_toml();
    let start = text.find("[simulation]").unwrap();
    let end = text[start + 1..]
        .find("\n[")
        .map_or(text.len(), |e| start + 1 + e);
    let partial = format!(
        "{}[simulation]\nmethod = \"rk4\"\n{}",
        &text[..start],
        &text[end..]
    );
    let back = Config::from_toml(&partial).unwrap();
    assert_eq!(back.simulation.method, "rk4");
    assert_eq!(back.simulation.rtol, SimulationConfig::default().rtol);
    assert_eq!(back.simulation.record_periods, 100);
}

#[test]
fn errors_name_the_field() {
    let mut c = Config::preset("classic").unwrap();
    let e = c.apply_set("omgea=1").unwrap_err().to_string();
    assert!(e.contains("omgea") && e.contains("omega"), "{e}");
    assert!(c.apply_set("omega").is_err());
    assert!(c.apply_set("omega=abc").is_err());
    c.apply_set("D=-1").unwrap();
    let e = c.resolve().unwrap_err().to_string();
    assert!(e.contains("D_d") && e.contains("[1e-9, 1000]"), "{e}");
    let e = Config::from_toml("[model]\nomega = \"fast\"")
        .unwrap_err()
        .to_string();
    assert!(e.contains("malformed"), "{e}");
    // a wrong-typed value names its key and the kind of value needed (serde's message alone
    // said `invalid type: string "fast", expected f64`)
    assert!(
        e.contains("model.omega:") && e.contains("expected a number"),
        "{e}"
    );
    let e = Config::from_toml("[simulation]\ndecision_periods = \"x\"")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("simulation.decision_periods:") && e.contains("expected a whole number"),
        "{e}"
    );
    let mut t = Config::preset("classic").unwrap().to_toml();
    t = t.replace("omega = 0.8", "omega = 0.8\nomegaa = 1.0");
    let e = Config::from_toml(&t).unwrap_err().to_string();
    assert!(e.contains("omegaa"), "{e}");
}

#[test]
fn contact_law_from_the_command_line() {
    let mut c = Config::preset("internal").unwrap();
    c.apply_contact("linear").unwrap();
    assert_eq!(c.model.contact, ContactLaw::Linear);
    assert_eq!(c.resolve().unwrap().params().contact, ContactLaw::Linear);
    c.apply_contact("lankarani_nikravesh:1.2:0.8").unwrap();
    assert_eq!(
        c.model.contact,
        ContactLaw::LankaraniNikravesh {
            exponent: 1.2,
            restitution: 0.8
        }
    );
    for (bad, says) in [
        ("linear:1.5", "linear has no exponent"),
        ("power:1.5:0.3", "restitution"),
        ("lankarani_nikravesh:1.1", "restitution"),
        ("hertz", "unknown variant"),
        ("power:x", "exponent 'x'"),
        ("power:inf", "not finite"),
        ("", "no law name"),
    ] {
        let e = c.apply_contact(bad).unwrap_err().to_string();
        assert!(e.contains(says) && e.contains("--contact"), "{bad}: {e}");
    }
    // ranges are checked with the rest of the model
    c.apply_contact("power:0.5").unwrap();
    let e = c.resolve().unwrap_err().to_string();
    assert!(e.contains("exponent") && e.contains("[1, 3]"), "{e}");
    // impact damping's factor 3(1-e)/(2e) is bounded by its smallest restitution
    c.apply_contact("impact_damping:1:0.05").unwrap();
    let e = c.resolve().unwrap_err().to_string();
    assert!(e.contains("restitution") && e.contains("[0.1, 1]"), "{e}");
    c.apply_contact("impact_damping:1:0.1").unwrap();
    c.resolve().unwrap();
}
