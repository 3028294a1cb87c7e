//! Every hostile session of the generator (`tests/corpus`) through the real binary: no panic,
//! no abort, no hang (each ends within seconds), no NaN or infinity in any output, and every
//! error names the field the user wrote.

use crate::corpus;

use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A case running longer than this is a hang.
const HANG: Duration = Duration::from_secs(20);

/// What one case did.
struct Outcome {
    label: String,
    problem: Option<String>,
    seconds: f64,
    accepted: bool,
}

fn run_case(dir: &Path, i: usize, case: &corpus::Case) -> Outcome {
    let path = dir.join(format!("case{i}.toml"));
    std::fs::write(&path, &case.text).unwrap();
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_isola"))
        .arg("run")
        .arg(&path)
        .args(["--threads", "1", "--budget", "5"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // most cases are refused within milliseconds: poll often at first, then less
    let mut nap = Duration::from_micros(200);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if started.elapsed() > HANG {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(nap);
        nap = (nap * 2).min(Duration::from_millis(10));
    };
    let seconds = started.elapsed().as_secs_f64();
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    let outcome = |problem: Option<String>, accepted| Outcome {
        label: case.label.clone(),
        problem,
        seconds,
        accepted,
    };
    let Some(status) = status else {
        return outcome(Some(format!("hang (killed after {HANG:?})")), false);
    };
    match status.code() {
        Some(0) => {
            let results = dir.join(format!("case{i}.results"));
            for entry in std::fs::read_dir(&results).into_iter().flatten().flatten() {
                let p = entry.path();
                if p.extension().is_some_and(|e| e == "csv") {
                    let text = std::fs::read_to_string(&p).unwrap_or_default();
                    if text.split([',', '\n', ';']).any(|cell| {
                        let c = cell.trim().to_ascii_lowercase();
                        c == "nan" || c == "inf" || c == "-inf" || c == "infinity"
                    }) {
                        return outcome(
                            Some(format!("non-finite number in {}", p.display())),
                            true,
                        );
                    }
                }
            }
            outcome(None, true)
        }
        Some(1) => {
            // the whole path (`dx.points`), or the key on the line the error shows
            let leaf = case.field.rsplit('.').next().unwrap_or_default();
            let named = stderr.contains(&case.field)
                || (stderr.contains("line ") && stderr.contains(&format!("{leaf} = ")));
            if named {
                outcome(None, false)
            } else {
                outcome(
                    Some(format!(
                        "the error does not name `{}`: {}",
                        case.field,
                        stderr.trim()
                    )),
                    false,
                )
            }
        }
        other => outcome(
            Some(format!(
                "exit {other:?} (a panic or abort): {}",
                stderr.trim()
            )),
            false,
        ),
    }
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
    eprintln!(
        "{} hostile sessions: {} refused with an error, {} accepted and run; slowest {:.2} s ({})",
        outcomes.len(),
        outcomes.len() - accepted,
        accepted,
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
