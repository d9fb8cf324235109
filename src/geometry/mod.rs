//! Geometry: polygon meshes with flat facets, and their loading.

pub mod asc;
pub mod convex;
pub mod cuts;
pub mod mesh;
pub mod obj;
pub mod overlap;
pub mod validate;

pub use mesh::{Facet, Mesh, TopologyError};
pub use obj::{load_obj, parse_obj, ObjError};
