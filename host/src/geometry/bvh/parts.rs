//! Parts of a depth-first array built in parallel, placed once into their final slots.
//!
//! The binary build and the collapse both build subtrees in parallel tasks, each into its own
//! part, with references that do not change when the part moves (distances, or indices from
//! the part's start). Appending the parts one after another at every parallel level would copy
//! the whole array on one thread per level; instead their places are prefix sums of their
//! lengths and every part is copied once, in parallel, into its slots, fixing its references
//! on the way.

use std::mem::MaybeUninit;

use rayon::prelude::*;

use crate::geometry::huge_pages::HugePageBuf;

/// The concatenation of `parts` (`total` elements in all), each copied in its own task; `fix`
/// receives every element with its part's first slot in the result and its index in the part
/// (to turn relative references into indices). Each part is freed as soon as it is copied.
pub(super) fn place_parts<T, F>(parts: Vec<Vec<T>>, total: usize, fix: F) -> Vec<T>
where
    T: Copy + Send + Sync,
    F: Fn(&mut T, usize, usize) + Sync,
{
    if parts.len() == 1 {
        // One part (a small tree): fixed where it is, no copy.
        return fix_single(parts, total, fix);
    }
    let mut out: Vec<T> = Vec::with_capacity(total);
    place_parts_into(parts, &mut out.spare_capacity_mut()[..total], fix);
    // SAFETY: `place_parts_into` wrote all `total` slots.
    unsafe { out.set_len(total) };
    out
}

/// [`place_parts`] into a [`HugePageBuf`] (the traversal's node arrays: on 2 MiB pages when
/// large, written for the first time here, after the advice).
pub(super) fn place_parts_huge<T, F>(parts: Vec<Vec<T>>, total: usize, fix: F) -> HugePageBuf<T>
where
    T: Copy + Send + Sync,
    F: Fn(&mut T, usize, usize) + Sync,
{
    if parts.len() == 1 {
        return HugePageBuf::from_vec(fix_single(parts, total, fix));
    }
    let mut out = HugePageBuf::<T>::uninit(total);
    place_parts_into(parts, &mut out, fix);
    // SAFETY: `place_parts_into` wrote all `total` slots.
    unsafe { out.assume_init() }
}

/// The one part of `parts`, fixed where it is.
fn fix_single<T, F>(parts: Vec<Vec<T>>, total: usize, fix: F) -> Vec<T>
where
    F: Fn(&mut T, usize, usize),
{
    let mut out = parts.into_iter().next().unwrap_or_default();
    assert_eq!(out.len(), total, "the part's length is the total");
    for (i, v) in out.iter_mut().enumerate() {
        fix(v, 0, i);
    }
    out
}

/// Copies `parts` one after another into `out` (exactly their total length), each in its own
/// task, fixing every element on the way; afterwards every slot of `out` is written.
fn place_parts_into<T, F>(parts: Vec<Vec<T>>, out: &mut [MaybeUninit<T>], fix: F)
where
    T: Copy + Send + Sync,
    F: Fn(&mut T, usize, usize) + Sync,
{
    assert_eq!(
        parts.iter().map(Vec::len).sum::<usize>(),
        out.len(),
        "the parts' lengths add up to the total"
    );
    let mut rest = out;
    let mut targets = Vec::with_capacity(parts.len());
    let mut start = 0;
    for part in &parts {
        let (t, r) = std::mem::take(&mut rest).split_at_mut(part.len());
        targets.push((start, t));
        start += part.len();
        rest = r;
    }
    // The targets tile `out` (the lengths add up, as asserted), so every slot is written.
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
}
