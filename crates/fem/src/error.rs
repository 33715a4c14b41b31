//! Errors of mesh construction and assembly. Each names the input at fault (field, file,
//! element, node set) and the offending value, so that a scene file can be fixed from the
//! message alone.
use std::path::PathBuf;

/// Why a mesh could not be built, read or queried.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// An argument (coordinate list, ratio, box, ...) is out of its domain.
    #[error("invalid {field}: {reason}")]
    InvalidInput { field: &'static str, reason: String },
    /// The file could not be read from disk.
    #[error("cannot read Gmsh file {path}: {reason}")]
    Io { path: PathBuf, reason: String },
    /// The bytes are not a Gmsh 4.1 file we can use (syntax, truncation, unsupported content).
    #[error("Gmsh file: {reason}")]
    Msh { reason: String },
    /// One element is unusable: inverted, degenerate, wrong node count, unknown node.
    /// `element` reads e.g. "Gmsh element 12" or "triangle 3".
    #[error("{element}: {reason}")]
    BadElement { element: String, reason: String },
    /// A box query selected nothing; scenes name node and edge sets by box, so an empty
    /// selection is almost always a typo in the box.
    #[error("no {what} of the mesh lies in the box min = {min:?}, max = {max:?}")]
    EmptyBox {
        what: &'static str,
        min: [f64; 2],
        max: [f64; 2],
    },
}

impl MeshError {
    pub(crate) fn invalid(field: &'static str, reason: impl Into<String>) -> Self {
        MeshError::InvalidInput {
            field,
            reason: reason.into(),
        }
    }

    pub(crate) fn msh(reason: impl Into<String>) -> Self {
        MeshError::Msh {
            reason: reason.into(),
        }
    }

    pub(crate) fn element(element: impl Into<String>, reason: impl Into<String>) -> Self {
        MeshError::BadElement {
            element: element.into(),
            reason: reason.into(),
        }
    }
}

/// Why degrees of freedom or global operators could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FemError {
    /// An argument (density, constraint, load, field length, ...) is out of its domain.
    #[error("invalid {field}: {reason}")]
    InvalidInput { field: &'static str, reason: String },
    /// The mesh itself is unusable.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

impl FemError {
    pub(crate) fn invalid(field: &'static str, reason: impl Into<String>) -> Self {
        FemError::InvalidInput {
            field,
            reason: reason.into(),
        }
    }
}
