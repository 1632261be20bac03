//! Large read-mostly arrays of the traversal (BVH nodes, leaf triangles, the leaf slots'
//! primitives) on 2 MiB pages where the operating system offers them.
//!
//! A ray through a large scene touches a few cache lines on each of dozens of pages spread over
//! ~90 MB (1.3 M triangles): far beyond what the data TLB covers with 4 KiB pages, so most
//! node and leaf reads there also walk the page table. With 2 MiB pages the same arrays need
//! some fifty TLB entries. Linux's transparent huge pages give them to a mapping only when
//! asked (`/sys/kernel/mm/transparent_hugepage/enabled` is `madvise` on many systems), and
//! only for 2 MiB-aligned stretches of it, so an array of at least [`HUGE_PAGE`] bytes is
//! allocated 2 MiB-aligned, its size rounded up to whole huge pages, and marked with
//! `madvise(MADV_HUGEPAGE)` before anything is written to it (pages faulted in before the
//! advice stay small). Embree's allocator does the same for its BVH (`common/sys/alloc.cpp`:
//! `mmap` then `madvise(MADV_HUGEPAGE)` for allocations of 2 MiB or more).
//!
//! The advice is a hint: it changes no value, and where it is refused (THP `never`, kernels
//! without THP) or unknown (other systems) the array is an ordinary allocation. Smaller arrays
//! are plain `Vec`s. `docs/performance.md`, "Huge pages, tree statistics and leaves of up to eight in large trees".

use std::alloc::Layout;
use std::mem::MaybeUninit;
use std::ptr::NonNull;

use rayon::prelude::*;

/// Arrays of at least this many bytes go on 2 MiB pages (the x86-64 and AArch64 huge page
/// size with 4 KiB base pages).
pub(crate) const HUGE_PAGE: usize = 2 << 20;

/// A fixed-length array of `T`, on huge pages when it is at least [`HUGE_PAGE`] bytes (see
/// the module documentation). Dereferences to `[T]`.
pub(crate) struct HugePageBuf<T: Copy> {
    ptr: NonNull<T>,
    len: usize,
    owner: Owner,
}

/// How the memory of a [`HugePageBuf`] was obtained, so that it is freed the same way.
#[derive(Clone, Copy, Debug)]
enum Owner {
    /// A `Vec`'s buffer of this capacity.
    Vec { cap: usize },
    /// The global allocator with this 2 MiB-aligned layout.
    Pages(Layout),
}

// SAFETY: a `HugePageBuf<T>` owns its elements as a `Vec<T>` does (no shared state, the
// pointer is unique), so it may move to and be shared between threads as `Vec<T>` may.
unsafe impl<T: Copy + Send> Send for HugePageBuf<T> {}
// SAFETY: as above; `&HugePageBuf<T>` only gives `&[T]`.
unsafe impl<T: Copy + Sync> Sync for HugePageBuf<T> {}

impl<T: Copy> HugePageBuf<T> {
    /// Keeps a `Vec` below [`HUGE_PAGE`] bytes as it is; copies a larger one onto huge pages.
    pub(crate) fn from_vec(v: Vec<T>) -> HugePageBuf<T> {
        if Self::huge_layout(v.len()).is_none() {
            return Self::wrap_vec(v);
        }
        let mut buf = Self::uninit(v.len());
        for (d, s) in buf.iter_mut().zip(&v) {
            d.write(*s);
        }
        // SAFETY: every element was written from `v`, which has `buf`'s length.
        unsafe { buf.assume_init() }
    }

    /// `v`'s buffer as it is.
    fn wrap_vec(v: Vec<T>) -> HugePageBuf<T> {
        let mut v = std::mem::ManuallyDrop::new(v);
        HugePageBuf {
            // A `Vec`'s pointer is never null (dangling but aligned when it holds nothing).
            ptr: NonNull::new(v.as_mut_ptr()).unwrap_or(NonNull::dangling()),
            len: v.len(),
            owner: Owner::Vec { cap: v.capacity() },
        }
    }

    /// `len` elements, element `i` being `f(i)`, computed in parallel.
    pub(crate) fn from_fn_par(len: usize, f: impl Fn(usize) -> T + Sync) -> HugePageBuf<T>
    where
        T: Send,
    {
        let mut buf = Self::uninit(len);
        buf.par_iter_mut()
            .with_min_len(1 << 12)
            .enumerate()
            .for_each(|(i, d)| {
                d.write(f(i));
            });
        // SAFETY: the parallel loop wrote every index `0..len`.
        unsafe { buf.assume_init() }
    }

    /// A copy of `s` (on huge pages if large).
    pub(crate) fn from_slice(s: &[T]) -> HugePageBuf<T> {
        if Self::huge_layout(s.len()).is_none() {
            return Self::from_vec(s.to_vec());
        }
        let mut buf = Self::uninit(s.len());
        for (d, v) in buf.iter_mut().zip(s) {
            d.write(*v);
        }
        // SAFETY: every element was written from `s`, which has `buf`'s length.
        unsafe { buf.assume_init() }
    }

    /// `len` uninitialised elements: advised onto huge pages before anything touches them
    /// when they take at least [`HUGE_PAGE`] bytes, a `Vec`'s buffer otherwise.
    pub(crate) fn uninit(len: usize) -> HugePageBuf<MaybeUninit<T>> {
        let Some(layout) = Self::huge_layout(len) else {
            let mut v: Vec<MaybeUninit<T>> = Vec::with_capacity(len);
            // SAFETY: `MaybeUninit` needs no initialisation, and the capacity is `len`.
            unsafe { v.set_len(len) };
            return HugePageBuf::wrap_vec(v);
        };
        // SAFETY: the layout's size is at least `HUGE_PAGE`, so not zero.
        let raw = unsafe { std::alloc::alloc(layout) };
        let Some(ptr) = NonNull::new(raw.cast::<MaybeUninit<T>>()) else {
            std::alloc::handle_alloc_error(layout)
        };
        advise_huge_pages(raw, layout.size());
        HugePageBuf {
            ptr,
            len,
            owner: Owner::Pages(layout),
        }
    }

