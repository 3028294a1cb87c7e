//! Session files, results beside them, headless runs that survive a kill, and export.

use std::path::{Path, PathBuf};
use std::process::Command;

use isola::analysis::Progress;
use isola::analysis::orbit::scalogram::ScalogramSpec;
use isola::session::run::{Shard, is_current, run_analysis};
use isola::session::store::ResultPaths;
use isola::session::{Session, Settings};

/// A fresh folder, removed when the returned guard is dropped (at the test's end).
fn scratch(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("isola-test-{name}-"))
        .tempdir()
        .unwrap()
}

fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
    v.sort();
    v
}

/// Every figure of the paper has its session; each loads, and its cheapest analysis runs and
/// writes its CSV with a complete manifest (a chirp sweep without a scalogram where the
/// session has one).
#[test]
fn every_example_session_loads_and_its_cheapest_analysis_runs() {
    let files = examples();
    for fig in [
        "fig02a", "fig02b", "fig03", "fig04", "fig05", "fig06a", "fig06b", "fig07", "fig08",
        "fig09", "fig10", "fig11a", "fig11b", "fig12",
    ] {
        assert!(
            files
                .iter()
                .any(|f| f.file_name().unwrap().to_string_lossy().starts_with(fig)),
            "{fig}"
        );
    }
    let guard = scratch("examples");
    let dir = guard.path().to_path_buf();
    for file in files {
        let copy = dir.join(file.file_name().unwrap());
        std::fs::copy(&file, &copy).unwrap();
        let session = Session::load(&copy).unwrap_or_else(|e| panic!("{e}"));
        assert!(session.file.description.is_some(), "{}", file.display());
        let cheap = session
            .analyses
            .iter()
            .find(|a| {
                matches!(
                    a.settings,
                    Settings::ForceCurve(_) | Settings::TimeHistory(_) | Settings::Continuation(_)
                )
            })
            .or_else(|| {
                session
                    .analyses
                    .iter()
                    // without a scalogram where the session has one (Fig 3's scalograms
                    // are checked in global_analyses; their CSVs at a small size below)
                    .filter(|a| matches!(a.settings, Settings::ChirpSweep(_)))
                    .min_by_key(
                        |a| matches!(&a.settings, Settings::ChirpSweep(c) if c.scalogram.is_some()),
                    )
            })
            .expect("a cheap analysis");
        run_analysis(&session, cheap, Shard::ALL, &Progress::new(0)).unwrap();
        assert!(is_current(&session, cheap), "{}", file.display());
        assert!(ResultPaths::new(&session, &cheap.name).csv.exists());
    }
}

/// The viscoelastic catalogue session's basin runs to its end: its starts at Δλ = ±0.8 put a
/// membrane's viscous branch past its Gent pole, where its stretch xi ran away to a value
/// that is not finite and stopped the whole basin; the session now ends such a start as a
/// collision (outside the model), and every other start reaches the 1:1 response.
#[test]
fn the_viscoelastic_sessions_basin_runs_with_its_edges_outside_the_model() {
    let guard = scratch("viscoelastic");
    let copy = guard.path().join("visco.toml");
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/user_model_viscoelastic.toml");
    std::fs::copy(file, &copy).unwrap();
    let session = Session::load(&copy).unwrap();
    let basin = session.analysis("basin_3_7").unwrap();
    run_analysis(&session, basin, Shard::ALL, &Progress::new(0)).unwrap();
    let mut reader = csv::Reader::from_path(ResultPaths::new(&session, "basin_3_7").csv).unwrap();
    let (mut edges, mut inside) = (0, 0);
    for row in reader.records() {
        let row = row.unwrap();
        let dx: f64 = row[0].parse().unwrap();
        let kind = &row[3];
        if (dx.abs() - 0.8).abs() < 1e-12 {
            assert_eq!(kind, "collision", "{row:?}");
            edges += 1;
        } else {
            assert_eq!(kind, "1:1 harmonic", "{row:?}");
            inside += 1;
        }
    }
    assert_eq!((edges, inside), (2 * 51, 39 * 51));
}

/// Load → edit → save → load keeps the user's comments and layout, and applies the edit.
#[test]
fn round_trip_keeps_comments() {
    let guard = scratch("roundtrip");
    let dir = guard.path().to_path_buf();
    let src = examples()
        .into_iter()
        .find(|p| p.to_string_lossy().contains("fig04"))
        .unwrap();
    let path = dir.join("s.toml");
    std::fs::copy(&src, &path).unwrap();
    let original = std::fs::read_to_string(&path).unwrap();
    let mut s = Session::load(&path).unwrap();
    s.save_as(&path).unwrap();
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        original,
        "an unedited save is byte-identical"
    );
    s.set_model_key(None, "lambda_p", 1.03).unwrap();
    s.save_as(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    for comment in original.lines().filter(|l| l.trim_start().starts_with('#')) {
        assert!(text.contains(comment), "lost comment: {comment}");
    }
    assert!(text.contains("# starts in the 1:2 basin"));
    let again = Session::load(&path).unwrap();
    assert_eq!(again.params(None).unwrap().lambda_p(), 1.03);
}

fn error_of(text: &str) -> String {
    Session::parse(Path::new("t.toml"), text)
        .unwrap_err()
        .to_string()
}

