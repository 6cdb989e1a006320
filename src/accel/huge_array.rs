//! Immutable arrays for what traversal reads at random (BVH nodes, triangles), kept in memory the
//! system may back with 2 MiB pages (Linux transparent huge pages, asked for by `madvise`). With
//! 4 KiB pages nearly every load from a mesh's 10-40 MB of nodes and triangles also misses the
//! TLB and waits for a page walk.

use std::fmt;
use std::ops::Deref;

use bytemuck::Pod;
use memmap2::{Mmap, MmapOptions};

/// Smaller arrays would not fill a huge page: they stay on the heap.
const MIN_BYTES: usize = 2 << 20;

pub struct HugeArray<T> {
    storage: Storage<T>,
}

enum Storage<T> {
    /// Exactly the items' bytes, in a page-aligned anonymous mapping.
    Mapped(Mmap),
    Heap(Vec<T>),
}

impl<T: Pod> HugeArray<T> {
    pub fn new(items: Vec<T>) -> Self {
        let bytes: &[u8] = bytemuck::cast_slice(&items);
        let storage = if bytes.len() >= MIN_BYTES {
            map_huge(bytes).map_or(Storage::Heap(items), Storage::Mapped)
        } else {
            Storage::Heap(items)
        };
        HugeArray { storage }
    }

    fn is_mapped(&self) -> bool {
        matches!(self.storage, Storage::Mapped(_))
    }
}

/// A read-only copy of `bytes`, advised to use huge pages before it is written, so the page
/// faults of the copy allocate them.
fn map_huge(bytes: &[u8]) -> std::io::Result<Mmap> {
    let mut map = MmapOptions::new().len(bytes.len()).map_anon()?;
    #[cfg(target_os = "linux")]
    map.advise(memmap2::Advice::HugePage)?;
    map.copy_from_slice(bytes);
    map.make_read_only()
}

impl<T: Pod> Deref for HugeArray<T> {
    type Target = [T];

    /// (Checks the mapping's alignment and length: take the slice once per traversal.)
    #[inline]
    fn deref(&self) -> &[T] {
        match &self.storage {
            Storage::Mapped(map) => bytemuck::cast_slice(map),
            Storage::Heap(items) => items,
        }
    }
}

impl<T: Pod> fmt::Debug for HugeArray<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("HugeArray")
            .field("len", &self.len())
            .field("mapped", &self.is_mapped())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_arrays_are_mapped_small_ones_stay_and_both_keep_their_items() {
        let large: Vec<[f32; 4]> =
            (0..MIN_BYTES / 16 + 5).map(|i| [i as f32, 1.0, 2.0, 3.0]).collect();
        let array = HugeArray::new(large.clone());
        assert!(array.is_mapped());
        assert_eq!(&array[..], &large[..]);
        let small = vec![7u32, 8, 9];
        let array = HugeArray::new(small.clone());
        assert!(!array.is_mapped());
        assert_eq!(&array[..], &small[..]);
        assert!(HugeArray::<u32>::new(Vec::new()).is_empty());
    }
}
