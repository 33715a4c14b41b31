//! Reader for the Siconos plasticity test-problem text format
//! (`numerics/src/Plasticity/test/data/*.dat` in the Siconos project).
//!
//! # Conventions
//!
//! * All indices are 0-based; line numbers in errors are 1-based.
//! * The problem unknowns are grouped per cone: cone `i` owns entries
//!   `d*i .. d*(i+1)` of `R`, `v` and `q`; component 0 is the cone axis,
//!   components `1..d` the deviatoric part `T`.
//! * Values are returned exactly as stored in the file (no rescaling, no
//!   unit conversion; the Siconos files are dimensionless).
//!
//! # Layout (as written by Siconos `plasticity_printInFile`)
//!
//! ```text
//! d                 cone dimension
//! n_c               number of cones
//! model_type        1 = Drucker-Prager, 2 = von Mises   (absent in old files)
//! storage           NumericsMatrix storage id: 0 = dense, 2 = sparse
//! size0             rows (= n = d * n_c)
//! size1             columns (= n)
//! -- dense (0): --
//! size0<TAB>size1   sizes repeated
//! n*n values        column-major (the file's k-th value is entry (k % n, k / n))
//! -- sparse (2): --
//! origin            NumericsSparseMatrix origin: 1 = triplet, 2 = CSC
//! CSparse Version ...               (banner line, ignored)
//! triplet: m-by-n, nzmax: X nnz: Y  (then Y lines "row col : value")
//!   or, for CSC: m-by-n, nzmax: X nnz: Y, 1-norm: Z
//!                (then per column "col j : locations a to b" + "row : value")
//! -- then --
//! q                 n values
//! eta   | sigma_y   n_c values
//! theta             n_c values (Drucker-Prager only)
//! ```
//!
//! Old files (written by the former `plasticity2D_printInFile`, e.g.
//! `plasticity_2d_footing_10.dat`) have no `model_type` line and are always
//! Drucker-Prager. They are recognised by token structure, not file name.

mod lexer;
mod matrix;
mod parser;
mod sizes;

use std::path::{Path, PathBuf};

use parser::Parser;

/// Storage ids of Siconos `NM_types` (1 = sparse-block is not supported).
const STORAGE_DENSE: usize = 0;
const STORAGE_SPARSE: usize = 2;
/// `NumericsSparseOrigin`: 1 = triplet (COO), 2 = CSC.
const ORIGIN_TRIPLET: usize = 1;
const ORIGIN_CSC: usize = 2;

/// One reduced problem: find R, v with v = W R + q and, per cone i,
/// R_i = P_K(R_i - rho (v_i0 + theta_i |v_iT|, v_iT)).
///
/// `K_i` is the Drucker-Prager cone of slope `eta_i` (or the von Mises
/// cylinder of radius `sigma_y,i`); see [`SiconosModel`].
#[derive(Debug, Clone, PartialEq)]
pub struct SiconosProblem {
    /// Components per cone, `d` (3 in all shipped files).
    pub cone_dimension: usize,
    /// Number of cones, `n_c`.
    pub n_cones: usize,
    /// The `n x n` matrix `W` (Siconos calls it `M`), `n = d * n_c`.
    pub matrix: SiconosMatrix,
    /// The vector `q`, length `n`.
    pub q: Vec<f64>,
    /// Yield model and its per-cone parameters.
    pub model: SiconosModel,
}

/// Storage of the problem matrix, as found in the file.
#[derive(Debug, Clone, PartialEq)]
pub enum SiconosMatrix {
    /// Row-major n*n values (converted from the file's column-major order).
    Dense { n: usize, values: Vec<f64> },
    /// Triplets (row, col, value) as stored; duplicates are summed by consumers.
    Sparse {
        n: usize,
        triplets: Vec<(usize, usize, f64)>,
    },
}

/// Per-cone model parameters (each vector has length `n_c`).
#[derive(Debug, Clone, PartialEq)]
pub enum SiconosModel {
    /// Cone `|R_T| <= eta_i R_0` with flow coupling `theta_i`
    /// (`theta_i = 0`: associative). `eta_i >= 0`; `theta_i` any finite value.
    DruckerPrager { eta: Vec<f64>, theta: Vec<f64> },
    /// Cylinder `|R_T| <= sigma_y,i` (axis component free), `sigma_y,i >= 0`.
    VonMises { sigma_y: Vec<f64> },
}

/// Why a file could not be read. Every parse error names the 1-based line,
/// what was expected and what was found; read from a file ([`SiconosProblem::from_path`]),
/// it is wrapped in [`SiconosError::File`], which names the file.
#[derive(Debug, thiserror::Error)]
pub enum SiconosError {
    /// The file could not be read.
    #[error("cannot read Siconos problem {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A token had the wrong form or an invalid value.
    #[error("line {line}: expected {expected}, found `{found}`")]
    Invalid {
        line: usize,
        expected: String,
        found: String,
    },
    /// The input ended before the problem was complete.
    #[error("line {line}: unexpected end of input, expected {expected}")]
    UnexpectedEof { line: usize, expected: String },
    /// Non-whitespace text after the last model parameter.
    #[error("line {line}: expected end of input after the model parameters, found `{found}`")]
    TrailingData { line: usize, found: String },
    /// The sizes of the header disagree with each other (`d * n_c` against the matrix
    /// size lines); `message` says which line the data that follows contradicts.
    #[error("line {line}: {message}")]
    Size { line: usize, message: String },
    /// A parse error in the file `path`.
    #[error("{}: {error}", path.display())]
    File {
        path: PathBuf,
        error: Box<SiconosError>,
    },
}

impl SiconosError {
    /// The error without the file it was found in.
    pub fn in_text(&self) -> &SiconosError {
        match self {
            SiconosError::File { error, .. } => error,
            e => e,
        }
    }
}

impl SiconosProblem {
    /// Reads and parses a `.dat` file; a parse error names the file
    /// ([`SiconosError::File`]).
    pub fn from_path(path: &Path) -> Result<Self, SiconosError> {
        let text = std::fs::read_to_string(path).map_err(|source| SiconosError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text).map_err(|e| SiconosError::File {
            path: path.to_path_buf(),
            error: Box::new(e),
        })
    }

    /// Parses the text of a `.dat` file (either header variant).
    pub fn parse(text: &str) -> Result<Self, SiconosError> {
        Parser::new(text).problem()
    }

    /// Problem size `n = d * n_c`.
    pub fn n(&self) -> usize {
        self.cone_dimension * self.n_cones
    }

    /// entry (i, j) regardless of storage (sums duplicate triplets); used by tests
    ///
    /// Panics if `i >= n` or `j >= n` (caller error, like slice indexing).
    pub fn matrix_entry(&self, i: usize, j: usize) -> f64 {
        let n = self.n();
        assert!(
            i < n && j < n,
            "matrix_entry({i}, {j}) out of range for n = {n}"
        );
        match &self.matrix {
            SiconosMatrix::Dense { n, values } => values[i * n + j],
            SiconosMatrix::Sparse { triplets, .. } => triplets
                .iter()
                .filter(|&&(r, c, _)| r == i && c == j)
                .map(|&(_, _, v)| v)
                .sum(),
        }
    }
}
