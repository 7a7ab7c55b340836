//! Sorting pairs of ids: a counting sort on the first id, then each id's
//! few pairs by the second.

/// Runs of [`sort_pairs`] longer than this take the library's sort.
const SHORT_RUN: usize = 16;

/// `pairs`, each `(a, b)` with `a < b < ids`, sorted into `sorted`: a
/// counting sort on `a` (ids are dense: one pass counts, one places; Knuth,
/// TAOCP vol. 3, 5.2), then each id's few pairs by `b`. A fraction of a
/// comparison sort's time, and one pass over the pairs fewer than a radix
/// sort on both ids. `starts` is scratch; both buffers are reused, so a
/// frame that sorts its pairs allocates nothing.
///
/// ```
/// let (mut starts, mut sorted) = (Vec::new(), Vec::new());
/// bvol_tree::sort_pairs(&[(2, 5), (0, 9), (2, 3), (0, 1)], 10, &mut starts, &mut sorted);
/// assert_eq!(sorted, [(0, 1), (0, 9), (2, 3), (2, 5)]);
/// ```
pub fn sort_pairs(
    pairs: &[(u32, u32)],
    ids: usize,
    starts: &mut Vec<u32>,
    sorted: &mut Vec<(u32, u32)>,
) {
    starts.clear();
    starts.resize(ids + 1, 0);
    for &(a, _) in pairs {
        starts[a as usize + 1] += 1;
    }
    for i in 1..starts.len() {
        starts[i] += starts[i - 1];
    }
    sorted.clear();
    sorted.resize(pairs.len(), (0, 0));
    for &(a, b) in pairs {
        let at = &mut starts[a as usize];
        sorted[*at as usize] = (a, b);
        *at += 1;
    }
    // Each id's place now ends its run. Most runs hold a pair or two: an
    // insertion sort in line costs less than a library sort called for each.
    let mut begin = 0;
    for &end in &starts[..ids] {
        let run = &mut sorted[begin as usize..end as usize];
        if run.len() > SHORT_RUN {
            run.sort_unstable();
        } else {
            for i in 1..run.len() {
                let mut j = i;
                while j > 0 && run[j - 1].1 > run[j].1 {
                    run.swap(j - 1, j);
                    j -= 1;
                }
            }
        }
        begin = end;
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::sort_pairs;

    proptest! {
        /// The counting sort gives the order of a comparison sort, on pairs
        /// `a < b` of ids below the count, repeats of a first id included:
        /// with few ids, runs far longer than `SHORT_RUN`.
        #[test]
        fn sort_pairs_matches_a_comparison_sort(
            ids in 2u32..300,
            raw in prop::collection::vec((0u32..300, 0u32..300), 0..2000),
        ) {
            // Each pair once, in the generated (arbitrary) order.
            let mut seen = std::collections::HashSet::new();
            let pairs: Vec<(u32, u32)> = raw
                .into_iter()
                .map(|(a, b)| (a % ids, b % ids))
                .filter(|(a, b)| a != b)
                .map(|(a, b)| (a.min(b), a.max(b)))
                .filter(|&pair| seen.insert(pair))
                .collect();
            let mut want = pairs.clone();
            want.sort_unstable();
            let (mut starts, mut sorted) = (vec![7; 3], vec![(1, 2); 5]);
            sort_pairs(&pairs, ids as usize, &mut starts, &mut sorted);
            prop_assert_eq!(sorted, want);
        }
    }
}
