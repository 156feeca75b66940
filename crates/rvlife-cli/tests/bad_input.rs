//! Bad input to the `rvlife` binary: every refusal exits 2 before any work, naming the key the
//! user wrote, the value and the allowed range.

mod common;

use common::*;

#[test]
fn bad_fem_bore_cuts_the_teeth() {
    let t = add_line(&paper_text(), "fem", "crank_bore_diameter_mm = 40.0");
    check_bad_config(&t, &["fem.crank_bore_diameter_mm", "cuts the teeth"]);
}

#[test]
fn bad_fem_holes_cut_each_other() {
    check_bad_config(
        &add_line(&paper_text(), "fem", "centre_hole_diameter_mm = 60.0"),
        &["fem.", "cut each other"],
    );
}

#[test]
fn bad_fem_mesh_beyond_memory() {
    let t = set_key(&paper_text(), "fem", "flank_element_size_mm", "0.01");
    let t = set_key(&t, "fem", "load_patch_half_width_mm", "0.02");
    check_bad_config(&t, &["fem.flank_element_size_mm", "GB"]);
}

#[test]
fn bad_eccentricity_k1_above_one() {
    bad_key("cycloid", "eccentricity_mm", "1.7", &["eccentricity_mm"]);
}

#[test]
fn bad_too_few_pins() {
    bad_key("cycloid", "pins", "2", &["pins"]);
}

#[test]
fn bad_negative_pin_radius() {
    bad_key("cycloid", "pin_radius_mm", "-3.0", &["pin_radius_mm"]);
}

#[test]
fn bad_zero_width() {
    bad_key("cycloid", "width_mm", "0.0", &["width_mm"]);
}

#[test]
fn bad_undercut_profile() {
    bad_key(
        "cycloid",
        "pin_radius_mm",
        "5.0",
        &["pin_radius_mm", "undercut"],
    );
}

#[test]
fn bad_nan_pin_radius() {
    bad_key("cycloid", "pin_radius_mm", "nan", &["pin_radius_mm"]);
}

#[test]
fn bad_infinite_eccentricity() {
    bad_key("cycloid", "eccentricity_mm", "inf", &["eccentricity_mm"]);
}

#[test]
fn bad_unknown_key() {
    check_bad_config(&add_line(&paper_text(), "cycloid", "bogus = 1"), &["bogus"]);
}

#[test]
fn bad_negative_sinusoidal_amplitude() {
    let text = replace_table(
        &paper_text(),
        "load",
        "kind = \"sinusoidal\"\namplitude_nm = -5.0",
    );
    check_bad_config(&text, &["amplitude_nm"]);
}

#[test]
fn bad_stage_hours_not_increasing() {
    bad_key(
        "wear",
        "stage_hours",
        "[0.0, 2500.0, 1250.0]",
        &["stage_hours"],
    );
}

#[test]
fn bad_load_share_above_one() {
    let text = set_key(&paper_text(), "contact", "support", "\"rigid\"");
    check_bad_config(
        &add_line(&text, "contact", "load_share = 1.5"),
        &["contact.load_share"],
    );
}

#[test]
fn bad_contact_band_force() {
    for v in ["0.0", "-5.0", "1e300"] {
        check_bad_config(
            &add_line(&paper_text(), "contact", &format!("band_force_n = {v}")),
            &["contact.band_force_n"],
        );
    }
}

#[test]
fn bad_contact_band() {
    check_bad_config(
        &set_key(&paper_text(), "contact", "band", "\"widest\""),
        &["contact.band"],
    );
}

#[test]
fn bad_poisson_ratio() {
    bad_key("materials.disc", "poisson_ratio", "0.6", &["poisson_ratio"]);
}

#[test]
fn bad_unparsable_toml() {
    check_bad_config("[cycloid\npins = 40\n", &[]);
}

#[test]
fn bad_missing_config_file() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("no-such-config.toml");
    let out = dir.path().join("results");
    let o = rvlife([
        "run".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_input_error(&o, "run with a missing config", &["no-such-config.toml"]);
    assert!(!out.exists(), "run left {} behind", out.display());
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
    let o = rvlife(["te".as_ref(), cfg.as_os_str()]);
    assert_input_error(&o, "te with a missing config", &["no-such-config.toml"]);
}

#[test]
fn bad_contact_arguments() {
    let o = rvlife(["contact", "--crank-deg", "nan", "--torque-nm", "412"]);
    assert_input_error(&o, "contact --crank-deg nan", &["--crank-deg"]);
    let o = rvlife(["contact", "--crank-deg", "0", "--torque-nm", "inf"]);
    assert_input_error(&o, "contact --torque-nm inf", &["--torque-nm"]);
    let o = rvlife([
        "contact",
        "--crank-deg",
        "0",
        "--torque-nm",
        "412",
        "--wear-um",
        "-1",
    ]);
    assert_input_error(&o, "contact --wear-um -1", &["--wear-um"]);
    // Missing required argument and conflicting wear options: clap's usage errors, also code 2.
    let o = rvlife(["contact", "--crank-deg", "0"]);
    assert_input_error(&o, "contact without --torque-nm", &["--torque-nm"]);
    let o = rvlife(["te", "--wear-um", "5", "--hours", "100"]);
    assert_input_error(&o, "te --wear-um with --hours", &[]);
    let o = rvlife(["te", "--torque-nm", "nan"]);
    assert_input_error(&o, "te --torque-nm nan", &["--torque-nm"]);
    let o = rvlife(["no-such-subcommand"]);
    assert_input_error(&o, "unknown subcommand", &[]);
}

#[test]
fn bad_profile_extension() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.txt");
    let o = rvlife(["profile".as_ref(), "--out".as_ref(), out.as_os_str()]);
    assert_input_error(&o, "profile --out x.txt", &["--out"]);
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(
        left.is_empty(),
        "profile with a bad extension wrote {left:?}"
    );
}

