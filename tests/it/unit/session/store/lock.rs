//! Unit tests of `session::store::lock` (`src/session/store/lock.rs`).

use isola::session::store::lock::*;

#[test]
fn exclusive_excludes_and_is_released_on_drop() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.lock");
    let held = Lock::acquire(&path, Mode::Exclusive).unwrap();
    assert!(held.still_at_path());
    assert!(Lock::try_acquire(&path, Mode::Exclusive).unwrap().is_none());
    assert!(Lock::try_acquire(&path, Mode::Shared).unwrap().is_none());
    drop(held);
    let a = Lock::try_acquire(&path, Mode::Shared).unwrap().unwrap();
    let b = Lock::try_acquire(&path, Mode::Shared).unwrap().unwrap();
    assert!(Lock::try_acquire(&path, Mode::Exclusive).unwrap().is_none());
    drop((a, b));
    let c = Lock::try_acquire(&path, Mode::Exclusive).unwrap().unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!(!c.still_at_path(), "removed under its holder");
}
