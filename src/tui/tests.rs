//! The app drawn into a `TestBackend` at 80×24 and 120×40 and driven by key events, as a user
//! would: views snapshotted with insta, edits, runs, cancels, saves and exports checked on disk.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use isola::analysis::orbit::chirp_sweep::ChirpSpec;
use isola::analysis::orbit::scalogram::ScalogramSpec;
use isola::session::results::{ResultStatus, ResultView};
use isola::session::store::ResultPaths;
use isola::session::{Session, Settings};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use super::app::{App, Focus, Overlay};
use super::jobs::JobState;
use super::keymap::Keymap;
use super::line_edit::LineEdit;
use super::theme::{ColorMode, Theme};
use super::ui;

/// A session file in a fresh folder of its own, removed with the returned guard (at the
/// test's end).
fn fixture(test: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::Builder::new()
        .prefix(&format!("isola-tui-{test}-"))
        .tempdir()
        .unwrap();
    let path = dir.path().join("session.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn app(path: &Path, mode: ColorMode) -> App {
    let session = Session::load(path).unwrap();
    let theme = Theme::load("dark", mode, None).unwrap();
    App::new(session, theme, Keymap::default(), 2)
}

fn key(app: &mut App, code: KeyCode) {
    app.handle_key(KeyEvent::new(code, KeyModifiers::NONE));
}

fn keys(app: &mut App, text: &str) {
    for c in text.chars() {
        key(app, KeyCode::Char(c));
    }
}

/// Ticks until no job is active (a minute at most).
fn settle(app: &mut App) {
    let start = Instant::now();
    while app.jobs.any_active() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "jobs did not finish"
        );
        app.tick();
        std::thread::sleep(Duration::from_millis(5));
    }
    app.tick();
    app.sync_results();
}

fn draw(app: &App, w: u16, h: u16) -> String {
    let mut terminal = Terminal::new(TestBackend::new(w, h)).unwrap();
    terminal.draw(|f| ui::draw(f, app)).unwrap();
    terminal.backend().to_string()
}

/// Snapshots with times and rates (which vary run to run) blanked.
macro_rules! snapshot {
    ($name:expr, $value:expr) => {
        insta::with_settings!({filters => vec![
            // a time and the padding after it, whose width varies with it
            (r"\d+(\.\d+)?s\b *", "[time] "),
            (r"[\d.]+ s of computing", "[time] of computing"),
            (r"in \S+config\.toml *", "in [config file] "),
            (r"log: \S+ *", "log: [log file] "),
            // a test's own folder, and the border after it, whose length varies with it
            (r"· \S*isola-tui-[^ ]+ ─+", "· [folder] ──"),
        ]}, {
            insta::assert_snapshot!($name, $value);
        });
    };
}

const RESPONSE: &str = r#"# Fig 4, on a coarse grid
schema = 1
[model]
adr = 0.6
e_a = 0.04

[[analysis]]
name = "response"
kind = "frequency_response"
[analysis.settings]
omega = { min = 3.0, max = 6.0, points = 31 }
dx = { min = -0.6, max = 0.6, points = 5 }
v = { min = -0.6, max = 0.6, points = 5 }

[[analysis]]
name = "basin"
kind = "basin"
model = { omega = 3.7 }
[analysis.settings]
dx = { min = -0.8, max = 0.8, points = 41 }
v = { min = -1.0, max = 1.0, points = 51 }
"#;

#[test]
fn a_frequency_response_runs_and_draws_with_its_isola() {
    let (_dir, path) = fixture("response", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    snapshot!("response_not_run_80x24", draw(&app, 80, 24));
    key(&mut app, KeyCode::Char('r'));
    assert!(app.jobs.any_active());
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    let Some(ResultView::Response(points)) = app.view() else {
        panic!("no response view");
    };
    // the 1:2 isola of Fig 4: found, and hidden at ω 3.7
    let isola: Vec<_> = points
        .iter()
        .filter(|p| p.response_type.starts_with("1:2"))
        .collect();
    assert!(
        isola
            .iter()
            .any(|p| (p.omega - 3.7).abs() < 1e-9 && p.hidden == Some(true))
    );
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("1:2 isola, hidden"), "{screen}");
    snapshot!("response_80x24", screen);
    snapshot!("response_120x40", draw(&app, 120, 40));
    // the cursor reads a point; Enter integrates its orbit
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Right);
    key(&mut app, KeyCode::Enter);
    assert!(app.picked.is_some());
    settle(&mut app);
    let picked = app.picked.as_ref().unwrap();
    assert!(picked.view.is_some(), "the orbit was not integrated");
    snapshot!("response_pick_orbit_80x24", draw(&app, 80, 24));
    // what is on screen is what is exported: the picked orbit's time history
    let orbit = path.with_file_name("orbit.csv");
    command(&mut app, &format!("export {}", orbit.display()));
    let text = std::fs::read_to_string(&orbit).unwrap();
    assert!(text.starts_with(
        "tau,time_s,lambda_stretch,v_per_tau,phi_i,steady,tension_i_nondim,tension_ii_nondim,slack_i,slack_ii\n"
    ));
    assert!(
        text.lines().count() > 100 && text.contains(",true"),
        "{:?}",
        app.message
    );
    key(&mut app, KeyCode::Esc);
    assert!(app.picked.is_none());
    // only the hidden responses, as `isola export --where` selects them
    let hidden = path.with_file_name("hidden.csv");
    command(
        &mut app,
        &format!("export {} --where hidden = true", hidden.display()),
    );
    let mut reader = csv::Reader::from_path(&hidden).unwrap();
    let column = reader.headers().unwrap().iter().position(|h| h == "hidden");
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert!(!rows.is_empty(), "{:?}", app.message);
    assert!(rows.iter().all(|r| &r[column.unwrap()] == "true"));
    assert!(
        app.message
            .as_ref()
            .unwrap()
            .text
            .contains(&format!("{} rows", rows.len()))
    );
    // a condition on a column the result has not is named
    command(
        &mut app,
        &format!("export {} --where colour=red", hidden.display()),
    );
    assert!(
        matches!(app.overlay, Some(Overlay::Confirm { .. })),
        "replacing asks first"
    );
    key(&mut app, KeyCode::Char('y'));
    let m = app.message.as_ref().unwrap();
    assert!(
        m.error && m.text.contains("no column 'colour'"),
        "{}",
        m.text
    );
}

#[test]
fn a_basin_draws_live_and_in_monochrome() {
    let (_dir, path) = fixture("basin", RESPONSE);
    let mut app = app(&path, ColorMode::None);
    key(&mut app, KeyCode::Down);
    assert_eq!(app.selected, 1);
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    let Some(ResultView::Basin(b)) = app.view() else {
        panic!("no basin view");
    };
    assert_eq!(b.labels.len(), 41 * 51);
    assert!(b.labels.iter().all(Option::is_some));
    let shares: f64 = b.attractors.iter().map(|a| a.fraction).sum();
    assert!((shares - 1.0).abs() < 1e-5, "fractions sum to {shares}");
    let screen = draw(&app, 80, 24);
    // the legend wraps rather than cut an entry off: what ▒ means is on screen
    assert!(screen.contains("▒▒ 1:2 A 0.416"), "{screen}");
    snapshot!("basin_mono_80x24", screen);
    // z from the analyses list gives the keys to the zoomed plot (arrows move its cursor,
    // Tab stays), and unzooming gives them back
    assert_eq!(app.focus, Focus::Analyses);
    key(&mut app, KeyCode::Char('z'));
    assert_eq!(app.focus, Focus::Plot);
    let cursor = app.cursor;
    key(&mut app, KeyCode::Right);
    assert_ne!(
        app.cursor, cursor,
        "the arrows move the zoomed plot's cursor"
    );
    key(&mut app, KeyCode::Tab);
    assert_eq!(app.focus, Focus::Plot, "no hidden pane takes the keys");
    key(&mut app, KeyCode::Char('z'));
    assert_eq!((app.zoom, app.focus), (false, Focus::Analyses));
    key(&mut app, KeyCode::Char('z'));
    key(&mut app, KeyCode::Left);
    snapshot!("basin_mono_zoom_120x40", draw(&app, 120, 40));
    // the cell under the cursor integrates to its attractor
    key(&mut app, KeyCode::Enter);
    settle(&mut app);
    let summary = app
        .picked
        .as_ref()
        .and_then(|p| p.summary.clone())
        .expect("the orbit's summary");
    // the plot's title keeps the orbit's type and amplitude whole, its start cut to fit
    app.zoom = false;
    let screen = draw(&app, 80, 24);
    let title = screen.lines().next().unwrap();
    assert!(title.contains(&format!(" · {summary} ")), "{screen}");
    assert!(title.contains("orbit ω") && title.contains('…'), "{screen}");
}

const OTHERS: &str = r#"schema = 1
[model]
adr = 0.6
e_a = 0.04
omega = 3.7

[[analysis]]
name = "force"
kind = "force_curve"
[analysis.settings]
lambda_p = [1.0, 1.02, 1.05]
phi_i = [0.0]

[[analysis]]
name = "orbit"
kind = "time_history"
[analysis.settings]
dx0 = 0.3

[[analysis]]
name = "up"
kind = "chirp_sweep"
[analysis.settings]
omega_start = 3.0
omega_end = 5.0
span = 1500.0

[[analysis]]
name = "down"
kind = "chirp_sweep"
[analysis.settings]
omega_start = 5.0
omega_end = 3.0
span = 1500.0

[[analysis]]
name = "stepped"
kind = "stepped_sweep"
[analysis.settings]
omega = { min = 6.0, max = 3.0, points = 13 }

[[analysis]]
name = "family"
kind = "family"
[analysis.settings]
parameter = "adr"
values = [0.4, 1.0]
[analysis.settings.response]
omega = { min = 3.0, max = 6.0, points = 13 }
dx = { min = -0.6, max = 0.6, points = 4 }
v = { min = -0.6, max = 0.6, points = 4 }
"#;

