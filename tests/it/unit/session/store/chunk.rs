//! Unit tests of `session::store::chunk` (`src/session/store/chunk.rs`).

use isola::session::store::chunk::*;

const ID: ChunkId = ChunkId {
    fingerprint: "f00d",
    index: 3,
    chunks: 9,
};

fn ok(_: &Vec<f64>) -> Result<(), String> {
    Ok(())
}

#[test]
fn a_good_chunk_reads_back_exactly() {
    let value = vec![0.1, 1.0 / 3.0, -2.5e-300];
    let bytes = encode(&ID, &value, 0.5).unwrap();
    let back = decode::<Vec<f64>>(&bytes, &ID, ok).unwrap();
    assert_eq!(back.value, value);
    assert_eq!(back.seconds, 0.5);
}

#[test]
fn every_kind_of_bad_chunk_is_refused() {
    let value = vec![0.1, 0.2, 0.3];
    let bytes = encode(&ID, &value, 0.0).unwrap();
    let refused = |b: &[u8], id: &ChunkId| decode::<Vec<f64>>(b, id, ok).unwrap_err();
    assert_eq!(refused(b"", &ID), ChunkError::NoHeader);
    assert_eq!(refused(b"[]", &ID), ChunkError::NoHeader);
    assert!(matches!(refused(&bytes[..10], &ID), ChunkError::NoHeader));
    assert!(matches!(
        refused(&bytes[..bytes.len() - 1], &ID),
        ChunkError::Length { .. }
    ));
    let mut flipped = bytes.clone();
    let last = flipped.len() - 2;
    flipped[last] ^= 0x01; // 0.3 -> 0.2 or similar: still JSON, wrong checksum
    assert_eq!(refused(&flipped, &ID), ChunkError::Checksum);
    let other = ChunkId {
        fingerprint: "beef",
        ..ID
    };
    assert!(matches!(
        refused(&bytes, &other),
        ChunkError::Foreign { .. }
    ));
    let moved = ChunkId { index: 4, ..ID };
    assert!(matches!(
        refused(&bytes, &moved),
        ChunkError::WrongIndex { .. }
    ));
    let content = decode::<Vec<f64>>(&bytes, &ID, |v| {
        if v.len() == 512 {
            Ok(())
        } else {
            Err(format!("{} cells, expected 512", v.len()))
        }
    })
    .unwrap_err();
    assert!(matches!(content, ChunkError::Content(_)));
}

#[test]
fn non_finite_numbers_never_reach_a_chunk() {
    let e = encode(&ID, &vec![1.0, f64::NAN], 0.0).unwrap_err();
    assert_eq!(e.path, "[1]");
}
