//! Acceleration structures: the BVH, and the unbounded planes tested four at a time.

mod bvh;
mod huge_array;
mod planes;

pub use bvh::{Bvh, MAX_PRIMITIVES};
pub use huge_array::HugeArray;
pub use planes::Planes;

/// Asks the CPU to start loading the cache line that holds `value`, and goes on without waiting
/// for it: traversal of a large hierarchy waits on memory, so the loads of what it will visit
/// next are started while it works on the current step.
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    safe_arch::prefetch_t0(value);
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
