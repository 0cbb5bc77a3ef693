//! Wavefront OBJ files: an atomic writer and a reader for the subset it writes.

pub(crate) mod read;
pub(crate) mod write;
