//! The `/` filter: which analyses and parameters are listed, and moving among them.

/// The indices of `names` containing `filter` (case-insensitive); all of them when the
/// filter is empty or matches none (a filter for parameters leaves the analyses listed).
pub fn matching(filter: &str, names: &[String]) -> Vec<usize> {
    let filter = filter.trim().to_lowercase();
    let all = || (0..names.len()).collect();
    if filter.is_empty() {
        return all();
    }
    let hits: Vec<usize> = (0..names.len())
        .filter(|&i| names[i].to_lowercase().contains(&filter))
        .collect();
    if hits.is_empty() { all() } else { hits }
}

/// The listed index `by` steps from `current` (clamped to the ends); `None` if none is.
pub fn step(visible: &[usize], current: usize, by: isize) -> Option<usize> {
    let last = visible.len().checked_sub(1)?;
    // where `current` is, or where it would be among the listed
    let at = visible.iter().position(|&i| i >= current).unwrap_or(last);
    let at = if visible[at] != current && by > 0 {
        at as isize - 1
    } else {
        at as isize
    };
    Some(visible[(at + by).clamp(0, last as isize) as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filter_lists_what_matches_and_moves_among_it() {
        let names: Vec<String> = ["response", "basin", "orbit_3_7", "basin_b2"]
            .map(String::from)
            .to_vec();
        assert_eq!(matching("BAS", &names), vec![1, 3]);
        assert_eq!(matching("", &names), vec![0, 1, 2, 3]);
        assert_eq!(matching("nothing", &names), vec![0, 1, 2, 3]);
        let visible = [1, 3];
        assert_eq!(step(&visible, 1, 1), Some(3));
        assert_eq!(step(&visible, 3, 1), Some(3));
        assert_eq!(step(&visible, 3, -1), Some(1));
        // from a row not listed: to the next listed one down, the one before up
        assert_eq!(step(&visible, 2, 1), Some(3));
        assert_eq!(step(&visible, 2, -1), Some(1));
        assert_eq!(step(&[], 0, 1), None);
    }
}
