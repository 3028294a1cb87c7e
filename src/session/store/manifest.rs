//! The record of a finished result: what produced it and a checksum of every file it wrote.
//! It is written last, after the files are in place and read back, so its presence with
//! matching checksums is what "complete" means.

use std::path::Path;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::chunk::hex;

/// The manifest format this build writes and reads (1 was an unchecked record of earlier
/// builds, never trusted now; 2 had the responses' stroboscopic points `;`-joined in their
/// rows and no record of the values computed from).
pub const MANIFEST_FORMAT: u32 = 3;

/// `A.manifest.json`: exists only for a complete result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    pub format: u32,
    pub analysis: String,
    pub kind: String,
    /// Fingerprint of model, device, settings, kind and numerics (see `Session::fingerprint`).
    pub fingerprint: String,
    /// What the fingerprint is the hash of: the model's values the analysis uses, the device,
    /// the settings and the numerics version (see `Session::fingerprint_input`), so a reader
    /// sees, and can check, what the result was computed from.
    pub computed_from: serde_json::Value,
    /// The numerics version of the build that computed it.
    pub numerics: u32,
    /// The build: package version and commit.
    pub isola_version: String,
    pub chunks_total: usize,
    /// Seconds of computing, summed over chunks (on whichever host) and assembly.
    pub compute_seconds: f64,
    /// Who assembled it (`host pid N`) and when (seconds since 1970).
    pub assembled_by: String,
    pub assembled_unix: u64,
    /// Every file of the result, beside the manifest.
    pub files: Vec<StoredFile>,
}

/// One file of a result and its checksum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StoredFile {
    /// File name in the results folder.
    pub name: String,
    pub bytes: u64,
    pub sha256: String,
}

/// Why a stored result is not (verifiably) a result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unverified {
    #[error("no manifest")]
    Missing,
    #[error("manifest {file} unreadable: {why}")]
    Unreadable { file: String, why: String },
    #[error("{file}: {why}")]
    Damaged { file: String, why: String },
}

/// SHA-256 and length of the file at `path`.
pub fn checksum(path: &Path) -> std::io::Result<(u64, String)> {
    use std::io::Read;
    let mut file = std::fs::File::open(path)?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
        bytes += n as u64;
    }
    Ok((bytes, hex(&h.finalize())))
}

impl StoredFile {
    /// The record of the file at `path`, as it is on disk now.
    pub fn of(path: &Path) -> std::io::Result<StoredFile> {
        let (bytes, sha256) = checksum(path)?;
        Ok(StoredFile {
            name: path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            bytes,
            sha256,
        })
    }

    /// Checks the file of this name in `dir` against the record.
    pub fn verify(&self, dir: &Path) -> Result<(), Unverified> {
        let path = dir.join(&self.name);
        let damaged = |why: String| Unverified::Damaged {
            file: path.display().to_string(),
            why,
        };
        let meta = std::fs::metadata(&path).map_err(|e| damaged(e.to_string()))?;
        if meta.len() != self.bytes {
            return Err(damaged(format!(
                "{} bytes, the manifest says {}",
                meta.len(),
                self.bytes
            )));
        }
        let (_, sha) = checksum(&path).map_err(|e| damaged(e.to_string()))?;
        if sha != self.sha256 {
            return Err(damaged("checksum differs from the manifest's".into()));
        }
        Ok(())
    }
}

impl Manifest {
    /// Reads the manifest at `path`.
    pub fn read(path: &Path) -> Result<Manifest, Unverified> {
        let bytes = match std::fs::read(path) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(Unverified::Missing),
            Err(e) => {
                return Err(Unverified::Unreadable {
                    file: path.display().to_string(),
                    why: e.to_string(),
                });
            }
        };
        let m: Manifest = serde_json::from_slice(&bytes).map_err(|e| Unverified::Unreadable {
            file: path.display().to_string(),
            why: e.to_string(),
        })?;
        if m.format != MANIFEST_FORMAT {
            return Err(Unverified::Unreadable {
                file: path.display().to_string(),
                why: format!("format {}, this isola reads {MANIFEST_FORMAT}", m.format),
            });
        }
        Ok(m)
    }

    /// Checks every file of the result against its checksum.
    pub fn verify_files(&self, dir: &Path) -> Result<(), Unverified> {
        if self.files.is_empty() {
            return Err(Unverified::Damaged {
                file: self.analysis.clone(),
                why: "the manifest lists no files".into(),
            });
        }
        self.files.iter().try_for_each(|f| f.verify(dir))
    }
}
