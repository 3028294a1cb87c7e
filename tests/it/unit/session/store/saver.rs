//! Unit tests of `session::store::saver` (`src/session/store/saver.rs`).

use std::path::Path;

use isola::session::store::lock::{Lock, Mode};
use isola::session::store::saver::ChunkSaver;

fn claim(dir: &Path, i: usize) -> Lock {
    Lock::try_acquire(&dir.join(format!("{i:06}.claim")), Mode::Exclusive)
        .unwrap()
        .expect("free")
}

/// Every queued chunk is on disk, whole, once `finish` returns, and its claim is free
/// again; a killed writer's temporary of a chunk written is gone, another chunk's kept.
#[test]
fn chunks_are_written_whole_and_their_claims_released() {
    let dir = tempfile::tempdir().unwrap();
    let leftover = |i: usize| dir.path().join(format!(".{i:06}.json.Xy12ab.tmp"));
    std::fs::write(leftover(3), "half a chunk").unwrap();
    std::fs::write(leftover(99), "half a chunk").unwrap();
    let saver = ChunkSaver::start(dir.path()).unwrap();
    for i in 0..20 {
        let bytes = format!("chunk {i}\n").repeat(1000).into_bytes();
        let path = dir.path().join(format!("{i:06}.json"));
        saver.save(path, bytes, claim(dir.path(), i), format!("chunk {i}"));
    }
    saver.finish().unwrap();
    for i in 0..20 {
        let text = std::fs::read_to_string(dir.path().join(format!("{i:06}.json"))).unwrap();
        assert_eq!(text, format!("chunk {i}\n").repeat(1000));
        claim(dir.path(), i);
    }
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert_eq!(names, [".000099.json.Xy12ab.tmp"]);
}

/// A chunk that cannot be written is an error naming it and its file, seen by the
/// threads still computing and returned by `finish`; its claim is released all the same.
#[test]
fn a_chunk_that_cannot_be_written_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let saver = ChunkSaver::start(dir.path()).unwrap();
    saver.healthy().unwrap();
    let gone = dir.path().join("gone").join("000003.json");
    saver.save(
        gone,
        b"x".to_vec(),
        claim(dir.path(), 3),
        "basin, chunk 3".into(),
    );
    let started = std::time::Instant::now();
    while saver.healthy().is_ok() {
        assert!(started.elapsed().as_secs() < 60, "no failure seen");
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let e = format!("{:#}", saver.finish().unwrap_err());
    assert!(
        e.contains("basin, chunk 3") && e.contains("000003.json"),
        "{e}"
    );
    claim(dir.path(), 3);
}
