//! The files the last load read (the scene, its includes, meshes, image maps), polled for a
//! change: a save is seen within `POLL` and stops the render under way.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::input::Stamp;

/// How often the files are looked at: a stat of each, a few microseconds, against a save seen a
/// fraction of a second after it is made.
pub const POLL: Duration = Duration::from_millis(25);

#[derive(Default)]
pub struct Watch {
    files: Mutex<Vec<Stamp>>,
    changed: AtomicBool,
}

impl Watch {
    /// Watches `files`, stamped as they were when read; one that changed since is a change.
    pub fn set(&self, files: Vec<Stamp>) {
        let mut watched = self.files.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        self.changed.store(files.iter().any(Stamp::changed), Ordering::SeqCst);
        *watched = files;
    }

    /// Whether a watched file changed since it was read.
    pub fn changed(&self) -> bool {
        self.changed.load(Ordering::SeqCst)
    }

    /// Looks at the files once; true if one changed.
    pub fn poll(&self) -> bool {
        let watched = self.files.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if watched.iter().any(Stamp::changed) {
            self.changed.store(true, Ordering::SeqCst);
        }
        self.changed()
    }

    /// Polls until a watched file changes.
    pub fn wait_for_change(&self) {
        while !self.poll() {
            std::thread::sleep(POLL);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_saved_after_it_was_read_is_a_change_even_before_it_is_watched() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("a.scn");
        std::fs::write(&scene, "one").unwrap();
        let watch = Watch::default();
        let read = Stamp::now(&scene);
        watch.set(vec![read.clone()]);
        assert!(!watch.poll());
        std::fs::write(&scene, "two!").unwrap();
        assert!(watch.poll());
        // Saved between the read and the watch: still seen.
        watch.set(vec![read]);
        assert!(watch.changed());
        watch.set(vec![Stamp::now(&scene)]);
        assert!(!watch.changed());
    }
}
