//! The `isola` binary as a user runs it.

use std::process::Command;

fn isola(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_isola"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = isola(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

#[test]
fn orbit_json_has_the_documented_fields() {
    let v = json(&[
        "orbit", "--adr", "0.6", "--omega", "3.7", "--x0", "0.3", "--v0", "0", "--json",
    ]);
    assert_eq!(v["class"], "periodic");
    assert_eq!(v["period"], 2);
    assert_eq!(v["ratio"], "1:2");
    assert_eq!(v["response_type"], "1:2 subharmonic");
    let amp = v["amplitude"].as_f64().unwrap();
    assert!((amp - 0.4156).abs() < 1e-3, "{amp}");
    let poincare = v["poincare"].as_array().unwrap();
    assert_eq!(poincare.len(), 2);
    assert_eq!(poincare[0].as_array().unwrap().len(), 2);
    assert!(v["transient_periods"].as_u64().unwrap() > 10);
}

#[test]
fn negative_values_are_written_the_natural_way() {
    let v = json(&["orbit", "--x0", "-0.3", "--v0", "-0.6", "--json"]);
    assert_eq!(v["v0"], -0.6);
    assert_eq!(v["x0"], -0.3);
    assert_eq!(v["class"], "periodic");
    // φ_DC/φ_AC instead of E_a/ADR: the same drive gives the same orbit
    let (dc, ac) = (v["phi_dc"].as_f64().unwrap(), v["phi_ac"].as_f64().unwrap());
    let w = json(&[
        "orbit",
        "--phi-dc",
        &dc.to_string(),
        "--phi-ac",
        &ac.to_string(),
        "--x0",
        "-0.3",
        "--v0",
        "-0.6",
        "--json",
    ]);
    let (a, b) = (
        v["amplitude"].as_f64().unwrap(),
        w["amplitude"].as_f64().unwrap(),
    );
    assert!((a - b).abs() < 1e-9);
}

#[test]
fn collision_is_reported_in_json_without_nan() {
    let out = isola(&[
        "orbit", "--omega", "1.8", "--x0", "0.8", "--v0", "3", "--json",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(!text.contains("NaN") && !text.contains("nan"), "{text}");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["class"], "collision");
    assert!(v["amplitude"].is_null());
    assert!(v["collision"]["tau"].as_f64().unwrap() > 0.0);
}

#[test]
fn bad_parameters_name_the_field_and_range() {
    for (flag, value, field) in [
        ("--lambda-p", "-1", "lambda_p"),
        ("--j", "0", "j"),
        ("--damping", "-0.1", "c_tilde"),
        ("--omega", "0", "omega"),
        ("--adr", "-0.5", "adr"),
        ("--ea", "-1", "e_a"),
        ("--omega", "nan", "omega"),
    ] {
        let out = isola(&["orbit", flag, value]);
        assert!(!out.status.success(), "{flag} {value} must fail");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(field) && err.contains("allowed"),
            "{flag}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn summary_shows_physical_units() {
    let out = isola(&["orbit", "--omega", "1.8"]);
    let text = String::from_utf8(out.stdout).unwrap();
    for unit in ["Hz", "kV", "MV/m", "mm"] {
        assert!(text.contains(unit), "{unit} missing in\n{text}");
    }
    assert!(text.contains("25.6"), "ω_e 1.8 is 25.6 Hz:\n{text}");
}
