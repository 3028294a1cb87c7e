//! The `isola` binary as a user runs it.

use std::process::Command;

use crate::common::{isola, json};

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

/// RK4 locates a collision within the step that met it, where the Dormand–Prince reference
/// locates it exactly: thrown into the frame from Δλ −0.8, v −1 at Fig 6A's point, τ agrees
/// to 1e-6 (2.5e-8 here; the step's end, where it was reported before, was 0.0106 late) and
/// λ_I is at the frame, not 0.003 past it.
#[test]
fn rk4_locates_a_collision_where_the_reference_does() {
    let args = ["orbit", "--x0", "-0.8", "--v0", "-1", "--json"];
    let rk4 = json(&args);
    let reference = json(&[&args[..], &["--reference"]].concat());
    assert_eq!(rk4["integrator"], "rk4");
    assert_eq!(reference["integrator"], "dopri5");
    let at = |v: &serde_json::Value| {
        (
            v["collision"]["tau"].as_f64().unwrap(),
            v["collision"]["lambda_i"].as_f64().unwrap(),
        )
    };
    let ((tau, lambda), (tau_ref, _)) = (at(&rk4), at(&reference));
    assert!((tau - tau_ref).abs() < 1e-6, "{tau} against {tau_ref}");
    assert!(lambda <= 0.0 && lambda > -1e-12, "λ_I {lambda}");
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

/// `isola ARGS` that must succeed: its stdout, as text.
fn stdout_of(args: &[&str]) -> String {
    let out = isola(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// `isola ARGS` with `--json` and without: the document and the text summary.
fn json_and_text(args: &[&str]) -> (serde_json::Value, String) {
    let with_json: Vec<&str> = args.iter().copied().chain(["--json"]).collect();
    (json(&with_json), stdout_of(args))
}

/// `--json` prints one document with the basin's attractors as the text lists them, their
/// shares summing to 1, and the files written; `--json` also works before the command.
#[test]
fn basin_json_agrees_with_the_text() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("b.csv");
    let args = [
        "basin",
        "--grid",
        "5x5",
        "--omega",
        "3.7",
        "--csv",
        csv.to_str().unwrap(),
    ];
    let (v, text) = json_and_text(&args);
    let attractors = v["attractors"].as_array().unwrap();
    let listed = text.lines().filter(|l| l.starts_with("  #")).count();
    assert_eq!(attractors.len(), listed, "{text}");
    let total: f64 = attractors
        .iter()
        .map(|a| a["fraction"].as_f64().unwrap())
        .sum();
    assert!((total - 1.0).abs() < 1e-12, "{total}");
    let cells: u64 = attractors
        .iter()
        .map(|a| a["cells"].as_u64().unwrap())
        .sum();
    assert_eq!((v["cells"].as_u64(), cells), (Some(25), 25));
    for a in attractors {
        let line = format!("#{}  {}", a["id"], a["response_type"].as_str().unwrap());
        assert!(text.contains(&line), "{line} in\n{text}");
    }
    assert_eq!(
        (v["adr"].as_f64(), v["omega"].as_f64()),
        (Some(0.6), Some(3.7))
    );
    assert_eq!(v["dx"]["points"], 5);
    let wrote: Vec<&str> = v["wrote"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap())
        .collect();
    let table = dir.path().join("b.attractors.csv");
    let points = dir.path().join("b.points.csv");
    assert_eq!(
        wrote,
        [csv.as_path(), &table, &points].map(|p| p.to_str().unwrap())
    );
    assert!(table.exists() && points.exists());
    assert!(v["elapsed_seconds"].as_f64().unwrap() >= 0.0);
    let before = json(&["--json", "basin", "--grid", "3x3"]);
    assert_eq!(before["cells"], 9);
}

/// A frequency response's branches and responses, as many in the document as in the text.
#[test]
fn response_json_agrees_with_the_text() {
    let (v, text) = json_and_text(&["response", "--omega", "3.6:3.8:0.1", "--ics", "3x3"]);
    let branches = v["branches"].as_array().unwrap();
    let head = text.lines().next().unwrap();
    assert!(
        head.contains(&format!(
            "{} responses, {} branches",
            v["responses"],
            branches.len()
        )),
        "{head}"
    );
    assert_eq!(v["omega"]["points"], 3);
    assert_eq!(v["initial_states"], 9);
    for b in branches {
        let (lo, hi) = (
            b["omega_min"].as_f64().unwrap(),
            b["omega_max"].as_f64().unwrap(),
        );
        assert!((3.6..=3.8 + 1e-12).contains(&lo) && lo <= hi, "{b}");
        assert!(b["hidden"].is_boolean() && b["response_type"].is_string());
        assert!(b["frequency_hz_min"].as_f64().unwrap() > 0.0);
        let line = format!(
            "#{:<5}  {}",
            b["id"].as_u64().unwrap(),
            b["response_type"].as_str().unwrap()
        );
        assert!(text.contains(&line), "{line} in\n{text}");
        // the response frequency ω_r in Hz: ω_e's times the ratio (half for a 1:2)
        let ratio: Vec<f64> = b["ratio"]
            .as_str()
            .unwrap()
            .split(':')
            .map(|n| n.parse().unwrap())
            .collect();
        for end in ["min", "max"] {
            let excitation = b[format!("frequency_hz_{end}")].as_f64().unwrap();
            let response = b[format!("response_frequency_hz_{end}")].as_f64().unwrap();
            let expected = excitation * ratio[0] / ratio[1];
            assert!((response - expected).abs() < 1e-12 * expected, "{b}");
        }
    }
    assert!(
        branches.iter().any(|b| b["ratio"] == "1:2"),
        "the hidden 1:2 at ω 3.6–3.8: {text}"
    );
}

/// A stepped sweep: one entry per step, with the steady state's fields as `orbit`'s.
#[test]
fn stepped_sweep_json_lists_the_steps() {
    let (v, text) = json_and_text(&["sweep", "--stepped", "--omega", "3.6:3.8:0.1"]);
    assert_eq!(v["stepped"], true);
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    assert_eq!(text.lines().filter(|l| l.starts_with("  ω_e")).count(), 3);
    for (s, omega) in steps.iter().zip([3.6, 3.7, 3.8]) {
        assert!((s["omega"].as_f64().unwrap() - omega).abs() < 1e-12, "{s}");
        assert!(s["class"].is_string() && s["poincare"].is_array());
        let amplitude = s["amplitude"].as_f64().unwrap();
        assert!(
            text.contains(&format!("amplitude {amplitude:.5}")),
            "{text}"
        );
    }
}

/// A continuation: the branch, its arcs and bifurcations, as the text has them.
#[test]
fn continue_json_has_the_branch() {
    let (v, text) = json_and_text(&[
        "continue", "--omega", "3.7", "--x0", "0.3", "--range", "3.5:3.9",
    ]);
    let b = &v["branches"][0];
    assert_eq!(v["parameter"], "omega");
    assert!(
        text.starts_with(&format!("period-{} branch, omega", b["period"])),
        "{text}"
    );
    let arcs = b["arcs"].as_array().unwrap();
    assert_eq!(text.matches(" arc: omega").count(), arcs.len());
    let bifurcations = b["bifurcations"].as_array().unwrap();
    for f in bifurcations {
        assert!(text.contains(f["kind"].as_str().unwrap()), "{f}");
    }
    assert_eq!(v["points"], b["points"]);
    assert!(
        text.contains(&format!("{} points in", v["points"])),
        "{text}"
    );
    assert!(v["switches"].as_array().unwrap().is_empty());
}

/// A hunt: each continued branch with its verdict, arcs and located bifurcations. Found in
/// the window ω 3.5–3.9, the 1:2 isola is continued beyond it and called an isola.
#[test]
fn hunt_json_agrees_with_the_text() {
    let (v, text) = json_and_text(&["hunt", "--omega", "3.5:3.9:0.2", "--ics", "3x3"]);
    let branches = v["branches"].as_array().unwrap();
    assert!(!branches.is_empty(), "{text}");
    assert!(
        branches
            .iter()
            .any(|h| h["response_type"] == "1:2 subharmonic" && h["verdict"] == "isola"),
        "{text}"
    );
    assert_eq!(
        text.lines().filter(|l| l.starts_with('#')).count(),
        branches.len()
    );
    assert!(text.starts_with(&format!(
        "hunt: 3 ω values × 9 initial states, {} subharmonic brute-force branches → {} continued",
        v["subharmonic_branches"],
        branches.len()
    )));
    for h in branches {
        let head = format!(
            "{} {}",
            h["response_type"].as_str().unwrap(),
            h["verdict"].as_str().unwrap()
        );
        assert!(text.contains(&head), "{head} in\n{text}");
        // each arc along the branch with its ω and amplitude at both ends, as in --json
        let arcs: Vec<(bool, [f64; 4])> = h["branch"]["arcs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| {
                let f = |k: &str| a[k].as_f64().unwrap();
                (
                    a["stable"].as_bool().unwrap(),
                    [
                        f("parameter_start"),
                        f("parameter_end"),
                        f("amplitude_start"),
                        f("amplitude_end"),
                    ],
                )
            })
            .collect();
        for (stable, a) in arcs {
            let line = format!(
                "{:<8} ω {:.4} → {:.4}, amplitude {:.4} → {:.4}",
                if stable { "stable" } else { "unstable" },
                a[0],
                a[1],
                a[2],
                a[3]
            );
            assert!(text.contains(&line), "{line} in\n{text}");
        }
        for f in h["branch"]["bifurcations"].as_array().unwrap() {
            let omega = f["omega"].as_f64().unwrap();
            assert!(
                text.contains(&format!("ω {omega:.9}")),
                "{omega} in\n{text}"
            );
        }
    }
    let (total, parts) = (
        v["elapsed_seconds"].as_f64().unwrap(),
        v["brute_force_seconds"].as_f64().unwrap() + v["continuation_seconds"].as_f64().unwrap(),
    );
    assert!((total - parts).abs() < 1e-9);
}

/// `run`, `status` and `export` on a tiny session: what each did, as JSON; a second run is up
/// to date, and `--quiet` prints nothing at all.
#[test]
fn session_commands_report_in_json() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.toml");
    std::fs::write(
        &session,
        "schema = 1\n[model]\nomega = 3.7\n[[analysis]]\nname = \"b\"\nkind = \"basin\"\n\
         [analysis.settings]\ndx = { min = -0.8, max = 0.8, points = 4 }\n\
         v = { min = -1.0, max = 1.0, points = 4 }\n",
    )
    .unwrap();
    let s = session.to_str().unwrap();
    let run = json(&["run", s, "--json"]);
    let analysis = &run["analyses"][0];
    assert_eq!(analysis["name"], "b");
    assert_eq!(analysis["kind"], "basin");
    assert_eq!(analysis["outcome"], "completed");
    assert_eq!(analysis["assembled_here"], true);
    assert_eq!(run["wrote"][0], analysis["csv"]);
    let csv = analysis["csv"].as_str().unwrap();
    assert!(std::path::Path::new(csv).exists());
    let status = json(&["status", s, "--verify", "--json"]);
    assert_eq!(status["analyses"][0]["result"], "complete");
    assert!(status["analyses"][0]["chunks"].is_null());
    let selection = dir.path().join("sel.csv");
    let export = json(&[
        "export",
        s,
        "--analysis",
        "b",
        "--csv",
        selection.to_str().unwrap(),
        "--json",
    ]);
    let rows = std::fs::read_to_string(&selection).unwrap().lines().count() - 1;
    assert_eq!(export["rows"], rows);
    assert_eq!(export["wrote"][0], selection.to_str().unwrap());
    // a table the basin has not: the error lists those it has
    let out = isola(&[
        "export",
        s,
        "--analysis",
        "b",
        "--table",
        "branches",
        "--csv",
        selection.to_str().unwrap(),
    ]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success()
            && said.contains("a basin has no branches table; its tables: attractors"),
        "{said}"
    );
    let quiet = isola(&["run", s, "--quiet"]);
    assert!(quiet.status.success());
    assert!(
        quiet.stdout.is_empty() && quiet.stderr.is_empty(),
        "{quiet:?}"
    );
    let again = json(&["run", s, "--json"]);
    assert_eq!(again["analyses"][0]["outcome"], "up_to_date");
    assert!(again["wrote"].as_array().unwrap().is_empty());
}

