//! OpenImageIO safe wrapper (work in progress).
