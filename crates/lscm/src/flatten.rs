//! The whole flattening stage: LSCM, optional isometric refinement, placement.

use flatcut_mesh::{Topology, TriMesh};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::LscmError;
use crate::lscm::{Flattening, LscmOptions, lscm_with_topology};
use crate::placement::{PlacementOptions, place};
use crate::refine::{RefineOptions, RefineReport, refine_isometric};

/// Which flattening to compute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Method {
    /// Conformal only: angles kept, sizes drift (not a true-size pattern on curved pieces).
    #[serde(rename = "lscm")]
    Lscm,
    /// LSCM, then ARAP and Gauss–Newton on edge lengths: as close to true size as the piece
    /// allows (an isometry on a developable piece). The default.
    #[default]
    #[serde(rename = "lscm+arap")]
    LscmArap,
}

/// Options of [`flatten`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FlattenOptions {
    /// Default [`Method::LscmArap`].
    pub method: Method,
    /// The LSCM stage.
    pub lscm: LscmOptions,
    /// The refinement stage (used by [`Method::LscmArap`]).
    pub refine: RefineOptions,
    /// Placement of the pieces.
    pub placement: PlacementOptions,
}

/// A placed flattening and what the refinement did per piece.
#[derive(Clone, Debug, PartialEq)]
pub struct FlattenOutput {
    /// The pieces and combined coordinates, placed (grain along +y, side by side).
    pub flattening: Flattening,
    /// One report per piece for [`Method::LscmArap`], empty for [`Method::Lscm`].
    pub refine: Vec<RefineReport>,
}

/// Flattens every component of `mesh` ([`crate::lscm`]), refines it towards an isometry if
/// asked ([`refine_isometric`]) and places it ([`place`]). Errors as [`crate::lscm`].
pub fn flatten(mesh: &TriMesh, opts: &FlattenOptions) -> Result<FlattenOutput, LscmError> {
    let topo = Topology::build(mesh)?;
    flatten_with_topology(mesh, &topo, opts)
}

/// [`flatten`] with a topology already built for `mesh`.
pub fn flatten_with_topology(
    mesh: &TriMesh,
    topo: &Topology,
    opts: &FlattenOptions,
) -> Result<FlattenOutput, LscmError> {
    let mut flat = lscm_with_topology(mesh, topo, &opts.lscm)?;
    let refine = match opts.method {
        Method::Lscm => Vec::new(),
        Method::LscmArap => flat
            .pieces
            .par_iter_mut()
            .map(|p| refine_isometric(p, &opts.refine))
            .collect::<Result<Vec<_>, _>>()?,
    };
    place(&mut flat, &opts.placement)?;
    Ok(FlattenOutput {
        flattening: flat,
        refine,
    })
}
