//! Mapping the pages of large new result arrays in one go.
//!
//! A new numpy array of tens of megabytes is memory the kernel has not mapped yet; writing it
//! faults its pages in one at a time, and on a small virtual machine those faults cost as much
//! as the kinematics that fill the array and do not get faster with more threads. Asking the
//! kernel to map the whole range first (`MADV_POPULATE_WRITE`, Linux ≥ 5.14) is several times
//! cheaper. Best effort: on other systems, or when the kernel refuses, nothing happens and the
//! pages are faulted in as they are written.

/// Maps every whole page of `buffer` (contents unchanged).
pub fn populate(buffer: &mut [f64]) {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: sysconf has no preconditions.
        let page = match unsafe { libc::sysconf(libc::_SC_PAGESIZE) } {
            size if size > 0 => size as usize,
            _ => return,
        };
        let start = buffer.as_mut_ptr() as usize;
        let first = start.next_multiple_of(page);
        let end = (start + size_of_val(buffer)) / page * page;
        if end > first {
            // SAFETY: [first, end) lies inside `buffer`, which is borrowed mutably here;
            // populating maps pages in without changing their contents. The result is ignored:
            // failure only means the pages are faulted in later.
            unsafe {
                libc::madvise(
                    first as *mut libc::c_void,
                    end - first,
                    libc::MADV_POPULATE_WRITE,
                )
            };
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = buffer;
}