/// Malformed TOML, unknown keys, bad values and huge grids give messages a user can act on.
#[test]
fn bad_files_get_clear_errors() {
    let good = "schema = 1\n[model]\nadr = 0.6\n\n[[analysis]]\nname = \"b\"\nkind = \"basin\"\n[analysis.settings]\ndx = { min = -0.8, max = 0.8, points = 21 }\n";
    assert!(Session::parse(Path::new("t.toml"), good).is_ok());
    let e = error_of(&good.replace("adr = 0.6", "adr = = 0.6"));
    assert!(e.contains("line 3, column 7"), "{e}");
    let e = error_of(&good.replace("[model]", "colour = 1\n[model]"));
    assert!(e.contains("colour") && e.contains("line 2"), "{e}");
    let e = error_of(&good.replace("points = 21 }", "points = 21, stpe = 3 }"));
    assert!(e.contains("stpe") && e.contains("line 9"), "{e}");
    let e = error_of(&good.replace("kind = \"basin\"", "kind = \"basin\"\nkolor = 2"));
    assert!(e.contains("kolor") && e.contains("line 8"), "{e}");
    let e = error_of(&good.replace("adr = 0.6", "adr = -0.6"));
    assert!(
        e.contains("line 3") && e.contains("adr = -0.6") && e.contains("[0, 1000]"),
        "{e}"
    );
    let e = error_of(&good.replace("points = 21", "points = 1000000000"));
    assert!(
        e.contains("line 9") && e.contains("dx.points = 1000000000") && e.contains("16384"),
        "{e}"
    );
    // the field as the user wrote it, with its line and its value as written
    // a scalogram's frequencies below the samples' Nyquist frequency π/dt
    let chirp = "schema = 1\n[[analysis]]\nname = \"c\"\nkind = \"chirp_sweep\"\n[analysis.settings]\ndt = 0.5\nscalogram = { frequencies = { min = 1.0, max = 8.0, points = 8 } }\n";
    let e = error_of(chirp);
    assert!(
        e.contains("scalogram.frequencies.max") && e.contains("< 6.28") && e.contains("Nyquist"),
        "{e}"
    );
    let e = error_of(
        &chirp
            .replace("max = 8.0", "max = 6.0")
            .replace(" }\n", ", columns = 0 }\n"),
    );
    assert!(
        e.contains("scalogram.columns") && e.contains("[1, 100000]"),
        "{e}"
    );
    // at most 10⁷ cells: 4096 frequencies leave 2441 columns
    let e = error_of(&chirp.replace(
        "max = 8.0, points = 8 }",
        "max = 6.0, points = 4096 }, columns = 2442",
    ));
    assert!(
        e.contains("scalogram.columns") && e.contains("at most 2441"),
        "{e}"
    );
    let e = error_of(&good.replace("adr = 0.6", "frequency_hz = -1"));
    assert!(
        e.contains("line 3") && e.contains("frequency_hz = -1") && e.contains("Hz"),
        "{e}"
    );
    let e = error_of(&good.replace("adr = 0.6", "phi_dc_ii = -0.1"));
    assert!(e.contains("phi_dc_ii = -0.1"), "{e}");
    let e = error_of(&good.replace("adr = 0.6", "adr = nan"));
    assert!(e.contains("adr = nan"), "{e}");
    let e = error_of(&good.replace("adr = 0.6", "omega = 1e-9"));
    assert!(
        e.contains("omega = 1e-9") && e.contains("[0.01, 100]"),
        "{e}"
    );
    let e = error_of(&good.replace("points = 21", "points = -3"));
    assert!(
        e.contains("line 9") && e.contains("dx.points = -3") && e.contains("whole number"),
        "{e}"
    );
    let e = error_of(&good.replace(
        "[analysis.settings]",
        "[analysis.settings]
early_stop = 3",
    ));
    assert!(
        e.contains("line 9") && e.contains("early_stop = 3") && e.contains("true or false"),
        "{e}"
    );
    let e = error_of(&good.replace(
        "points = 21",
        "points = 21
capture = 1e400",
    ));
    assert!(
        e.contains("line 10") && e.contains("capture = 1e400"),
        "{e}"
    );
    let long = "n".repeat(300);
    let e = error_of(&good.replace("name = \"b\"", &format!("name = \"{long}\"")));
    assert!(e.contains("line 6") && e.contains("1 to 64"), "{e}");
    assert!(error_of("\n").contains("the file is empty"));
    let e = error_of(&good.replace("kind = \"basin\"", "kind = \"basins\""));
    assert!(e.contains("unknown kind 'basins'"), "{e}");
    let e = error_of(&good.replace("schema = 1", "schema = 2"));
    assert!(e.contains("schema = 2"), "{e}");
    let e = error_of(&good.replace("adr = 0.6", "omega = 3.7\nfrequency_hz = 50"));
    assert!(e.contains("omega") && e.contains("one form only"), "{e}");
    // a continuation starts at the model's ω_e: a range without it is refused, as is a step
    // too small to move the parameter past rounding
    let branch = "schema = 1\n[model]\nomega = 3.7\n[[analysis]]\nname = \"c\"\nkind = \"continuation\"\n[analysis.settings]\ndx0 = 0.3\n[analysis.settings.continuation]\nmin = 3.0\nmax = 4.0\n";
    assert!(Session::parse(Path::new("t.toml"), branch).is_ok());
    let e = error_of(
        &branch
            .replace("min = 3.0", "min = 4.0\nmax = 6.0")
            .replace("max = 4.0\n", ""),
    );
    assert!(
        e.contains("continuation.min = 4")
            && e.contains("<= 3.7, the omega the branch starts from"),
        "{e}"
    );
    let e = error_of(&branch.replace("max = 4.0", "max = 3.5"));
    assert!(
        e.contains("continuation.max = 3.5") && e.contains(">= 3.7"),
        "{e}"
    );
    let e = error_of(&branch.replace("max = 4.0", "max = 4.0\nstep_min = 1e-14\nstep = 1e-14"));
    assert!(
        e.contains("step_min = 1e-14") && e.contains("[1e-12, step_max"),
        "{e}"
    );
}

/// Physical units in the model table: Hz and kV are converted with the device.
#[test]
fn physical_model_values_are_converted() {
    let text = "schema = 1\n[model]\nfrequency_hz = 25.6235\ndc_kv = 2.34\nac_kv = 1.40\n";
    let s = Session::parse(Path::new("t.toml"), text).unwrap();
    let p = s.params(None).unwrap();
    assert!((p.omega() - 1.8).abs() < 1e-4, "{}", p.omega());
    assert!((p.drive_i().phi_dc() - 0.1841).abs() < 1e-3);
}

/// A changed setting makes the stored result stale rather than mixing it in.
#[test]
fn changed_settings_make_results_stale() {
    let guard = scratch("stale");
    let dir = guard.path().to_path_buf();
    let path = dir.join("s.toml");
    std::fs::write(
        &path,
        "schema = 1\n[[analysis]]\nname = \"o\"\nkind = \"time_history\"\n",
    )
    .unwrap();
    let mut s = Session::load(&path).unwrap();
    let entry = s.analyses[0].clone();
    run_analysis(&s, &entry, Shard::ALL, &Progress::new(0)).unwrap();
    assert!(is_current(&s, &entry));
    s.set_model_key(None, "omega", 1.8).unwrap();
    let entry = s.analyses[0].clone();
    assert!(!is_current(&s, &entry));
}

/// A write that fails before its rename leaves the old file as it was, and no temporary.
#[test]
fn interrupted_save_leaves_the_old_file() {
    let guard = scratch("atomic");
    let dir = guard.path().to_path_buf();
    let path = dir.join("r.csv");
    std::fs::write(&path, "old,contents\n").unwrap();
    let result = isola::session::export::write_atomic(&path, |w| {
        w.write_record(["new", "half"])?;
        anyhow::bail!("interrupted")
    });
    assert!(result.is_err());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old,contents\n");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "no temporary left behind: {names:?}");
}

