//! The resolution a user sets (`resolution` in a session, `--resolution` on the command
//! line) and the convergence mode (`isola run --convergence`): what the doubled run reports on
//! the paper's Fig 6A basin and Fig 4 response, the same numbers from a session and the CLI,
//! stored results made stale by the setting only, and bad values refused.

use std::path::{Path, PathBuf};

use isola::session::Session;

use crate::common::{isola, json};

/// `sessions/NAME` with `edit` applied, written to `s.toml` in a fresh folder.
fn paper_session(name: &str, edit: impl Fn(String) -> String) -> (tempfile::TempDir, PathBuf) {
    let text = std::fs::read_to_string(Path::new("sessions").join(name)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(&path, edit(text)).unwrap();
    (dir, path)
}

/// `isola run SESSION --only NAME --convergence --json`: the one analysis' changes.
fn convergence(session: &Path, name: &str) -> serde_json::Value {
    let s = session.to_str().unwrap();
    let v = json(&[
        "run",
        s,
        "--only",
        name,
        "--convergence",
        "--threads",
        "2",
        "--json",
    ]);
    let runs = v["convergence"].as_array().unwrap();
    assert_eq!(runs.len(), 1);
    // a time history names its Dormand–Prince tolerance after it
    let doubled = runs[0]["doubled"].as_str().unwrap();
    assert!(
        doubled.starts_with("RK4 128 steps per period (h ≤ 0.025)"),
        "{doubled}"
    );
    runs[0]["changes"].clone()
}

/// The Fig 6A basin on every fourth cell of the paper's grid (51 × 63): at twice the
/// resolution no cell changes attractor and none is gained or lost; the attractors move by
/// 1e-7 (the 1:2's amplitude error at 64 steps, 1.1e-7 against the reference). Checked by hand
/// on the full 201 × 251 grid too: 0 of 50451 cells, the same 1.0e-7 (the ignored test below).
#[test]
fn fig6a_basin_is_converged_at_the_default_resolution() {
    let (dir, path) = paper_session("fig06a_basin_adr06.toml", |t| {
        t.replace("points = 201", "points = 51")
            .replace("points = 251", "points = 63")
    });
    let c = convergence(&path, "basin");
    assert_eq!(c["kind"], "basin");
    assert_eq!(c["cells"], 51 * 63);
    assert_eq!(c["changed"], 0);
    assert_eq!(c["share"], 0.0);
    assert_eq!(c["gained"], serde_json::json!([]));
    assert_eq!(c["lost"], serde_json::json!([]));
    let moved = c["largest_amplitude_difference"].as_f64().unwrap();
    assert!(moved > 5e-8 && moved < 2e-7, "{moved}");
    // the doubled run is kept apart: the session's own result is current and unchanged
    let own = dir.path().join("s.results/basin.csv");
    let doubled = dir.path().join("s.results/convergence.results/basin.csv");
    assert!(own.is_file() && doubled.is_file());
    let again = json(&["run", path.to_str().unwrap(), "--only", "basin", "--json"]);
    assert_eq!(again["analyses"][0]["outcome"], "up_to_date");
}

/// The Fig 4 response on a coarser grid (ω_e step 0.1, 7 × 7 starts): at twice the resolution
/// no response is gained or lost, no branch edge moves (5 branches), and the largest amplitude
/// difference is the high 1:1's 1.26e-6 (1.3e-6 against the reference at ω_e 1.8).
#[test]
fn fig4_response_is_converged_at_the_default_resolution() {
    let (_dir, path) = paper_session("fig04_response_adr06.toml", |t| {
        t.replace("points = 117", "points = 59")
            .replace("points = 15 }", "points = 7 }")
    });
    let c = convergence(&path, "response");
    assert_eq!(c["kind"], "responses");
    assert_eq!(c["responses"], 84);
    assert_eq!(c["gained"], serde_json::json!([]));
    assert_eq!(c["lost"], serde_json::json!([]));
    assert_eq!(c["branches"], 5);
    assert_eq!(c["edges_moved"], serde_json::json!([]));
    assert_eq!(c["branches_gained"], serde_json::json!([]));
    assert_eq!(c["branches_lost"], serde_json::json!([]));
    let moved = c["largest_amplitude_difference"].as_f64().unwrap();
    assert!((moved - 1.26e-6).abs() < 0.05e-6, "{moved}");
}

/// The paper's grids themselves (201 × 251 cells; 117 ω_e × 15 × 15 starts): 0 of 50451 cells
/// change, 0 of 168 responses, no edge of the 5 branches moves. About a minute.
#[test]
#[ignore]
fn the_paper_grids_are_converged_at_the_default_resolution() {
    let (_d, basin) = paper_session("fig06a_basin_adr06.toml", |t| t);
    let c = convergence(&basin, "basin");
    assert_eq!(
        (c["cells"].as_u64(), c["changed"].as_u64()),
        (Some(50451), Some(0))
    );
    let (_d, response) = paper_session("fig04_response_adr06.toml", |t| t);
    let c = convergence(&response, "response");
    assert_eq!(c["responses"], 168);
    assert_eq!(c["gained"], serde_json::json!([]));
    assert_eq!(c["lost"], serde_json::json!([]));
    assert_eq!(c["edges_moved"], serde_json::json!([]));
}

const SMALL_BASIN: &str = "schema = 1\n[model]\nadr = 0.6\nomega = 3.7\n\n[[analysis]]\nname = \"basin\"\nkind = \"basin\"\n[analysis.settings]\ndx = { min = -0.8, max = 0.8, points = 9 }\nv = { min = -1.0, max = 1.0, points = 9 }\n";

fn write(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// `resolution = 96` in a session computes what `isola basin --resolution 96` does, byte for
/// byte, and not what the default does.
#[test]
fn a_session_resolution_computes_what_the_flag_computes() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), &format!("{SMALL_BASIN}resolution = 96\n"));
    json(&["run", path.to_str().unwrap(), "--json"]);
    let cli = |name: &str, extra: &[&str]| {
        let csv = dir.path().join(name);
        let mut args = vec!["basin", "--adr", "0.6", "--omega", "3.7", "--grid", "9x9"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--csv", csv.to_str().unwrap(), "--json"]);
        json(&args);
        csv
    };
    let read = |p: PathBuf| std::fs::read_to_string(p).unwrap();
    let at_96 = cli("cli.csv", &["--resolution", "96"]);
    let default = cli("default.csv", &[]);
    let stored = dir.path().join("s.results");
    assert_eq!(read(stored.join("basin.csv")), read(at_96.clone()));
    let attractors = |p: &Path| read(p.with_extension("attractors.csv"));
    assert_eq!(attractors(&stored.join("basin.csv")), attractors(&at_96));
    assert_ne!(attractors(&at_96), attractors(&default));
}