#[test]
fn every_other_view_draws() {
    let (_dir, path) = fixture("views", OTHERS);
    let mut app = app(&path, ColorMode::Truecolor);
    for i in 0..6 {
        app.selected = i;
        app.run_selected();
    }
    settle(&mut app);
    for (i, name) in ["force", "orbit", "up", "down", "stepped", "family"]
        .iter()
        .enumerate()
    {
        assert_eq!(app.status_of(i), ResultStatus::Complete, "{name}");
    }
    app.focus = Focus::Analyses;
    app.selected = 0;
    key(&mut app, KeyCode::Down); // selecting moves the cursor and rows
    key(&mut app, KeyCode::Up);
    snapshot!("force_80x24", draw(&app, 80, 24));
    key(&mut app, KeyCode::Down);
    snapshot!("history_80x24", draw(&app, 80, 24));
    snapshot!("history_120x40", draw(&app, 120, 40));
    key(&mut app, KeyCode::Down);
    let screen = draw(&app, 80, 24);
    assert!(
        screen.contains("━→ up") && screen.contains("━← down"),
        "{screen}"
    );
    snapshot!("sweeps_80x24", screen);
    key(&mut app, KeyCode::Char('w'));
    settle(&mut app);
    let Some(ResultView::Chirp(c)) = app.view() else {
        panic!("no chirp shown")
    };
    assert!(app.scalogram("up", c).is_some());
    // never shown for another response (a re-run of the sweep) or other settings
    let mut rerun = c.clone();
    rerun.lambda[10] += 1e-12;
    assert!(app.scalogram("up", &rerun).is_none());
    let up = app
        .session
        .analyses
        .iter()
        .position(|e| e.name == "up")
        .unwrap();
    let Settings::ChirpSweep(spec) = &app.session.analyses[up].settings else {
        panic!("up is a chirp sweep")
    };
    let mut edited = app.session.clone();
    edited.analyses[up].settings = Settings::ChirpSweep(ChirpSpec {
        scalogram: Some(ScalogramSpec {
            columns: 99,
            ..ScalogramSpec::default()
        }),
        ..spec.clone()
    });
    let shown = std::mem::replace(&mut app.session, edited);
    let Some(ResultView::Chirp(c)) = app.view() else {
        panic!("no chirp shown")
    };
    assert!(app.scalogram("up", c).is_none());
    app.session = shown;
    snapshot!("scalogram_80x24", draw(&app, 80, 24));
    key(&mut app, KeyCode::Char('w'));
    key(&mut app, KeyCode::Down);
    key(&mut app, KeyCode::Down);
    let Some(ResultView::Stepped(steps)) = app.view() else {
        panic!("no stepped sweep view");
    };
    assert_eq!(steps.len(), 13);
    // each step keeps where its orbit starts: Enter on one opens it
    assert!(
        steps
            .iter()
            .all(|p| p.start.as_ref().is_some_and(|s| s.len() == 2))
    );
    snapshot!("stepped_80x24", draw(&app, 80, 24));
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Enter);
    settle(&mut app);
    let picked = app.picked.as_ref().expect("the step's orbit");
    assert!(picked.history.is_some(), "{:?}", app.message);
    key(&mut app, KeyCode::Esc);
    app.focus = Focus::Analyses;
    key(&mut app, KeyCode::Down);
    let screen = draw(&app, 120, 40);
    assert!(screen.contains("adr: ■ 0.4  ■ 1"), "{screen}");
    snapshot!("family_120x40", screen);
}

const HUNT: &str = r#"# the isola hunted, and continued in ADR
schema = 1
[model]
adr = 0.6
e_a = 0.04

[[analysis]]
name = "hunt"
kind = "hunt"
[analysis.settings.response]
omega = { min = 3.0, max = 6.0, points = 31 }
dx = { min = -0.6, max = 0.6, points = 5 }
v = { min = -0.6, max = 0.6, points = 5 }
[analysis.settings.continuation]
min = 2.0
max = 6.5

[[analysis]]
name = "in_adr"
kind = "continuation"
model = { omega = 4.6 }
[analysis.settings]
dx0 = 0.3
[analysis.settings.continuation]
parameter = "adr"
min = 0.1
max = 1.5

[[analysis]]
name = "map"
kind = "map"
[analysis.settings]
parameter = "adr"
values = { min = 0.55, max = 0.7, points = 4 }
[analysis.settings.response]
omega = { min = 3.0, max = 6.0, points = 16 }
dx = { min = -0.8, max = 0.8, points = 5 }
v = { min = -1.0, max = 1.0, points = 5 }
"#;

/// A hunt draws its continued isola over the brute-force points (folds marked, the verdict
/// in the footer); a continuation in ADR draws alone, and its cursor picks an orbit; a map
/// draws its cells, hidden marks and curves, in colour and without.
#[test]
fn continued_branches_draw_over_the_brute_force() {
    let (_dir, path) = fixture("hunt", HUNT);
    let mut app = app(&path, ColorMode::Truecolor);
    for i in 0..3 {
        app.selected = i;
        app.run_selected();
    }
    settle(&mut app);
    app.focus = Focus::Analyses;
    app.selected = 1;
    key(&mut app, KeyCode::Up);
    let Some(ResultView::Hunt(h)) = app.view() else {
        panic!("no hunt view");
    };
    assert_eq!(h.continued.len(), 1);
    assert_eq!(h.continued[0].verdict, "isola");
    assert_eq!(h.continued[0].bifurcations.len(), 2);
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("1:2 isola  ω 3.5896–5.4439"), "{screen}");
    assert_eq!(
        screen.matches('✕').count(),
        4,
        "two folds and the legend's\n{screen}"
    );
    snapshot!("hunt_80x24", screen);
    key(&mut app, KeyCode::Down);
    let Some(ResultView::Continuation(c)) = app.view() else {
        panic!("no continuation view");
    };
    assert_eq!(c.parameter, "adr");
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("✕ 0.20657"), "{screen}");
    snapshot!("continuation_80x24", screen);
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Right);
    key(&mut app, KeyCode::Enter);
    settle(&mut app);
    assert!(app.picked.as_ref().is_some_and(|p| p.view.is_some()));
    key(&mut app, KeyCode::Esc);
    app.focus = Focus::Analyses;
    key(&mut app, KeyCode::Down);
    let Some(ResultView::Map(m)) = app.view() else {
        panic!("no map view");
    };
    assert_eq!(m.rows.len(), 4);
    assert!(m.rows.iter().all(Option::is_some));
    assert!(!m.curves.is_empty());
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("◇ hidden"), "{screen}");
    snapshot!("map_80x24", screen);
    let mono = {
        let mut app = super::tests::app(&path, ColorMode::None);
        app.selected = 2;
        app.tick();
        app.sync_results();
        draw(&app, 80, 24)
    };
    assert!(mono.contains("▒") || mono.contains("░"), "{mono}");
}

#[test]
fn a_parameter_edit_is_checked_applied_and_saved() {
    let (_dir, path) = fixture("edit", RESPONSE);
    let original = std::fs::read_to_string(&path).unwrap();
    let mut app = app(&path, ColorMode::Truecolor);
    key(&mut app, KeyCode::Tab);
    assert_eq!(app.focus, Focus::Params);
    let adr = app
        .param_rows
        .iter()
        .position(|r| r.label == "ADR")
        .unwrap();
    for _ in 0..adr {
        key(&mut app, KeyCode::Down);
    }
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.editing.as_ref().map(LineEdit::value), Some("0.6"));
    // an invalid value is refused, named with its range, and the edit stays open
    for _ in 0..3 {
        key(&mut app, KeyCode::Backspace);
    }
    keys(&mut app, "-2");
    key(&mut app, KeyCode::Enter);
    let error = app.param_error.clone().expect("an error for ADR -2");
    assert!(error.contains("adr") && error.contains("-2"), "{error}");
    assert!(app.editing.is_some());
    snapshot!("edit_rejected_80x24", draw(&app, 80, 24));
    // not a number at all
    for _ in 0..2 {
        key(&mut app, KeyCode::Backspace);
    }
    keys(&mut app, "abc");
    key(&mut app, KeyCode::Enter);
    assert!(app.param_error.as_deref().unwrap().contains("not a number"));
    // a valid value
    for _ in 0..3 {
        key(&mut app, KeyCode::Backspace);
    }
    keys(&mut app, "0.8");
    key(&mut app, KeyCode::Enter);
    assert!(app.editing.is_none() && app.param_error.is_none());
    assert_eq!(app.session.file.model.adr, Some(0.8));
    assert!(app.modified);
    // the old value is selected: what is typed replaces it (QA: 0.8 then 0.7 gave 0.80.7)
    key(&mut app, KeyCode::Enter);
    keys(&mut app, "0.7");
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.session.file.model.adr, Some(0.7));
    // a move edits it in place; Ctrl-U clears it, and types no u
    key(&mut app, KeyCode::Enter);
    key(&mut app, KeyCode::End);
    keys(&mut app, "5");
    assert_eq!(app.editing.as_ref().map(LineEdit::value), Some("0.75"));
    app.handle_key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL));
    assert_eq!(app.editing.as_ref().map(LineEdit::value), Some(""));
    keys(&mut app, "0.8");
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.session.file.model.adr, Some(0.8));
    // a setting, through its path; a physical unit, written in its physical form
    let points = app
        .param_rows
        .iter()
        .position(|r| r.label == "omega.points")
        .unwrap();
    app.param_row = points;
    app.commit_edit("16");
    assert!(app.param_error.is_none(), "{:?}", app.param_error);
    let omega = app
        .param_rows
        .iter()
        .position(|r| r.label == "ω_e")
        .unwrap();
    app.param_row = omega;
    app.commit_edit("50 Hz");
    assert!(app.param_error.is_none(), "{:?}", app.param_error);
    assert_eq!(app.session.file.model.frequency_hz, Some(50.0));
    // s saves: the edits are in the file, the comment kept
    key(&mut app, KeyCode::Esc);
    key(&mut app, KeyCode::Char('s'));
    assert!(!app.modified);
    let saved = std::fs::read_to_string(&path).unwrap();
    assert_ne!(saved, original);
    assert!(saved.starts_with("# Fig 4, on a coarse grid"), "{saved}");
    let reread = Session::load(&path).unwrap();
    assert_eq!(reread.file.model.adr, Some(0.8));
    assert_eq!(reread.file.model.frequency_hz, Some(50.0));
    assert!(saved.contains("points = 16"), "{saved}");
}

#[test]
fn a_result_exports_to_csv_and_goes_stale_after_an_edit() {
    let (_dir, path) = fixture("export", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    key(&mut app, KeyCode::Char('e'));
    assert!(app.overlay.is_none(), "nothing to export before a run");
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    key(&mut app, KeyCode::Char('e'));
    let Some(Overlay::Input { text, .. }) = &app.overlay else {
        panic!("no export prompt");
    };
    // beside the session, as a figure is
    let stem = path.file_stem().unwrap().to_string_lossy();
    let beside = path.with_file_name(format!("{stem}-response.csv"));
    assert_eq!(text.value(), beside.display().to_string());
    let target = path.with_file_name("exported.csv");
    app.handle_key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL));
    keys(&mut app, &target.display().to_string());
    key(&mut app, KeyCode::Enter);
    let stored = ResultPaths::new(&app.session, "response").csv;
    assert_eq!(
        std::fs::read(&target).unwrap(),
        std::fs::read(&stored).unwrap()
    );
    // exporting over an existing file asks first: n leaves it, y replaces it
    std::fs::write(&target, "mine").unwrap();
    let export_again = |app: &mut App| {
        key(app, KeyCode::Char('e'));
        app.handle_key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL));
        keys(app, &target.display().to_string());
        key(app, KeyCode::Enter);
        assert!(
            matches!(app.overlay, Some(Overlay::Confirm { .. })),
            "no question"
        );
    };
    export_again(&mut app);
    assert!(draw(&app, 80, 24).contains("exists: replace it?"));
    key(&mut app, KeyCode::Char('n'));
    assert_eq!(std::fs::read(&target).unwrap(), b"mine");
    export_again(&mut app);
    key(&mut app, KeyCode::Char('y'));
    assert_eq!(
        std::fs::read(&target).unwrap(),
        std::fs::read(&stored).unwrap()
    );
    // saving keeps the result on view (it used to show "not run" until a restart)
    key(&mut app, KeyCode::Char('s'));
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(app.view().is_some());
    // an export onto the session file is refused, and the session is left as it was
    let session_text = std::fs::read(&path).unwrap();
    app.export(&super::app::ExportRequest {
        path: path.clone(),
        table: None,
        filters: Vec::new(),
    });
    assert_eq!(std::fs::read(&path).unwrap(), session_text);
    // editing the model makes the stored result stale (shown, not silently reused)
    let row = app.param_rows.iter().position(|r| r.label == "c̃").unwrap();
    app.param_row = row;
    // (wide enough for the hint, which gives way in a narrow plot)
    let before = draw(&app, 200, 50);
    assert!(before.contains("Enter: orbit"), "{before}");
    app.commit_edit("0.05");
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Stale);
    let screen = draw(&app, 200, 50);
    assert!(screen.contains("stale"));
    // no orbit is offered from a result of other settings
    assert!(!screen.contains("Enter: orbit"), "{screen}");
}

