//! A global allocator that counts live bytes and refuses to go past a cap,
//! so that an allocation sized from a bad header (a 16-byte file asking for
//! 34 GB) is caught and reported instead of taking the machine's memory.
//!
//! The runner installs [`CappedAlloc`] and, before each input, sets the cap
//! to what is live plus what the input's size can justify. A refused
//! allocation calls the hook the runner set (which saves the input) and then
//! fails, which makes the standard library abort.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::Relaxed};

static LIVE: AtomicUsize = AtomicUsize::new(0);
static CAP: AtomicUsize = AtomicUsize::new(usize::MAX);
static HOOK: OnceLock<fn(usize, usize)> = OnceLock::new();
static IN_HOOK: AtomicBool = AtomicBool::new(false);

/// The system allocator, counted and capped.
pub struct CappedAlloc;

/// Bytes allocated and not yet freed, in the whole process.
pub fn live() -> usize {
    LIVE.load(Relaxed)
}

/// From now on at most `bytes` more may be live than are now.
pub fn allow(bytes: usize) {
    CAP.store(live().saturating_add(bytes), Relaxed);
}

/// Lifts the cap.
pub fn lift() {
    CAP.store(usize::MAX, Relaxed);
}

/// Calls `hook(size, live)` when an allocation of `size` bytes is refused
/// (not again from inside the hook, whose own allocations are not capped).
/// Only the first hook set is kept.
pub fn on_refusal(hook: fn(usize, usize)) {
    let _ = HOOK.set(hook);
}

fn grow(size: usize) -> bool {
    let live = LIVE.fetch_add(size, Relaxed) + size;
    if live <= CAP.load(Relaxed) || IN_HOOK.load(Relaxed) {
        return true;
    }
    LIVE.fetch_sub(size, Relaxed);
    if let Some(hook) = HOOK.get()
        && !IN_HOOK.swap(true, Relaxed)
    {
        hook(size, live - size);
        IN_HOOK.store(false, Relaxed);
    }
    false
}

/// Counts and caps an allocation of `size` bytes made by `allocate`:
/// refused (null) past the cap, uncounted again if the system fails it.
fn counted(size: usize, allocate: impl FnOnce() -> *mut u8) -> *mut u8 {
    if !grow(size) {
        return std::ptr::null_mut();
    }
    let p = allocate();
    if p.is_null() {
        LIVE.fetch_sub(size, Relaxed);
    }
    p
}

// SAFETY: every call is passed on to `System` unchanged, or refused with a
// null pointer before it reaches it; the count only follows what `System`
// holds.
unsafe impl GlobalAlloc for CappedAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's layout, passed on.
        counted(layout.size(), || unsafe { System.alloc(layout) })
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's layout, passed on.
        counted(layout.size(), || unsafe { System.alloc_zeroed(layout) })
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's pointer and layout, passed on.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !grow(new_size - old) {
            return std::ptr::null_mut();
        }
        // SAFETY: the caller's pointer, layout and size, passed on.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        match (p.is_null(), new_size > old) {
            (true, true) => _ = LIVE.fetch_sub(new_size - old, Relaxed),
            (false, false) => _ = LIVE.fetch_sub(old - new_size, Relaxed),
            _ => {}
        }
        p
    }
}