/// Without `resolution` a session's fingerprint is the one it always had (its stored results
/// stay current), and so with the default `resolution = 64`, which computes the same; any
/// other value makes the stored result stale, and the next run recomputes it.
#[test]
fn resolution_makes_the_result_stale_and_absent_keeps_the_fingerprint() {
    let fingerprint = |text: &str| {
        let s = Session::parse(Path::new("s.toml"), text).unwrap();
        s.fingerprint(&s.analyses[0])
    };
    // the fingerprint of this basin before `resolution` existed (numerics version 2)
    let s = Session::parse(Path::new("s.toml"), SMALL_BASIN).unwrap();
    let pinned = s.fingerprint_with(&s.analyses[0], 2);
    assert_eq!(pinned, "90d81be824afe7bcd91d59e6abff0bcd");
    assert_eq!(
        fingerprint(&format!("{SMALL_BASIN}resolution = 64\n")),
        fingerprint(SMALL_BASIN)
    );
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), SMALL_BASIN);
    let s = path.to_str().unwrap();
    let outcome = |v: serde_json::Value| v["analyses"][0]["outcome"].clone();
    assert_eq!(outcome(json(&["run", s, "--json"])), "completed");
    write(dir.path(), &format!("{SMALL_BASIN}resolution = 64\n"));
    assert_eq!(outcome(json(&["run", s, "--json"])), "up_to_date");
    write(dir.path(), &format!("{SMALL_BASIN}resolution = 80\n"));
    let manifest = dir.path().join("s.results/basin.manifest.json");
    let before = std::fs::read_to_string(&manifest).unwrap();
    assert_eq!(outcome(json(&["run", s, "--json"])), "completed");
    assert_ne!(std::fs::read_to_string(&manifest).unwrap(), before);
    assert_eq!(outcome(json(&["run", s, "--json"])), "up_to_date");
}

