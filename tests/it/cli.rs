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
    for (flag, value, says) in [
        ("--lambda-p", "-1", "allowed"),
        ("--j", "0", "allowed [0.5, 10000]"),
        ("--damping", "-0.1", "allowed [0, 10]"),
        ("--omega", "0", "allowed [0.01, 100]"),
        ("--omega", "1e-9", "allowed [0.01, 100]"),
        ("--adr", "-0.5", "allowed [0, 1000]"),
        ("--adr", "1e400", "not a finite number"),
        ("--ea", "-1", "allowed [0, 1]"),
        ("--omega", "nan", "not a finite number"),
    ] {
        let out = isola(&["orbit", flag, value]);
        assert!(!out.status.success(), "{flag} {value} must fail");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(flag) && err.contains(says),
            "{flag} {value}: {err}"
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

/// `isola continue --switch` at ADR 1.0: the 1:1 branch's two period doublings, the 1:2
/// branch born at the first and ending at the second, once, in one CSV with a row per point
/// and per located bifurcation.
#[test]
fn continue_switches_at_period_doublings_into_one_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("switch.csv");
    let out = isola(&[
        "continue",
        "--adr",
        "1.0",
        "--omega",
        "3.0",
        "--range",
        "2:6",
        "--switch",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(text.matches("period-2 branch").count(), 1, "{text}");
    assert!(text.contains("is the one above"), "{text}");
    let rows = std::fs::read_to_string(&csv).unwrap();
    let header = rows.lines().next().unwrap();
    assert_eq!(
        header,
        "branch,period,verdict,kind,omega,omega_e,lambda_i_0,v_0,amplitude_stretch,stable,mu1_re,mu1_im,mu2_re,mu2_im"
    );
    let kinds = |branch: &str, kind: &str| {
        rows.lines()
            .filter(|l| l.starts_with(&format!("{branch},")) && l.split(',').nth(3) == Some(kind))
            .count()
    };
    assert_eq!(kinds("0", "period-doubling"), 2);
    assert_eq!(kinds("1", "parent-period-doubling"), 2);
    assert_eq!(kinds("1", "fold"), 2);
    assert!(kinds("1", "point") > 50);
    // the small-amplitude end near ω 4.93 stops at the doubling, not on the doubled 1:1
    // response beyond it (amplitude ≈ 0.006 there too)
    let low_end: f64 = rows
        .lines()
        .filter(|l| l.starts_with("1,") && l.split(',').nth(3) == Some("point"))
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .skip(5)
                .take(4)
                .map(|x| x.parse().unwrap())
                .collect();
            (f[0], f[3])
        })
        .filter(|(w, amplitude)| *w < 5.2 && *amplitude < 0.02)
        .map(|(w, _)| w)
        .fold(f64::INFINITY, f64::min);
    assert!((4.930032..4.94).contains(&low_end), "{low_end}");
    let _ = std::fs::remove_file(&csv);
}

/// `--version` names the commit the build comes from; the workbench without a terminal says
/// what to do instead of a system error.
#[test]
fn version_names_the_commit_and_the_workbench_needs_a_terminal() {
    let out = Command::new(env!("CARGO_BIN_EXE_isola"))
        .arg("--version")
        .output()
        .unwrap();
    let version = String::from_utf8_lossy(&out.stdout);
    assert!(
        version.starts_with("isola 0.") && version.contains('+'),
        "{version}"
    );
    for args in [&[][..], &["tui"][..]] {
        let out = Command::new(env!("CARGO_BIN_EXE_isola"))
            .args(args)
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains("needs a terminal") && err.contains("isola run"),
            "{err}"
        );
    }
}

/// Shell completions and the man page come from the commands' own definitions.
#[test]
fn completions_and_the_man_page_list_the_commands() {
    let bash = isola(&["completions", "bash"]);
    assert!(bash.status.success());
    let script = String::from_utf8_lossy(&bash.stdout);
    assert!(
        script.contains("_isola") && script.contains("slurm"),
        "{script}"
    );
    let man = isola(&["man"]);
    assert!(man.status.success());
    let page = String::from_utf8_lossy(&man.stdout);
    assert!(
        page.starts_with(".ie") || page.contains(".TH isola"),
        "{page}"
    );
    assert!(
        page.contains("completions") && page.contains("export"),
        "{page}"
    );
    let bad = isola(&["completions", "tcsh"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("bash"));
}