#[test]
fn the_view_is_written_as_a_figure_by_its_key_and_by_figure_file() {
    let (_dir, path) = fixture("figure", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    key(&mut app, KeyCode::Char('p'));
    let said = app.message.as_ref().map(|m| (m.text.clone(), m.error));
    assert!(
        matches!(&said, Some((text, true)) if text.contains("no result to draw")),
        "{said:?}"
    );
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    key(&mut app, KeyCode::Char('p'));
    let svg = std::fs::read_to_string(path.with_file_name("session-response.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("excitation frequency ωₑ"));
    let png = path.with_file_name("response.png");
    command(&mut app, &format!("figure {}", png.display()));
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let pdf = path.with_file_name("response.pdf");
    command(&mut app, &format!("figure {}", pdf.display()));
    assert!(std::fs::read(&pdf).unwrap().starts_with(b"%PDF-"));
    // a name of no figure format, or a file in the results store: refused, saying why
    command(&mut app, "figure response.eps");
    let said = app.message.as_ref().map(|m| (m.text.clone(), m.error));
    assert!(
        matches!(&said, Some((text, true)) if text.contains("'eps'") && text.contains("svg, png, pdf")),
        "{said:?}"
    );
    let stored = app.session.results_dir().join("response.svg");
    command(&mut app, &format!("figure {}", stored.display()));
    let said = app.message.as_ref().map(|m| (m.text.clone(), m.error));
    assert!(matches!(&said, Some((_, true))), "{said:?}");
    assert!(!stored.exists());
    // once the settings change, the result on view is stale: no figure is drawn of it
    command(&mut app, "set omega.points 21");
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Stale);
    let stale = path.with_file_name("stale.svg");
    command(&mut app, &format!("figure {}", stale.display()));
    let said = app.message.as_ref().map(|m| (m.text.clone(), m.error));
    assert!(
        matches!(&said, Some((text, true)) if text.contains("no current result to draw")),
        "{said:?}"
    );
    assert!(!stale.exists());
}

/// Types `:` and a command line, then Enter.
/// The status line's message, or nothing.
fn said(app: &App) -> String {
    app.message
        .as_ref()
        .map_or(String::new(), |m| m.text.clone())
}

fn command(app: &mut App, line: &str) {
    key(app, KeyCode::Char(':'));
    keys(app, line);
    key(app, KeyCode::Enter);
}

/// Tab completes what is before the cursor and keeps what is after it; where several things
/// fit it lists them under the line; after `open` (and in the path boxes) it completes paths.
#[test]
fn tab_completes_before_the_cursor_lists_choices_and_completes_paths() {
    let (dir, path) = fixture("tab", RESPONSE);
    std::fs::write(dir.path().join("second.toml"), RESPONSE).unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let mut app = app(&path, ColorMode::Truecolor);
    let line_text = |app: &App| match &app.overlay {
        Some(Overlay::Input { text, .. }) => {
            let (before, after) = text.split();
            (before.to_string(), after.to_string())
        }
        _ => panic!("no line being typed"),
    };
    // `:ru stale`, cursor moved back after `ru`: Tab completes `run` and keeps `stale`
    key(&mut app, KeyCode::Char(':'));
    keys(&mut app, "ru stale");
    for _ in 0.." stale".len() {
        key(&mut app, KeyCode::Left);
    }
    key(&mut app, KeyCode::Tab);
    assert_eq!(line_text(&app), ("run".into(), " stale".into()));
    // inside a word, the whole word is completed: `o|pe` + Tab is `open `
    key(&mut app, KeyCode::Esc);
    key(&mut app, KeyCode::Char(':'));
    keys(&mut app, "ope");
    key(&mut app, KeyCode::Home);
    key(&mut app, KeyCode::Right);
    key(&mut app, KeyCode::Tab);
    assert_eq!(line_text(&app), ("open ".into(), String::new()));
    // `:se` fits two commands: both listed under the line until the next key
    key(&mut app, KeyCode::Esc);
    key(&mut app, KeyCode::Char(':'));
    keys(&mut app, "se");
    key(&mut app, KeyCode::Tab);
    assert_eq!(line_text(&app).0, "se");
    assert_eq!(app.tab_choices, ["set", "select"]);
    assert!(draw(&app, 80, 24).contains("Tab:  set  select"));
    key(&mut app, KeyCode::Char('t'));
    assert!(app.tab_choices.is_empty());
    assert!(!draw(&app, 80, 24).contains("Tab:  set"));
    // `:open DIR/s`: the session file and the folder are listed, `DIR/se` completes the file
    key(&mut app, KeyCode::Esc);
    key(&mut app, KeyCode::Char(':'));
    let folder = dir.path().display().to_string();
    keys(&mut app, &format!("open {folder}/s"));
    key(&mut app, KeyCode::Tab);
    assert_eq!(app.tab_choices, ["second.toml", "session.toml", "sub/"]);
    keys(&mut app, "ec");
    key(&mut app, KeyCode::Tab);
    assert_eq!(line_text(&app).0, format!("open {folder}/second.toml "));
    // the save-as box completes its path, with no space after it
    key(&mut app, KeyCode::Esc);
    app.overlay = Some(Overlay::Input {
        purpose: super::app::InputPurpose::SaveAs,
        text: LineEdit::new(format!("{folder}/su")),
    });
    key(&mut app, KeyCode::Tab);
    assert_eq!(line_text(&app).0, format!("{folder}/sub/"));
}

/// A message longer than the status bar is shown whole on up to three lines (the plot gives
/// them up), the unsaved marker after it; it used to be cut at the bar's end.
#[test]
fn a_long_message_takes_more_lines_of_the_status_bar() {
    let (_dir, path) = fixture("long-message", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    app.modified = true;
    let text = format!(
        "not saved: {}/a/folder/with/a/long/name/session.toml: No space left on device (os error 28)",
        "/tmp/isola-tui-long-message-x"
    );
    app.message = Some(super::app::Message {
        text: text.clone(),
        error: true,
    });
    let screen = draw(&app, 80, 24);
    let rows: Vec<&str> = screen.lines().collect();
    let bottom = rows[rows.len() - 3..].join(" ").replace('"', "");
    let shown: String = bottom.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(shown.contains("(os error 28) [+]"), "{screen}");
    assert!(
        shown.contains("not saved: /tmp/isola-tui-long-message-x/a/folder"),
        "{screen}"
    );
}

/// The command line makes and changes analyses: add, set, run, save (the result stays on
/// view), duplicate, rename, delete (asked first), run stale; Tab completes; bad commands say
/// why on the status bar.
#[test]
fn the_command_line_makes_and_changes_analyses() {
    let (_dir, path) = fixture("command", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    let n = app.session.analyses.len();
    // Tab completes the command and the kind
    key(&mut app, KeyCode::Char(':'));
    keys(&mut app, "ad");
    key(&mut app, KeyCode::Tab);
    keys(&mut app, "bas");
    key(&mut app, KeyCode::Tab);
    let Some(Overlay::Input { text, .. }) = &app.overlay else {
        panic!("no command line");
    };
    assert_eq!(text.value(), "add basin ");
    snapshot!("command_line_80x24", draw(&app, 80, 24));
    keys(&mut app, "b2");
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.session.analyses.len(), n + 1);
    assert_eq!(app.session.analyses[app.selected].name, "b2");
    assert!(app.modified);
    command(&mut app, "set adr 1.0");
    command(&mut app, "set dx.points 9");
    command(&mut app, "set v.points 9");
    command(&mut app, "set omega 50 Hz");
    assert!(
        app.message.as_ref().is_some_and(|m| !m.error),
        "{:?}",
        app.message
    );
    // c̃ is typed as `c`; a name that is none says which it may be
    command(&mut app, "set c 0.05");
    assert!(
        app.message.as_ref().is_some_and(|m| !m.error),
        "{:?}",
        app.message
    );
    command(&mut app, "set c_t 0.06");
    let said = app
        .message
        .as_ref()
        .map(|m| m.text.clone())
        .unwrap_or_default();
    assert_eq!(
        said,
        "c_t: not a parameter of this analysis (did you mean c_tilde (c̃)?)"
    );
    let b2 = app.session.analysis("b2").unwrap();
    let p = app.session.params(Some(b2)).unwrap();
    assert!((p.drive_i().adr().unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(p.c_tilde(), 0.05);
    assert_eq!(app.session.file.model.frequency_hz, Some(50.0));
    command(&mut app, "run");
    // the status bar says it runs (it used to say "queued" for the whole run)
    let said = app.message.as_ref().map(|m| m.text.clone());
    assert_eq!(said.as_deref(), Some("b2: running"));
    settle(&mut app);
    assert_eq!(app.status_of(app.selected), ResultStatus::Complete);
    // saving keeps it on view and exportable
    key(&mut app, KeyCode::Char('s'));
    app.sync_results();
    assert_eq!(app.status_of(app.selected), ResultStatus::Complete);
    let csv = path.with_file_name("b2.csv");
    command(&mut app, &format!("export {}", csv.display()));
    assert!(csv.exists(), "{:?}", app.message);
    let reread = Session::load(&path).unwrap();
    assert!(reread.analysis("b2").is_some());
    // a copy, renamed, then deleted (asked first; n keeps it); the copy starts with the
    // result, and takes it along when renamed (the session on disk keeps b2's own)
    command(&mut app, "dup b3");
    assert_eq!(app.session.analyses[app.selected].name, "b3");
    assert!(
        app.message
            .as_ref()
            .unwrap()
            .text
            .contains("with its result")
    );
    app.sync_results();
    assert_eq!(app.status_of(app.selected), ResultStatus::Complete);
    command(&mut app, "rename b4");
    assert_eq!(app.session.analyses[app.selected].name, "b4");
    app.sync_results();
    assert_eq!(app.status_of(app.selected), ResultStatus::Complete);
    let b2 = app.session.analysis_index("b2").unwrap();
    assert_eq!(app.status_of(b2), ResultStatus::Complete);
    let b4 = ResultPaths::new(&app.session, "b4");
    assert_eq!(
        isola::session::store::verified(&b4).unwrap().analysis,
        "b4",
        "the copy is a result of its own, with its own manifest"
    );
    command(&mut app, "delete b4");
    assert!(matches!(app.overlay, Some(Overlay::Confirm { .. })));
    key(&mut app, KeyCode::Char('n'));
    assert!(app.session.analysis("b4").is_some());
    command(&mut app, "delete b4");
    key(&mut app, KeyCode::Char('y'));
    assert!(app.session.analysis("b4").is_none());
    assert_eq!(app.session.analyses.len(), n + 1);
    // run stale runs what has no current result, not b2
    command(&mut app, "run stale");
    let queued: Vec<String> = app
        .jobs
        .entries
        .iter()
        .filter_map(|e| e.analysis.clone())
        .collect();
    assert!(!queued[1..].contains(&"b2".to_string()), "{queued:?}");
    assert!(queued.len() > 1, "{queued:?}");
    app.jobs.cancel_all();
    settle(&mut app);
    // errors, named
    for (line, says) in [
        ("add basin b2", "used twice"),
        ("add orbit o", "unknown kind"),
        ("set lambda 2", "not a parameter"),
        ("set adr -3", "adr"),
        ("fly", "not a command"),
        ("select nowhere", "no analysis nowhere"),
    ] {
        command(&mut app, line);
        let m = app.message.as_ref().unwrap();
        assert!(m.error && m.text.contains(says), "{line}: {}", m.text);
    }
    assert_eq!(app.session.analyses.len(), n + 1);
    // a, the kind picker: each kind with what it computes; Enter asks the name, a free one
    // proposed
    for (i, (kind, _)) in super::command::KIND_ABOUT.iter().enumerate() {
        assert_eq!(*kind, isola::session::schema::KINDS[i]);
    }
    key(&mut app, KeyCode::Char('a'));
    for _ in 0..5 {
        key(&mut app, KeyCode::Down);
    }
    let picker = draw(&app, 80, 24);
    assert!(
        picker.contains("which start goes to which response"),
        "{picker}"
    );
    snapshot!("kind_picker_80x24", picker);
    key(&mut app, KeyCode::Enter);
    let Some(Overlay::Input { text, .. }) = &app.overlay else {
        panic!("no name asked");
    };
    assert_eq!(text.value(), "basin2", "basin is taken");
    key(&mut app, KeyCode::Enter);
    let added = &app.session.analyses[app.selected];
    assert_eq!(
        (added.name.as_str(), added.settings.kind()),
        ("basin2", "basin")
    );
    // help, open and quit as commands
    command(&mut app, "help");
    assert_eq!(app.overlay, Some(Overlay::Help));
    key(&mut app, KeyCode::Esc);
    key(&mut app, KeyCode::Char('s'));
    let other = path.with_file_name("commands-other.toml");
    std::fs::write(&other, OTHERS).unwrap();
    command(&mut app, &format!("open {}", other.display()));
    assert_eq!(app.session.path, other);
    command(&mut app, "quit");
    assert!(app.should_quit);
}

/// Edits are undone and redone (u, Ctrl-R, :undo) back to the session as it was saved;
/// `/` lists only what matches; `f` holds the plot; `:goto` moves the cursor; `:theme`
/// switches the colours; every key's name is a command.
#[test]
fn undo_filter_freeze_goto_and_theme() {
    let (_dir, path) = fixture("undo", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    let saved = app.session.to_text();
    command(&mut app, "set adr 1.0");
    command(&mut app, "add basin b2");
    assert_eq!(app.session.analyses.len(), 3);
    key(&mut app, KeyCode::Char('u'));
    assert_eq!(app.session.analyses.len(), 2);
    assert!(
        app.message
            .as_ref()
            .unwrap()
            .text
            .contains("undid add basin b2")
    );
    assert!(app.modified, "the ADR edit is still there");
    command(&mut app, "undo");
    assert_eq!(
        app.session.to_text(),
        saved,
        "back to the file as saved, byte for byte"
    );
    assert!(!app.modified);
    key(&mut app, KeyCode::Char('u'));
    assert!(
        app.message
            .as_ref()
            .unwrap()
            .text
            .contains("nothing to undo")
    );
    app.handle_key(KeyEvent::new(KeyCode::Char('r'), KeyModifiers::CONTROL));
    let p = app.session.params(Some(&app.session.analyses[0])).unwrap();
    assert!((p.drive_i().adr().unwrap() - 1.0).abs() < 1e-12);
    command(&mut app, "redo");
    assert!(app.session.analysis("b2").is_some());
    assert!(app.modified);
    // an edit after undoing drops the redo
    key(&mut app, KeyCode::Char('u'));
    command(&mut app, "set adr 0.8");
    command(&mut app, "redo");
    assert!(
        app.message
            .as_ref()
            .unwrap()
            .text
            .contains("nothing to redo")
    );
    assert!(app.session.analysis("b2").is_none());

    // the filter, typed on the status bar: only the basin is listed and selected
    key(&mut app, KeyCode::Char('/'));
    keys(&mut app, "bas");
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("/bas▏"), "{screen}");
    assert!(screen.contains("Analyses /bas") && !screen.contains("response frequency"));
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.session.analyses[app.selected].name, "basin");
    assert_eq!(app.visible_analyses(), vec![1]);
    // it filters the parameters too: "points" lists the grid sizes only
    key(&mut app, KeyCode::Char('/'));
    for _ in 0..3 {
        key(&mut app, KeyCode::Backspace);
    }
    keys(&mut app, "points");
    key(&mut app, KeyCode::Enter);
    let rows: Vec<String> = app
        .visible_rows()
        .iter()
        .map(|&i| app.param_rows[i].label.clone())
        .collect();
    assert!(rows.contains(&"dx.points".to_string()) && rows.contains(&"v.points".to_string()));
    assert!(rows.iter().all(|r| r.ends_with("points")), "{rows:?}");
    assert_eq!(
        app.visible_analyses().len(),
        2,
        "no analysis is called points"
    );
    snapshot!("filtered_80x24", draw(&app, 80, 24));
    key(&mut app, KeyCode::Char('/'));
    key(&mut app, KeyCode::Esc);
    assert!(app.filter.is_empty() && app.visible_rows().len() == app.param_rows.len());

    // a result, held on the plot while another run of it writes a new one
    command(&mut app, "select response");
    command(&mut app, "run");
    settle(&mut app);
    key(&mut app, KeyCode::Char('f'));
    let held = app.view().cloned();
    assert!(held.is_some());
    assert!(draw(&app, 80, 24).contains("held (f resumes)"));
    let columns = |app: &App| match app.view() {
        Some(ResultView::Response(points)) => {
            let mut omegas: Vec<u64> = points.iter().map(|p| p.omega.to_bits()).collect();
            omegas.dedup();
            omegas.len()
        }
        _ => 0,
    };
    assert_eq!(columns(&app), 31);
    command(&mut app, "set omega.points 11");
    command(&mut app, "run");
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert_eq!(columns(&app), 31, "the held view stays");
    command(&mut app, "freeze");
    assert_eq!(columns(&app), 11, "and follows the new result when let go");
    command(&mut app, "undo");
    command(&mut app, "run");
    settle(&mut app);

    // goto: the cursor on the response nearest ω_e 3.7, then by frequency
    app.sync_results();
    command(&mut app, "goto 3.7");
    assert_eq!(app.focus, Focus::Plot);
    assert!(draw(&app, 80, 24).contains("ω 3.700"));
    command(&mut app, "goto 60 Hz");
    let hz = app.session.device().omega_from_hz(60.0);
    let screen = draw(&app, 80, 24);
    let nearest = (0..31)
        .map(|i| 3.0 + 0.1 * i as f64)
        .min_by(|a, b| (a - hz).abs().total_cmp(&(b - hz).abs()));
    assert!(
        screen.contains(&format!("ω {:.3}", nearest.unwrap())),
        "{screen}"
    );
    command(&mut app, "goto x");
    assert!(app.message.as_ref().unwrap().error);

    // themes by name, keys by name
    command(&mut app, "theme light");
    assert_eq!(app.theme.name, "light");
    command(&mut app, "theme solarised");
    assert!(
        app.message
            .as_ref()
            .unwrap()
            .text
            .contains("not a built-in theme")
    );
    command(&mut app, "zoom");
    assert!(app.zoom);
    command(&mut app, "zoom");
    assert!(!app.zoom);
}

fn click(app: &mut App, column: u16, row: u16, kind: crossterm::event::MouseEventKind) {
    app.handle_mouse(crossterm::event::MouseEvent {
        kind,
        column,
        row,
        modifiers: KeyModifiers::NONE,
    });
}

/// The mouse, on the layout last drawn: a click selects an analysis or a parameter and
/// focuses its pane; a click on the plot puts the cursor on the nearest point; the wheel
/// moves the selection of the pane under it.
#[test]
fn the_mouse_selects_focuses_and_places_the_cursor() {
    use crossterm::event::{MouseButton, MouseEventKind};
    let left = MouseEventKind::Down(MouseButton::Left);
    let (_dir, path) = fixture("mouse", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    command(&mut app, "run");
    settle(&mut app);
    let screen = draw(&app, 80, 24);
    let row_of = |text: &str| screen.lines().position(|l| l.contains(text)).unwrap() as u16;
    // the basin's row in the analyses pane
    click(&mut app, 3, row_of("basin basin"), left);
    assert_eq!((app.selected, app.focus), (1, Focus::Analyses));
    // the wheel over the analyses moves back up, over the parameters it moves their row
    click(&mut app, 3, 2, MouseEventKind::ScrollUp);
    assert_eq!(app.selected, 0);
    let screen = draw(&app, 80, 24);
    let row_of = |text: &str| screen.lines().position(|l| l.contains(text)).unwrap() as u16;
    click(&mut app, 4, row_of("│J "), left);
    assert_eq!(app.focus, Focus::Params);
    assert_eq!(app.param_rows[app.param_row].label, "J");
    click(&mut app, 4, row_of("│J "), MouseEventKind::ScrollDown);
    assert_eq!(app.param_rows[app.param_row].label, "c̃");
    assert_eq!(app.focus, Focus::Params);
    // the plot: a click at ω_e 3.7, amplitude 0.42 lands on the hidden 1:2 response there
    let frame = *app
        .layout
        .borrow()
        .frames
        .first()
        .expect("a plot was drawn");
    let (x, y) = (
        super::plots::frame::Axis::new("", frame.x.0, frame.x.1),
        super::plots::frame::Axis::new("", frame.y.0, frame.y.1),
    );
    let col = super::plots::frame::col_of(frame.canvas, &x, 3.7);
    let row = super::plots::frame::row_of(frame.canvas, &y, 0.42);
    click(&mut app, col, row, left);
    assert_eq!(app.focus, Focus::Plot);
    let screen = draw(&app, 80, 24);
    assert!(
        screen.contains("ω 3.700") && screen.contains("A 0.4156"),
        "{screen}"
    );
    // over an overlay the mouse does nothing
    key(&mut app, KeyCode::Char('?'));
    click(&mut app, 3, 2, left);
    assert_eq!(app.overlay, Some(Overlay::Help));
}

/// A session that cannot be opened says why in full (the line, the value, the range), in a
/// box any key closes; the open session stays.
#[test]
fn a_malformed_session_says_why_in_full() {
    let (_dir, path) = fixture("malformed", RESPONSE);
    let bad = path.with_file_name("bad.toml");
    std::fs::write(&bad, "schema = 1\n[model]\nadr = -2\n").unwrap();
    let mut app = app(&path, ColorMode::Truecolor);
    app.open(&bad);
    let Some(Overlay::Notice { text, .. }) = &app.overlay else {
        panic!("no notice: {:?}", app.overlay);
    };
    assert!(
        text.contains("line 3") && text.contains("adr") && text.contains("-2"),
        "{text}"
    );
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("bad.toml was not opened"), "{screen}");
    key(&mut app, KeyCode::Char('x'));
    assert!(app.overlay.is_none());
    assert_eq!(app.session.path, path);
}

/// `o` with unsaved edits and `S` over another file ask first; `n` changes nothing.
#[test]
fn opening_over_edits_and_saving_over_a_file_ask_first() {
    let (_dir, path) = fixture("ask", RESPONSE);
    let other = path.with_file_name("other.toml");
    std::fs::write(&other, OTHERS).unwrap();
    let mut app = app(&path, ColorMode::Truecolor);
    app.param_row = app.param_rows.iter().position(|r| r.label == "c̃").unwrap();
    app.commit_edit("0.05");
    assert!(app.modified);
    // o, then Enter on other.toml (the picker lists it first)
    key(&mut app, KeyCode::Char('o'));
    let Some(Overlay::Picker { files, .. }) = &app.overlay else {
        panic!("no picker");
    };
    let at = files.iter().position(|f| *f == other).unwrap();
    if let Some(Overlay::Picker { selected, .. }) = &mut app.overlay {
        *selected = at;
    }
    key(&mut app, KeyCode::Enter);
    let Some(Overlay::Confirm { question, .. }) = &app.overlay else {
        panic!("opened without asking: {:?}", app.overlay);
    };
    assert!(question.contains("unsaved changes"), "{question}");
    snapshot!("confirm_open_80x24", draw(&app, 80, 24));
    key(&mut app, KeyCode::Char('n'));
    assert_eq!(app.session.path, path);
    assert!(app.modified, "the edit is kept");
    // S over other.toml asks; n leaves it as it was
    let save_as = |app: &mut App| {
        key(app, KeyCode::Char('S'));
        let Some(Overlay::Input { text, .. }) = &mut app.overlay else {
            panic!("no save-as prompt");
        };
        *text = LineEdit::new(other.display().to_string());
        key(app, KeyCode::Enter);
    };
    save_as(&mut app);
    assert!(matches!(app.overlay, Some(Overlay::Confirm { .. })));
    key(&mut app, KeyCode::Esc);
    assert_eq!(std::fs::read_to_string(&other).unwrap(), OTHERS);
    save_as(&mut app);
    key(&mut app, KeyCode::Char('y'));
    assert!(!app.modified);
    assert_eq!(
        Session::load(&other).unwrap().file.model.c_tilde,
        Some(0.05)
    );
    // saved as another file, the results go along (they used to show "not run")
    app.open(&path);
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    let third = path.with_file_name("third.toml");
    command(&mut app, &format!("save {}", third.display()));
    assert!(
        app.message.as_ref().unwrap().text.contains("with 1 result"),
        "{:?}",
        app.message
    );
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert_eq!(app.session.path, third);
    assert!(path.with_file_name("third.results/response.csv").exists());
    // with nothing unsaved, o opens at once
    app.open(&path);
    key(&mut app, KeyCode::Char('o'));
    key(&mut app, KeyCode::Enter);
    assert!(app.overlay.is_none());
}

#[test]
fn a_running_job_cancels_and_quitting_asks_first() {
    let (_dir, path) = fixture(
        "cancel",
        &RESPONSE
            .replace("points = 41", "points = 201")
            .replace("points = 51", "points = 251"),
    );
    let mut app = app(&path, ColorMode::Truecolor);
    key(&mut app, KeyCode::Down);
    key(&mut app, KeyCode::Char('r'));
    // the basin's job (its coarse preview is queued first)
    let job = app
        .jobs
        .entries
        .iter()
        .position(|e| e.analysis.is_some())
        .unwrap();
    let start = Instant::now();
    // past two chunks' cells: one at least is done, whichever thread took what
    let two_chunks = 2 * isola::analysis::global::basin::cells_per_chunk(201 * 251);
    while app.jobs.entries[job].progress.get().0 < two_chunks + 64 {
        app.tick();
        std::thread::sleep(Duration::from_millis(5));
        assert!(start.elapsed() < Duration::from_secs(30));
    }
    key(&mut app, KeyCode::Char('q'));
    assert_eq!(app.overlay, Some(Overlay::ConfirmQuit));
    let screen = draw(&app, 80, 24);
    assert!(
        screen.contains("1 job(s) running") && screen.contains("Quit? y / n"),
        "{screen}"
    );
    key(&mut app, KeyCode::Char('n'));
    assert!(app.overlay.is_none() && !app.should_quit);
    key(&mut app, KeyCode::Char('c'));
    let asked = Instant::now();
    settle(&mut app);
    assert!(
        asked.elapsed() < Duration::from_millis(1500),
        "cancel took {:?}",
        asked.elapsed()
    );
    assert_eq!(app.jobs.entries[job].state, JobState::Cancelled);
    // what finished is kept: the reader shows a partial result
    assert!(matches!(app.status_of(1), ResultStatus::Partial { done, .. } if done > 0));
    key(&mut app, KeyCode::Char('q'));
    assert!(app.should_quit, "nothing runs: q quits at once");
}

#[test]
fn ctrl_c_quits_even_from_an_edit() {
    let (_dir, path) = fixture("ctrlc", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    key(&mut app, KeyCode::Tab);
    key(&mut app, KeyCode::Enter);
    assert!(app.editing.is_some());
    app.handle_key(KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL));
    assert!(app.should_quit);
}

#[test]
fn help_small_terminals_and_the_session_picker() {
    let (_dir, path) = fixture("help", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    key(&mut app, KeyCode::Char('?'));
    assert_eq!(app.overlay, Some(Overlay::Help));
    let help = draw(&app, 80, 24);
    // each key beside its command name: the help lists both
    assert!(
        help.contains("r :run        run selected analysis"),
        "{help}"
    );
    snapshot!("help_80x24", help);
    // at 120×40 in two columns, down to the commands
    let wide = draw(&app, 120, 40);
    assert!(
        wide.contains(":goto X [Y]") && wide.contains("C-r :redo"),
        "{wide}"
    );
    snapshot!("help_120x40", wide);
    key(&mut app, KeyCode::Esc);
    assert!(app.overlay.is_none());
    let small = draw(&app, 50, 15);
    assert!(small.contains("at least 60×18"), "{small}");
    snapshot!("too_small_50x15", small);
    // at 60×18 the help is one column, no entry wrapped, and scrolls to its end
    key(&mut app, KeyCode::Char('?'));
    let top = draw(&app, 60, 18);
    assert!(
        top.contains("q :quit       quit (asks: jobs, edits)") && top.contains("scroll"),
        "{top}"
    );
    assert!(!top.contains("theme: dark"), "{top}");
    snapshot!("help_60x18", top);
    for _ in 0..8 {
        key(&mut app, KeyCode::PageDown);
    }
    let bottom = draw(&app, 60, 18);
    assert!(
        bottom.contains("theme: dark") && !bottom.contains("q quit (asks"),
        "{bottom}"
    );
    key(&mut app, KeyCode::Esc);
    // a quit question in a window too small for the panes is still seen
    app.modified = true;
    key(&mut app, KeyCode::Char('q'));
    let small = draw(&app, 50, 15);
    assert!(small.contains("Quit? y / n"), "{small}");
    key(&mut app, KeyCode::Char('n'));
    app.modified = false;
    // o lists the session files beside this one, each with what it is about, and the
    // folders; Enter on a folder looks in it, on a file opens it
    std::fs::write(path.with_file_name("other.toml"), OTHERS).unwrap();
    let more = path.with_file_name("more");
    std::fs::create_dir_all(&more).unwrap();
    std::fs::write(more.join("third.toml"), format!("# A third one\n{OTHERS}")).unwrap();
    key(&mut app, KeyCode::Char('o'));
    let Some(Overlay::Picker { files, .. }) = &app.overlay else {
        panic!("no picker");
    };
    let sessions = files.iter().filter(|f| f.is_file()).count();
    assert_eq!(sessions, 2, "{files:?}");
    assert!(files.iter().any(|f| f.ends_with("more")), "{files:?}");
    assert!(
        !files.iter().any(|f| f.ends_with("session.results")),
        "{files:?}"
    );
    let picker = draw(&app, 80, 24);
    assert!(picker.contains("Fig 4, on a coarse grid"), "{picker}");
    snapshot!("picker_80x24", picker);
    let at = files.iter().position(|f| f.ends_with("more")).unwrap();
    if let Some(Overlay::Picker { selected, .. }) = &mut app.overlay {
        *selected = at;
    }
    key(&mut app, KeyCode::Enter);
    let Some(Overlay::Picker { files, .. }) = &app.overlay else {
        panic!("no picker in the folder");
    };
    assert!(files.iter().any(|f| f.ends_with("third.toml")), "{files:?}");
    assert!(draw(&app, 80, 24).contains("A third one"));
    // .. goes back up
    if let Some(Overlay::Picker { selected, .. }) = &mut app.overlay {
        *selected = 0;
    }
    key(&mut app, KeyCode::Enter);
    let Some(Overlay::Picker { files, .. }) = &app.overlay else {
        panic!("no picker after ..");
    };
    let at = files
        .iter()
        .position(|f| f.ends_with("other.toml"))
        .unwrap();
    if let Some(Overlay::Picker { selected, .. }) = &mut app.overlay {
        *selected = at;
    }
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.session.path.file_name().unwrap(), "other.toml");
    assert_eq!(app.session.analyses.len(), 6);
}

#[test]
fn a_headless_run_is_watched_live() {
    let (_dir, path) = fixture("watch", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Missing);
    // another process (here: another thread, through the same library call) runs it
    let session = Session::load(&path).unwrap();
    let progress = isola::analysis::Progress::new(0);
    isola::session::run::run_analysis(
        &session,
        &session.analyses[0],
        isola::session::run::Shard { index: 0, count: 2 },
        &progress,
    )
    .unwrap();
    std::thread::sleep(Duration::from_millis(250));
    app.tick();
    app.sync_results();
    let ResultStatus::Partial { done, total } = app.status_of(0) else {
        panic!(
            "half the chunks should show as partial: {:?}",
            app.status_of(0)
        );
    };
    assert_eq!((done, total), (16, 31));
    let Some(ResultView::Response(points)) = app.view() else {
        panic!("no partial view");
    };
    assert!(!points.is_empty());
    // the plot title says how far the work is, and that nothing computes it now
    let screen = draw(&app, 120, 40);
    assert!(
        screen.contains("16/31 chunks · nothing computing"),
        "{screen}"
    );
    // a run on another host claims chunk 1 (its claim is a lock this process holds here)
    use isola::session::store::lock::{Lock, Mode};
    let work = isola::session::store::ResultPaths::new(&session, &session.analyses[0].name)
        .work_dir(&session.fingerprint(&session.analyses[0]));
    let mut claim = Lock::try_acquire(&work.join("000001.claim"), Mode::Exclusive)
        .unwrap()
        .unwrap();
    claim.describe("node9 pid 4242").unwrap();
    // a claim changes no chunk file: it is seen at the next glance
    std::thread::sleep(super::watcher::GLANCE_EVERY + Duration::from_millis(250));
    app.tick();
    app.sync_results();
    let screen = draw(&app, 120, 40);
    assert!(
        screen.contains("16/31 chunks · computing on node9 (1)"),
        "{screen}"
    );
    drop(claim);
    // the user moves the plot cursor on the live view
    app.focus = Focus::Plot;
    for _ in 0..3 {
        key(&mut app, KeyCode::Right);
    }
    let cursor = app.cursor;
    isola::session::run::run_analysis(
        &session,
        &session.analyses[0],
        isola::session::run::Shard { index: 1, count: 2 },
        &progress,
    )
    .unwrap();
    std::thread::sleep(Duration::from_millis(250));
    app.tick();
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    // the final view does not throw the cursor back to its default point
    assert_eq!(app.cursor, cursor);
}

/// Ticks (the app polls the results folder every 200 ms) until analysis `i`'s status is
/// `wanted` (5 s at most).
fn watch_until(app: &mut App, i: usize, wanted: impl Fn(ResultStatus) -> bool) {
    let start = Instant::now();
    while !wanted(app.status_of(i)) {
        assert!(
            start.elapsed() < Duration::from_secs(5),
            "analysis {i} stayed {:?}",
            app.status_of(i)
        );
        std::thread::sleep(Duration::from_millis(50));
        app.tick();
        app.sync_results();
    }
}

/// Undo and redo bring back the result of the settings they restore, kept when the other
/// settings' result replaced it: complete at once, byte for byte, with no preview and nothing
/// computed; an edit back to earlier settings, or opening the session again, does the same.
#[test]
fn undo_and_redo_bring_back_the_results_of_their_settings() {
    let (_dir, path) = fixture("kept", RESPONSE);
    let mut app = app(&path, ColorMode::None);
    let csv = ResultPaths::new(&app.session, "response").csv;
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    let first = std::fs::read(&csv).unwrap();
    command(&mut app, "set adr 1.0");
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    let second = std::fs::read(&csv).unwrap();
    assert!(first != second);
    let jobs = app.jobs.entries.len();
    key(&mut app, KeyCode::Char('u'));
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(said(&app).contains("response: its result for these settings brought back"));
    assert!(std::fs::read(&csv).unwrap() == first);
    assert_eq!(app.jobs.entries.len(), jobs + 1, "one job, no preview");
    app.handle_key(KeyEvent::new(KeyCode::Char('r'), KeyModifiers::CONTROL));
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(said(&app).contains("brought back"), "{}", said(&app));
    assert!(std::fs::read(&csv).unwrap() == second);
    command(&mut app, "set adr 0.6");
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(std::fs::read(&csv).unwrap() == first);
    // settings never computed: nothing is run until asked
    command(&mut app, "set adr 0.8");
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Stale);
    // the session opened again: the result of its settings on disk comes back
    command(&mut app, "set adr 1.0");
    settle(&mut app);
    assert!(std::fs::read(&csv).unwrap() == second);
    drop(app);
    let mut reopened = self::app(&path, ColorMode::None);
    settle(&mut reopened);
    assert_eq!(reopened.status_of(0), ResultStatus::Complete);
    assert!(std::fs::read(&csv).unwrap() == first);
    // a kept result damaged meanwhile is said, and nothing is computed in its place
    let paths = ResultPaths::new(&reopened.session, "response");
    let kept = std::fs::read_dir(paths.earlier_dir()).unwrap();
    for folder in kept.flatten() {
        std::fs::write(folder.path().join("response.csv"), "damaged").unwrap();
    }
    command(&mut reopened, "set adr 1.0");
    settle(&mut reopened);
    assert!(
        said(&reopened).contains("failed its checks and was removed: r computes it"),
        "{}",
        said(&reopened)
    );
    assert_eq!(reopened.status_of(0), ResultStatus::Stale);
    assert!(std::fs::read(&csv).unwrap() == first);
}

/// A renamed analysis, and a session saved as another file, keep the results of earlier
/// settings: an edit back to them brings the result back under the new name, computing
/// nothing. (Before, only the current result went with them.)
#[test]
fn a_renamed_analysis_keeps_the_results_of_its_earlier_settings() {
    let (dir, path) = fixture("kept-rename", RESPONSE);
    let mut app = app(&path, ColorMode::None);
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    let first = std::fs::read(ResultPaths::new(&app.session, "response").csv).unwrap();
    command(&mut app, "set adr 1.0");
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    let second = std::fs::read(ResultPaths::new(&app.session, "response").csv).unwrap();
    command(&mut app, "rename renamed");
    assert!(
        said(&app).contains("with its result and 1 result of earlier settings"),
        "{}",
        said(&app)
    );
    let renamed = ResultPaths::new(&app.session, "renamed");
    assert_eq!(std::fs::read(&renamed.csv).unwrap(), second);
    let jobs = app.jobs.entries.len();
    command(&mut app, "set adr 0.6");
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(said(&app).contains("brought back"), "{}", said(&app));
    assert_eq!(std::fs::read(&renamed.csv).unwrap(), first);
    assert_eq!(
        app.jobs.entries.len(),
        jobs + 1,
        "one job, computing nothing"
    );
    // saved as another file: its results folder has both
    let other = dir.path().join("other.toml");
    command(&mut app, &format!("w {}", other.display()));
    settle(&mut app);
    assert!(
        said(&app).contains("with 1 result and 1 result of earlier settings"),
        "{}",
        said(&app)
    );
    command(&mut app, "set adr 1.0");
    settle(&mut app);
    let moved = ResultPaths::new(&app.session, "renamed");
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert_eq!(std::fs::read(&moved.csv).unwrap(), second);
}

/// After an edit, the run of the new settings is drawn over the previous settings' complete
/// result (muted) until it completes; the previous result stays on disk until then, so a
/// cancelled run loses nothing.
#[test]
fn a_rerun_keeps_the_previous_result_beside_the_new_one() {
    let (_dir, path) = fixture("previous", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    let whole = isola::session::run::Shard { index: 0, count: 1 };
    let progress = isola::analysis::Progress::new(0);
    let run = |session: &Session, i: usize, shard| {
        isola::session::run::run_analysis(session, &session.analyses[i], shard, &progress).unwrap();
    };
    run(&app.session, 0, whole);
    run(&app.session, 1, whole);
    let old_fingerprint = app.session.fingerprint(&app.session.analyses[0]);
    command(&mut app, "set adr 1.0");
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Stale);
    // half the chunks of the new settings, as a cancelled run leaves them
    let half = isola::session::run::Shard { index: 0, count: 2 };
    run(&app.session, 0, half);
    watch_until(&mut app, 0, |s| matches!(s, ResultStatus::Partial { .. }));
    let paths = ResultPaths::new(&app.session, "response");
    assert_eq!(
        isola::session::store::verified(&paths).unwrap().fingerprint,
        old_fingerprint,
        "the previous complete result is still on disk"
    );
    let Some(ResultView::Response(previous)) = app.stored[0].previous.as_deref() else {
        panic!("no previous result kept");
    };
    assert!(previous.len() >= 31, "a response per ω at least");
    let screen = draw(&app, 80, 24);
    assert!(
        screen.contains("the previous settings, until done"),
        "{screen}"
    );
    snapshot!("response_over_previous_80x24", screen);
    // the basin: the cells not computed yet show the previous settings' basin, faded
    command(&mut app, "select basin");
    run(&app.session, 1, half);
    watch_until(&mut app, 1, |s| matches!(s, ResultStatus::Partial { .. }));
    let screen = draw(&app, 120, 40);
    assert!(
        screen.contains("faded: the previous settings, until done"),
        "{screen}"
    );
    // once complete, only the new result is drawn
    command(&mut app, "select response");
    run(
        &app.session,
        0,
        isola::session::run::Shard { index: 1, count: 2 },
    );
    watch_until(&mut app, 0, |s| s == ResultStatus::Complete);
    assert!(app.stored[0].previous.is_none());
    assert!(!draw(&app, 80, 24).contains("previous settings"));
    // kept and compared: a copy under other settings, with the original drawn under it
    command(&mut app, "dup stiffer");
    command(&mut app, "override c_tilde 0.06");
    let stiffer = app.session.analysis("stiffer").unwrap();
    assert_eq!(app.session.params(Some(stiffer)).unwrap().c_tilde(), 0.06);
    let response = app.session.analysis("response").unwrap();
    assert_eq!(app.session.params(Some(response)).unwrap().c_tilde(), 0.04);
    app.sync_results();
    assert_eq!(
        app.status_of(0),
        ResultStatus::Complete,
        "the original stays current"
    );
    command(&mut app, "run");
    settle(&mut app);
    command(&mut app, "compare response");
    let screen = draw(&app, 80, 24);
    assert!(screen.contains("⣿ response"), "{screen}");
    command(&mut app, "compare stiffer");
    assert!(app.message.as_ref().unwrap().error, "not with itself");
    command(&mut app, "compare");
    assert!(!draw(&app, 80, 24).contains("⣿ response"));
}

#[test]
fn the_config_file_sets_theme_colours_and_keys() {
    let (_dir, path) = fixture("config", RESPONSE);
    let config = path.with_file_name("config.toml");
    std::fs::write(
        &config,
        "theme = \"light\"\ncolor = \"16\"\n[keys]\nrun = [\"f5\"]\nquit = [\"ctrl-q\"]\n",
    )
    .unwrap();
    let args = super::TuiArgs {
        session: Some(path.clone()),
        config: Some(config.clone()),
        ..super::TuiArgs::default()
    };
    let mut app = super::build_app(&args).unwrap();
    assert_eq!(app.theme.name, "light");
    // 16 colours: a named ANSI colour, never RGB or a 256-colour index
    assert!(!matches!(
        app.theme.type_color("1:2"),
        ratatui::style::Color::Rgb(..) | ratatui::style::Color::Indexed(_)
    ));
    key(&mut app, KeyCode::Char('r'));
    assert!(!app.jobs.any_active(), "r is no longer bound");
    key(&mut app, KeyCode::F(5));
    assert!(app.jobs.any_active(), "F5 runs");
    app.jobs.cancel_all();
    settle(&mut app);
    app.handle_key(KeyEvent::new(KeyCode::Char('q'), KeyModifiers::CONTROL));
    assert!(app.should_quit);
    // a bad config names what is wrong
    std::fs::write(&config, "[keys]\nrun = [\"hyper-r\"]\n").unwrap();
    let e = super::build_app(&args).err().unwrap();
    assert!(format!("{e:#}").contains("hyper-r"), "{e:#}");
    std::fs::write(&config, "colour = \"16\"\n").unwrap();
    let e = super::build_app(&args).err().unwrap();
    assert!(format!("{e:#}").contains("colour"), "{e:#}");
}

/// `r` on a basin draws a coarse picture first (every 4th Δλ and 5th v of this 41 × 51 grid,
/// integrated to full convergence in memory), faded under the cells not done and named so; at
/// its starts it shows the attractors the full result finds there; once the result is complete
/// it is gone.
#[test]
fn a_run_draws_a_coarse_preview_first() {
    const BASIN: &str = "schema = 1\n[model]\nadr = 0.6\ne_a = 0.04\nomega = 3.7\n\
        [[analysis]]\nname = \"basin\"\nkind = \"basin\"\n[analysis.settings]\n\
        dx = { min = -0.8, max = 0.8, points = 41 }\nv = { min = -1.0, max = 1.0, points = 51 }\n";
    let (_dir, path) = fixture("preview", BASIN);
    let mut app = app(&path, ColorMode::Truecolor);
    let started = Instant::now();
    key(&mut app, KeyCode::Char('r'));
    let preview = loop {
        app.tick();
        if let Some((ResultView::Basin(b), label)) = app.underlay()
            && label.contains("coarse preview")
        {
            break b.clone();
        }
        assert!(started.elapsed() < Duration::from_secs(30), "no preview");
        std::thread::sleep(Duration::from_millis(2));
    };
    eprintln!(
        "preview after {:.0} ms",
        started.elapsed().as_secs_f64() * 1e3
    );
    assert_eq!((preview.dx.len(), preview.v.len()), (41, 51));
    assert!(
        preview.labels.iter().all(Option::is_some),
        "a complete picture"
    );
    let screen = draw(&app, 120, 40);
    if app.status_of(0) != ResultStatus::Complete {
        assert!(screen.contains("faded: a coarse preview"), "{screen}");
    }
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(app.underlay().is_none(), "the preview outlived the result");
    assert!(!draw(&app, 120, 40).contains("coarse preview"));
    let Some(ResultView::Basin(full)) = app.view() else {
        panic!("no basin drawn");
    };
    // the starts of the preview: the same attractors
    let attractor = |b: &isola::session::results::BasinView, cell: usize| {
        let a = &b.attractors[b.labels[cell].unwrap()];
        (a.response_type.clone(), a.amplitude)
    };
    let mut compared = 0;
    for ix in (0..41).step_by(4) {
        for iv in (0..51).step_by(5) {
            let cell = ix * 51 + iv;
            let ((t_p, a_p), (t_f, a_f)) = (attractor(&preview, cell), attractor(full, cell));
            assert_eq!(t_p, t_f, "cell ({ix}, {iv})");
            match (a_p, a_f) {
                (Some(p), Some(f)) => assert!((p - f).abs() < 1e-6, "({ix}, {iv}): {p} {f}"),
                (p, f) => assert_eq!(p.is_some(), f.is_some(), "cell ({ix}, {iv})"),
            }
            compared += 1;
        }
    }
    assert_eq!(compared, 121);
    let kinds: std::collections::BTreeSet<_> = preview
        .attractors
        .iter()
        .map(|a| a.response_type.clone())
        .collect();
    assert!(
        kinds.len() >= 2,
        "the preview finds the coexisting responses: {kinds:?}"
    );
}

/// A forced Duffing oscillator coupled to a first-order lag z: three states, a grid over two.
const WRITTEN_LAG: &str = r#"schema = 1
[model]
states = ["x", "v", "z"]
frequency = "omega"
amplitude = "x"
grid = ["x", "v"]
[model.parameters]
omega = { value = 1.2, min = 0.1, max = 5.0 }
[model.derivatives]
x = "v"
v = "-0.1*v - x - x^3 + 0.5*(z - x) + 0.3*cos(omega*t)"
z = "x - z"

[[analysis]]
name = "response"
kind = "frequency_response"
[analysis.settings]
omega = { min = 1.0, max = 1.4, points = 3 }
dx = { min = -0.5, max = 0.5, points = 2 }
v = { min = -0.5, max = 0.5, points = 2 }
"#;

/// A written model's chirp sweep, added with `:add`, runs in the workbench: swept from half
/// the model's frequency to twice it, its envelope drawn under the model's names (no ω, τ or
/// Δλ), and its scalogram computed with `w`.
#[test]
fn a_written_models_chirp_sweep_runs_and_draws() {
    let (_dir, path) = fixture("written-chirp", WRITTEN_LAG);
    let mut app = app(&path, ColorMode::None);
    command(&mut app, "add chirp_sweep sweep");
    assert_eq!(app.session.analyses.len(), 2);
    let Settings::ChirpSweep(spec) = &app.session.analyses[1].settings else {
        panic!("a chirp sweep");
    };
    assert_eq!((spec.omega_start, spec.omega_end), (0.6, 2.4));
    app.selected = 1;
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    assert_eq!(app.status_of(1), ResultStatus::Complete);
    let Some(ResultView::Chirp(view)) = app.view() else {
        panic!("no chirp view");
    };
    assert_eq!(view.lambda.len(), 240_001);
    let screen = draw(&app, 120, 40);
    assert!(
        screen.contains("envelope of x")
            && screen.contains("▸ sweep: omega 0.600")
            && !screen.contains('ω')
            && !screen.contains('Δ'),
        "{screen}"
    );
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Char('w'));
    settle(&mut app);
    let Some(ResultView::Chirp(view)) = app.view() else {
        panic!("no chirp view");
    };
    assert!(app.scalogram("sweep", view).is_some(), "the scalogram");
    let screen = draw(&app, 120, 40);
    assert!(screen.contains("▸ t 0  omega 0.600"), "{screen}");
}

/// On a written model, Enter on a response integrates the orbit from the response's whole
/// stroboscopic state (its lag state too, kept in the result's `start_` columns), at the
/// point's ω, and the orbit is that response; `e` exports it as the model's time history.
#[test]
fn a_written_models_response_opens_its_orbit() {
    use super::orbit::OrbitHistory;
    let (_dir, path) = fixture("written-pick", WRITTEN_LAG);
    let mut app = app(&path, ColorMode::None);
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    let csv = ResultPaths::new(&app.session, "response").csv;
    let header = std::fs::read_to_string(&csv).unwrap();
    assert!(
        header
            .lines()
            .next()
            .unwrap()
            .ends_with(",start_x,start_v,start_z")
    );
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Right);
    let view = app.view().expect("a response view");
    let pick = super::plots::pick(view, app.cursor).expect("a point under the cursor");
    let Some(ResultView::Response(points)) = app.view() else {
        panic!("no response view");
    };
    let point = points
        .iter()
        .find(|p| Some(p.omega) == pick.omega && p.start.as_ref() == start_of(&pick))
        .expect("the picked point")
        .clone();
    let start = point.start.clone().unwrap();
    assert_eq!(start.len(), 3);
    assert!(
        start[2].abs() > 1e-3,
        "the lag state is away from its origin"
    );
    // the readouts name the model's frequency and time, not the built-in's ω and τ
    let screen = draw(&app, 120, 40);
    assert!(
        screen.contains("▸ omega 1.") && !screen.contains('ω'),
        "{screen}"
    );
    key(&mut app, KeyCode::Enter);
    settle(&mut app);
    let screen = draw(&app, 120, 40);
    assert!(
        screen.contains("orbit omega 1.") && screen.contains("▸ t 0.00") && !screen.contains('τ'),
        "{screen}"
    );
    let picked = app.picked.as_ref().expect("an orbit");
    // its steady part summarised as the response's: its period and amplitude (sampled)
    let Some(ResultView::History(view)) = &picked.view else {
        panic!("no orbit drawn");
    };
    let summary = view.summary.expect("a steady summary");
    let k = point.response_type[2..].split(' ').next().unwrap();
    assert_eq!(
        summary
            .period_forcing_periods
            .map(|p| p.to_string())
            .as_deref(),
        Some(k)
    );
    assert!((summary.amplitude - point.amplitude.unwrap()).abs() < 2e-3);
    assert!(screen.contains(&format!("steady 1:{k}  A {:.4}", summary.amplitude)));
    let picked = app.picked.as_ref().expect("an orbit");
    let Some(OrbitHistory::Written(h, grid)) = picked.history.as_deref() else {
        panic!("no written orbit: {:?}", picked.summary);
    };
    assert_eq!(*grid, [0, 1]);
    assert_eq!(
        h.samples[0].state, start,
        "it starts at the whole stroboscopic state"
    );
    let amplitude = h.steady_state.amplitude.unwrap();
    assert!(
        (amplitude - point.amplitude.unwrap()).abs() < 1e-6,
        "{amplitude} against {:?}",
        point.amplitude
    );
    assert!(
        picked
            .label
            .contains(&format!("orbit omega {:.3}", point.omega))
    );
    let orbit = path.with_file_name("orbit.csv");
    command(&mut app, &format!("export {}", orbit.display()));
    let text = std::fs::read_to_string(&orbit).unwrap();
    assert!(
        text.starts_with("tau,x,v,z,amplitude_output,steady,collision\n"),
        "{text:.80}"
    );
}

fn start_of(pick: &super::plots::Pick) -> Option<&Vec<f64>> {
    match &pick.start {
        super::plots::Start::Absolute(x) => Some(x),
        super::plots::Start::Offset(_) => None,
    }
}

/// What the workbench draws, picks and saves is of the settings it shows: a figure is of the
/// stored current result even while the plot is held on an older one; Enter on a stale result
/// integrates nothing; an orbit closes once the settings it was integrated on change; a copy
/// or a rename never replaces another stored result; a save asks before replacing a session
/// file that changed on disk.
#[test]
fn what_is_drawn_picked_and_saved_is_of_the_current_settings() {
    let (_dir, path) = fixture("current", RESPONSE);
    let mut app = app(&path, ColorMode::None);
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    // held on the 31-point result while a 21-point one is computed and stored
    key(&mut app, KeyCode::Char('f'));
    command(&mut app, "set omega.points 21");
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    assert!(app.frozen.is_some());
    let (held, resumed) = (
        path.with_file_name("held.svg"),
        path.with_file_name("resumed.svg"),
    );
    command(&mut app, &format!("figure {}", held.display()));
    key(&mut app, KeyCode::Char('f'));
    assert!(app.frozen.is_none());
    command(&mut app, &format!("figure {}", resumed.display()));
    assert_eq!(
        std::fs::read(&held).unwrap(),
        std::fs::read(&resumed).unwrap(),
        "the held plot's figure is the stored result's"
    );
    // Enter opens an orbit of the current result; an edit closes it
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Enter);
    settle(&mut app);
    assert!(app.picked.as_ref().is_some_and(|p| p.history.is_some()));
    command(&mut app, "set adr 0.7");
    app.tick();
    assert!(app.picked.is_none(), "the orbit of ADR 0.6 is closed");
    // the result is stale now: nothing is picked from it
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Stale);
    app.focus = Focus::Plot;
    key(&mut app, KeyCode::Enter);
    assert!(app.picked.is_none());
    let said = app
        .message
        .as_ref()
        .map(|m| m.text.clone())
        .unwrap_or_default();
    assert!(said.contains("of other settings"), "{said}");
    // a copy carries the result; a rename onto that copy's name would replace it: refused
    command(&mut app, "dup copy");
    let copy = ResultPaths::new(&app.session, "copy").csv;
    let before = std::fs::read(&copy).unwrap();
    command(&mut app, "select response");
    command(&mut app, "rename copy");
    let said = app.message.as_ref().map(|m| (m.text.clone(), m.error));
    assert!(
        matches!(&said, Some((t, true)) if t.contains("copy has a result on disk")),
        "{said:?}"
    );
    assert_eq!(app.session.analyses[app.selected].name, "response");
    assert_eq!(std::fs::read(&copy).unwrap(), before);
    // another editor changed the file: a save asks, and `n` keeps that editor's text
    let theirs = format!("{}# their note\n", std::fs::read_to_string(&path).unwrap());
    std::fs::write(&path, &theirs).unwrap();
    key(&mut app, KeyCode::Char('s'));
    assert!(matches!(app.overlay, Some(Overlay::Confirm { .. })));
    key(&mut app, KeyCode::Char('n'));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), theirs);
    key(&mut app, KeyCode::Char('s'));
    key(&mut app, KeyCode::Char('y'));
    let ours = std::fs::read_to_string(&path).unwrap();
    assert!(
        !ours.contains("their note") && ours.contains("adr = 0.7"),
        "{ours}"
    );
}

