//! Unit tests of `session::edit` (`src/session/edit.rs`).

use isola::session::schema::{KINDS, Session};
use std::path::Path;

const TEXT: &str = "# my study\nschema = 1\n[model]\nadr = 0.6 # the paper's\n\n\
    # the basin of Fig 6A\n[[analysis]]\nname = \"basin\"\nkind = \"basin\"\n\
    model = { omega = 3.6 }\n[analysis.settings]\ndx = { min = -0.8, max = 0.8, points = 21 }\n";

fn session() -> Session {
    Session::parse(Path::new("/tmp/s.toml"), TEXT).unwrap()
}

#[test]
fn add_duplicate_rename_delete() {
    let mut s = session();
    // every kind can be added, with what it needs
    for kind in KINDS {
        let i = s.add_analysis(kind, &format!("new_{kind}")).unwrap();
        assert_eq!(s.analyses[i].settings.kind(), kind);
    }
    assert_eq!(s.analyses.len(), 1 + KINDS.len());
    // a copy keeps model overrides and settings, and sits after its original
    let i = s.duplicate_analysis(0, "basin2").unwrap();
    assert_eq!(i, 1);
    assert_eq!(s.analyses[1].settings, s.analyses[0].settings);
    assert_eq!(s.params(Some(&s.analyses[1])).unwrap().omega(), 3.6);
    s.rename_analysis(1, "basin_b").unwrap();
    assert_eq!(s.analyses[1].name, "basin_b");
    s.delete_analysis(1).unwrap();
    assert!(s.analysis("basin_b").is_none());
    // the rest of the file is as it was written, comments and all
    let text = s.to_text();
    assert!(text.starts_with("# my study\nschema = 1\n[model]\nadr = 0.6 # the paper's\n"));
    assert!(text.contains("# the basin of Fig 6A\n[[analysis]]\nname = \"basin\""));
    let reread = Session::parse(Path::new("/tmp/s.toml"), &text).unwrap();
    assert_eq!(reread.analyses.len(), s.analyses.len());
}

#[test]
fn bad_edits_are_refused_and_change_nothing() {
    let mut s = session();
    let before = s.to_text();
    let error = s.add_analysis("basin", "basin").unwrap_err().to_string();
    assert!(error.contains("'basin' is used twice"), "{error}");
    let error = s.add_analysis("orbit", "o").unwrap_err().to_string();
    assert!(error.contains("unknown kind 'orbit'") && error.contains("time_history"));
    let error = s.rename_analysis(0, "a b").unwrap_err().to_string();
    assert!(error.contains("letters, digits, _ and -"), "{error}");
    assert!(s.duplicate_analysis(5, "x").is_err());
    assert!(s.delete_analysis(5).is_err());
    assert_eq!(s.to_text(), before);
    // the last analysis can go too
    s.delete_analysis(0).unwrap();
    assert!(s.analyses.is_empty());
}

/// A family or a map added to a session that writes its model varies the model's first
/// parameter but its frequency, around its value and within its range (the built-in's ADR
/// is not the model's); a chirp sweeps its frequency from half its value to twice it, within
/// its range (not from 0, the built-in's default, which a written model refuses).
#[test]
fn a_family_or_map_added_to_a_written_model_varies_its_own_parameter() {
    let text = "schema = 1\n[model]\nstates = [\"x\", \"v\"]\nfrequency = \"omega\"\namplitude = \"x\"\n[model.parameters]\nomega = 1.0\nk = { value = 2, min = 1.5, max = 10 }\n[model.derivatives]\nx = \"v\"\nv = \"-k*x - 0.1*v + cos(omega*t)\"\n";
    let mut s = Session::parse(std::path::Path::new("t.toml"), text).unwrap();
    s.add_analysis("family", "f").unwrap();
    s.add_analysis("map", "m").unwrap();
    s.add_analysis("chirp_sweep", "c").unwrap();
    let out = s.to_text();
    assert!(out.contains("omega_start = 0.5\nomega_end = 2.0"), "{out}");
    assert!(
        out.contains("parameter = \"k\"\nvalues = [1.5, 2.0, 3.0]"),
        "{out}"
    );
    assert!(
        out.contains("values = { min = 1.5, max = 3.0, points = 12 }"),
        "{out}"
    );
}
