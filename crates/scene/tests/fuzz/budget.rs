//! The allocation cap: a counting global allocator that refuses what takes a case over 1 GiB.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Mutex;

/// What one case may hold live at once. The inputs are at most a few hundred KiB,
/// so a loader that needs more is amplifying a count from the file.
pub(crate) const ALLOC_CAP: usize = 1 << 30;

pub(crate) struct Meter {
    pub(crate) armed: Cell<bool>,
    pub(crate) live: Cell<usize>,
    pub(crate) peak: Cell<usize>,
    /// Size of a refused request (0: none).
    pub(crate) refused: Cell<usize>,
}

thread_local! {
    pub(crate) static METER: Meter = const {
        Meter { armed: Cell::new(false), live: Cell::new(0), peak: Cell::new(0), refused: Cell::new(0) }
    };
}

/// Printed when a case goes over the cap, just before the allocation fails (which
/// aborts the process): names the case and where its input is.
pub(crate) static OVER_CAP_NOTE: Mutex<String> = Mutex::new(String::new());

/// Counts the bytes the armed thread (the one running a case) holds; refuses a
/// request that would take it over [`ALLOC_CAP`].
struct Capped;

#[global_allocator]
static ALLOCATOR: Capped = Capped;

/// Books `n` more bytes for the current thread; `false` refuses them.
fn charge(n: usize) -> bool {
    METER
        .try_with(|m| {
            if !m.armed.get() {
                return true;
            }
            let live = m.live.get().saturating_add(n);
            if live > ALLOC_CAP {
                // Disarmed first: the report below allocates.
                m.armed.set(false);
                m.refused.set(n);
                if let Ok(note) = OVER_CAP_NOTE.try_lock() {
                    eprintln!(
                        "\nfuzz: a case asked for {n} more bytes with {} live, over the 1 GiB cap. {note}",
                        m.live.get()
                    );
                }
                return false;
            }
            m.live.set(live);
            m.peak.set(m.peak.get().max(live));
            true
        })
        .unwrap_or(true)
}

fn credit(n: usize) {
    let _ = METER.try_with(|m| {
        if m.armed.get() {
            m.live.set(m.live.get().saturating_sub(n));
        }
    });
}

unsafe impl GlobalAlloc for Capped {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !charge(layout.size()) {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !charge(layout.size()) {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        credit(layout.size());
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !charge(new_size - old) {
            return std::ptr::null_mut();
        }
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() && new_size < old {
            credit(old - new_size);
        }
        p
    }
}
