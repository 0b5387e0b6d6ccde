//! A counting global allocator for the allocation tests: each binary that
//! includes this module registers it (`#[global_allocator]`) and reads
//! either the calling thread's count (tests run side by side on several
//! threads) or, while armed, the count over all threads (for work on
//! rayon's pool; such a binary holds one test).
#![allow(dead_code)] // each binary uses one of the two counts
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

pub struct Counting;

thread_local! {
    static LOCAL: Cell<usize> = const { Cell::new(0) };
}
static ARMED: AtomicBool = AtomicBool::new(false);
static GLOBAL: AtomicUsize = AtomicUsize::new(0);

fn count() {
    let _ = LOCAL.try_with(|c| c.set(c.get() + 1));
    if ARMED.load(Ordering::Relaxed) {
        GLOBAL.fetch_add(1, Ordering::Relaxed);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(p, l, n) }
    }
}

/// Allocations made by this thread so far.
pub fn on_this_thread() -> usize {
    LOCAL.with(Cell::get)
}

/// Allocations made by every thread while `f` runs.
pub fn on_all_threads<T>(f: impl FnOnce() -> T) -> (usize, T) {
    GLOBAL.store(0, Ordering::SeqCst);
    ARMED.store(true, Ordering::SeqCst);
    let out = f();
    ARMED.store(false, Ordering::SeqCst);
    (GLOBAL.load(Ordering::SeqCst), out)
}