/// `steady.resolution = 96`, a number where the table `{ min_steps_per_period, max_step }`
/// goes, is `resolution = 96`: the same settings, so the same fingerprint; a bad number names
/// the field as written, the value and the range (it said "invalid type: integer, expected
/// struct Resolution").
#[test]
fn the_steady_resolution_takes_a_number_as_resolution_does() {
    let fingerprint = |text: &str| {
        let s = Session::parse(Path::new("s.toml"), text).unwrap();
        s.fingerprint(&s.analyses[0])
    };
    let shorthand = fingerprint(&format!("{SMALL_BASIN}resolution = 96\n"));
    assert_eq!(
        fingerprint(&format!("{SMALL_BASIN}steady.resolution = 96\n")),
        shorthand
    );
    let table = format!(
        "{SMALL_BASIN}steady = {{ resolution = {{ min_steps_per_period = 96, max_step = {} }} }}\n",
        3.2 / 96.0
    );
    assert_eq!(fingerprint(&table), shorthand);
    assert_ne!(fingerprint(SMALL_BASIN), shorthand);
    for bad in ["4", "0", "-3", "1.5", "\"fine\""] {
        let e = refused(&format!("{SMALL_BASIN}steady.resolution = {bad}\n"));
        assert!(e.contains("steady.resolution"), "{bad}: {e}");
        assert!(e.contains("[8, 100000]"), "{bad}: {e}");
        eprintln!("{e}");
    }
}

fn refused(text: &str) -> String {
    Session::parse(Path::new("s.toml"), text)
        .expect_err("refused")
        .to_string()
}

/// Bad values name the field as written, the value and the allowed range; a form the analysis'
/// integrator does not take, and `resolution` beside the key it sets, are refused too.
#[test]
fn bad_resolutions_are_refused_with_the_field_the_value_and_the_range() {
    for bad in ["4", "100001", "0", "\"fine\"", "\"rtol=2\"", "1.5"] {
        let e = refused(&format!("{SMALL_BASIN}resolution = {bad}\n"));
        assert!(e.contains(&format!("settings.resolution = {bad}")), "{e}");
        assert!(e.contains("line 12"), "{e}");
        assert!(e.contains("[8, 100000]") && e.contains("rtol=X"), "{e}");
    }
    let e = refused(&format!("{SMALL_BASIN}resolution = \"rtol=1e-12\"\n"));
    assert!(e.contains("a basin integrates with RK4 only"), "{e}");
    let e = refused(&format!(
        "{SMALL_BASIN}resolution = 128\nsteady = {{ resolution = {{ min_steps_per_period = 96 }} }}\n"
    ));
    assert!(
        e.contains("128 and settings.steady.resolution both set"),
        "{e}"
    );
    let chirp = "schema = 1\n[[analysis]]\nname = \"c\"\nkind = \"chirp_sweep\"\n[analysis.settings]\nresolution = 128\n";
    let e = refused(chirp);
    assert!(
        e.contains("a chirp sweep integrates with Dormand–Prince only"),
        "{e}"
    );
    let stderr = |args: &[&str]| {
        let out = isola(args);
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let e = stderr(&["basin", "--grid", "4x4", "--resolution", "4"]);
    assert!(
        e.contains("'4'") && e.contains("--resolution") && e.contains("[8, 100000]"),
        "{e}"
    );
    let e = stderr(&["basin", "--grid", "4x4", "--resolution", "rtol=1e-12"]);
    assert!(
        e.contains("--resolution rtol=1e-12 is out of range: a basin integrates with RK4 only"),
        "{e}"
    );
    let e = stderr(&["orbit", "--resolution", "96", "--steps-per-period", "96"]);
    assert!(
        e.contains("--steps-per-period") && e.contains("--resolution"),
        "{e}"
    );
}

/// A written model's time history at twice the resolution compares its own first state by
/// name (not the built-in's λ_I), and the orbit agrees to RK4's error at 64 steps.
#[test]
fn a_written_models_history_converges_under_its_own_names() {
    let (_d, path) = paper_session("user_model_duffing_isola.toml", |t| t);
    let c = convergence(&path, "orbit_main");
    assert_eq!(c["of"], "x at each sample", "{c}");
    assert_eq!(c["unmatched"], 0, "{c}");
    let largest = c["largest_difference"].as_f64().unwrap();
    assert!(largest > 0.0 && largest < 1e-8, "{c}");
}
