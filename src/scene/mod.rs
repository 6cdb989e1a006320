//! Scenes: the graph `lang` produces, and `build`, which turns it into a render-ready `Scene`.

pub mod graph;
