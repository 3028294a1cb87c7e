//! What the store holds of one analysis' work under way, for `isola status` and the
//! workbench: chunks done (by which host, when), claimed (by whom), missing. Read only: it
//! takes no lock a run would wait for, but a claim's lock for an instant.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, SystemTime};

use std::io::{BufRead, Read};

use super::chunk::{ChunkError, ChunkId, Payload};
use super::lock::{Lock, Mode};
use super::{ResultPaths, chunk_name};

/// One finished chunk.
#[derive(Debug, Clone, PartialEq)]
pub struct Done {
    pub index: usize,
    /// The host that computed it (`node7`).
    pub host: String,
    /// Seconds it took.
    pub seconds: f64,
    /// When it was saved.
    pub saved: SystemTime,
}

/// The chunks of one fingerprint's work.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Survey {
    pub chunks: usize,
    pub done: Vec<Done>,
    /// (chunk, who holds its claim: `host pid N`).
    pub claimed: Vec<(usize, String)>,
    /// Chunk files that fail their checks (they will be recomputed).
    pub bad: Vec<usize>,
}

/// One host's part of the work.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HostWork {
    pub host: String,
    pub done: usize,
    pub claimed: usize,
    /// Compute seconds of its chunks done.
    pub seconds: f64,
    /// Chunks a minute it saved over the last [`RATE_WINDOW`].
    pub per_minute: f64,
}

impl HostWork {
    /// Chunks a minute of all `hosts` together.
    pub fn total_per_minute(hosts: &[HostWork]) -> f64 {
        hosts.iter().map(|h| h.per_minute).sum()
    }
}

/// Rates are taken over the chunks saved in this last stretch of time.
pub const RATE_WINDOW: Duration = Duration::from_secs(300);

impl Survey {
    pub fn missing(&self) -> usize {
        self.chunks - self.done.len()
    }

    /// Each host's chunks done and claimed, and its rate at `now`, by host name.
    pub fn by_host(&self, now: SystemTime) -> Vec<HostWork> {
        let mut hosts: BTreeMap<&str, (HostWork, Vec<SystemTime>)> = BTreeMap::new();
        for d in &self.done {
            let (h, recent) = hosts.entry(&d.host).or_default();
            h.done += 1;
            h.seconds += d.seconds;
            if now.duration_since(d.saved).unwrap_or_default() <= RATE_WINDOW {
                recent.push(d.saved);
            }
        }
        for (_, holder) in &self.claimed {
            hosts.entry(host_of(holder)).or_default().0.claimed += 1;
        }
        hosts
            .into_iter()
            .map(|(name, (mut h, recent))| {
                h.host = name.to_string();
                h.per_minute = rate_per_minute(&recent, now);
                h
            })
            .collect()
    }

    /// Seconds left at the hosts' rates (`None` if none saved a chunk lately).
    pub fn seconds_left(&self, hosts: &[HostWork]) -> Option<f64> {
        let rate = HostWork::total_per_minute(hosts);
        (rate > 0.0).then(|| 60.0 * self.missing() as f64 / rate)
    }
}

/// Chunks a minute over those saved in the last [`RATE_WINDOW`] (0 if none).
fn rate_per_minute(saved: &[SystemTime], now: SystemTime) -> f64 {
    let Some(first) = saved.iter().min() else {
        return 0.0;
    };
    let span = now
        .duration_since(*first)
        .unwrap_or_default()
        .max(Duration::from_secs(1))
        .min(RATE_WINDOW);
    saved.len() as f64 * 60.0 / span.as_secs_f64()
}

/// The host part of `host pid N`.
pub fn host_of(holder: &str) -> &str {
    holder.split(" pid ").next().unwrap_or(holder)
}

/// Surveys the work folder of `fingerprint` for an analysis of `chunks` chunks whose payload
/// is `T` (checked as a run would check it, by `content`).
pub fn survey<T: Payload>(
    paths: &ResultPaths,
    fingerprint: &str,
    chunks: usize,
    content: impl Fn(usize, &T) -> Result<(), String>,
) -> Survey {
    walk(paths, fingerprint, chunks, |id, file| {
        let bytes = std::fs::read(file).ok()?;
        Some(
            super::chunk::decode::<T>(&bytes, id, |v| content(id.index, v))
                .map(|d| (d.host, d.seconds)),
        )
    })
}

/// [`survey`] from the chunks' header lines alone (their fingerprint and index checked, not
/// their payload): cheap enough for the workbench to repeat every few seconds, for progress
/// only.
pub fn glance(paths: &ResultPaths, fingerprint: &str, chunks: usize) -> Survey {
    walk(paths, fingerprint, chunks, |id, file| {
        let mut line = Vec::new();
        let mut reader = std::io::BufReader::new(std::fs::File::open(file).ok()?).take(64 * 1024);
        reader.read_until(b'\n', &mut line).ok()?;
        let line = line.strip_suffix(b"\n").unwrap_or(&line);
        Some(super::chunk::made_by(line, id))
    })
}

/// The chunks of `fingerprint`'s work folder: each existing chunk file checked by `check`
/// (who made it and in how long, or why it is bad), and the claims of the others.
fn walk(
    paths: &ResultPaths,
    fingerprint: &str,
    chunks: usize,
    check: impl Fn(&ChunkId, &Path) -> Option<Result<(String, f64), ChunkError>>,
) -> Survey {
    let dir = paths.work_dir(fingerprint);
    let mut s = Survey {
        chunks,
        ..Survey::default()
    };
    if !dir.is_dir() {
        return s;
    }
    for index in 0..chunks {
        let file = dir.join(chunk_name(index));
        let id = ChunkId {
            fingerprint,
            index,
            chunks,
        };
        match check(&id, &file) {
            Some(Ok((host, seconds))) => {
                s.done.push(Done {
                    index,
                    host: host_of(&host).to_string(),
                    seconds,
                    saved: modified(&file),
                });
                continue;
            }
            Some(Err(_)) => s.bad.push(index),
            None => {}
        }
        if let Some(holder) = claimed_by(&dir, index) {
            s.claimed.push((index, holder));
        }
    }
    s
}

fn modified(path: &Path) -> SystemTime {
    std::fs::metadata(path)
        .and_then(|m| m.modified())
        .unwrap_or(SystemTime::UNIX_EPOCH)
}

/// Who holds the claim on chunk `i`, if anyone does now.
fn claimed_by(dir: &Path, i: usize) -> Option<String> {
    let path = dir.join(format!("{i:06}.claim"));
    if !path.exists() {
        return None;
    }
    match Lock::try_acquire(&path, Mode::Shared) {
        Ok(Some(_free)) => None,
        Ok(None) => Some(
            std::fs::read_to_string(&path)
                .map(|t| t.trim().to_string())
                .unwrap_or_default(),
        ),
        Err(_) => None,
    }
}
