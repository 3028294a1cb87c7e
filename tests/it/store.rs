//! The results store under every fault, driven through the real binary: damaged, empty,
//! foreign, over-long and copied chunks; a missing or damaged manifest or result; settings or
//! device changed between runs; two runs of one session at once; four shards at once (also
//! each in its own PID namespace); `kill -9` at random moments. Every run must end with the
//! CSV an uninterrupted run writes, byte for byte, or with a non-zero exit and an error naming
//! the file; never "complete" with a wrong, partial or missing CSV, and no finished chunk lost.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use isola::analysis::SteadyState;
use isola::analysis::global::basin::cells_per_chunk;
use isola::session::Session;
use isola::session::store::ResultPaths;
use isola::session::store::chunk::{self, ChunkId};

/// A basin of 8 chunks (64 × 64 cells) with 1:1 and 1:2 responses and collisions, at twice the
/// paper's damping (c̃ 0.08, ADR 1.0, ω_e 4.0: its 1:2 survives there) and 32 RK4 steps per
/// period, half the default: the store does not care how accurate its chunks are or how long
/// the transients, and these tests run it some sixty times (a run takes 0.37 CPU-s against
/// 0.70 at the Fig 6A point, and 1.04 there at the default resolution).
const BASIN: &str = "schema = 1\n[model]\nadr = 1.0\nomega = 4.0\nc_tilde = 0.08\n\n[[analysis]]\nname = \"basin\"\nkind = \"basin\"\n[analysis.settings]\nresolution = 32\ndx = { min = -0.8, max = 0.8, points = 64 }\nv = { min = -1.0, max = 1.0, points = 64 }\n";
const BASIN_CHUNKS: usize = 8;

/// A longer basin for kills at random moments: [`BASIN`] on 128 × 128 cells, 32 chunks.
fn long_basin() -> String {
    BASIN.replace("points = 64", "points = 128")
}
const LONG_CHUNKS: usize = 32;

/// A frequency response of 12 chunks (one per ω_e), with sweeps and seeding at assembly.
const RESPONSE: &str = "schema = 1\n[model]\nadr = 0.6\n\n[[analysis]]\nname = \"response\"\nkind = \"frequency_response\"\n[analysis.settings]\nomega = { min = 3.4, max = 4.5, points = 12 }\ndx = { min = -0.6, max = 0.6, points = 5 }\nv = { min = -0.8, max = 0.8, points = 5 }\n";

fn isola() -> Command {
    Command::new(env!("CARGO_BIN_EXE_isola"))
}

