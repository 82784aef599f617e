//! Scan preparation: isotropic remeshing to a working resolution, decimation of huge scans,
//! hole filling; every output vertex maps back to a point of the input surface.
//!
//! Entry points: [`remesh`] (Botsch & Kobbelt 2004 isotropic remeshing with boundaries and
//! feature lines kept, optional hole filling and curvature adaptivity) and [`decimate`]
//! (Garland & Heckbert quadric error decimation to a face budget). Both return a new
//! [`TriMesh`](flatcut_mesh::TriMesh), a [`Provenance`] per output vertex and a
//! [`QualityReport`].

mod decimate;
mod error;
mod halfedge;
mod holes;
mod quality;
mod remesh;
pub mod taubin;

pub use decimate::{DecimateOptions, Decimated, decimate};
pub use error::RemeshError;
pub use holes::{Hole, find_holes};
pub use quality::{DistanceStats, QualityReport, quality_report};
pub use remesh::{Provenance, RemeshOptions, Remeshed, remesh, roughness};