/// `isola export --where` selects rows of a stored result.
#[test]
fn export_selects_rows() {
    let guard = scratch("export");
    let dir = guard.path().to_path_buf();
    let path = dir.join("s.toml");
    std::fs::write(&path, "schema = 1\n[model]\nomega = 3.7\n[[analysis]]\nname = \"b\"\nkind = \"basin\"\n[analysis.settings]\ndx = { min = -0.8, max = 0.8, points = 11 }\nv = { min = -1.0, max = 1.0, points = 11 }\n").unwrap();
    let s = Session::load(&path).unwrap();
    run_analysis(&s, &s.analyses[0], Shard::ALL, &Progress::new(0)).unwrap();
    let out = dir.join("sel.csv");
    let status = Command::new(env!("CARGO_BIN_EXE_isola"))
        .args([
            "export",
            &path.to_string_lossy(),
            "--analysis",
            "b",
            "--where",
            "response_type=1:2 subharmonic",
            "--where",
            "dx_stretch>=0",
            "--csv",
            &out.to_string_lossy(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(&out).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert!(!rows.is_empty());
    for r in rows {
        let cells: Vec<&str> = r.split(',').collect();
        assert_eq!(cells[3], "1:2 subharmonic");
        assert!(cells[0].parse::<f64>().unwrap() >= 0.0);
    }
}

/// A model value set for one analysis only goes into its own `model` table (made inline if it
/// has none, the other form of the same quantity replaced); the session's model and the other
/// analyses keep theirs, and the file reads back the same.
#[test]
fn a_model_value_overridden_for_one_analysis_leaves_the_others() {
    let text = "# two\nschema = 1\n[model]\nadr = 0.6\n\n[[analysis]]\nname = \"a\"\nkind = \"basin\"\n[analysis.settings]\ndx = { min = -0.8, max = 0.8, points = 5 }\n\n[[analysis]]\nname = \"b\"\nkind = \"basin\"\nmodel = { frequency_hz = 50.0 }\n";
    let mut s = Session::parse(Path::new("two.toml"), text).unwrap();
    s.override_model_key(0, "adr", 1.0).unwrap();
    s.override_model_key(1, "omega", 3.5).unwrap();
    let written = s.to_text();
    assert!(written.contains("model = { adr = 1.0 }"), "{written}");
    assert!(written.contains("model = { omega = 3.5 }"), "{written}");
    let again = Session::parse(Path::new("two.toml"), &written).unwrap();
    let adr = |i: usize| {
        let p = again.params(Some(&again.analyses[i])).unwrap();
        p.drive_i().adr().unwrap()
    };
    assert_eq!((adr(0), adr(1)), (1.0, 0.6));
    assert_eq!(again.params(Some(&again.analyses[1])).unwrap().omega(), 3.5);
    assert_eq!(again.params(None).unwrap().drive_i().adr(), Some(0.6));
    assert!(written.starts_with("# two\n"));
}

/// Every `frequency_hz` and `time_s` written follows the session's `[device]`: with 4× the
/// mass, frequencies are half the default device's (the map's column once always used the
/// default device).
#[test]
fn frequencies_and_times_follow_the_device() {
    let response = "[analysis.settings.response]\nomega = { min = 3.5, max = 4.0, points = 2 }\ndx = { min = -0.6, max = 0.6, points = 2 }\nv = { min = -0.8, max = 0.8, points = 2 }\n";
    let text = format!(
        "schema = 1\n[device]\nmu = 400e3\nj = 16.0\nl1 = 20e-3\nl2 = 200e-3\nl3 = 0.1e-3\nmass = 200e-3\nepsilon = 2.48e-11\n[model]\nadr = 0.6\n\n\
         [[analysis]]\nname = \"response\"\nkind = \"frequency_response\"\n[analysis.settings]\nomega = {{ min = 3.5, max = 4.0, points = 2 }}\ndx = {{ min = -0.6, max = 0.6, points = 2 }}\nv = {{ min = -0.8, max = 0.8, points = 2 }}\n\n\
         [[analysis]]\nname = \"stepped\"\nkind = \"stepped_sweep\"\n[analysis.settings]\nomega = {{ min = 3.0, max = 4.0, points = 3 }}\n\n\
         [[analysis]]\nname = \"chirp\"\nkind = \"chirp_sweep\"\n[analysis.settings]\nomega_start = 3.0\nomega_end = 3.5\nspan = 300.0\n\n\
         [[analysis]]\nname = \"family\"\nkind = \"family\"\n[analysis.settings]\nparameter = \"adr\"\nvalues = [0.6]\n{response}\n\
         [[analysis]]\nname = \"map\"\nkind = \"map\"\n[analysis.settings]\nparameter = \"adr\"\nvalues = {{ min = 0.5, max = 0.6, points = 2 }}\ncurves = false\n{response}\n\
         [[analysis]]\nname = \"orbit\"\nkind = \"time_history\"\n[analysis.settings]\ndx0 = 0.3\n"
    );
    let guard = scratch("device");
    let dir = guard.path().to_path_buf();
    let path = dir.join("s.toml");
    std::fs::write(&path, &text).unwrap();
    let session = Session::load(&path).unwrap();
    let device = session.device();
    let silicone = isola::model::Device::silicone();
    assert!(
        (device.hz(3.7) - 0.5 * silicone.hz(3.7)).abs() < 1e-12,
        "4× the mass"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_isola"))
        .arg("run")
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut checked = 0;
    let results = dir.join("s.results");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&results)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    for file in &files {
        let mut reader = csv::Reader::from_path(file).unwrap();
        let headers = reader.headers().unwrap().clone();
        let col = |name: &str| headers.iter().position(|h| h == name);
        let pairs = [("omega", "frequency_hz"), ("tau", "time_s")];
        for (from, to) in pairs {
            let (Some(a), Some(b)) = (col(from), col(to)) else {
                continue;
            };
            for row in reader.records() {
                let row = row.unwrap();
                let (x, written) = (&row[a], &row[b]);
                if x.is_empty() || written.is_empty() {
                    continue;
                }
                let x: f64 = x.parse().unwrap();
                let written: f64 = written.parse().unwrap();
                let expected = if to == "time_s" {
                    device.seconds(x)
                } else {
                    device.hz(x)
                };
                // as printed: 4 decimals of Hz (8 of seconds), and ω itself to 6
                let tolerance = 6e-5 + 1e-6 * expected.abs();
                assert!(
                    (written - expected).abs() < tolerance,
                    "{}: {to} {written} for {from} {x}: {expected} for this device",
                    file.display()
                );
                checked += 1;
            }
            break;
        }
    }
    assert!(checked > 20, "only {checked} values checked in {files:?}");
    // the map, the family's responses, the stepped sweep and the chirp each have the column
    for name in [
        "map.csv",
        "stepped.csv",
        "chirp.csv",
        "response.csv",
        "orbit.csv",
    ] {
        assert!(
            files.iter().any(|f| f.ends_with(name)),
            "{name} missing: {files:?}"
        );
    }
}

/// A result's CSV holds the very numbers computed: a time history read back from its CSV is,
/// to the bit, the one the library computes in memory.
#[test]
fn numbers_read_back_from_a_csv_are_the_ones_computed() {
    let guard = scratch("roundtrip-numbers");
    let path = guard.path().join("s.toml");
    std::fs::write(
        &path,
        "schema = 1\n[model]\nadr = 0.6\n\n[[analysis]]\nname = \"orbit\"\nkind = \"time_history\"\n[analysis.settings]\ndx0 = 0.3\n",
    )
    .unwrap();
    let session = Session::load(&path).unwrap();
    let entry = &session.analyses[0];
    run_analysis(&session, entry, Shard::ALL, &Progress::new(0)).unwrap();
    let Settings::TimeHistory(spec) = &entry.settings else {
        panic!("a time history");
    };
    let params = session.params(Some(entry)).unwrap();
    let computed = isola::analysis::orbit::time_history::time_history(&params, spec).unwrap();
    let mut reader = csv::Reader::from_path(ResultPaths::new(&session, "orbit").csv).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), computed.samples.len());
    for (row, sample) in rows.iter().zip(&computed.samples) {
        let read = |i: usize| row[i].parse::<f64>().unwrap().to_bits();
        assert_eq!(
            (read(0), read(2), read(3)),
            (
                sample.tau.to_bits(),
                sample.lambda.to_bits(),
                sample.v.to_bits()
            ),
            "row {row:?}"
        );
    }
}

/// The paper's model written as equations (`sessions/user_model_paper.toml`) gives the
/// built-in model's results through the session path: the same responses (type, hidden flag,
/// share of starts, branch) at each ω_e with amplitudes within 1e-7, the same basin label
/// in every cell with the same attractor counts, and the same chirp sweep (samples within
/// 1e-6, its scalogram's magnitudes within 1e-5 of the largest) under the model's names.
#[test]
fn the_paper_model_written_as_equations_gives_the_built_in_results() {
    let dir = scratch("written");
    let written = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/user_model_paper.toml"),
    )
    .unwrap();
    let model =
        &written[written.find("\n[model]\n").unwrap()..written.find("\n[[analysis]]").unwrap()];
    let analyses = r#"
[[analysis]]
name = "response"
kind = "frequency_response"
[analysis.settings]
omega = { min = 3.6, max = 3.8, points = 3 }
dx = { min = -0.8, max = 0.8, points = 5 }
v = { min = -1.0, max = 1.0, points = 5 }

[[analysis]]
name = "basin"
kind = "basin"
model = { omega = 3.7 }
[analysis.settings]
dx = { min = -0.8, max = 0.8, points = 9 }
v = { min = -1.0, max = 1.0, points = 11 }

[[analysis]]
name = "chirp"
kind = "chirp_sweep"
[analysis.settings]
omega_start = 1.0
omega_end = 2.5
span = 400.0
dx0 = 0.1
scalogram = { frequencies = { min = 0.5, max = 5.0, points = 10 }, columns = 50 }
"#;
    let built_in = format!("schema = 1\n[model]\nadr = 0.6\ne_a = 0.04\n{analyses}");
    let written = format!("schema = 1\n{model}\n{analyses}");
    let mut csv = Vec::new();
    for (name, text) in [("built_in", built_in), ("written", written)] {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let session = Session::load(&path).unwrap_or_else(|e| panic!("{e}"));
        for entry in &session.analyses {
            run_analysis(&session, entry, Shard::ALL, &Progress::new(0)).unwrap();
        }
        let read = |file: &str| -> Vec<std::collections::HashMap<String, String>> {
            let mut r = csv::Reader::from_path(session.results_dir().join(file)).unwrap();
            r.deserialize().map(|row| row.unwrap()).collect()
        };
        csv.push((
            read("response.csv"),
            read("basin.csv"),
            read("basin.attractors.csv"),
            [
                read("chirp.csv"),
                read("chirp.scalogram.csv"),
                read("chirp.extremes.csv"),
            ],
        ));
        // the workbench reads the sweep back, under either model's names
        let chirp = session.analyses.iter().find(|a| a.name == "chirp").unwrap();
        let Ok(isola::session::results::ResultView::Chirp(view)) =
            isola::session::results::current_view(&session, chirp)
        else {
            panic!("{name}: the chirp reads back as a chirp");
        };
        assert_eq!(view.lambda.len(), 8001, "{name}");
        assert_eq!(view.envelope.len(), 21, "{name}");
    }
    let key = |r: &std::collections::HashMap<String, String>| {
        [
            "omega",
            "response_type",
            "hidden",
            "seeded",
            "branch",
            "share",
        ]
        .map(|c| r[c].clone())
    };
    let (b, w) = (&csv[0], &csv[1]);
    assert_eq!(b.0.len(), w.0.len());
    for (rb, rw) in b.0.iter().zip(&w.0) {
        assert_eq!(key(rb), key(rw));
        // the written model's columns carry its names
        assert!(rw.contains_key("start_lambda_I") && rw.contains_key("lambda_I_min"));
        if let (Ok(x), Ok(y)) = (
            rb["amplitude_stretch"].parse::<f64>(),
            rw["amplitude"].parse::<f64>(),
        ) {
            assert!((x - y).abs() < 1e-7, "{x} {y}");
        }
    }
    let labels = |rows: &[std::collections::HashMap<String, String>]| -> Vec<String> {
        rows.iter()
            .map(|r| format!("{} {}", r["attractor"], r["response_type"]))
            .collect()
    };
    assert_eq!(labels(&b.1), labels(&w.1));
    let counts = |rows: &[std::collections::HashMap<String, String>]| -> Vec<String> {
        rows.iter()
            .map(|r| format!("{} {}", r["response_type"], r["cells"]))
            .collect()
    };
    assert_eq!(counts(&b.2), counts(&w.2));
    assert!(
        b.2.len() >= 2,
        "the basin shows the 1:1 response and the 1:2 isola"
    );
    // the chirp: λ_I as `lambda_I`, its envelope as `envelope_amplitude`, no seconds or Hz
    let [samples_b, cells_b, extremes_b] = &b.3;
    let [samples_w, cells_w, extremes_w] = &w.3;
    let number = |r: &std::collections::HashMap<String, String>, c: &str| -> f64 {
        r[c].parse().unwrap_or_else(|_| panic!("{c} in {r:?}"))
    };
    assert_eq!(samples_b.len(), samples_w.len());
    for (rb, rw) in samples_b.iter().zip(samples_w) {
        assert_eq!((&rb["tau"], &rb["omega"]), (&rw["tau"], &rw["omega"]));
        assert!(rw["time_s"].is_empty() && rw["frequency_hz"].is_empty());
        let (x, y) = (number(rb, "lambda_stretch"), number(rw, "lambda_I"));
        assert!((x - y).abs() < 1e-6, "τ {}: {x} {y}", rb["tau"]);
        let (x, y) = (
            number(rb, "envelope_amplitude_stretch"),
            number(rw, "envelope_amplitude"),
        );
        assert!((x - y).abs() < 2e-6, "τ {}: {x} {y}", rb["tau"]);
    }
    let largest = cells_b
        .iter()
        .map(|r| number(r, "magnitude_stretch"))
        .fold(0.0, f64::max);
    assert_eq!(cells_b.len(), cells_w.len());
    for (rb, rw) in cells_b.iter().zip(cells_w) {
        let (x, y) = (number(rb, "magnitude_stretch"), number(rw, "magnitude"));
        assert!((x - y).abs() < 1e-5 * largest, "{x} {y}");
    }
    let (eb, ew) = (&extremes_b[0], &extremes_w[0]);
    assert_eq!(eb["peak_omega"], ew["peak_omega"]);
    for (c_b, c_w) in [
        ("lambda_min", "lambda_I_min"),
        ("lambda_max", "lambda_I_max"),
        ("peak_envelope_amplitude_stretch", "peak_envelope_amplitude"),
    ] {
        assert!((number(eb, c_b) - number(ew, c_w)).abs() < 2e-6, "{c_b}");
    }
}

