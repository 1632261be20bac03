//! Parts of a depth-first array built in parallel, placed once into their final slots.
//!
//! The binary build and the collapse both build subtrees in parallel tasks, each into its own
//! part, with references that do not change when the part moves (distances, or indices from
//! the part's start). Appending the parts one after another at every parallel level would copy
//! the whole array on one thread per level; instead their places are prefix sums of their
//! lengths and every part is copied once, in parallel, into its slots, fixing its references
//! on the way.

use rayon::prelude::*;

/// The concatenation of `parts` (`total` elements in all), each copied in its own task; `fix`
/// receives every element with its part's first slot in the result and its index in the part
/// (to turn relative references into indices). Each part is freed as soon as it is copied.
pub(super) fn place_parts<T, F>(parts: Vec<Vec<T>>, total: usize, fix: F) -> Vec<T>
where
    T: Copy + Send + Sync,
    F: Fn(&mut T, usize, usize) + Sync,
{
    assert_eq!(
        parts.iter().map(Vec::len).sum::<usize>(),
        total,
        "the parts' lengths add up to the total"
    );
    if parts.len() == 1 {
        // One part (a small tree): fixed where it is, no copy.
        let mut out = parts.into_iter().next().unwrap_or_default();
        for (i, v) in out.iter_mut().enumerate() {
            fix(v, 0, i);
        }
        return out;
    }
    let mut out: Vec<T> = Vec::with_capacity(total);
    let mut rest = &mut out.spare_capacity_mut()[..total];
    let mut targets = Vec::with_capacity(parts.len());
    let mut start = 0;
    for part in &parts {
        let (t, r) = std::mem::take(&mut rest).split_at_mut(part.len());
        targets.push((start, t));
        start += part.len();
        rest = r;
    }
    parts
        .into_par_iter()
        .zip(targets)
        .for_each(|(part, (start, dst))| {
            for (i, (v, d)) in part.iter().zip(dst.iter_mut()).enumerate() {
                let mut v = *v;
                fix(&mut v, start, i);
                d.write(v);
            }
        });
    // SAFETY: the targets tile the first `total` slots (the parts' lengths sum to `total`, as
    // asserted above) and every slot was written by its part's task.
    unsafe { out.set_len(total) };
    out
}
