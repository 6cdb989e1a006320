//! Splitting a render across processes and machines: what one command renders (`plan`, with the
//! scheduler's task for `--part auto`), the part files (`part_file`), and their merge
//! (`coverage` checks the headers, `merge` adds the pixels). Which samples a share takes is
//! `crate::region`'s.

pub mod coverage;
pub mod merge;
pub mod part_file;
pub mod plan;
pub mod scheduler;