/// Enter on a failed job shows its whole error, which the jobs pane and the status bar cut.
#[test]
fn enter_on_a_failed_job_shows_its_whole_error() {
    let failing = "schema = 1\n[model]\nstates = [\"x\", \"v\"]\nfrequency = \"omega\"\namplitude = \"x\"\n[model.parameters]\nomega = 1.0\n[model.let]\na = \"sqrt(x - 10)\"\n[model.derivatives]\nx = \"v\"\nv = \"-a + cos(omega*t)\"\n\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"\n";
    let (_dir, path) = fixture("failed-job", failing);
    let mut app = app(&path, ColorMode::None);
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    app.focus = Focus::Jobs;
    app.job_row = app.jobs.entries.len() - 1;
    key(&mut app, KeyCode::Enter);
    let Some(Overlay::Notice { title, text }) = &app.overlay else {
        panic!("no notice: {:?}", app.message);
    };
    assert_eq!(title, "h failed");
    assert!(
        text.contains("not finite at τ = 0") && text.contains("model.let.a = NaN"),
        "{text}"
    );
}

#[test]
fn an_edit_of_the_session_file_made_outside_is_loaded_or_said() {
    let (_dir, path) = fixture("outside", RESPONSE);
    let mut app = app(&path, ColorMode::Truecolor);
    // no edits here: loaded, and undoable
    std::fs::write(&path, RESPONSE.replace("adr = 0.6", "adr = 0.8\n# tuned")).unwrap();
    app.notice_session_file();
    assert_eq!(app.session.file.model.adr, Some(0.8), "{}", said(&app));
    assert!(
        !app.modified && said(&app).contains("reloaded"),
        "{}",
        said(&app)
    );
    key(&mut app, KeyCode::Char('u'));
    assert_eq!(app.session.file.model.adr, Some(0.6));
    assert!(app.modified, "the text on disk is 0.8's");
    // with edits here: said, nothing replaced, and s asks before replacing the file
    std::fs::write(&path, RESPONSE.replace("adr = 0.6", "adr = 0.9")).unwrap();
    app.notice_session_file();
    assert_eq!(app.session.file.model.adr, Some(0.6));
    assert!(
        said(&app).contains("changed on disk: :reload"),
        "{}",
        said(&app)
    );
    key(&mut app, KeyCode::Char('s'));
    assert!(matches!(app.overlay, Some(Overlay::Confirm { .. })));
    key(&mut app, KeyCode::Char('n'));
    // :reload asks over the edits, then loads
    command(&mut app, "reload");
    assert!(matches!(app.overlay, Some(Overlay::Confirm { .. })));
    key(&mut app, KeyCode::Char('y'));
    assert_eq!(app.session.file.model.adr, Some(0.9));
    assert!(!app.modified);
    // a text that does not load is said, and the session shown stays
    std::fs::write(&path, RESPONSE.replace("adr = 0.6", "adr = [")).unwrap();
    app.notice_session_file();
    assert_eq!(app.session.file.model.adr, Some(0.9));
    assert!(said(&app).contains("does not load"), "{}", said(&app));
    // deleted: said, and what is shown is unsaved work (q asks)
    std::fs::remove_file(&path).unwrap();
    app.notice_session_file();
    assert!(said(&app).contains("deleted on disk"), "{}", said(&app));
    assert!(app.modified);
    key(&mut app, KeyCode::Char('q'));
    assert!(matches!(app.overlay, Some(Overlay::ConfirmQuit)));
    key(&mut app, KeyCode::Char('n'));
    // put back as loaded: the warning goes, nothing is unsaved
    std::fs::write(&path, app.session.to_text()).unwrap();
    app.notice_session_file();
    assert!(app.message.is_none() && !app.modified, "{}", said(&app));
}