/// `--quiet` (or `-q`) prints nothing on success; errors still reach stderr; `--json` with
/// `--quiet` is refused, and so is either for the workbench.
#[test]
fn quiet_prints_nothing_and_json_refuses_quiet() {
    for args in [
        &["orbit", "--quiet"][..],
        &["-q", "basin", "--grid", "3x3"],
        &["force", "--points", "5", "-q"],
    ] {
        let out = isola(args);
        assert!(out.status.success(), "{args:?}");
        assert!(
            out.stdout.is_empty() && out.stderr.is_empty(),
            "{args:?}: {out:?}"
        );
    }
    let bad = isola(&["orbit", "--omega", "0", "--quiet"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("error: "));
    let both = isola(&["orbit", "--json", "--quiet"]);
    assert!(!both.status.success() && both.stdout.is_empty());
    assert!(String::from_utf8_lossy(&both.stderr).contains("cannot be used with"));
    let workbench = isola(&["tui", "--json"]);
    assert_eq!(workbench.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&workbench.stderr).contains("neither --json nor --quiet"));
    let force = json(&["force", "--points", "5", "--json"]);
    assert_eq!(force["curves"].as_array().unwrap().len(), 3);
}

/// `isola model` gives the baseline's derived quantities (the README's figures), in units of
/// the paper's device too.
#[test]
fn model_prints_the_equilibrium_and_natural_frequency() {
    let m = json(&["model", "--json"]);
    let num = |key: &str| m[key].as_f64().unwrap_or_else(|| panic!("{key}: {m}"));
    assert!((num("lambda_i_equilibrium") - 1.0254357280757076).abs() < 1e-13);
    assert!((num("omega_0") - 2.7398979598).abs() < 1e-9);
    assert_eq!(num("omega_parametric"), 2.0 * num("omega_0"));
    assert!((num("e_b") - 0.041).abs() < 5e-4 && (num("e_c") - 0.006).abs() < 5e-4);
    assert!((m["physical"]["omega_0_hz"].as_f64().unwrap() - 39.003).abs() < 1e-3);
    let quiet = isola(&["model", "-q"]);
    assert!(quiet.status.success() && quiet.stdout.is_empty());
}

