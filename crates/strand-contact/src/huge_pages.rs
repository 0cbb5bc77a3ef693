//! Transparent huge pages for the large arrays a mesh load writes into.
//!
//! A cache hit reads every section of the file straight into freshly allocated arrays:
//! in a new process each 4 KiB page of them is faulted in (zeroed, then copied into)
//! one at a time, about 14.5k faults for a 1M-triangle mesh and a fifth of the hit's
//! time. Advising the kernel to back the arrays with 2 MiB pages before they are
//! written turns them into a few dozen faults (measured on Linux with
//! `transparent_hugepage=madvise`: one core, 1M triangles, 53 → 41–47 ms per hit,
//! 30.9k → 11.0k page faults per process).
//!
//! This is the workspace's one `unsafe` block: `madvise(MADV_HUGEPAGE)` on pages inside
//! memory the caller exclusively borrows. The advice changes only how the pages are
//! backed, never their contents, and is ignored where the kernel has no huge pages.

#![allow(unsafe_code)]

/// Arrays smaller than this are left as they are (bytes: a huge page is 2 MiB, and the
/// advice is a system call).
pub(crate) const MIN_ADVISED_BYTES: usize = 4 << 20;

/// Advises the kernel to back the whole pages inside `array` with transparent huge
/// pages. Call it before the array is first written: pages already touched stay as
/// they are until the kernel's background merging. Does nothing for arrays below
/// [`MIN_ADVISED_BYTES`], off Linux, or where the kernel refuses the advice.
pub(crate) fn advise<T>(array: &mut [T]) {
    let bytes = std::mem::size_of_val(array);
    if bytes < MIN_ADVISED_BYTES {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        let start = array.as_mut_ptr() as usize;
        let first_page = start.next_multiple_of(PAGE);
        let length = (start + bytes - first_page) / PAGE * PAGE;
        // SAFETY: `[first_page, first_page + length)` lies inside `array`, which the
        // caller borrows exclusively, and is page-aligned as madvise requires.
        // MADV_HUGEPAGE only changes how those pages are backed, not what they hold,
        // so no Rust value is affected; a refusal (EINVAL without THP) is harmless.
        let _ =
            unsafe { libc::madvise(first_page as *mut libc::c_void, length, libc::MADV_HUGEPAGE) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advice_keeps_what_the_array_holds() {
        // Unaligned starts and lengths, below and above the size that is advised,
        // written before and after the advice.
        for count in [3, MIN_ADVISED_BYTES / 8 - 1, MIN_ADVISED_BYTES / 8 + 4099] {
            let mut array: Vec<u64> = (0..count as u64).map(|i| i * 2654435761).collect();
            for skip in [0, 1, 511] {
                let part = &mut array[skip.min(count)..];
                advise(part);
            }
            assert!(
                array
                    .iter()
                    .enumerate()
                    .all(|(i, &x)| x == i as u64 * 2654435761)
            );
            let mut fresh = vec![0u32; count * 2];
            advise(&mut fresh[1..]);
            fresh
                .iter_mut()
                .enumerate()
                .for_each(|(i, x)| *x = i as u32);
            assert!(fresh.iter().enumerate().all(|(i, &x)| x == i as u32));
        }
    }
}
