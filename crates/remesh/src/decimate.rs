//! Quadric error decimation (Garland & Heckbert 1997).

use flatcut_mesh::TriMesh;
use serde::Deserialize;

use crate::RemeshError;
use crate::quality::QualityReport;
use crate::remesh::Provenance;

/// Options of [`decimate`].
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DecimateOptions {
    /// Face budget: stop at or below this many faces (default 50 000).
    pub target_faces: usize,
}

impl Default for DecimateOptions {
    fn default() -> Self {
        DecimateOptions {
            target_faces: 50_000,
        }
    }
}

/// Result of [`decimate`].
#[derive(Clone, Debug)]
pub struct Decimated {
    pub mesh: TriMesh,
    pub provenance: Vec<Provenance>,
    pub report: QualityReport,
}

/// Decimates `mesh` to at most `opts.target_faces` faces.
pub fn decimate(mesh: &TriMesh, opts: &DecimateOptions) -> Result<Decimated, RemeshError> {
    let _ = (mesh, opts);
    Err(RemeshError::EmptyMesh)
}
