//! Renders in a loop keep the library's memory flat: every byte the Rust side allocates for a
//! render (scene, BVH, tracers, films, threads) is freed when it ends. Counted by a global
//! allocator, so the driver's own allocations (lavapipe's, through malloc) do not blur it.

#[path = "../common/mod.rs"]
mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

use platoon::devices::DeviceSpec;
use platoon::Request;

struct Counting;

static OUTSTANDING: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        OUTSTANDING.fetch_add(layout.size() as isize, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        OUTSTANDING.fetch_sub(layout.size() as isize, Ordering::Relaxed);
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        OUTSTANDING.fetch_add(
            new_size as isize - layout.size() as isize,
            Ordering::Relaxed,
        );
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

#[test]
fn renders_in_a_loop_give_back_what_they_take() {
    common::init();
    let request = Request {
        width: 8,
        height: 8,
        spp: 1,
        devices: DeviceSpec::Lavapipe(vec![1]),
        aovs: vec![platoon::core::frame::aov::Aov::Albedo],
        ..Default::default()
    };
    // The first renders fill what lives for the process (the compiled kernels' cache).
    for _ in 0..3 {
        request.render(&mut |_| {}).unwrap();
    }
    let before = OUTSTANDING.load(Ordering::Relaxed);
    for _ in 0..20 {
        request.render(&mut |_| {}).unwrap();
    }
    let grown = OUTSTANDING.load(Ordering::Relaxed) - before;
    assert!(
        grown < 16 * 1024,
        "{grown} bytes not given back over 20 renders"
    );
}
