//! The error of a contact pair whose geometry cannot give contact points.

/// A contact pair whose geometry cannot give contact points: the message
/// names what is wrong (a master with no facet, meshes of different
/// dimensions, a slave node at a sphere's centre...).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct GeometryError(pub String);
