//! What the store holds of one analysis' work under way, for `isola status` and the
//! workbench: chunks done (by which host, when), claimed (by whom), missing. Read only: it
//! takes no lock a run would wait for, but a claim's lock for an instant.

use std::path::Path;
use std::time::SystemTime;

use super::chunk::Payload;
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

impl Survey {
    pub fn missing(&self) -> usize {
        self.chunks - self.done.len()
    }
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
    let dir = paths.work_dir(fingerprint);
    let mut s = Survey {
        chunks,
        ..Survey::default()
    };
    if !dir.is_dir() {
        return s;
    }
    for i in 0..chunks {
        let file = dir.join(chunk_name(i));
        if let Ok(bytes) = std::fs::read(&file) {
            let id = super::chunk::ChunkId {
                fingerprint,
                index: i,
                chunks,
            };
            match super::chunk::decode::<T>(&bytes, &id, |v| content(i, v)) {
                Ok(d) => {
                    s.done.push(Done {
                        index: i,
                        host: host_of(&d.host).to_string(),
                        seconds: d.seconds,
                        saved: modified(&file),
                    });
                    continue;
                }
                Err(_) => s.bad.push(i),
            }
        }
        if let Some(holder) = claimed_by(&dir, i) {
            s.claimed.push((i, holder));
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
