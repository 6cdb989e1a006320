//! The pool of worker threads a command runs on (`--threads`).

/// The most worker threads `--threads` starts.
pub const MAX_THREADS: usize = 1024;

#[derive(Debug, thiserror::Error)]
pub enum ThreadsError {
    #[error("error: --threads {0} is out of range (1 to {max})", max = MAX_THREADS)]
    OutOfRange(usize),
    #[error("error: cannot start {0} threads: {1}")]
    Start(usize, rayon::ThreadPoolBuildError),
}

/// Runs `f` on a pool of `threads` workers (rayon's default pool when `None`).
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> T + Send,
) -> Result<T, ThreadsError> {
    match threads {
        None => Ok(f()),
        Some(n) if !(1..=MAX_THREADS).contains(&n) => Err(ThreadsError::OutOfRange(n)),
        Some(n) => Ok(rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| ThreadsError::Start(n, e))?
            .install(f)),
    }
}
