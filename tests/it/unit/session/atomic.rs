//! Unit tests of `session::atomic` (`src/session/atomic.rs`).

use isola::session::atomic::*;
use std::time::Duration;

#[test]
fn replaces_whole_and_leaves_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.txt");
    write_atomic(&path, b"old").unwrap();
    write_atomic(&path, b"new").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"new");
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["a.txt"]);
}

/// A write into a folder that is missing names that folder, not the temporary's random name.
#[test]
fn a_missing_folder_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("not/there");
    let e = write_atomic(&folder.join("a.toml"), b"x").unwrap_err();
    assert_eq!(e.to_string(), format!("no folder {}", folder.display()));
    assert!(!e.to_string().contains(".a.toml."));
}

#[test]
fn stale_temporaries_of_one_stem_are_removed() {
    let dir = tempfile::tempdir().unwrap();
    for name in [".basin.csv.AbC123.tmp", ".basin-2.csv.x.tmp", "basin.csv"] {
        std::fs::write(dir.path().join(name), "x").unwrap();
    }
    assert!(is_temporary_of(".basin.csv.AbC123.tmp", "basin"));
    assert!(!is_temporary_of(".basin-2.csv.x.tmp", "basin"));
    assert_eq!(
        remove_stale_temporaries(dir.path(), "basin", Duration::ZERO),
        1
    );
    assert!(dir.path().join(".basin-2.csv.x.tmp").exists());
    assert!(dir.path().join("basin.csv").exists());
}