/// A written model's mistakes name the key, line and column, and the token or name; a value
/// that is not finite stops the run with τ, the state and the expression; nothing panics or
/// hangs, however the model is written.
#[test]
fn a_written_model_gets_clear_errors() {
    let good = "schema = 1\n[model]\nstates = [\"x\", \"v\"]\nfrequency = \"omega\"\namplitude = \"x\"\n[model.parameters]\nomega = 1.0\nk = { value = 2, min = 0, max = 10 }\n[model.let]\na = \"2*x\"\n[model.derivatives]\nx = \"v\"\nv = \"-k*a + cos(omega*t)\"\n\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"\n";
    assert!(Session::parse(Path::new("t.toml"), good).is_ok());
    let cases = [
        (
            "a = \"2*x\"",
            "a = \"2*b\"\nb = \"a + 1\"",
            "cyclic definition: a → b → a",
        ),
        (
            "cos(omega*t)\"",
            "cos(omega*t) + * 2\"",
            "line 13, column 28: expected a number, a name or `(` at `*`",
        ),
        ("-k*a", "-k*aa", "unknown name `aa`; did you mean `a`?"),
        (
            "-k*a + cos(omega*t)",
            "-k*a + 1e999*x",
            "line 13, column 13: a number beyond the largest a double holds (1.8e308) at `1e999`",
        ),
        // a string with an escape: its characters are not the file's, its line is
        (
            "-k*a + cos(omega*t)",
            "-k*a \\u002b * 2",
            "model.derivatives.v, line 13, character 8 of its text: expected a number",
        ),
        (
            "kind = \"time_history\"",
            "kind = \"time_history\"\n[analysis.settings]\ntolerance = 1e-20",
            "settings.tolerance = 1e-20: a table { rtol = …, atol = … } is expected, not a number",
        ),
        (
            "cos(omega*t)",
            "max(omega)",
            "max(…) takes 2 or more arguments, not 1",
        ),
        (
            "cos(omega*t)",
            "cos(omega, t)",
            "cos(…) takes 1 argument, not 2",
        ),
        (
            "v = \"-k*a + cos(omega*t)\"",
            "",
            "the state `v` has no derivative",
        ),
        ("x = \"v\"", "x = \"v\"\ny = \"1\"", "`y` is not a state"),
        (
            "frequency = \"omega\"",
            "frequency = \"w\"",
            "`w` is not a parameter",
        ),
        (
            "k = { value = 2,",
            "k = { value = 20,",
            "value 20 is outside its range [0, 10]",
        ),
        (
            "k = { value = 2, min = 0, max = 10 }",
            "k = { value = 2, min = 10, max = 0 }",
            "model.parameters.k: min = 10 and max = 0: give min ≤ max",
        ),
        (
            "k = { value = 2,",
            "k = { value = nan,",
            "value = NaN: give a finite number",
        ),
        (
            "k = { value = 2,",
            "k = { value = 2, mni = 1,",
            "line 8, column 5",
        ),
        (
            "k = { value = 2,",
            "k = { value = 2, mni = 1,",
            "unknown field `mni`, expected one of `value`, `min`, `max`, `unit`, `about`",
        ),
        (
            "omega = 1.0",
            "omega = \"fast\"",
            "a parameter is a number or { value, min, max, unit, about }, not a string",
        ),
        (
            "kind = \"time_history\"",
            "kind = \"force_curve\"",
            "a written model runs time_history, chirp_sweep, stepped_sweep",
        ),
        (
            "kind = \"time_history\"",
            "kind = \"force_curve\"",
            "(force curves are the built-in DEA's own)",
        ),
        // a written model's chirp: its frequency parameter swept, above 0 and in its range
        (
            "kind = \"time_history\"",
            "kind = \"chirp_sweep\"",
            "omega_start = 0 is out of range: allowed > 0 (the forcing frequency) (as omega)",
        ),
        (
            "kind = \"time_history\"",
            "kind = \"chirp_sweep\"\n[analysis.settings]\nomega_start = 0.5\nomega_end = -1",
            "omega_end = -1 is out of range: allowed > 0 (the forcing frequency) (as omega)",
        ),
        // and its time read as the sweep's phase: only as k·ω·t inside a periodic function
        (
            "cos(omega*t)\"\n\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"",
            "cos(omega*t)*exp(-t)\"\n\n[[analysis]]\nname = \"h\"\nkind = \"chirp_sweep\"\n[analysis.settings]\nomega_start = 0.5\nomega_end = 2",
            "analysis 'h' (chirp_sweep): a chirp sweep reads omega*t as the sweep's phase, so \
             the model's time t may enter only as k*omega*t (k a whole number, plus a fixed \
             phase) inside sin, cos or tan; this model uses t otherwise",
        ),
        (
            "kind = \"time_history\"",
            "kind = \"continuation\"\n[analysis.settings.continuation]\nparameter = \"adr\"",
            "parameter `adr` is out of range: allowed one of the model's: k, omega",
        ),
        (
            "kind = \"time_history\"",
            "kind = \"time_history\"\nmodel = { kk = 1 }",
            "`kk` is not a parameter",
        ),
        (
            "cos(omega*t)",
            "cos(omega*t) + (x < 0)",
            "a comparison is a condition",
        ),
        (
            "[model.let]",
            "[model.functions]\n\"g(b, b)\" = \"b\"\n[model.let]",
            "the argument `b` is named twice in `g(b, b)`",
        ),
        // a forcing period of 6.3e6 τ: refused by its steps per period, not run for hours
        (
            "omega = 1.0",
            "omega = 1e-6",
            "cuts a forcing period (ω_e 0.000001) into at most 1000000 steps",
        ),
    ];
    for (from, to, want) in cases {
        let text = good.replace(from, to);
        assert_ne!(text, good, "{from}");
        let e = error_of(&text);
        assert!(e.contains(want), "{from} → {to}: {e}");
    }
    // a chirp stays in its frequency parameter's range
    let ranged = good
        .replace("omega = 1.0", "omega = { value = 1.0, min = 0.5, max = 3 }")
        .replace(
            "kind = \"time_history\"",
            "kind = \"chirp_sweep\"\n[analysis.settings]\nomega_start = 0.5\nomega_end = 4",
        );
    let e = error_of(&ranged);
    assert!(
        e.contains("omega_end = 4 is out of range: allowed [0.5, 3] (as omega)"),
        "{e}"
    );
    // a parameter is the model's own by its name: `w` or `damping` is no other name for
    // the forcing frequency or the built-in model's damping
    for name in ["w", "damping", "ea"] {
        let text = good
            .replace("k = { value = 2,", &format!("{name} = 1.0\nk = {{ value = 2,"))
            .replace(
                "kind = \"time_history\"",
                &format!(
                    "kind = \"continuation\"\n[analysis.settings.continuation]\nparameter = \"{name}\"\nmin = 0.5\nmax = 1.5"
                ),
            );
        let s = Session::parse(Path::new("t.toml"), &text).unwrap();
        let Settings::Continuation(spec) = &s.analyses[0].settings else {
            panic!("a continuation");
        };
        assert_eq!(spec.continuation.parameter.name(), name);
        let Ok(isola::session::written::ModelPoint::Written(sys)) = s.point(None) else {
            panic!("a written model");
        };
        use isola::analysis::Oscillator;
        let resolved = sys.resolve(spec.continuation.parameter).unwrap();
        assert_eq!(Some(resolved), sys.model().parameter(name), "{name}");
    }
    // an override out of range names the parameter, its value as written and its range
    let e = error_of(&good.replace(
        "kind = \"time_history\"",
        "kind = \"time_history\"\nmodel = { k = -1 }",
    ));
    assert!(e.contains("k = -1") && e.contains("[0, 10]"), "{e}");
    // a function that expands exponentially is refused, not compiled for ever
    let mut nested = good.replace(
        "[model.let]",
        "[model.functions]\n\"f0(y)\" = \"y\"\n[model.let]",
    );
    for i in 1..40 {
        nested = nested.replace(
            "[model.let]",
            &format!(
                "\"f{i}(y)\" = \"f{}(y) + f{}(y + 1)\"\n[model.let]",
                i - 1,
                i - 1
            ),
        );
    }
    let nested = nested.replace("a = \"2*x\"", "a = \"f39(x)\"");
    assert!(error_of(&nested).contains("expands to more than"));
    // a deeply nested expression compiles (or is refused) without overflowing the stack
    let deep = good.replace(
        "a = \"2*x\"",
        &format!("a = \"{}x{}\"", "(".repeat(20_000), ")".repeat(20_000)),
    );
    assert!(Session::parse(Path::new("t.toml"), &deep).is_ok());
    // a model of one state has no grid of starts: its time history runs, its basin is
    // refused naming why (it ran over a second axis that was the first again)
    let one = "schema = 1\n[model]\nstates = [\"x\"]\nfrequency = \"omega\"\namplitude = \"x\"\n[model.parameters]\nomega = 1.0\n[model.derivatives]\nx = \"-x + 0.5*max(x, 0) + cos(omega*t)\"\n\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"\n";
    assert!(Session::parse(Path::new("t.toml"), one).is_ok());
    for kind in ["basin", "frequency_response", "family", "hunt", "map"] {
        let settings = match kind {
            "family" => "\n[analysis.settings]\nparameter = \"k\"\nvalues = [0.5]",
            "map" => {
                "\n[analysis.settings]\nparameter = \"k\"\nvalues = { min = 0.4, max = 0.6, points = 2 }"
            }
            _ => "",
        };
        let text = one
            .replace("omega = 1.0", "omega = 1.0\nk = 0.5")
            .replace("0.5*max", "k*max")
            .replace("\"time_history\"", &format!("\"{kind}\"{settings}"));
        let e = error_of(&text);
        assert!(
            e.contains(&format!("line 14: analysis 'h' ({kind}): a grid of starts spans two states, and this model has one (`x`)")),
            "{kind}: {e}"
        );
    }
    // a value that is not finite stops the run, saying where
    let dir = scratch("not-finite");
    let path = dir.path().join("nan.toml");
    std::fs::write(&path, good.replace("a = \"2*x\"", "a = \"sqrt(x - 10)\"")).unwrap();
    let s = Session::load(&path).unwrap();
    let e = run_analysis(&s, &s.analyses[0], Shard::ALL, &Progress::new(0)).unwrap_err();
    let e = format!("{e:#}");
    assert!(
        e.contains("not finite at τ = 0")
            && e.contains("x = 0, v = 0")
            && e.contains("model.let.a = NaN"),
        "{e}"
    );
}

