//! Unit tests of `session::budget` (`src/session/budget.rs`).

use std::path::Path;

use isola::session::Session;
use isola::session::budget::{Budget, BudgetError, check_all};

/// One trajectory's worst case is told on one thread, however many the run has; a basin's
/// on all of them, its worst case the same steps spread over the threads.
#[test]
fn one_trajectory_is_costed_on_one_thread() {
    let text = "schema = 1\n[model]\nadr = 0.6\n\n[[analysis]]\nname = \"h\"\nkind = \"time_history\"\n\n[[analysis]]\nname = \"b\"\nkind = \"basin\"\n";
    let s = Session::parse(Path::new("t.toml"), text).unwrap();
    let over = |threads: usize, i: usize| -> (usize, f64) {
        let budget = Budget::on_this_machine(threads, Some(1e-9), false);
        match check_all(&s, [&s.analyses[i]], &budget) {
            Err(BudgetError::Time {
                threads, seconds, ..
            }) => (threads, seconds),
            other => panic!("{other:?}"),
        }
    };
    let (one, eight) = (over(1, 0), over(8, 0));
    assert_eq!((one.0, eight.0), (1, 1));
    assert_eq!(one.1, eight.1);
    let (one, eight) = (over(1, 1), over(8, 1));
    assert_eq!((one.0, eight.0), (1, 8));
    assert!((one.1 / eight.1 - 8.0).abs() < 1e-9, "{one:?} {eight:?}");
}