/// A fresh folder with `s.toml` holding `text`.
fn session_dir(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn spawn_run(session: &Path, extra: &[&str]) -> Child {
    isola()
        .arg("run")
        .arg(session)
        .args(["--threads", "2"])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn run(session: &Path, extra: &[&str]) -> Output {
    spawn_run(session, extra).wait_with_output().unwrap()
}

fn text(out: &Output) -> String {
    format!(
        "exit {:?}\nstdout: {}\nstderr: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

fn run_ok(session: &Path, extra: &[&str]) -> String {
    let out = run(session, extra);
    assert!(out.status.success(), "{}", text(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Chunks this run computed, from its report line for `analysis`.
fn computed(stdout: &str, analysis: &str) -> usize {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(&format!("{analysis}:")))
        .unwrap_or_else(|| panic!("no line for {analysis}: {stdout}"));
    if line.contains("up to date") || line.contains("brought back") {
        return 0;
    }
    let number_before = |marker: &str| -> Option<usize> {
        let head = line.split(marker).next()?;
        head.rsplit(|c: char| !c.is_ascii_digit())
            .find(|s| !s.is_empty())?
            .parse()
            .ok()
    };
    if line.contains("chunks computed now") {
        number_before(" chunks computed now").unwrap()
    } else {
        number_before(" chunks; ").unwrap()
    }
}

/// The files of a complete result, by name.
fn result_files(session: &Path, names: &[&str]) -> Vec<Vec<u8>> {
    let dir = session.with_file_name("s.results");
    names
        .iter()
        .map(|n| std::fs::read(dir.join(n)).unwrap_or_else(|e| panic!("{n}: {e}")))
        .collect()
}

/// What an uninterrupted single run of `text` writes.
fn reference(text: &str, names: &[&str]) -> Vec<Vec<u8>> {
    // one clean run per session text and files for all the tests (they run at once: the
    // lock makes the second wait for the first's run instead of repeating it)
    type Runs = Mutex<HashMap<(String, String), Vec<Vec<u8>>>>;
    static RUNS: OnceLock<Runs> = OnceLock::new();
    let mut runs = RUNS.get_or_init(Runs::default).lock().unwrap();
    runs.entry((text.to_string(), names.join(",")))
        .or_insert_with(|| {
            let (_dir, session) = session_dir(text);
            run_ok(&session, &[]);
            result_files(&session, names)
        })
        .clone()
}

const BASIN_FILES: [&str; 3] = ["basin.csv", "basin.attractors.csv", "basin.points.csv"];

fn work_dir(session: &Path, analysis: &str) -> PathBuf {
    let s = Session::load(session).unwrap();
    let entry = s.analysis(analysis).unwrap();
    ResultPaths::new(&s, analysis).work_dir(&s.fingerprint(entry))
}

fn chunk_files(work: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(work)
        .map(|d| {
            d.flatten()
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|e| e == "json"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Shard 0 of 2 of the basin in `session`: half its chunks computed, none assembled.
fn half_done(session: &Path) {
    let out = run_ok(session, &["--shard", "0/2"]);
    assert_eq!(computed(&out, "basin"), BASIN_CHUNKS / 2, "{out}");
}

/// The fingerprint of the basin, the first analysis of `session`.
fn basin_fingerprint(session: &Path) -> String {
    let s = Session::load(session).unwrap();
    s.fingerprint(&s.analyses[0])
}

fn log(session: &Path) -> String {
    std::fs::read_to_string(session.with_file_name("s.results").join("run.log")).unwrap_or_default()
}

/// After a half-done sharded run, chunks damaged in every way are recomputed, never used; each
/// is named in the log; the good chunks are kept; the CSV is the uninterrupted run's.
#[test]
fn damaged_foreign_copied_and_recut_chunks_are_recomputed() {
    let expected = reference(BASIN, &BASIN_FILES);
    let (_dir, session) = session_dir(BASIN);
    half_done(&session);
    let work = work_dir(&session, "basin");
    let good = |i: usize| work.join(format!("{i:06}.json"));
    let fingerprint = basin_fingerprint(&session);
    let id = |index| ChunkId {
        fingerprint: &fingerprint,
        index,
        chunks: BASIN_CHUNKS,
    };
    let chunk0: Vec<SteadyState> =
        chunk::decode(&std::fs::read(good(0)).unwrap(), &id(0), |_| Ok(()))
            .unwrap()
            .value;
    // chunk 0 truncated; 2 overwritten with the old unchecked format's `[]`; 4 empty;
    // 6 made over-long with a valid header and checksum (twice the cells)
    let bytes0 = std::fs::read(good(0)).unwrap();
    std::fs::write(good(0), &bytes0[..bytes0.len() / 2]).unwrap();
    std::fs::write(good(2), "[]").unwrap();
    std::fs::write(good(4), "").unwrap();
    let doubled: Vec<SteadyState> = chunk0.iter().chain(&chunk0).cloned().collect();
    std::fs::write(good(6), chunk::encode(&id(6), &doubled, 0.0).unwrap()).unwrap();
    // chunk 1 (another shard's) copied from chunk 0's good bytes; chunk 3 a chunk of other
    // settings (a foreign fingerprint, valid in every other way)
    std::fs::write(good(1), &bytes0).unwrap();
    let foreign = ChunkId {
        fingerprint: "0123456789abcdef0123456789abcdef",
        ..id(3)
    };
    std::fs::write(good(3), chunk::encode(&foreign, &chunk0, 0.0).unwrap()).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(
        computed(&out, "basin"),
        BASIN_CHUNKS,
        "all 4 of shard 0 damaged, all 4 of shard 1 missing or bad: {out}"
    );
    assert!(
        result_files(&session, &BASIN_FILES) == expected,
        "CSV differs"
    );
    let log = log(&session);
    for i in 0..=6 {
        if i == 5 {
            continue;
        }
        let name = format!("{i:06}.json");
        assert!(
            log.lines()
                .any(|l| l.contains("chunk rejected") && l.contains(&name)),
            "{name} not named in the log:\n{log}"
        );
    }
    // a run after the result is complete uses it and leaves no work folder behind
    assert!(run_ok(&session, &[]).contains("up to date"));
    assert!(!work.exists(), "work folder kept after completion");
}

/// Half the chunks of settings A, then settings B run to completion, then A again: A's saved
/// chunks were kept beside B's result (only B's own work folder went), so A computes only the
/// half it had not, and gives the uninterrupted run's bytes.
#[test]
fn chunks_of_other_settings_survive_another_result() {
    let expected = reference(BASIN, &BASIN_FILES);
    let (_dir, session) = session_dir(BASIN);
    run_ok(&session, &["--shard", "0/2"]);
    let work_a = work_dir(&session, "basin");
    std::fs::write(&session, BASIN.replace("c_tilde = 0.08", "c_tilde = 0.1")).unwrap();
    let work_b = work_dir(&session, "basin");
    run_ok(&session, &[]);
    assert!(!work_b.exists(), "B's work is in its result");
    assert!(
        work_a.exists(),
        "A's saved chunks were removed with B's work"
    );
    std::fs::write(&session, BASIN).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(computed(&out, "basin"), BASIN_CHUNKS / 2, "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected);
}

/// Settings that come back (an undo, a comparison run again) get their result back without
/// computing: a result replaced by other settings' is kept, verified again and brought back
/// byte for byte, and the one it replaces is kept in turn; a kept result damaged meanwhile, or
/// copied under the fingerprint of other settings, is removed and computed afresh; at most
/// four are kept.
#[test]
fn a_result_of_settings_that_come_back_is_brought_back_verified() {
    let other = BASIN.replace("adr = 1.0", "adr = 1.2");
    let expected = reference(BASIN, &BASIN_FILES);
    let expected_other = reference(&other, &BASIN_FILES);
    let (dir, session) = session_dir(BASIN);
    let kept = |text: &str| {
        let s = Session::parse(&session, text).unwrap();
        ResultPaths::new(&s, "basin").earlier(&s.fingerprint(&s.analyses[0]))
    };
    run_ok(&session, &[]);
    std::fs::write(&session, &other).unwrap();
    run_ok(&session, &[]);
    assert!(kept(BASIN).is_dir(), "the replaced result is kept");
    // back: nothing computed, the first result byte for byte, the other's kept in turn
    std::fs::write(&session, BASIN).unwrap();
    let status = isola().arg("status").arg(&session).output().unwrap();
    let status = String::from_utf8_lossy(&status.stdout).into_owned();
    assert!(
        status.contains("result stale") && status.contains("kept from before"),
        "{status}"
    );
    let out = run_ok(&session, &[]);
    assert!(out.contains("basin: brought back the result kept"), "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected);
    assert!(!kept(BASIN).exists() && kept(&other).is_dir());
    let status = isola().arg("status").arg(&session).output().unwrap();
    let status = String::from_utf8_lossy(&status.stdout).into_owned();
    assert!(status.contains("result complete, verified"), "{status}");
    std::fs::write(&session, &other).unwrap();
    let out = run_ok(&session, &[]);
    assert!(out.contains("basin: brought back"), "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected_other);
    // a kept result changed meanwhile: removed, never used, and computed afresh
    let csv = kept(BASIN).join("basin.csv");
    let mut bytes = std::fs::read(&csv).unwrap();
    let last = bytes.len() - 2;
    bytes[last] = if bytes[last] == b'1' { b'2' } else { b'1' };
    std::fs::write(&csv, bytes).unwrap();
    std::fs::write(&session, BASIN).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(computed(&out, "basin"), BASIN_CHUNKS, "{out}");
    assert!(
        log(&session).contains("kept result failed its checks"),
        "{}",
        log(&session)
    );
    assert!(result_files(&session, &BASIN_FILES) == expected);
    // a kept result copied under the fingerprint of other settings is never theirs
    let third = BASIN.replace("c_tilde = 0.08", "c_tilde = 0.09");
    let foreign = kept(&third);
    std::fs::create_dir_all(&foreign).unwrap();
    for f in std::fs::read_dir(kept(&other)).unwrap().flatten() {
        std::fs::copy(f.path(), foreign.join(f.file_name())).unwrap();
    }
    // a kept result of other numerics is never brought back, and goes at the next keep
    let old_numerics = dir
        .path()
        .join("s.results/basin.earlier/0123456789abcdef0123456789abcdef");
    std::fs::create_dir_all(&old_numerics).unwrap();
    let manifest = std::fs::read_to_string(kept(&other).join("basin.manifest.json")).unwrap();
    let mut manifest: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    manifest["numerics"] = serde_json::json!(0);
    std::fs::write(
        old_numerics.join("basin.manifest.json"),
        manifest.to_string(),
    )
    .unwrap();
    // four more settings, each computed: the last four replaced are kept, no more
    for c in ["0.09", "0.1", "0.11", "0.12"] {
        std::fs::write(
            &session,
            BASIN.replace("c_tilde = 0.08", &format!("c_tilde = {c}")),
        )
        .unwrap();
        let out = run_ok(&session, &[]);
        assert_eq!(computed(&out, "basin"), BASIN_CHUNKS, "c̃ {c}: {out}");
        assert!(
            !old_numerics.exists(),
            "c̃ {c}: of other numerics, still kept"
        );
    }
    assert!(result_files(&session, &BASIN_FILES) != expected_other);
    let folders = std::fs::read_dir(dir.path().join("s.results/basin.earlier"))
        .unwrap()
        .count();
    assert_eq!(folders, isola::session::store::earlier::KEEP_EARLIER);
    assert!(kept(BASIN).is_dir() && !kept(&other).exists());
}

/// A run of the session file started before an edit, ending after a run of the edited file
/// completed: it does not replace the current result with its stale one (it says it did not
/// store it, and ends well: nothing failed), and the current result stays complete; the
/// stale one is kept, and brought back when its settings come back.
#[test]
fn a_run_of_settings_since_edited_never_replaces_the_current_result() {
    let (_dir, session) = session_dir(&BASIN.replace("points = 64", "points = 160"));
    let mut old = isola()
        .arg("run")
        .arg(&session)
        .args(["--threads", "1"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    let edited = BASIN.replace("points = 64", "points = 24");
    std::fs::write(&session, &edited).unwrap();
    run_ok(&session, &[]);
    assert!(
        old.try_wait().unwrap().is_none(),
        "the old run ended before the edited one: nothing tested"
    );
    let current = std::fs::read(session.with_file_name("s.results/basin.csv")).unwrap();
    let old = old.wait_with_output().unwrap();
    assert!(old.status.success(), "{}", text(&old));
    assert!(
        String::from_utf8_lossy(&old.stdout).contains(&format!(
            "not stored ({} chunks computed now)",
            (160 * 160usize).div_ceil(cells_per_chunk(160 * 160))
        )),
        "{}",
        text(&old)
    );
    let status = isola().arg("status").arg(&session).output().unwrap();
    let status = String::from_utf8_lossy(&status.stdout).into_owned();
    assert!(status.contains("result complete, verified"), "{status}");
    assert!(std::fs::read(session.with_file_name("s.results/basin.csv")).unwrap() == current);
    // the old run's work is kept: back to its settings, its result is brought back
    std::fs::write(&session, BASIN.replace("points = 64", "points = 160")).unwrap();
    let out = run_ok(&session, &[]);
    assert!(out.contains("basin: brought back"), "{out}");
    let status = isola().arg("status").arg(&session).output().unwrap();
    let status = String::from_utf8_lossy(&status.stdout).into_owned();
    assert!(status.contains("result complete, verified"), "{status}");
}

/// A chunk whose file is whole (its header and checksum good) but whose payload this build
/// cannot read (another build's, say) passes the checks of the files and fails when the result
/// is assembled: it is moved aside and computed again, and the CSV is the uninterrupted run's.
#[test]
fn a_chunk_this_build_cannot_read_is_computed_again_at_assembly() {
    let expected = reference(BASIN, &BASIN_FILES);
    let (_dir, session) = session_dir(BASIN);
    half_done(&session);
    let fingerprint = basin_fingerprint(&session);
    let id = ChunkId {
        fingerprint: &fingerprint,
        index: 2,
        chunks: BASIN_CHUNKS,
    };
    // as many items as the chunk's cells, but numbers where steady states belong
    let numbers: Vec<u32> = (0..512).collect();
    let file = work_dir(&session, "basin").join("000002.json");
    std::fs::write(&file, chunk::encode(&id, &numbers, 0.0).unwrap()).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(
        computed(&out, "basin"),
        BASIN_CHUNKS / 2 + 1,
        "shard 1's chunks and chunk 2 again: {out}"
    );
    assert!(
        result_files(&session, &BASIN_FILES) == expected,
        "CSV differs"
    );
    let log = log(&session);
    assert!(
        log.lines()
            .any(|l| l.contains("000002.json") && l.contains("unreadable payload")),
        "{log}"
    );
}

/// Chunks of the other shard survive damage to a few of this shard's: nothing finished is
/// lost when one chunk is bad.
#[test]
fn one_bad_chunk_costs_one_chunk() {
    let expected = reference(BASIN, &BASIN_FILES);
    let (_dir, session) = session_dir(BASIN);
    run_ok(&session, &["--shard", "0/2"]);
    let work = work_dir(&session, "basin");
    std::fs::write(work.join("000002.json"), "{\"isola_chunk\":1}\n[]").unwrap();
    let out = run_ok(&session, &["--shard", "1/2"]);
    assert_eq!(computed(&out, "basin"), BASIN_CHUNKS / 2, "{out}");
    assert!(
        out.contains("1 chunks still missing"),
        "the bad chunk 2 is shard 0's: {out}"
    );
    let out = run_ok(&session, &[]);
    assert_eq!(computed(&out, "basin"), 1, "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected);
}

/// A missing, cut or foreign manifest, or a result file changed after completion: the result
/// is not used (export refuses, naming the file), and the next run computes it again.
#[test]
fn a_result_that_fails_its_checks_is_never_used() {
    let expected = reference(BASIN, &BASIN_FILES);
    let (dir, session) = session_dir(BASIN);
    run_ok(&session, &[]);
    let results = dir.path().join("s.results");
    let manifest = results.join("basin.manifest.json");
    let export = |to: &str| {
        isola()
            .arg("export")
            .arg(&session)
            .args(["--analysis", "basin", "--csv"])
            .arg(dir.path().join(to))
            .output()
            .unwrap()
    };
    assert!(export("ok.csv").status.success());
    type Damage<'a> = Box<dyn Fn() + 'a>;
    let damage: [(&str, Damage); 5] = [
        (
            "manifest removed",
            Box::new(|| std::fs::remove_file(&manifest).unwrap()),
        ),
        (
            "manifest cut short",
            Box::new(|| {
                let m = std::fs::read(&manifest).unwrap();
                std::fs::write(&manifest, &m[..m.len() / 2]).unwrap()
            }),
        ),
        (
            "one byte of the CSV changed",
            Box::new(|| {
                let path = results.join("basin.csv");
                let mut csv = std::fs::read(&path).unwrap();
                let at = csv.len() - 3;
                csv[at] = if csv[at] == b'0' { b'1' } else { b'0' };
                std::fs::write(&path, csv).unwrap()
            }),
        ),
        (
            "attractor table removed",
            Box::new(|| std::fs::remove_file(results.join("basin.attractors.csv")).unwrap()),
        ),
        (
            "manifest of another analysis",
            Box::new(|| {
                let m = std::fs::read_to_string(&manifest).unwrap();
                std::fs::write(&manifest, m.replace("\"basin\"", "\"other\"")).unwrap()
            }),
        ),
    ];
    for (what, damage) in damage {
        damage();
        let out = export("refused.csv");
        assert!(!out.status.success(), "{what}: export used it");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("no current result"), "{what}: {err}");
        if what.contains("CSV") {
            assert!(
                err.contains("basin.csv"),
                "{what}: the file is not named: {err}"
            );
        }
        let out = run_ok(&session, &[]);
        assert_eq!(computed(&out, "basin"), BASIN_CHUNKS, "{what}: {out}");
        assert!(result_files(&session, &BASIN_FILES) == expected, "{what}");
        assert!(export("ok.csv").status.success(), "{what}");
    }
}

/// Settings or device changed between runs: a partial result of the old settings is never
/// mixed in, a complete one is kept (as stale) until the new one replaces it.
#[test]
fn changed_settings_or_device_are_never_mixed() {
    let other = BASIN.replace("adr = 1.0", "adr = 1.2");
    let expected = reference(&other, &BASIN_FILES);
    let (dir, session) = session_dir(BASIN);
    run_ok(&session, &["--shard", "0/2"]);
    std::fs::write(&session, &other).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(computed(&out, "basin"), BASIN_CHUNKS, "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected);
    // a complete result of other settings is kept while the new one is under way, and the
    // new one's saved chunks are kept beside it
    std::fs::write(&session, BASIN).unwrap();
    let out = run_ok(&session, &["--shard", "0/2"]);
    assert!(out.contains("4 chunks still missing"), "{out}");
    assert!(
        result_files(&session, &BASIN_FILES) == expected,
        "stale result kept"
    );
    let s = Session::load(&session).unwrap();
    assert!(!isola::session::run::is_current(&s, &s.analyses[0]));
    let out = run_ok(&session, &[]);
    assert_eq!(
        computed(&out, "basin"),
        BASIN_CHUNKS / 2,
        "saved chunks kept: {out}"
    );
    assert!(result_files(&session, &BASIN_FILES) == reference(BASIN, &BASIN_FILES));
    // back to the first settings with the manifest gone and no result kept: still nothing
    // mixed
    std::fs::write(&session, BASIN).unwrap();
    run_ok(&session, &["--shard", "1/2"]);
    std::fs::remove_file(dir.path().join("s.results/basin.manifest.json")).unwrap();
    std::fs::remove_dir_all(dir.path().join("s.results/basin.earlier")).unwrap();
    std::fs::write(&session, &other).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(computed(&out, "basin"), BASIN_CHUNKS, "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected);

    // the device is part of what a result is: a time history's seconds change with the mass
    let history = "schema = 1\n[[analysis]]\nname = \"o\"\nkind = \"time_history\"\n";
    let device = "[device]\nmu = 400e3\nj = 16.0\nl1 = 20e-3\nl2 = 200e-3\nl3 = 0.1e-3\nmass = 80e-3\nepsilon = 2.48e-11\n";
    let with_device = history.replace("schema = 1\n", &format!("schema = 1\n{device}"));
    let expected = reference(&with_device, &["o.csv"]);
    let (_dir, session) = session_dir(history);
    run_ok(&session, &[]);
    let before = result_files(&session, &["o.csv"]);
    std::fs::write(&session, &with_device).unwrap();
    let out = run_ok(&session, &[]);
    assert!(!out.contains("up to date"), "{out}");
    let after = result_files(&session, &["o.csv"]);
    assert!(
        after == expected && after != before,
        "time_s follows the device"
    );
}

/// The fingerprint holds the numerics version: a build with other numerics never takes this
/// build's chunks or results.
#[test]
fn numerics_version_is_part_of_the_fingerprint() {
    let s = Session::parse(Path::new("s.toml"), BASIN).unwrap();
    let entry = &s.analyses[0];
    let now = isola::analysis::NUMERICS_VERSION;
    assert_eq!(s.fingerprint(entry), s.fingerprint_with(entry, now));
    assert_ne!(
        s.fingerprint_with(entry, now),
        s.fingerprint_with(entry, now + 1)
    );
}

/// A chirp sweep that writes a scalogram has the scalogram's numerics version in its
/// fingerprint; one without, and every other kind, do not depend on it.
#[test]
fn a_scalograms_numerics_version_is_part_of_its_sweeps_fingerprint() {
    let sweep = |scalogram: &str| {
        format!(
            "schema = 1\n[[analysis]]\nname = \"up\"\nkind = \"chirp_sweep\"\n\
             [analysis.settings]\nspan = 100.0\n{scalogram}"
        )
    };
    let now = isola::analysis::NUMERICS_VERSION;
    let with = Session::parse(Path::new("s.toml"), &sweep("scalogram = {}\n")).unwrap();
    let input = with.fingerprint_input(&with.analyses[0], now);
    assert_eq!(
        input["own_numerics"]["scalogram"],
        isola::analysis::orbit::scalogram::NUMERICS_VERSION,
        "{input}"
    );
    let without = Session::parse(Path::new("s.toml"), &sweep("")).unwrap();
    let input = without.fingerprint_input(&without.analyses[0], now);
    assert!(input.get("own_numerics").is_none(), "{input}");
    let basin = Session::parse(Path::new("s.toml"), BASIN).unwrap();
    let input = basin.fingerprint_input(&basin.analyses[0], now);
    assert!(input.get("own_numerics").is_none(), "{input}");
}

/// A written model's own numerics version is in its results' fingerprint (and the built-in
/// model's results do not depend on it).
#[test]
fn a_written_models_numerics_version_is_part_of_its_fingerprint() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/sessions/user_model_paper.toml"
    ))
    .unwrap();
    let s = Session::parse(Path::new("s.toml"), &text).unwrap();
    let input = s.fingerprint_input(&s.analyses[0], isola::analysis::NUMERICS_VERSION);
    assert_eq!(
        input["model"]["numerics"],
        isola::model::equations::NUMERICS_VERSION,
        "{input}"
    );
    let built_in = Session::parse(Path::new("s.toml"), BASIN).unwrap();
    let input = built_in.fingerprint_input(&built_in.analyses[0], 2);
    assert!(input["model"].get("numerics").is_none(), "{input}");
}

/// A written model's frequency response does not read the frequency parameter's value as
/// written (its grid sets it): an edit of that value keeps its fingerprint, and a time
/// history's (which reads it) changes. So does an edit of a value it reads.
#[test]
fn an_edit_of_a_written_frequencys_value_keeps_its_response_current() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/sessions/user_model_paper.toml"
    ))
    .unwrap();
    let history = "\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"\n";
    let before = Session::parse(Path::new("s.toml"), &format!("{text}{history}")).unwrap();
    let edit = |from: &str, to: &str| {
        let edited = text.replacen(from, to, 1);
        assert_ne!(edited, text, "{from}");
        Session::parse(Path::new("s.toml"), &format!("{edited}{history}")).unwrap()
    };
    let print = |s: &Session, name: &str| s.fingerprint(s.analysis(name).unwrap());
    let omega = edit("omega = { value = 1.8,", "omega = { value = 2.5,");
    assert_eq!(print(&before, "response"), print(&omega, "response"));
    assert_ne!(print(&before, "h"), print(&omega, "h"));
    let damping = edit("c = { value = 0.04,", "c = { value = 0.05,");
    assert_ne!(print(&before, "response"), print(&damping, "response"));
}

/// Two runs of one session started together, six times: each chunk is computed once, one run
/// assembles, both end "done" with the uninterrupted run's CSV.
#[test]
fn two_runs_of_one_session_share_the_work() {
    let expected = reference(BASIN, &BASIN_FILES);
    for trial in 0..6 {
        let (_dir, session) = session_dir(BASIN);
        let (a, b) = (spawn_run(&session, &[]), spawn_run(&session, &[]));
        let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
        assert!(a.status.success(), "trial {trial}: {}", text(&a));
        assert!(b.status.success(), "trial {trial}: {}", text(&b));
        let (sa, sb) = (
            String::from_utf8_lossy(&a.stdout),
            String::from_utf8_lossy(&b.stdout),
        );
        let total = computed(&sa, "basin") + computed(&sb, "basin");
        assert_eq!(
            total, BASIN_CHUNKS,
            "trial {trial}: each chunk once\n{sa}\n{sb}"
        );
        let assembled = [&sa, &sb]
            .iter()
            .filter(|s| s.contains("assembled here"))
            .count();
        assert!(
            assembled == 1
                || (assembled == 0 && (sa.contains("up to date") || sb.contains("up to date"))),
            "trial {trial}: one assembler\n{sa}\n{sb}"
        );
        assert!(
            result_files(&session, &BASIN_FILES) == expected,
            "trial {trial}"
        );
        assert!(
            run_ok(&session, &[]).contains("up to date"),
            "trial {trial}"
        );
    }
}

/// Four shards started at the same moment, five times each way: plainly, and each in its own
/// PID namespace (where all four are PID 1). One of them assembles; the CSV is the single
/// run's; every chunk is computed once.
#[test]
fn four_shards_at_once_also_in_separate_pid_namespaces() {
    let expected = reference(RESPONSE, &["response.csv"]);
    let chunks = 12;
    let namespaces = Command::new("unshare")
        .args(["--pid", "--fork", "--kill-child", "true"])
        .status()
        .is_ok_and(|s| s.success());
    if !namespaces {
        eprintln!("unshare --pid --fork refused here: PID-namespace trials skipped");
    }
    let ways: &[bool] = if namespaces { &[false, true] } else { &[false] };
    for &in_namespace in ways {
        for trial in 0..5 {
            let (_dir, session) = session_dir(RESPONSE);
            let children: Vec<Child> = (0..4)
                .map(|i| {
                    let shard = format!("{i}/4");
                    let mut c = if in_namespace {
                        let mut c = Command::new("unshare");
                        c.args(["--pid", "--fork", "--kill-child"])
                            .arg(env!("CARGO_BIN_EXE_isola"));
                        c
                    } else {
                        isola()
                    };
                    c.arg("run")
                        .arg(&session)
                        .args(["--threads", "1", "--shard", &shard])
                        .stdout(Stdio::piped())
                        .stderr(Stdio::piped())
                        .spawn()
                        .unwrap()
                })
                .collect();
            let outs: Vec<Output> = children
                .into_iter()
                .map(|c| c.wait_with_output().unwrap())
                .collect();
            let label = format!("namespace {in_namespace}, trial {trial}");
            let mut total = 0;
            let mut assembled = 0;
            for out in &outs {
                assert!(out.status.success(), "{label}: {}", text(out));
                let s = String::from_utf8_lossy(&out.stdout);
                total += computed(&s, "response");
                assembled += usize::from(s.contains("assembled here"));
            }
            assert_eq!(total, chunks, "{label}: each chunk once");
            assert_eq!(assembled, 1, "{label}: exactly one assembler");
            assert!(
                result_files(&session, &["response.csv"]) == expected,
                "{label}: CSV differs"
            );
            assert!(run_ok(&session, &[]).contains("up to date"), "{label}");
        }
    }
}

/// A small deterministic generator for the kill moments.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `kill -9` at moments spread over a whole run (chunks, assembly, commit): one random
/// moment in each seventh of [0.1, 1.1] of an uninterrupted run's time, so that every stage is
/// hit, then (if the machine's load made fewer than three land mid-way) more in the middle of
/// the run, up to twelve, the run's time taken as at most a kill that came after completion; the next run computes exactly the chunks that were not saved and
/// writes the uninterrupted run's files.
#[test]
fn kill_at_random_moments_then_resume() {
    const SPREAD: usize = 7;
    let (_dir, uninterrupted) = session_dir(&long_basin());
    let started = Instant::now();
    run_ok(&uninterrupted, &[]);
    let full = started.elapsed().as_secs_f64();
    let expected = result_files(&uninterrupted, &BASIN_FILES);
    let mut rng = Lcg(2026);
    let mut outcomes = [0usize; 3]; // before any chunk, mid-way, after completion
    // how long a run takes now (the machine's load changes while this test runs)
    let mut estimate = full;
    for trial in 0..12 {
        if trial >= SPREAD && outcomes[1] >= 3 {
            break;
        }
        let (_dir, session) = session_dir(&long_basin());
        let mut child = spawn_run(&session, &[]);
        let at = if trial < SPREAD {
            full * (0.1 + (trial as f64 + rng.next()) / SPREAD as f64)
        } else {
            // a kill that came after completion says a run now takes less than that
            estimate * (0.3 + 0.4 * rng.next())
        };
        std::thread::sleep(Duration::from_secs_f64(at));
        let _ = child.kill();
        let _ = child.wait();
        let work = work_dir(&session, "basin");
        let saved = chunk_files(&work).len();
        let out = run_ok(&session, &[]);
        let label = format!("trial {trial}, killed at {at:.2} s of {full:.2} s, {saved} saved");
        if out.contains("up to date") {
            outcomes[2] += 1;
            estimate = estimate.min(at);
        } else {
            assert_eq!(
                computed(&out, "basin") + saved,
                LONG_CHUNKS,
                "{label}: a finished chunk was lost or one computed twice\n{out}"
            );
            outcomes[usize::from(saved > 0)] += 1;
        }
        assert!(result_files(&session, &BASIN_FILES) == expected, "{label}");
    }
    eprintln!("kills: {outcomes:?} (no chunk yet, mid-way, after completion)");
    assert!(outcomes[1] >= 3, "too few kills mid-way: {outcomes:?}");
}

/// Start a run, edit the session, start a second run: the stored result is one of the two
/// settings, whole and with its own fingerprint; a last run makes it the edited one's.
#[test]
fn editing_the_session_during_a_run_never_mixes_settings() {
    let edited = BASIN.replace("adr = 1.0", "adr = 1.2");
    let expected_first = reference(BASIN, &BASIN_FILES);
    let expected_edited = reference(&edited, &BASIN_FILES);
    for trial in 0..5 {
        let (dir, session) = session_dir(BASIN);
        let first = spawn_run(&session, &[]);
        std::thread::sleep(Duration::from_millis(40 * trial));
        // saved as editors (and the workbench) save: whole, by a rename, so that the run
        // starting now reads the old file or the new one, never a truncated one
        let staged = dir.path().join("s.toml.new");
        std::fs::write(&staged, &edited).unwrap();
        std::fs::rename(&staged, &session).unwrap();
        let second = spawn_run(&session, &[]);
        for out in [
            first.wait_with_output().unwrap(),
            second.wait_with_output().unwrap(),
        ] {
            assert!(out.status.success(), "trial {trial}: {}", text(&out));
        }
        let stored = result_files(&session, &BASIN_FILES);
        let manifest =
            std::fs::read_to_string(dir.path().join("s.results/basin.manifest.json")).unwrap();
        let s_first = Session::parse(&session, BASIN).unwrap();
        let s_edited = Session::parse(&session, &edited).unwrap();
        let fp_first = s_first.fingerprint(&s_first.analyses[0]);
        let fp_edited = s_edited.fingerprint(&s_edited.analyses[0]);
        if manifest.contains(&fp_first) {
            assert!(
                stored == expected_first,
                "trial {trial}: first settings, other CSV"
            );
        } else {
            assert!(manifest.contains(&fp_edited), "trial {trial}: {manifest}");
            assert!(
                stored == expected_edited,
                "trial {trial}: edited settings, other CSV"
            );
        }
        run_ok(&session, &[]);
        assert!(
            result_files(&session, &BASIN_FILES) == expected_edited,
            "trial {trial}"
        );
    }
}

/// Temporaries left by killed writers are removed; chunks and results of this build are all
/// that is left beside the result.
#[test]
fn stale_temporaries_are_removed() {
    let (dir, session) = session_dir(BASIN);
    run_ok(&session, &["--shard", "0/2"]);
    let work = work_dir(&session, "basin");
    let results = dir.path().join("s.results");
    std::fs::write(work.join(".000001.json.kIlLeD.tmp"), "half").unwrap();
    std::fs::write(results.join(".basin.csv.kIlLeD.tmp"), "half").unwrap();
    run_ok(&session, &[]);
    let left: Vec<String> = std::fs::read_dir(&results)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    assert!(!work.exists());
}

/// No chunk may hold a non-finite number: saving one fails, naming where it is, and writes
/// nothing.
#[test]
fn a_non_finite_number_never_reaches_a_chunk() {
    let (_dir, session) = session_dir(BASIN);
    let s = Session::load(&session).unwrap();
    let paths = ResultPaths::new(&s, "basin");
    let fingerprint = s.fingerprint(&s.analyses[0]);
    std::fs::create_dir_all(&paths.dir).unwrap();
    let work = isola::session::store::Work::join(&paths, &fingerprint).unwrap();
    let e = work
        .encode_chunk(0, 1, &vec![1.0, f64::NAN], 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("[1] is NaN"), "{e}");
    assert!(chunk_files(&paths.work_dir(&fingerprint)).is_empty());
}

/// `export` and `--csv` never replace what is not a regular file, nor the session or its
/// stored results; a FIFO and a device are written through.
#[test]
fn outputs_never_replace_special_files_the_session_or_results() {
    let (dir, session) = session_dir(BASIN);
    run_ok(&session, &[]);
    let d = dir.path();
    let export = |to: &Path| {
        isola()
            .arg("export")
            .arg(&session)
            .args(["--analysis", "basin", "--csv"])
            .arg(to)
            .output()
            .unwrap()
    };
    let session_text = std::fs::read(&session).unwrap();
    for to in [
        session.clone(),
        d.join("s.results/basin.csv"),
        d.join("s.results/basin.attractors.csv"),
        d.join("s.results/new.csv"),
    ] {
        let out = export(&to);
        assert!(!out.status.success(), "{}", to.display());
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("would overwrite"),
            "{}",
            text(&out)
        );
    }
    assert_eq!(std::fs::read(&session).unwrap(), session_text);
    assert!(isola::session::run::is_current(
        &Session::load(&session).unwrap(),
        &Session::load(&session).unwrap().analyses[0]
    ));
    // a FIFO: written through, still a FIFO
    let fifo = d.join("pipe.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(&fifo).unwrap())
    };
    assert!(export(&fifo).status.success());
    let through = reader.join().unwrap();
    assert!(through.starts_with(b"dx_stretch,"));
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // a character device: written through, still a device
    assert!(export(Path::new("/dev/null")).status.success());
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
    // a link: the file it names is replaced, the link kept
    let real = d.join("real.csv");
    std::fs::write(&real, "old").unwrap();
    let link = d.join("link.csv");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    assert!(export(&link).status.success());
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(std::fs::read(&real).unwrap().starts_with(b"dx_stretch,"));
    // a folder: refused
    assert!(!export(d).status.success());
}

/// A tmpfs mounted for a test, unmounted when dropped; `None` where mounting is not allowed.
struct Mounted(PathBuf);

impl Mounted {
    fn tmpfs(at: &Path, size: &str) -> Option<Mounted> {
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(at)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        ok.then(|| Mounted(at.to_path_buf()))
    }

    fn resize(&self, size: &str) {
        let status = Command::new("mount")
            .args(["-o", &format!("remount,size={size}")])
            .arg(&self.0)
            .status()
            .unwrap();
        assert!(status.success());
    }
}

impl Drop for Mounted {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// A disk that fills up mid-run (another writer takes the space): the run fails naming the
/// file it could not write, leaves no temporary behind and loses no saved chunk; with space
/// again, the next run computes only the rest and writes the single run's CSV. A disk too
/// small from the start is refused before any work.
#[test]
fn a_full_disk_ends_in_an_error_and_loses_nothing() {
    let expected = reference(&long_basin(), &BASIN_FILES);
    let dir = tempfile::tempdir().unwrap();
    let Some(disk) = Mounted::tmpfs(dir.path(), "1m") else {
        eprintln!("mounting a tmpfs is not allowed here: full-disk test skipped");
        return;
    };
    let session = dir.path().join("s.toml");
    std::fs::write(&session, long_basin()).unwrap();
    let out = run(&session, &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("of chunks") && err.contains("free"),
        "refused up front: {}",
        text(&out)
    );
    disk.resize("8m");
    let work = work_dir(&session, "basin");
    let child = spawn_run(&session, &[]);
    let started = Instant::now();
    while chunk_files(&work).is_empty() {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no chunk appeared"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    // another writer fills the disk
    let mut filler = std::fs::File::create(dir.path().join("filler")).unwrap();
    let block = vec![0u8; 64 * 1024];
    use std::io::Write;
    while filler.write_all(&block).is_ok() {}
    drop(filler);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{}", text(&out));
    assert!(
        err.contains("No space left on device") && err.contains(".json"),
        "the error names the chunk file: {err}"
    );
    let saved = chunk_files(&work).len();
    assert!(saved < LONG_CHUNKS, "{saved} chunks saved on a full disk?");
    let temporaries: Vec<_> = std::fs::read_dir(&work)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(temporaries.is_empty(), "{temporaries:?}");
    std::fs::remove_file(dir.path().join("filler")).unwrap();
    let out = run_ok(&session, &[]);
    assert_eq!(computed(&out, "basin") + saved, LONG_CHUNKS, "{out}");
    assert!(result_files(&session, &BASIN_FILES) == expected);
    drop(disk);
}

/// Cluster workers (`--worker`) started together never wait for each other's chunks: each
/// chunk is computed once, and the last to finish assembles.
#[test]
fn workers_share_the_chunks_and_the_last_assembles() {
    let expected = reference(BASIN, &BASIN_FILES);
    for trial in 0..3 {
        let (_dir, session) = session_dir(BASIN);
        let runs: Vec<Child> = (0..3).map(|_| spawn_run(&session, &["--worker"])).collect();
        let outs: Vec<Output> = runs
            .into_iter()
            .map(|c| c.wait_with_output().unwrap())
            .collect();
        let mut total = 0;
        for out in &outs {
            assert!(out.status.success(), "trial {trial}: {}", text(out));
            total += computed(&String::from_utf8_lossy(&out.stdout), "basin");
        }
        assert_eq!(total, BASIN_CHUNKS, "trial {trial}: each chunk once");
        if !run_ok(&session, &[]).contains("up to date") {
            panic!("trial {trial}: no worker assembled");
        }
        assert!(
            result_files(&session, &BASIN_FILES) == expected,
            "trial {trial}"
        );
    }
}

/// `isola status` while work is under way: chunks done, claimed and missing, by host; and
/// `--verify` fails until the result is complete.
#[test]
fn status_shows_the_work_by_host_and_verifies() {
    let (_dir, session) = session_dir(BASIN);
    let status = |verify: bool| {
        let mut c = isola();
        c.arg("status").arg(&session);
        if verify {
            c.arg("--verify");
        }
        c.output().unwrap()
    };
    run_ok(&session, &["--shard", "0/2"]);
    let out = status(false);
    let text_out = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", text(&out));
    assert!(
        text_out.contains("4 of 8 done, 0 claimed, 4 missing"),
        "{text_out}"
    );
    // nothing computes it: no time to go, but how to go on
    assert!(
        !text_out.contains("to go") && text_out.contains("nothing computing it now"),
        "{text_out}"
    );
    let host = isola::session::store::lock::host_name();
    assert!(
        text_out
            .lines()
            .any(|l| l.trim_start().starts_with(&host) && l.contains(" 4 ")),
        "{text_out}"
    );
    assert!(!status(true).status.success());
    run_ok(&session, &[]);
    let out = status(true);
    assert!(out.status.success(), "{}", text(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("complete, verified"));
}

/// `isola slurm` writes a job array and an assembly job that run this isola on the session,
/// quoted so that any path works, and refuses options that would break the script.
#[test]
fn slurm_scripts_are_valid_shell_and_quote_paths() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("it's a folder");
    std::fs::create_dir_all(&folder).unwrap();
    let session = folder.join("s.toml");
    std::fs::write(&session, BASIN).unwrap();
    let out = isola()
        .arg("slurm")
        .arg(&session)
        .args(["--tasks", "3", "--cpus-per-task", "2", "--time", "1:00:00"])
        .arg("--sbatch-arg=--account=proj42")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out));
    for script in ["work.sh", "assemble.sh"] {
        let path = folder.join("s.results/slurm").join(script);
        let body = std::fs::read_to_string(&path).unwrap();
        assert!(body.contains("#SBATCH --cpus-per-task=2"), "{body}");
        assert!(
            body.contains("#SBATCH --time=1:00:00") && body.contains("#SBATCH --account=proj42")
        );
        let syntax = Command::new("bash").arg("-n").arg(&path).status().unwrap();
        assert!(syntax.success(), "{script} is not valid shell");
        // the session path, quoted, reaches isola intact
        let quoted_path = format!("'{}'", session.display().to_string().replace('\'', "'\\''"));
        assert!(body.contains(&quoted_path), "{body}");
    }
    let work = std::fs::read_to_string(folder.join("s.results/slurm/work.sh")).unwrap();
    assert!(work.contains("#SBATCH --array=0-2") && work.contains("--worker"));
    for bad in ["--time=1 2", "--sbatch-arg=account", "--partition=a#b"] {
        let out = isola()
            .arg("slurm")
            .arg(&session)
            .args(["--tasks", "2", bad])
            .output()
            .unwrap();
        assert!(!out.status.success(), "{bad} accepted");
    }
}

/// Every analysis but the time history sweeps its own ω or ignores the model (force curves):
/// editing the model's ω_e leaves their results current, and a fresh run at the new ω_e
/// computes the same bytes (the proof that they do not use it); the time history goes stale.
#[test]
fn an_edit_of_what_an_analysis_does_not_use_keeps_it_current() {
    let response = "[analysis.settings.response]\nomega = { min = 3.5, max = 4.0, points = 3 }\ndx = { min = -0.6, max = 0.6, points = 3 }\nv = { min = -0.8, max = 0.8, points = 2 }\n";
    let session = |omega: &str| {
        format!(
            "schema = 1\n[model]\nadr = 0.6\nomega = {omega}\n\n\
             [[analysis]]\nname = \"response\"\nkind = \"frequency_response\"\n[analysis.settings]\nomega = {{ min = 3.5, max = 4.0, points = 3 }}\ndx = {{ min = -0.6, max = 0.6, points = 3 }}\nv = {{ min = -0.8, max = 0.8, points = 2 }}\n\n\
             [[analysis]]\nname = \"stepped\"\nkind = \"stepped_sweep\"\n[analysis.settings]\nomega = {{ min = 3.0, max = 4.0, points = 5 }}\ndx0 = 0.3\n\n\
             [[analysis]]\nname = \"family\"\nkind = \"family\"\n[analysis.settings]\nparameter = \"c_tilde\"\nvalues = [0.04, 0.06]\n{response}\n\
             [[analysis]]\nname = \"hunt\"\nkind = \"hunt\"\n[analysis.settings]\n{response}[analysis.settings.continuation]\nmin = 3.0\nmax = 6.0\n\n\
             [[analysis]]\nname = \"map\"\nkind = \"map\"\n[analysis.settings]\nparameter = \"adr\"\nvalues = {{ min = 0.5, max = 0.7, points = 2 }}\ncurves = false\n{response}\n\
             [[analysis]]\nname = \"force\"\nkind = \"force_curve\"\n\n\
             [[analysis]]\nname = \"orbit\"\nkind = \"time_history\"\n[analysis.settings]\ndx0 = 0.3\n"
        )
    };
    let unused = ["response", "stepped", "family", "hunt", "map", "force"];
    let files = |s: &Path, name: &str| -> Vec<Vec<u8>> {
        let dir = s.with_file_name("s.results");
        let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                let f = p.file_name().unwrap().to_string_lossy();
                f.starts_with(&format!("{name}.")) && f.ends_with(".csv")
            })
            .collect();
        names.sort();
        assert!(!names.is_empty(), "no CSV for {name}");
        names.iter().map(|p| std::fs::read(p).unwrap()).collect()
    };
    let (_a, at_3_7) = session_dir(&session("3.7"));
    run_ok(&at_3_7, &[]);
    let before: Vec<_> = unused.iter().map(|n| files(&at_3_7, n)).collect();
    let orbit_before = files(&at_3_7, "orbit");
    // the model's ω_e edited
    std::fs::write(&at_3_7, session("2.9")).unwrap();
    let out = run_ok(&at_3_7, &[]);
    for name in unused {
        assert_eq!(computed(&out, name), 0, "{name} was recomputed:\n{out}");
    }
    assert!(
        computed(&out, "orbit") > 0,
        "the time history is stale:\n{out}"
    );
    assert_ne!(files(&at_3_7, "orbit"), orbit_before);
    // what a fresh run at the new ω_e computes is what was kept
    let (_b, at_2_9) = session_dir(&session("2.9"));
    run_ok(&at_2_9, &[]);
    for (name, kept) in unused.iter().zip(&before) {
        assert!(
            files(&at_2_9, name) == *kept,
            "{name} depends on the model's ω_e"
        );
    }
}

/// A family or map over ADR sets ADR itself: editing the model's ADR leaves them current,
/// and a fresh run with the new ADR computes the same bytes (the proof); a family over E_a
/// and a frequency response use it and go stale. A model given as voltages (no ADR written)
/// keys the family on them.
#[test]
fn an_edit_of_the_parameter_a_family_or_map_sets_keeps_it_current() {
    let response = "[analysis.settings.response]\nomega = { min = 3.5, max = 4.0, points = 3 }\ndx = { min = -0.6, max = 0.6, points = 3 }\nv = { min = -0.8, max = 0.8, points = 2 }\n";
    let session = |adr: &str| {
        format!(
            "schema = 1\n[model]\ne_a = 0.04\nadr = {adr}\n\n\
             [[analysis]]\nname = \"response\"\nkind = \"frequency_response\"\n[analysis.settings]\nomega = {{ min = 3.5, max = 4.0, points = 3 }}\ndx = {{ min = -0.6, max = 0.6, points = 3 }}\nv = {{ min = -0.8, max = 0.8, points = 2 }}\n\n\
             [[analysis]]\nname = \"by_adr\"\nkind = \"family\"\n[analysis.settings]\nparameter = \"adr\"\nvalues = [0.6, 1.0]\n{response}\n\
             [[analysis]]\nname = \"by_ea\"\nkind = \"family\"\n[analysis.settings]\nparameter = \"e_a\"\nvalues = [0.03, 0.04]\n{response}\n\
             [[analysis]]\nname = \"map\"\nkind = \"map\"\n[analysis.settings]\nparameter = \"adr\"\nvalues = {{ min = 0.5, max = 0.7, points = 2 }}\ncurves = false\n{response}"
        )
    };
    let csv = |s: &Path, name: &str| {
        std::fs::read(s.with_file_name(format!("s.results/{name}.csv"))).unwrap()
    };
    let (_a, first) = session_dir(&session("0.6"));
    run_ok(&first, &[]);
    let kept: Vec<Vec<u8>> = ["by_adr", "map"].iter().map(|n| csv(&first, n)).collect();
    std::fs::write(&first, session("0.85")).unwrap();
    let out = run_ok(&first, &[]);
    for name in ["by_adr", "map"] {
        assert_eq!(computed(&out, name), 0, "{name} was recomputed:\n{out}");
    }
    for name in ["response", "by_ea"] {
        assert!(computed(&out, name) > 0, "{name} uses the ADR:\n{out}");
    }
    let (_b, fresh) = session_dir(&session("0.85"));
    run_ok(&fresh, &[]);
    for (name, kept) in ["by_adr", "map"].iter().zip(&kept) {
        assert!(
            csv(&fresh, name) == *kept,
            "{name} depends on the model's ADR"
        );
    }
    // given as voltages, the drive's E_a comes from them: the family keys on them
    let s = Session::parse(
        Path::new("v.toml"),
        &session("0.6").replace("e_a = 0.04\nadr = 0.6", "phi_dc = 0.17\nphi_ac = 0.1"),
    )
    .unwrap();
    let t = Session::parse(
        Path::new("v.toml"),
        &session("0.6").replace("e_a = 0.04\nadr = 0.6", "phi_dc = 0.17\nphi_ac = 0.12"),
    )
    .unwrap();
    let i = s.analysis_index("by_adr").unwrap();
    assert_ne!(s.fingerprint(&s.analyses[i]), t.fingerprint(&t.analyses[i]));
}

/// A result copied under another name (a duplicated or renamed analysis) or into another
/// session's folder (save as) is a result of its own: verified before and after, with its own
/// manifest; replacing the original later leaves the copy as it was; a damaged original is
/// not copied.
#[test]
fn a_copied_result_is_verified_and_independent() {
    use isola::session::store::{copy::copy_result, verified};
    let (dir, path) = session_dir(RESPONSE);
    run_ok(&path, &[]);
    let session = Session::load(&path).unwrap();
    let from = ResultPaths::new(&session, "response");
    let elsewhere = dir.path().join("other.results");
    let to = ResultPaths::in_dir(&elsewhere, "copy");
    // nothing stored yet under a name: nothing copied, no error
    assert!(!copy_result(&ResultPaths::in_dir(&elsewhere, "none"), &to).unwrap());
    assert!(copy_result(&from, &to).unwrap());
    let original = verified(&from).unwrap();
    let copy = verified(&to).unwrap();
    assert_eq!(copy.analysis, "copy");
    assert_eq!(copy.fingerprint, original.fingerprint);
    let bytes = std::fs::read(&to.csv).unwrap();
    assert_eq!(bytes, std::fs::read(&from.csv).unwrap());
    // the original recomputed under other settings: the copy keeps the old result
    let edited = RESPONSE.replace("adr = 0.6", "adr = 0.8");
    std::fs::write(&path, &edited).unwrap();
    run_ok(&path, &[]);
    assert_ne!(std::fs::read(&from.csv).unwrap(), bytes);
    assert_eq!(std::fs::read(&to.csv).unwrap(), bytes);
    assert!(verified(&to).is_ok());
    // a damaged original is refused, and the copy it would replace is left as it was
    let mut damaged = std::fs::read(&from.csv).unwrap();
    damaged[40] ^= 1;
    std::fs::write(&from.csv, &damaged).unwrap();
    let err = copy_result(&from, &to).unwrap_err().to_string();
    assert!(err.contains("not copied"), "{err}");
    assert_eq!(std::fs::read(&to.csv).unwrap(), bytes);
    // onto itself: refused
    assert!(copy_result(&to, &to).is_err());
}
