//! Unit tests of `jobs` (`src/jobs/mod.rs`).

use isola::jobs::*;
use rayon::prelude::*;

#[test]
fn a_worker_panic_is_an_error_of_the_job() {
    let job = Job::<usize>::spawn(2, |ctx| {
        ctx.progress.grow_total(100);
        Ok((0..100usize)
            .into_par_iter()
            .map(|i| {
                if i == 57 {
                    panic!("boom at {i}");
                }
                i
            })
            .sum())
    })
    .unwrap();
    match job.join() {
        Err(JobError::Panicked(msg)) => assert!(msg.contains("boom"), "{msg}"),
        other => panic!("expected a panic error, got {other:?}"),
    }
}

#[test]
fn cancel_is_seen_by_the_work() {
    let job = Job::<()>::spawn(1, |ctx| {
        loop {
            ctx.check_cancel()?;
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    })
    .unwrap();
    job.cancel();
    assert_eq!(job.join(), Err(JobError::Cancelled));
}