/// A session with every kind of analysis, each tiny, and a written model's time history.
const EVERY_KIND: &str = r#"schema = 1
[model]
adr = 0.6

[[analysis]]
name = "force"
kind = "force_curve"
[analysis.settings]
lambda_p = [1.02]
phi_i = [0.0, 0.2]

[[analysis]]
name = "orbit"
kind = "time_history"
[analysis.settings]
dx0 = 0.3

[[analysis]]
name = "chirp"
kind = "chirp_sweep"
[analysis.settings]
omega_start = 3.0
omega_end = 3.5
span = 200.0
scalogram = { frequencies = { min = 1.0, max = 6.0, points = 21 }, columns = 40 }

[[analysis]]
name = "stepped"
kind = "stepped_sweep"
[analysis.settings]
omega = { min = 3.0, max = 4.0, points = 3 }

[[analysis]]
name = "response"
kind = "frequency_response"
[analysis.settings]
omega = { min = 3.6, max = 3.8, points = 3 }
dx = { min = -0.8, max = 0.8, points = 4 }
v = { min = -1.0, max = 1.0, points = 4 }

[[analysis]]
name = "basin"
kind = "basin"
model = { omega = 3.7 }
[analysis.settings]
dx = { min = -0.8, max = 0.8, points = 9 }
v = { min = -1.0, max = 1.0, points = 9 }

