//! Unit tests of `session::store::copy` (`src/session/store/copy.rs`).

use isola::session::store::copy::renamed;

#[test]
fn files_take_the_new_name() {
    assert_eq!(renamed("a.csv", "a", "b2"), "b2.csv");
    assert_eq!(renamed("a.attractors.csv", "a", "b"), "b.attractors.csv");
    // a name that only starts like the analysis' is not its file
    assert_eq!(renamed("ab.csv", "a", "b"), "ab.csv");
}
