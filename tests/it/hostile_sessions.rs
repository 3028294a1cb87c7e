//! Every hostile session of the generator (`tests/corpus`): no panic, no abort, no hang (each
//! ends within seconds), no NaN or infinity in any output, and every error names the field the
//! user wrote. A session the loader refuses is checked in this process (the message the binary
//! would print after `error: `), one in [`THROUGH_THE_BINARY`] of them also through the real
//! binary, which must print exactly that message; every session the loader accepts runs through
//! the real binary.

use crate::corpus;

use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use isola::session::Session;

/// A case running longer than this is a hang. The slowest that is not (a hunt whose
/// `tol_converged` of 5e-324 no trajectory meets, so each runs its 6000 forcing periods)
/// took 8.2 s alone in the test profile, and past 20 s while other tests shared the cores.
const HANG: Duration = Duration::from_secs(40);

/// One in this many of the sessions refused at load also goes through the binary (the rest
/// cost a process start each, ~7 ms, for the same message).
const THROUGH_THE_BINARY: usize = 25;

/// What one case did.
struct Outcome {
    label: String,
    problem: Option<String>,
    seconds: f64,
    accepted: bool,
    /// Whether the real binary ran it.
    binary: bool,
}

/// How the binary ended a session: exit code (None: killed as a hang) and its stderr.
struct Ended {
    code: Option<Option<i32>>,
    stderr: String,
}

fn run_binary(path: &Path) -> Ended {
    let mut child = Command::new(env!("CARGO_BIN_EXE_isola"))
        .arg("run")
        .arg(path)
        .args(["--threads", "1", "--budget", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    // most cases end within milliseconds: poll often at first, then less
    let mut nap = Duration::from_micros(200);
    let code = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status.code());
        }
        if started.elapsed() > HANG {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(nap);
        nap = (nap * 2).min(Duration::from_millis(10));
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    Ended { code, stderr }
}

/// Whether an error message names the field `case` touched: the whole path (`dx.points`), or
/// the key on the line the error shows.
fn names_the_field(message: &str, case: &corpus::Case) -> bool {
    let leaf = case.field.rsplit('.').next().unwrap_or_default();
    message.contains(&case.field)
        || (message.contains("line ") && message.contains(&format!("{leaf} = ")))
}

fn run_case(dir: &Path, i: usize, case: &corpus::Case) -> Outcome {
    let path = dir.join(format!("case{i}.toml"));
    std::fs::write(&path, &case.text).unwrap();
    let started = Instant::now();
    let outcome = |problem: Option<String>, accepted, binary| Outcome {
        label: case.label.clone(),
        problem,
        seconds: started.elapsed().as_secs_f64(),
        accepted,
        binary,
    };
    let loaded = std::panic::catch_unwind(|| {
        Session::load(&path)
            .map(drop)
            .map_err(|e| format!("{:#}", anyhow::Error::from(e)))
    });
    match loaded {
        Err(_) => outcome(Some("the loader panicked".into()), false, false),
        Ok(Err(message)) => {
            if !names_the_field(&message, case) {
                let problem = format!("the error does not name `{}`: {message}", case.field);
                return outcome(Some(problem), false, false);
            }
            let binary = i.is_multiple_of(THROUGH_THE_BINARY);
            if binary {
                let ended = run_binary(&path);
                let expected = format!("error: {message}\n");
                if ended.code != Some(Some(1)) || ended.stderr != expected {
                    let problem = format!(
                        "the binary ended with {:?} and printed {:?}, not {expected:?}",
                        ended.code, ended.stderr
                    );
                    return outcome(Some(problem), false, true);
                }
            }
            outcome(None, false, binary)
        }
        Ok(Ok(())) => {
            let ended = run_binary(&path);
            match ended.code {
                None => outcome(Some(format!("hang (killed after {HANG:?})")), true, true),
                Some(Some(0)) => outcome(non_finite_output(dir, i), true, true),
                Some(Some(1)) if names_the_field(&ended.stderr, case) => outcome(None, false, true),
                Some(Some(1)) => {
                    let problem = format!(
                        "the error does not name `{}`: {}",
                        case.field,
                        ended.stderr.trim()
                    );
                    outcome(Some(problem), false, true)
                }
                other => {
                    let problem =
                        format!("exit {other:?} (a panic or abort): {}", ended.stderr.trim());
                    outcome(Some(problem), false, true)
                }
            }
        }
    }
}

/// A non-finite number in any CSV the run of case `i` wrote, if there is one.
fn non_finite_output(dir: &Path, i: usize) -> Option<String> {
    let results = dir.join(format!("case{i}.results"));
    for entry in std::fs::read_dir(&results).into_iter().flatten().flatten() {
        let p = entry.path();
        if p.extension().is_some_and(|e| e == "csv") {
            let text = std::fs::read_to_string(&p).unwrap_or_default();
            if text.split([',', '\n', ';']).any(|cell| {
                let c = cell.trim().to_ascii_lowercase();
                c == "nan" || c == "inf" || c == "-inf" || c == "infinity"
            }) {
                return Some(format!("non-finite number in {}", p.display()));
            }
        }
    }
    None
}

#[test]
fn every_hostile_session_ends_in_a_clear_error_or_a_finite_result() {
    let cases = corpus::cases();
    assert!(cases.len() >= 400, "{} cases", cases.len());
    let dir = tempfile::tempdir().unwrap();
    let next = Mutex::new(0usize);
    let outcomes = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                loop {
                    let i = {
                        let mut n = next.lock().unwrap();
                        *n += 1;
                        *n - 1
                    };
                    let Some(case) = cases.get(i) else { break };
                    let o = run_case(dir.path(), i, case);
                    outcomes.lock().unwrap().push(o);
                }
            });
        }
    });
    let outcomes = outcomes.into_inner().unwrap();
    let problems: Vec<String> = outcomes
        .iter()
        .filter_map(|o| {
            o.problem
                .as_ref()
                .map(|p| format!("{}: {}", o.label, p.replace('\n', " ⏎ ")))
        })
        .collect();
    let accepted = outcomes.iter().filter(|o| o.accepted).count();
    let slowest = outcomes
        .iter()
        .max_by(|a, b| a.seconds.total_cmp(&b.seconds))
        .unwrap();
    let by_binary = outcomes.iter().filter(|o| o.binary).count();
    eprintln!(
        "{} hostile sessions: {} refused with an error, {} accepted and run, {} through the binary; slowest {:.2} s ({})",
        outcomes.len(),
        outcomes.len() - accepted,
        accepted,
        by_binary,
        slowest.seconds,
        slowest.label
    );
    assert!(
        problems.is_empty(),
        "{} of {} cases went wrong:\n{}",
        problems.len(),
        outcomes.len(),
        problems.join("\n")
    );
}