    /// The 2 MiB-aligned layout (size rounded up to whole huge pages) for `len` elements, if
    /// they take at least [`HUGE_PAGE`] bytes.
    fn huge_layout(len: usize) -> Option<Layout> {
        let bytes = len.checked_mul(std::mem::size_of::<T>())?;
        if bytes < HUGE_PAGE {
            return None;
        }
        let size = bytes.checked_next_multiple_of(HUGE_PAGE)?;
        Layout::from_size_align(size, HUGE_PAGE.max(std::mem::align_of::<T>())).ok()
    }
}

impl<T: Copy> HugePageBuf<MaybeUninit<T>> {
    /// The same memory as initialised elements.
    ///
    /// # Safety
    /// Every element must have been written.
    pub(crate) unsafe fn assume_init(self) -> HugePageBuf<T> {
        let me = std::mem::ManuallyDrop::new(self);
        HugePageBuf {
            ptr: me.ptr.cast::<T>(),
            len: me.len,
            owner: me.owner,
        }
    }
}

/// Asks the kernel for transparent huge pages on `bytes` bytes from `ptr` (2 MiB-aligned,
/// untouched so far). A hint: its result is ignored, and it does nothing off Linux.
fn advise_huge_pages(ptr: *mut u8, bytes: usize) {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: `ptr..ptr + bytes` is one live allocation of ours, page-aligned (2 MiB) and a
        // whole number of pages long; `MADV_HUGEPAGE` only sets a flag on the mapping and
        // neither reads nor changes its contents. Errors (EINVAL where THP is not built in)
        // leave the mapping as it was.
        let _ = unsafe { libc::madvise(ptr.cast(), bytes, libc::MADV_HUGEPAGE) };
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (ptr, bytes);
}

impl<T: Copy> Drop for HugePageBuf<T> {
    fn drop(&mut self) {
        match self.owner {
            // SAFETY: `ptr`, `len` and `cap` are those of the `Vec` this buffer took over
            // (`T: Copy`, so the elements need no drop either way).
            Owner::Vec { cap } => unsafe {
                drop(Vec::from_raw_parts(self.ptr.as_ptr(), self.len, cap));
            },
            // SAFETY: allocated by `uninit` with this layout.
            Owner::Pages(layout) => unsafe {
                std::alloc::dealloc(self.ptr.as_ptr().cast(), layout);
            },
        }
    }
}

impl<T: Copy> std::ops::Deref for HugePageBuf<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        // SAFETY: `ptr` points to `len` initialised elements owned by `self` (or is dangling
        // and aligned with `len == 0`).
        unsafe { std::slice::from_raw_parts(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Copy> std::ops::DerefMut for HugePageBuf<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        // SAFETY: as in `deref`, and `&mut self` makes the access unique.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.as_ptr(), self.len) }
    }
}

impl<'a, T: Copy> IntoIterator for &'a HugePageBuf<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<T: Copy> Default for HugePageBuf<T> {
    fn default() -> Self {
        Self::from_vec(Vec::new())
    }
}

impl<T: Copy> Clone for HugePageBuf<T> {
    fn clone(&self) -> Self {
        Self::from_slice(self)
    }
}

impl<T: Copy + std::fmt::Debug> std::fmt::Debug for HugePageBuf<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        (**self).fmt(f)
    }
}

impl<T: Copy + PartialEq> PartialEq for HugePageBuf<T> {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Small arrays stay `Vec`s, large ones are 2 MiB-aligned; either way the contents are
    // exactly what was put in (from a `Vec`, a slice, a function, a clone), and dropping
    // frees them (run under Miri or a leak checker to see the latter; here: no crash).
    #[test]
    fn contents_survive_every_constructor() {
        for len in [
            0usize,
            1,
            1000,
            HUGE_PAGE / 4 - 1,
            HUGE_PAGE / 4,
            3 * HUGE_PAGE / 4 + 7,
        ] {
            let want: Vec<u32> = (0..len as u32)
                .map(|i| i.wrapping_mul(2654435761))
                .collect();
            let a = HugePageBuf::from_vec(want.clone());
            let b = HugePageBuf::from_slice(&want);
            let c = HugePageBuf::from_fn_par(len, |i| want[i]);
            let d = c.clone();
            for buf in [&a, &b, &c, &d] {
                assert_eq!(&**buf, &want[..], "len {len}");
                let huge = len * 4 >= HUGE_PAGE;
                assert_eq!(matches!(buf.owner, Owner::Pages(_)), huge, "len {len}");
                if huge {
                    assert_eq!(buf.as_ptr() as usize % HUGE_PAGE, 0, "len {len}");
                }
            }
            assert_eq!(a, d);
        }
    }

    // Writable through `DerefMut`, and `uninit` + writes + `assume_init` gives the writes.
    #[test]
    fn uninit_then_written() {
        let len = HUGE_PAGE / 8 + 3;
        let mut u = HugePageBuf::<u64>::uninit(len);
        for (i, d) in u.iter_mut().enumerate() {
            d.write(i as u64 * 3);
        }
        // SAFETY: every element was written above.
        let mut b = unsafe { u.assume_init() };
        b[5] = 7;
        assert_eq!(b[5], 7);
        assert!(b
            .iter()
            .enumerate()
            .all(|(i, &v)| i == 5 || v == i as u64 * 3));
    }
}