#[test]
fn the_jobs_of_a_session_closed_for_another_run_on_under_its_name() {
    let (_dir, path) = fixture("aside", RESPONSE);
    let other = path.with_file_name("other.toml");
    std::fs::write(&other, RESPONSE.replace("adr = 0.6", "adr = 0.7")).unwrap();
    let mut app = app(&path, ColorMode::Truecolor);
    // the response runs, the basin waits for it
    command(&mut app, "run all");
    assert!(app.jobs.any_active());
    app.open(&other);
    assert_eq!(app.session.path, other);
    let active: Vec<String> = app
        .jobs
        .entries
        .iter()
        .filter(|e| e.is_active() && !e.preview)
        .map(|e| e.label.clone())
        .collect();
    assert!(!active.is_empty(), "the jobs were cancelled");
    assert!(
        active.iter().all(|l| l.starts_with("session.toml: ")),
        "{active:?}"
    );
    // the finished ones too (the previews)
    assert!(
        app.jobs
            .entries
            .iter()
            .all(|e| e.label.starts_with("session.toml: ")),
        "{:?}",
        app.jobs
            .entries
            .iter()
            .map(|e| &e.label)
            .collect::<Vec<_>>()
    );
    // this session's response is not taken for the other's, which is running
    key(&mut app, KeyCode::Char('r'));
    assert!(
        !app.message
            .as_ref()
            .unwrap()
            .text
            .contains("already running"),
        "{:?}",
        app.message
    );
    settle(&mut app);
    // none of them said to be of settings edited since (they are another session's)
    let said = app.message.as_ref().unwrap().text.clone();
    assert!(!said.contains("before the edit"), "{said}");
    let done: Vec<String> = app.jobs.entries.iter().map(|e| e.label.clone()).collect();
    assert!(
        done.contains(&"session.toml: basin".to_string()),
        "{done:?}"
    );
    assert!(done.contains(&"response".to_string()), "{done:?}");
    // each stored in its own session's folder: this one's response is current
    assert_eq!(app.status_of(0), ResultStatus::Complete);
    let theirs = Session::load(&path).unwrap();
    assert!(ResultPaths::new(&theirs, "basin").csv.exists());
    assert!(!ResultPaths::new(&app.session, "basin").csv.exists());
}

