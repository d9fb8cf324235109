//! Coherence matrices J = <E E^H> (work in progress).