[[analysis]]
name = "family"
kind = "family"
[analysis.settings]
parameter = "adr"
values = [0.6, 0.7]
[analysis.settings.response]
omega = { min = 3.6, max = 3.8, points = 3 }
dx = { min = -0.8, max = 0.8, points = 3 }
v = { min = -1.0, max = 1.0, points = 3 }

[[analysis]]
name = "map"
kind = "map"
[analysis.settings]
parameter = "adr"
values = { min = 0.5, max = 0.6, points = 2 }
curves = false
[analysis.settings.response]
omega = { min = 3.6, max = 3.8, points = 3 }
dx = { min = -0.8, max = 0.8, points = 3 }
v = { min = -1.0, max = 1.0, points = 3 }

[[analysis]]
name = "continued"
kind = "continuation"
model = { omega = 4.6 }
[analysis.settings]
dx0 = 0.3
[analysis.settings.continuation]
parameter = "adr"
min = 0.4
max = 0.8

[[analysis]]
name = "hunt"
kind = "hunt"
[analysis.settings.response]
omega = { min = 3.6, max = 3.8, points = 3 }
dx = { min = -0.8, max = 0.8, points = 4 }
v = { min = -1.0, max = 1.0, points = 4 }
[analysis.settings.continuation]
min = 3.0
max = 5.0
"#;

