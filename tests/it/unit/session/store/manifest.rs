//! Unit tests of `session::store::manifest` (`src/session/store/manifest.rs`).

use isola::session::store::manifest::*;

#[test]
fn a_changed_file_fails_verification() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.csv");
    std::fs::write(&path, "a,b\n1,2\n").unwrap();
    let record = StoredFile::of(&path).unwrap();
    assert!(record.verify(dir.path()).is_ok());
    std::fs::write(&path, "a,b\n1,3\n").unwrap();
    assert!(matches!(
        record.verify(dir.path()),
        Err(Unverified::Damaged { .. })
    ));
    std::fs::write(&path, "a,b\n").unwrap();
    assert!(record.verify(dir.path()).is_err());
    std::fs::remove_file(&path).unwrap();
    assert!(record.verify(dir.path()).is_err());
}