#[test]
fn a_unit_on_a_written_models_value_is_named() {
    let (_dir, path) = fixture("written-unit", WRITTEN_LAG);
    let mut app = app(&path, ColorMode::None);
    app.focus = Focus::Params;
    app.param_row = 0;
    app.commit_edit("50 Hz");
    let error = app.param_error.clone().expect("refused");
    assert!(
        error.contains("'50 Hz': it takes a plain number, with no unit"),
        "{error}"
    );
    app.commit_edit("fifty");
    assert!(
        app.param_error
            .as_deref()
            .unwrap()
            .contains("is not a number")
    );
}

#[test]
fn a_run_whose_settings_were_edited_meanwhile_says_so_when_done() {
    let (_dir, path) = fixture("edited-run", RESPONSE);
    let mut app = app(&path, ColorMode::None);
    key(&mut app, KeyCode::Char('r'));
    command(&mut app, "set adr 0.7");
    settle(&mut app);
    let said = app.message.as_ref().unwrap().text.clone();
    assert!(
        said.starts_with("response: done for the settings before the edit: stale"),
        "{said}"
    );
    app.sync_results();
    assert_eq!(app.status_of(0), ResultStatus::Stale);
    // run again on these: plainly done
    key(&mut app, KeyCode::Char('r'));
    settle(&mut app);
    let said = app.message.as_ref().unwrap().text.clone();
    assert!(said.starts_with("response: done ("), "{said}");
}

