//! Embree safe wrapper (work in progress).
