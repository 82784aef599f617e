//! Flattening of cut surface pieces into true-size 2D patterns.
//!
//! - [`lscm`]: free-boundary least squares conformal maps (Lévy et al. 2002), one problem
//!   per connected component, solved with faer's sparse Cholesky;
//! - [`arap`] and [`refine_isometric`]: local–global ARAP (Liu et al. 2008) with the
//!   Laplacian factorised once, then Gauss–Newton on edge lengths, towards an isometry;
//! - [`unfold`]: exact breadth-first unfolding of a developable piece (a cross-check);
//! - [`place`]: never mirrored, grain along +y, bounding box at the origin;
//! - [`distortion`]: E_h, E_r and edge strain at true scale;
//! - [`flatten`]: all of the above in order.
//!
//! Nothing here reads or writes files.

pub mod arap;
mod error;
pub mod flatten;
pub mod lscm;
pub mod metrics;
pub mod piece;
pub mod placement;
pub mod refine;
pub mod triangle;
pub mod unfold;

pub use arap::{ArapOptions, ArapReport, arap};
pub use error::LscmError;
pub use flatten::{FlattenOptions, FlattenOutput, Method, flatten, flatten_with_topology};
pub use lscm::{
    Flattening, LscmOptions, PieceFlattening, Pins, auto_pins, conformal_energy, lscm, lscm_piece,
    lscm_with_topology,
};
pub use metrics::{DistortionReport, FaceDistortion, LoopLength, Summary, distortion};
pub use piece::{Piece, split_pieces};
pub use placement::{PlacementOptions, place, place_piece, principal_axis};
pub use refine::{RefineOptions, RefineReport, refine_isometric};
pub use unfold::{Unfolding, unfold};
