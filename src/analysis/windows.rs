//! Work over indices taken in order, computed a window at a time side by side, so that only a
//! window's results are held however many indices there are.

use rayon::prelude::*;

/// `compute(i)` for `i` in `0..count`, in index order: each window of `window` indices is
/// computed side by side on the current rayon pool when the iterator reaches it.
pub fn in_windows<'a, T: Send + 'a>(
    count: usize,
    window: usize,
    compute: impl Fn(usize) -> T + Sync + Send + 'a,
) -> impl Iterator<Item = T> + 'a {
    (0..count).step_by(window.max(1)).flat_map(move |first| {
        (first..(first + window).min(count))
            .into_par_iter()
            .map(&compute)
            .collect::<Vec<_>>()
    })
}