/// Every result is tidy data: one value per cell (no `;`-joined lists), no text a
/// spreadsheet turns into a time (`1:2`), the responses of a frequency response periodic
/// only, with their stroboscopic points one per row and the other outcomes per ω_e in
/// tables of their own; the manifest records what the result was computed from, and that
/// record hashes to the fingerprint. Where Python with pandas is found (`ISOLA_PYTHON`, else
/// `python3`), `python/isola_results.py` loads every table with numbers as numbers, integers
/// as integers and flags as booleans.
#[test]
fn results_are_tidy_tables_that_pandas_reads_with_their_types() {
    use std::collections::HashMap;
    let guard = scratch("tidy");
    let path = guard.path().join("every.toml");
    std::fs::write(&path, EVERY_KIND).unwrap();
    let session = Session::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for entry in &session.analyses {
        run_analysis(&session, entry, Shard::ALL, &Progress::new(0))
            .unwrap_or_else(|e| panic!("{}: {e:#}", entry.name));
    }
    let results = session.results_dir();
    type Rows = Vec<HashMap<String, String>>;
    let read = |file: &str| -> Rows {
        let mut r = csv::Reader::from_path(results.join(file)).unwrap();
        r.deserialize().map(|row| row.unwrap()).collect()
    };
    let time_like = |cell: &str| {
        cell.split_once(':').is_some_and(|(a, b)| {
            [a, b]
                .iter()
                .all(|p| !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()))
        })
    };
    let mut tables = 0;
    for entry in &session.analyses {
        let manifest: serde_json::Value = serde_json::from_slice(
            &std::fs::read(results.join(format!("{}.manifest.json", entry.name))).unwrap(),
        )
        .unwrap();
        use sha2::Digest;
        let digest = sha2::Sha256::digest(manifest["computed_from"].to_string().as_bytes());
        let hex: String = digest[..16].iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(manifest["fingerprint"], hex.as_str(), "{}", entry.name);
        assert_eq!(hex, session.fingerprint(entry));
        for file in manifest["files"].as_array().unwrap() {
            let name = file["name"].as_str().unwrap();
            for row in read(name) {
                for (column, cell) in &row {
                    assert!(
                        !cell.contains(';') && !time_like(cell),
                        "{name}: {column} = {cell}"
                    );
                }
            }
            tables += 1;
        }
    }
    assert!(tables >= 20, "{tables} tables");

    // a frequency response: periodic responses, their points, the outcomes per ω_e
    let (responses, points, outcomes) = (
        read("response.csv"),
        read("response.points.csv"),
        read("response.outcomes.csv"),
    );
    let number = |r: &HashMap<String, String>, c: &str| -> f64 { r[c].parse().unwrap() };
    for (id, r) in responses.iter().enumerate() {
        assert_eq!(r["class"], "periodic");
        assert_eq!(r["response"], id.to_string());
        let period = number(r, "period_forcing_periods") as usize;
        let mine: Vec<&HashMap<String, String>> = points
            .iter()
            .filter(|p| p["response"] == r["response"])
            .collect();
        assert_eq!(mine.len(), period, "one row per stroboscopic point");
        for (k, p) in mine.iter().enumerate() {
            assert_eq!(p["point"], k.to_string());
            assert_eq!(p["omega"], r["omega"]);
        }
        assert_eq!(mine[0]["poincare_lambda"], r["start_lambda"]);
        assert!(r["branch"].parse::<usize>().is_ok() && r["hidden"].parse::<bool>().is_ok());
        let ratio = (number(r, "ratio_response"), number(r, "ratio_excitation"));
        assert!(r["response_type"].starts_with(&format!("{}:{}", ratio.0, ratio.1)) || period > 1);
    }
    assert_eq!(outcomes.len(), 3, "one row per ω_e");
    let mut collisions = 0.0;
    for o in &outcomes {
        let shares =
            ["periodic_share", "non_periodic_share", "collision_share"].map(|c| number(o, c));
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{o:?}");
        let periodic: f64 = responses
            .iter()
            .filter(|r| r["omega"] == o["omega"])
            .map(|r| number(r, "share"))
            .sum();
        assert!((periodic - shares[0]).abs() < 1e-12);
        collisions += shares[2];
    }
    assert!(collisions > 0.0, "starts near the frames hit them");

    // a chirp's scalogram: one row per column and frequency; its ridge, one row per column,
    // is that column's strongest frequency, at the sweep's ω_e then
    let (samples, cells, ridge) = (
        read("chirp.csv"),
        read("chirp.scalogram.csv"),
        read("chirp.scalogram.ridge.csv"),
    );
    assert_eq!((cells.len(), ridge.len()), (21 * 40, 40));
    for (c, r) in ridge.iter().enumerate() {
        let column = &cells[21 * c..21 * (c + 1)];
        assert!(column.iter().all(|x| x["tau"] == r["tau"]));
        let strongest = column
            .iter()
            .max_by(|a, b| {
                number(a, "magnitude_stretch").total_cmp(&number(b, "magnitude_stretch"))
            })
            .unwrap();
        assert_eq!(strongest["omega_r"], r["ridge_omega_r"], "column {c}");
        let sample = samples.iter().find(|x| x["tau"] == r["tau"]).unwrap();
        assert_eq!(sample["omega"], r["omega_e"], "column {c}");
        let ratio = number(r, "ridge_omega_r") / number(r, "omega_e");
        assert_eq!(number(r, "ridge_ratio"), ratio);
    }
    // a 1:1 response: the ridge follows ω_e (within a frequency step of 0.25) once the
    // start's transient has gone
    for r in &ridge[ridge.len() / 2..] {
        let off = number(r, "ridge_omega_r") - number(r, "omega_e");
        assert!(off.abs() <= 0.25, "{r:?}");
    }

    // the workbench reads the tables back: the collisions counted at their ω_e
    let entry = session.analysis("response").unwrap();
    let mut reader = isola::session::results::ResultReader::new(entry);
    reader.poll(&session, entry);
    assert_eq!(reader.error, None);
    let Some(isola::session::results::ResultView::Response(view)) = &reader.view else {
        panic!("no response view");
    };
    assert_eq!(
        view.iter().filter(|p| p.amplitude.is_some()).count(),
        responses.len()
    );
    assert!(view.iter().any(|p| p.response_type == "collision"));
    assert!(
        view.iter()
            .all(|p| p.amplitude.is_none() || p.start.is_some())
    );

    pandas_reads(&results);
}