#[test]
fn enter_on_a_value_left_as_it_is_changes_nothing() {
    let (_dir, path) = fixture("untouched", RESPONSE);
    let mut app = app(&path, ColorMode::None);
    command(&mut app, "set adr 0.612345678901");
    app.focus = Focus::Params;
    app.param_row = app
        .param_rows
        .iter()
        .position(|r| r.label == "ADR")
        .unwrap();
    // shown rounded, edited in full
    assert_eq!(app.param_rows[app.param_row].value, "0.612346");
    key(&mut app, KeyCode::Enter);
    assert_eq!(
        app.editing.as_ref().map(LineEdit::value),
        Some("0.612345678901")
    );
    key(&mut app, KeyCode::Enter);
    assert!(app.editing.is_none());
    assert_eq!(app.session.file.model.adr, Some(0.612345678901));
    // one edit to undo, the set; the untouched Enter made none
    key(&mut app, KeyCode::Char('u'));
    assert_eq!(app.session.file.model.adr, Some(0.6));
    assert!(!app.modified);
}

/// A written parameter's words cut short beside its value are shown whole under it while it
/// is selected, and only then.
#[test]
fn a_selected_parameters_cut_words_are_shown_whole_under_it() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/user_model_viscoelastic.toml"),
    )
    .unwrap();
    let (_dir, path) = fixture("whole-words", &text);
    let mut app = app(&path, ColorMode::Truecolor);
    let about = "modulus ratio μ_B/μ of the viscous branch";
    let row = app
        .param_rows
        .iter()
        .position(|r| r.physical == about)
        .expect("a parameter with these words");
    // the words of the left panes (32 cells at 80 columns), row after row
    let whole = |screen: &str| {
        screen
            .lines()
            .map(|row| row.chars().skip(1).take(32).collect::<String>())
            .collect::<Vec<_>>()
            .join(" ")
            .replace('│', " ")
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .contains(about)
    };
    app.focus = Focus::Params;
    app.param_row = (row + 1) % app.param_rows.len();
    let screen = draw(&app, 80, 24);
    assert!(!whole(&screen), "{screen}");
    assert!(screen.contains('…'), "{screen}");
    app.param_row = row;
    let screen = draw(&app, 80, 24);
    assert!(whole(&screen), "{screen}");
}