#[test]
fn bad_dynamics_stiffness_damping_and_times() {
    let ex = paper_text();
    check_bad_dynamics(
        &ex.replace(
            "# crank_disc_stiffness_n_per_um = 500.0",
            "crank_disc_stiffness_n_per_um = -5.0",
        ),
        &["reducer.bearings.crank_disc_stiffness_n_per_um", "-5"],
    );
    check_bad_dynamics(
        &set_key(&ex, "reducer.bearings", "crank_disc_rollers", "-5"),
        &["reducer.bearings.crank_disc_rollers", "-5"],
    );
    // Roller sets: a diameter out of range, rollers that do not fit round their pitch circle,
    // a pitch circle inside the rollers.
    let angle = "crank_carrier_contact_angle_deg = 15.0";
    assert!(ex.contains(angle));
    for (extra, needles) in [
        (
            "crank_disc_roller_diameter_mm = 0.1",
            &[
                "reducer.bearings.crank_disc_roller_diameter_mm",
                "0.1",
                "[0.5, 100]",
            ][..],
        ),
        (
            "crank_disc_roller_diameter_mm = 9.0",
            &[
                "reducer.bearings.crank_disc_roller_diameter_mm",
                "9.000",
                "no room",
            ][..],
        ),
        (
            "crank_carrier_pitch_diameter_mm = 2.5",
            &[
                "reducer.bearings.crank_carrier_pitch_diameter_mm",
                "2.500",
                "must exceed",
            ][..],
        ),
    ] {
        check_bad_dynamics(&ex.replace(angle, &format!("{angle}\n{extra}")), needles);
    }
    check_bad_dynamics(
        &set_key(&ex, "reducer.gears", "mesh_stiffness_n_per_um", "1e12"),
        &["reducer.gears.mesh_stiffness_n_per_um"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics.impact", "damping_ratio", "-0.1"),
        &["dynamics.impact.damping_ratio"],
    );
    check_bad_dynamics(
        &add_line(
            &ex,
            "dynamics.impact",
            "stiffness_n_per_m_e = 1e30\nexponent = 1.5",
        ),
        &["dynamics.impact.stiffness_n_per_m_e"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics", "window_s", "[0.5, 0.9]"),
        &["dynamics.window_s", "end_time_s"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics", "end_time_s", "0.0"),
        &["dynamics.end_time_s"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics.drive", "ramp_end_s", "2.0"),
        &["dynamics.drive.ramp_end_s"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics", "relative_tolerance", "0.5"),
        &["dynamics.relative_tolerance"],
    );
}

#[test]
fn bad_load_tables_unsorted_gaps_nan() {
    for (table, needles) in [
        (
            "time_s,torque_nm\n0,0\n0.5,100\n0.3,200\n1.0,0\n",
            &["load.csv row 3 column time_s", "increase"][..],
        ),
        (
            "time_s,torque_nm\n0,0\n0.5,\n1.0,0\n",
            &["load.csv row 2 column torque_nm", "gap"][..],
        ),
        (
            "time_s,torque_nm\n0,0\n0.5,NaN\n1.0,0\n",
            &["load.csv row 2 column torque_nm", "finite"][..],
        ),
        (
            "time_s,torque_nm\n0,0\n0.1,10\n",
            &["load.csv column time_s", "cover"][..],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let cfg = table_config(dir.path(), table);
        let o = rvlife(["dynamics".as_ref(), cfg.as_os_str(), "--json".as_ref()]);
        assert_input_error(&o, "load table", needles);
    }
    // A good table runs.
    let dir = tempfile::tempdir().unwrap();
    let cfg = table_config(dir.path(), "time_s,torque_nm\n0,0\n0.05,200\n1.0,200\n");
    let v = json_ok(
        &rvlife(["dynamics".as_ref(), cfg.as_os_str(), "--json".as_ref()]),
        "good load table",
    );
    assert!(num(&v, "te_mean_arcmin") > 0.0, "{v}");
}

/// Pins turning by their friction balance: an unknown mode, a friction coefficient out of
/// (0, 1], the balance beside a given rolling fraction.
#[test]
fn bad_pin_turning() {
    let ex = paper_text();
    for (extra, needles) in [
        (
            "pin_turning = \"sometimes\"",
            &["wear.pin_turning", "sometimes", "\"balance\""][..],
        ),
        (
            "pin_turning = \"balance\"\npin_friction_coefficient = 0.0",
            &["wear.pin_friction_coefficient", "0", "(0, 1]"][..],
        ),
        (
            "pin_turning = \"balance\"\ngroove_friction_coefficient = 1.5",
            &["wear.groove_friction_coefficient", "1.5"][..],
        ),
    ] {
        check_bad_config(&add_line(&ex, "wear", extra), needles);
    }
    check_bad_config(
        &add_line(
            &set_key(&ex, "wear", "pin_rolling_fraction", "0.3"),
            "wear",
            "pin_turning = \"balance\"",
        ),
        &["wear.pin_rolling_fraction", "0.3", "pin_turning"],
    );
}