/// Checks, where Python with pandas is found, that `python/isola_results.py` loads every
/// table of `results` with numbers as numbers, integers as integers and flags as booleans,
/// and refuses a result its session was edited since (isola asked through `ISOLA`).
fn pandas_reads(results: &Path) {
    let python = std::env::var("ISOLA_PYTHON").unwrap_or_else(|_| "python3".into());
    let has_pandas = Command::new(&python)
        .args(["-c", "import pandas"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_pandas {
        eprintln!("skipped the pandas check: no pandas for '{python}' (set ISOLA_PYTHON)");
        return;
    }
    let reader = Path::new(env!("CARGO_MANIFEST_DIR")).join("python");
    let script = r#"
import sys
sys.path.insert(0, sys.argv[1])
import isola_results
found = isola_results.load_all(sys.argv[2])
bad = []
columns = 0
for analysis, tables in found.items():
    for name, frame in tables.items():
        for column, dtype in frame.dtypes.items():
            columns += 1
            kind = str(dtype)
            if kind == "object":
                bad.append((analysis, name, column, kind))
            if column in isola_results.INTEGER and kind != "Int64":
                bad.append((analysis, name, column, kind))
            if column in isola_results.BOOLEAN and kind != "boolean":
                bad.append((analysis, name, column, kind))
        if "stable" in frame and name == analysis and analysis == "continued":
            assert str(frame["stable"].dtype) == "boolean"
assert not bad, bad
response = found["response"]
assert str(response["response"]["response_type"].dtype) == "string"
assert response["points"]["point"].max() >= 0
# a result its session was edited since is refused, unless asked for as it is
session = isola_results.Path(sys.argv[2]).with_suffix(".toml")
text = session.read_text()
session.write_text(text.replace('name = "response"', 'name = "response"\nmodel = { adr = 0.7 }', 1))
try:
    isola_results.load(sys.argv[2], "response")
    raise SystemExit("a stale result loaded")
except isola_results.StaleResult as e:
    assert "'response' is stale for its session" in str(e), e
isola_results.load(sys.argv[2], "response", current=False)
isola_results.load(sys.argv[2], "orbit")
session.write_text(text)
print(len(found), "analyses", columns, "columns")
"#;
    let out = Command::new(&python)
        .args(["-c", script])
        .arg(&reader)
        .arg(results)
        .env("ISOLA", env!("CARGO_BIN_EXE_isola"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("pandas: {}", String::from_utf8_lossy(&out.stdout).trim());
}

/// A chirp sweep without a scalogram offers one at its defaults; setting one of its values
/// (as the workbench's Parameters pane does) writes the whole table, which then runs.
#[test]
fn setting_a_scalogram_value_writes_the_scalogram() {
    let text = "schema = 1\n[[analysis]]\nname = \"c\"\nkind = \"chirp_sweep\"\n[analysis.settings]\nomega_start = 3.0\nomega_end = 3.5\nspan = 200.0\n";
    let mut session = Session::parse(Path::new("t.toml"), text).unwrap();
    assert!(!session.settings_table(0).contains_key("scalogram"));
    let offered = session.settings_offered(0);
    assert_eq!(offered["scalogram"]["columns"].as_integer(), Some(600));
    session
        .set_setting(0, &["scalogram", "columns"], toml::Value::Integer(30))
        .unwrap();
    let Settings::ChirpSweep(spec) = &session.analyses[0].settings else {
        panic!("a chirp sweep")
    };
    let expected = ScalogramSpec {
        columns: 30,
        ..ScalogramSpec::default()
    };
    assert_eq!(spec.scalogram.as_ref(), Some(&expected));
    assert!(
        session.to_text().contains("scalogram = { columns = 30"),
        "{}",
        session.to_text()
    );
    // a value out of range is refused, and the session stays as it was
    let before = session.to_text();
    let e = session
        .set_setting(
            0,
            &["scalogram", "frequencies", "max"],
            toml::Value::Float(100.0),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("scalogram.frequencies.max"), "{e}");
    assert_eq!(session.to_text(), before);
}

/// The first analysis of the session `text`, written to `path` and run; its error as the
/// user reads it.
fn run_first_analysis(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).unwrap();
    let s = Session::load(path).unwrap();
    run_analysis(&s, &s.analyses[0], Shard::ALL, &Progress::new(0))
        .map(|_| ())
        .map_err(|e| format!("{e:#}"))
}

/// A NaN that decides a kink or a collision stops the run with an error naming the value,
/// on one trajectory (its compiled steps) and in a basin's lanes alike; it never picks a
/// branch. `&&` decides as it reads: `x < 2 && ln(2 - x) > 0` is false past x = 2 without
/// its second half, in an `if` and in a collision.
#[test]
fn a_nan_that_decides_a_kink_or_a_collision_stops_the_run() {
    // x'' + 0.1x' + x = cos t from rest: x passes 2 near τ = 8 (the resonance's amplitude
    // grows to 10), where sqrt(2 - x) and ln(2 - x) have no value
    let model = |a: &str, collision: &str, kind: &str| {
        format!(
            "schema = 1\n[model]\nstates = [\"x\", \"v\"]\nfrequency = \"omega\"\namplitude = \"x\"\ncollision = [{collision}]\n[model.parameters]\nomega = 1.0\n[model.let]\na = \"{a}\"\n[model.derivatives]\nx = \"v\"\nv = \"-x - 0.1*v + cos(omega*t) + 1e-9*a\"\n\n[[analysis]]\nname = \"run\"\nkind = \"{kind}\"\n{}",
            if kind == "basin" {
                "[analysis.settings]\ndx = { min = -0.1, max = 0.1, points = 3 }\nv = { min = -0.1, max = 0.1, points = 5 }\n"
            } else {
                ""
            }
        )
    };
    let dir = scratch("nan-kinks");
    let run = |text: String| run_first_analysis(&dir.path().join("nan.toml"), &text);
    for kind in ["time_history", "basin"] {
        for a in [
            "max(sqrt(2 - x), 0)",
            "min(1, sqrt(2 - x))",
            "abs(sqrt(2 - x))",
            "if(ln(2 - x) > -100, 1, 0)",
            "max(sqrt(2 - x), 0.5)",
            "if(sqrt(2 - x) > 1, 1, 0)",
        ] {
            // named where a step ends in it, else where the step it went wrong in heads
            let e = run(model(a, "", kind)).expect_err(a);
            assert!(
                e.contains("not finite at τ = ") && e.contains("model.let.a = NaN"),
                "{kind} {a}: {e}"
            );
            // a basin's error names the analysis and the chunk of starts
            assert!(
                kind != "basin"
                    || e.starts_with("run (basin): chunk 0, cells 0–14, (dx -0.1, v -0.1)"),
                "{e}"
            );
        }
        // a branch not taken may have no value, and `&&` needs no second half after a false
        for a in [
            "if(x < 2, sqrt(2 - x), 0)",
            "if(x < 2 && ln(2 - x) > 0, 1, 0)",
        ] {
            run(model(a, "", kind)).unwrap_or_else(|e| panic!("{kind} {a}: {e}"));
        }
        for (collision, stops) in [
            ("\"ln(2 - x) > 5\"", true),
            ("\"x > -100 && ln(2 - x) > 5\"", true),
            ("\"x < -100 || ln(2 - x) > 5\"", true),
            ("\"x < 2 && ln(2 - x) > 5\"", false),
            ("\"x > 2 || ln(2 - x) > 5\"", false),
        ] {
            let result = run(model("0", collision, kind));
            if stops {
                let e = result.expect_err(collision);
                assert!(
                    e.contains("not finite at τ = ")
                        && e.contains("model.collision[0] = `")
                        && e.contains("compares a value that is not a number"),
                    "{kind} {collision}: {e}"
                );
            } else {
                result.unwrap_or_else(|e| panic!("{kind} {collision}: {e}"));
            }
        }
    }
}

#[test]
fn a_slope_without_bound_on_the_orbit_is_named_when_the_tolerance_cannot_be_met() {
    // x'' = sqrt(x) + 0.5 cos t − 0.1 x' from rest: sqrt's slope is infinite at x = 0, where
    // the orbit starts, so refining the steps stops gaining there at tight tolerances
    let model = |tolerance: &str| {
        format!(
            "schema = 1\n[model]\nstates = [\"x\", \"v\"]\nfrequency = \"omega\"\namplitude = \"x\"\n[model.parameters]\nomega = 1.0\n[model.derivatives]\nx = \"v\"\nv = \"sqrt(x) + 0.5*cos(omega*t) - 0.1*v\"\n\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"\n{tolerance}"
        )
    };
    let dir = scratch("unbounded-slope");
    let run = |text: String| run_first_analysis(&dir.path().join("sqrt.toml"), &text);
    let e = run(model("")).expect_err("the default tolerance on sqrt at 0");
    assert!(
        e.contains("cannot meet its tolerance")
            && e.contains("slope is unbounded")
            && e.contains("a larger one will do"),
        "{e}"
    );
    // as it says, a looser tolerance is met
    run(model(
        "[analysis.settings]\ntolerance = { rtol = 1e-6, atol = 1e-8 }\n",
    ))
    .unwrap();
}
