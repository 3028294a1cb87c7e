//! Self-describing chunk files: a header line that says what produced the chunk, then the
//! payload. A chunk is used only if every check passes; otherwise it is recomputed.
//!
//! ```text
//! {"isola_chunk":1,"fingerprint":"…","index":12,"chunks":99,"items":512,"payload_bytes":83211,"sha256":"…","host":"node7 pid 4242","seconds":0.41}
//! [ …payload JSON… ]
//! ```
//!
//! The SHA-256 covers the fingerprint, index, chunk count, item count and payload, so a
//! truncated, damaged, foreign (other settings, device or numerics), copied (other index) or
//! re-cut (other item count) chunk is told apart from a good one.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::finite::{NonFinite, first_non_finite};

/// The chunk file format this build writes and reads.
pub const CHUNK_FORMAT: u32 = 1;

/// What a chunk file must say of itself to be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChunkId<'a> {
    /// The fingerprint of the analysis (model, device, settings, kind, numerics).
    pub fingerprint: &'a str,
    pub index: usize,
    /// How many chunks the analysis has.
    pub chunks: usize,
}

/// A value that can be a chunk's payload: it knows how many items (cells, responses) it holds.
pub trait Payload: Serialize + DeserializeOwned + Send {
    fn items(&self) -> usize;
}

impl<T: Serialize + DeserializeOwned + Send> Payload for Vec<T> {
    fn items(&self) -> usize {
        self.len()
    }
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Header {
    isola_chunk: u32,
    fingerprint: String,
    index: usize,
    chunks: usize,
    items: usize,
    payload_bytes: usize,
    sha256: String,
    /// Who computed it (`host pid N`).
    host: String,
    /// Seconds it took.
    seconds: f64,
}

/// Why a chunk file was not used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ChunkError {
    #[error("no header line (not an isola chunk, or cut short)")]
    NoHeader,
    #[error("unreadable header: {0}")]
    BadHeader(String),
    #[error("chunk format {found}, this isola reads format {CHUNK_FORMAT}")]
    Format { found: u32 },
    #[error("belongs to other settings, device or numerics (fingerprint {found})")]
    Foreign { found: String },
    #[error("holds chunk {found} of {found_of}, expected chunk {expected} of {expected_of}")]
    WrongIndex {
        found: usize,
        found_of: usize,
        expected: usize,
        expected_of: usize,
    },
    #[error("payload has {found} bytes, its header says {expected} (cut short or appended to)")]
    Length { found: usize, expected: usize },
    #[error("checksum mismatch (damaged)")]
    Checksum,
    #[error("unreadable payload: {0}")]
    BadPayload(String),
    #[error("holds {found} items, its header says {expected}")]
    Items { found: usize, expected: usize },
    #[error("content does not fit the analysis: {0}")]
    Content(String),
}

fn digest(id: &ChunkId, items: usize, payload: &[u8]) -> String {
    let mut h = Sha256::new();
    h.update(format!("{}\n{}\n{}\n{items}\n", id.fingerprint, id.index, id.chunks).as_bytes());
    h.update(payload);
    hex(&h.finalize())
}

/// Lower-case hexadecimal of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The file for chunk `id` holding `value`; `Err` names the first non-finite number, which no
/// chunk may hold (JSON cannot carry it back).
pub fn encode<T: Payload>(id: &ChunkId, value: &T, seconds: f64) -> Result<Vec<u8>, NonFinite> {
    if let Some(found) = first_non_finite(value) {
        return Err(found);
    }
    let payload = serde_json::to_vec(value).expect("a finite payload serializes");
    let items = value.items();
    let header = Header {
        isola_chunk: CHUNK_FORMAT,
        fingerprint: id.fingerprint.to_string(),
        index: id.index,
        chunks: id.chunks,
        items,
        payload_bytes: payload.len(),
        sha256: digest(id, items, &payload),
        host: super::lock::holder(),
        seconds: if seconds.is_finite() { seconds } else { 0.0 },
    };
    let mut bytes = serde_json::to_vec(&header).expect("a header serializes");
    bytes.push(b'\n');
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

/// A chunk read back and checked, with what its header says of its making.
#[derive(Debug)]
pub struct Decoded<T> {
    pub value: T,
    pub host: String,
    pub seconds: f64,
}

/// Checks chunk `id` in `bytes` without parsing its payload: format, fingerprint, index,
/// length and checksum (so a damaged, cut, foreign or copied file is told apart); the
/// seconds it took. The payload itself is parsed and checked by [`decode`] when it is used.
pub fn check(bytes: &[u8], id: &ChunkId) -> Result<f64, ChunkError> {
    checked(bytes, id).map(|(header, _)| header.seconds)
}

/// Reads chunk `id` from `bytes`, checking format, fingerprint, index, length, checksum and
/// item count, then `content` (the analysis' own check of what the chunk must hold).
pub fn decode<T: Payload>(
    bytes: &[u8],
    id: &ChunkId,
    content: impl FnOnce(&T) -> Result<(), String>,
) -> Result<Decoded<T>, ChunkError> {
    let (header, payload) = checked(bytes, id)?;
    let value: T =
        serde_json::from_slice(payload).map_err(|e| ChunkError::BadPayload(e.to_string()))?;
    if value.items() != header.items {
        return Err(ChunkError::Items {
            found: value.items(),
            expected: header.items,
        });
    }
    content(&value).map_err(ChunkError::Content)?;
    Ok(Decoded {
        value,
        host: header.host,
        seconds: header.seconds,
    })
}

/// The header and payload of chunk `id` in `bytes`, checked up to the payload's checksum.
fn checked<'b>(bytes: &'b [u8], id: &ChunkId) -> Result<(Header, &'b [u8]), ChunkError> {
    let newline = bytes
        .iter()
        .position(|&b| b == b'\n')
        .ok_or(ChunkError::NoHeader)?;
    let header = header_of(&bytes[..newline], id)?;
    let payload = &bytes[newline + 1..];
    if payload.len() != header.payload_bytes {
        return Err(ChunkError::Length {
            found: payload.len(),
            expected: header.payload_bytes,
        });
    }
    if digest(id, header.items, payload) != header.sha256 {
        return Err(ChunkError::Checksum);
    }
    Ok((header, payload))
}

/// What a chunk's header line (without its line break) says of its making, if it names chunk
/// `id`: a look at a chunk without reading its payload, for progress, never for a result.
pub fn made_by(line: &[u8], id: &ChunkId) -> Result<(String, f64), ChunkError> {
    let header = header_of(line, id)?;
    Ok((header.host, header.seconds))
}

/// The header line parsed and checked against `id`.
fn header_of(line: &[u8], id: &ChunkId) -> Result<Header, ChunkError> {
    let header: Header =
        serde_json::from_slice(line).map_err(|e| ChunkError::BadHeader(e.to_string()))?;
    if header.isola_chunk != CHUNK_FORMAT {
        return Err(ChunkError::Format {
            found: header.isola_chunk,
        });
    }
    if header.fingerprint != id.fingerprint {
        return Err(ChunkError::Foreign {
            found: header.fingerprint,
        });
    }
    if header.index != id.index || header.chunks != id.chunks {
        return Err(ChunkError::WrongIndex {
            found: header.index,
            found_of: header.chunks,
            expected: id.index,
            expected_of: id.chunks,
        });
    }
    Ok(header)
}