/// `orbit --samples-per-period` sets the written history's sampling (4 to 4096) and needs
/// `--history-csv`; a bad value is refused naming the flag, the value and the range.
#[test]
fn orbit_history_sampling_is_the_users() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("h.csv");
    let csv_arg = csv.to_str().unwrap();
    let v = json(&[
        "orbit",
        "--x0",
        "0.3",
        "--history-csv",
        csv_arg,
        "--samples-per-period",
        "16",
        "--json",
    ]);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with(
        "tau,time_s,lambda_stretch,v_per_tau,phi_i,steady,tension_i_nondim,tension_ii_nondim,slack_i,slack_ii\n"
    ));
    let samples = v["history_samples"].as_u64().unwrap() as usize;
    assert_eq!(text.lines().count(), samples + 1);
    // the start, then 16 samples per forcing period integrated
    assert_eq!((samples - 1) % 16, 0, "{samples}");
    for bad in ["0", "3", "5000", "1.5"] {
        let out = isola(&[
            "orbit",
            "--history-csv",
            csv_arg,
            "--samples-per-period",
            bad,
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {err}");
        assert!(
            err.contains(&format!("'{bad}' is not a whole number in [4, 4096]"))
                && err.contains("--samples-per-period"),
            "{bad}: {err}"
        );
    }
    let alone = isola(&["orbit", "--samples-per-period", "16"]);
    assert!(!alone.status.success());
    assert!(String::from_utf8_lossy(&alone.stderr).contains("--history-csv"));
}

/// `hunt --vary` writes each change of the picture between two values, located where it can
/// be, beside its CSV (`FILE.limits.csv`) and in `--json`, the same numbers in both: over λ_p
/// the ADR 0.6 isola vanishes between 1.04 and 1.05, at the maximum of λ_p on its fold curve
/// (1.0480627675, which `bifurcation_curves::a_vanishing_isola_is_located_on_its_fold_curve`
/// checks against continuations in λ_p at fixed ω). The isola spans ω 3.92–4.88 at λ_p 1.04:
/// found in the window 3.9–4.5, it is continued beyond it (by default over the paper's range)
/// and called an isola, not an open branch.
#[test]
fn hunt_over_a_parameter_writes_where_the_isola_vanishes() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("h.csv");
    let v = json(&[
        "hunt",
        "--adr",
        "0.6",
        "--omega",
        "3.9:4.5:0.1",
        "--vary",
        "lambda_p",
        "--values",
        "1.04,1.05",
        "--csv",
        csv.to_str().unwrap(),
        "--json",
    ]);
    let transitions = v["transitions"].as_array().unwrap();
    assert_eq!(transitions.len(), 1, "{v}");
    let t = &transitions[0];
    assert_eq!(t["event"], "vanishing");
    let value = t["limit"]["value"].as_f64().expect("located");
    assert!((value - 1.0480627675).abs() < 1e-8, "{t}");
    assert!(t["limit"]["precision"].as_f64().unwrap() <= 1e-8, "{t}");
    let limits = std::fs::read_to_string(dir.path().join("h.limits.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(limits.as_bytes());
    let header = rows.headers().unwrap().clone();
    let cell = |row: &csv::StringRecord, name: &str| {
        row[header.iter().position(|h| h == name).unwrap()].to_string()
    };
    let rows: Vec<_> = rows.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 1, "{limits}");
    assert_eq!(cell(&rows[0], "event"), "vanishing");
    assert_eq!(cell(&rows[0], "before"), "isola");
    assert_eq!(cell(&rows[0], "after"), "none");
    assert_eq!(cell(&rows[0], "located"), "true");
    assert_eq!(cell(&rows[0], "lambda_p").parse::<f64>().unwrap(), value);
    assert_eq!(
        cell(&rows[0], "omega").parse::<f64>().unwrap(),
        t["limit"]["omega"].as_f64().unwrap()
    );
    assert_eq!(cell(&rows[0], "lambda_p_from"), "1.04");
}

/// A stdout that fails (`> log` on a full disk: `/dev/full`) ends the command with an error
/// naming it, after the work: every analysis of the session is computed and stored, none is
/// lost to a panic half-way through its summaries.
#[test]
fn a_full_stdout_is_an_error_after_the_work() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("skipped: this system has no /dev/full");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.toml");
    let force = "[[analysis]]\nname = \"NAME\"\nkind = \"force_curve\"\n[analysis.settings]\nlambda_p = [1.0, 1.02]\npoints = 5\n";
    let text = format!(
        "schema = 1\n{}{}",
        force.replace("NAME", "first"),
        force.replace("NAME", "second")
    );
    std::fs::write(&session, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_isola"))
        .arg("run")
        .arg(&session)
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("writing the summary to stdout failed") && !stderr.contains("panicked"),
        "{stderr}"
    );
    let status = isola(&["status", session.to_str().unwrap()]);
    let status = String::from_utf8_lossy(&status.stdout);
    assert_eq!(
        status.matches("result complete, verified").count(),
        2,
        "{status}"
    );
}
