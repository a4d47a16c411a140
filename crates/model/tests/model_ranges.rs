//! Range checks of the dimensionless model that the integrator needs.

#[test]
fn a_backlash_below_what_event_location_resolves_is_refused_with_its_bound() {
    // D = 1e-13 ran away ("diverged") while every D from 1e-12 up gives one bounded orbit
    let mut p = geardyn_model::presets::classic();
    p.d_double = 1e-15;
    p.d_single = 1e-15;
    let e = geardyn_model::MeshModel::new(&p).unwrap_err().to_string();
    assert!(e.contains("D_d") && e.contains("1e-9"), "{e}");
    p.d_double = geardyn_model::mesh_model::MIN_BACKLASH;
    p.d_single = geardyn_model::mesh_model::MIN_BACKLASH;
    assert!(geardyn_model::MeshModel::new(&p).is_ok());
}
