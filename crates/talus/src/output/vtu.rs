//! ParaView snapshot of one time step: VTK XML `UnstructuredGrid`, ASCII.
use std::f64::consts::SQRT_2;
use std::fmt::Write as _;
use std::path::Path;

use super::mesh::{check_finite, check_finite_scalars, check_finite_value, check_len};
use super::{MeshView, OutputError};

/// VTK cell type ids; VTK's quadratic triangle orders its nodes like Gmsh's 6-node
/// triangle (corners, then mid-edges 01, 12, 20), so connectivity is copied as is. VTK's
/// quadratic tetrahedron takes the mid-edges 01, 12, 02, 03, 13, 23 where Gmsh's 10-node
/// one has 01, 12, 20, 30, 32, 31: the last two are swapped ([`vtk_connectivity`]).
const VTK_TRIANGLE: u8 = 5;
const VTK_QUADRATIC_TRIANGLE: u8 = 22;
const VTK_TETRA: u8 = 10;
const VTK_QUADRATIC_TETRA: u8 = 24;

/// The fields of one time step: on triangles in the plane (`N = 2`, Mandel size `D = 4`,
/// the defaults) or on tetrahedra in space (`N = 3`, `D = 6`).
///
/// Units: time s, displacement m, velocity m/s, stress Pa (tension positive), plastic
/// strain dimensionless.
#[derive(Debug, Clone, Copy)]
pub struct FieldSnapshot<'a, const N: usize = 2, const D: usize = 4> {
    pub mesh: MeshView<'a, N>,
    pub time: f64,
    /// Per node, m.
    pub displacement: &'a [[f64; N]],
    /// Per node, m/s.
    pub velocity: &'a [[f64; N]],
    /// Per element (average over its Gauss points), Mandel `(xx, yy, zz, √2 xy)` (2D) or
    /// `(xx, yy, zz, √2 yz, √2 xz, √2 xy)` (3D), Pa.
    pub stress: &'a [[f64; D]],
    /// Per element, cumulative equivalent plastic strain `∫‖ε̇ᵖ‖ dt`.
    pub plastic_strain: &'a [f64],
    /// Per element, its material's index in the scene's list (`material`, from 0).
    pub material: Option<&'a [usize]>,
    /// Per element, the pore pressure (Pa, compression positive); with it the VTU also
    /// holds `effective_stress = stress + p_w I` (tension positive).
    pub pore_pressure: Option<&'a [f64]>,
}

impl<const N: usize, const D: usize> FieldSnapshot<'_, N, D> {
    /// Checked, with the stress's derived values (computed once: checked, then written).
    fn validate(&self) -> Result<Derived, OutputError> {
        if (N, D) != (2, 4) && (N, D) != (3, 6) {
            return Err(OutputError::invalid(
                "stress",
                format!("{D} Mandel components on a mesh in {N}D: 4 in 2D, 6 in 3D"),
            ));
        }
        self.mesh.validate()?;
        let (n_nodes, n_elements) = (self.mesh.nodes.len(), self.mesh.elements.len());
        check_finite_value("time", self.time)?;
        check_len("displacement", self.displacement.len(), n_nodes, "node")?;
        check_len("velocity", self.velocity.len(), n_nodes, "node")?;
        check_len("stress", self.stress.len(), n_elements, "element")?;
        check_len(
            "plastic_strain",
            self.plastic_strain.len(),
            n_elements,
            "element",
        )?;
        check_finite("displacement", self.displacement)?;
        check_finite("velocity", self.velocity)?;
        check_finite("stress", self.stress)?;
        let derived = derived(self.stress)?;
        if let Some(m) = self.material {
            check_len("material", m.len(), n_elements, "element")?;
        }
        if let Some(p) = self.pore_pressure {
            check_len("pore_pressure", p.len(), n_elements, "element")?;
            check_finite_scalars("pore_pressure", p)?;
        }
        check_finite_scalars("plastic_strain", self.plastic_strain)?;
        Ok(derived)
    }
}

/// Element fields a FEM run adds to a [`FieldSnapshot`] ([`write_vtu_with`]); each `None`
/// is left out of the file.
///
/// Both are Mandel `(xx, yy, zz, √2 xy)` like `stress`, tension (extension) positive,
/// dimensionless, one entry per element (the mean over its Gauss points); zz is the hoop
/// component `θθ` in axisymmetry.
#[derive(Debug, Clone, Copy, Default)]
pub struct FieldExtras<'a, const D: usize = 4> {
    /// Total small strain `B u` of the nodal displacement.
    pub strain: Option<&'a [[f64; D]]>,
    /// The last step's plastic strain increment `Δεᵖ = Δε − S Δσ` (`S` the elastic
    /// compliance of the element's material).
    pub plastic_strain_increment: Option<&'a [[f64; D]]>,
}

impl<const D: usize> FieldExtras<'_, D> {
    fn validate(&self, n_elements: usize) -> Result<(), OutputError> {
        let fields = [
            ("strain", self.strain),
            ("plastic_strain_increment", self.plastic_strain_increment),
        ];
        for (name, field) in fields {
            if let Some(f) = field {
                check_len(name, f.len(), n_elements, "element")?;
                check_finite(name, f)?;
            }
        }
        Ok(())
    }
}

/// Von Mises equivalent stress `√(3/2) ‖dev σ‖` of a Mandel stress (4 or 6 components:
/// normal components first, then shears), Pa.
///
/// The Mandel norm is the tensor (Frobenius) norm, so no factor is needed for the shear.
pub fn von_mises<const D: usize>(m: &[f64; D]) -> f64 {
    let p = (m[0] + m[1] + m[2]) / 3.0;
    let normal = (m[0] - p).powi(2) + (m[1] - p).powi(2) + (m[2] - p).powi(2);
    let s2 = m[3..].iter().fold(normal, |s, t| s + t.powi(2));
    (1.5 * s2).sqrt()
}

/// Mean pressure `−tr σ / 3` of a Mandel stress, Pa (compression positive).
pub fn pressure<const D: usize>(m: &[f64; D]) -> f64 {
    -(m[0] + m[1] + m[2]) / 3.0
}

/// Principal stresses `[σ1, σ2, σ3]`, `σ1 ≥ σ2 ≥ σ3`, of a Mandel stress, Pa (tension
/// positive). 2D: the in-plane pair `(σxx + σyy)/2 ± √(((σxx − σyy)/2)² + σxy²)` and
/// `σzz` (the hoop stress in axisymmetry), sorted; 3D: the eigenvalues of the tensor.
pub fn principal_stresses<const D: usize>(m: &[f64; D]) -> [f64; 3] {
    let m: &[f64] = m;
    let mut s = if m.len() == 6 {
        let t = tensor_components(m);
        let tensor = nalgebra::Matrix3::new(
            t[0], t[3], t[5], //
            t[3], t[1], t[4], //
            t[5], t[4], t[2],
        );
        let e = tensor.symmetric_eigenvalues();
        [e[0], e[1], e[2]]
    } else {
        let centre = 0.5 * (m[0] + m[1]);
        let radius = (0.5 * (m[0] - m[1])).hypot(m[3] / SQRT_2);
        [centre + radius, centre - radius, m[2]]
    };
    s.sort_by(|a, b| b.total_cmp(a));
    s
}

/// A Mandel vector's plain tensor components in VTK's order `XX, YY, ZZ, XY, YZ, XZ`
/// (2D: `YZ = XZ = 0`; 3D Mandel order `xx, yy, zz, √2 yz, √2 xz, √2 xy`).
fn tensor_components(m: &[f64]) -> [f64; 6] {
    if m.len() == 6 {
        [
            m[0],
            m[1],
            m[2],
            m[5] / SQRT_2,
            m[3] / SQRT_2,
            m[4] / SQRT_2,
        ]
    } else {
        [m[0], m[1], m[2], m[3] / SQRT_2, 0.0, 0.0]
    }
}

/// Each stress entry's von Mises stress, pressure and principal stresses ([`derived`]).
pub(super) struct Derived {
    von_mises: Vec<f64>,
    pressure: Vec<f64>,
    principal: Vec<[f64; 3]>,
}

impl Derived {
    /// The entries `range` (a piece's, computed once with the whole snapshot's).
    pub(super) fn slice(&self, range: std::ops::Range<usize>) -> Self {
        Self {
            von_mises: self.von_mises[range.clone()].to_vec(),
            pressure: self.pressure[range.clone()].to_vec(),
            principal: self.principal[range].to_vec(),
        }
    }
}

/// The derived values of every stress entry; `Invalid` unless all are finite: finite
/// stresses near `f64::MAX` could overflow.
pub(super) fn derived<const D: usize>(stress: &[[f64; D]]) -> Result<Derived, OutputError> {
    let mut d = Derived {
        von_mises: Vec::with_capacity(stress.len()),
        pressure: Vec::with_capacity(stress.len()),
        principal: Vec::with_capacity(stress.len()),
    };
    for (i, m) in stress.iter().enumerate() {
        let (q, p, s) = (von_mises(m), pressure(m), principal_stresses(m));
        if !(q.is_finite() && p.is_finite() && s.iter().all(|v| v.is_finite())) {
            return Err(OutputError::invalid(
                "stress",
                format!("entry {i} {m:?} overflows its invariants or principal stresses"),
            ));
        }
        d.von_mises.push(q);
        d.pressure.push(p);
        d.principal.push(s);
    }
    Ok(d)
}

/// Writes `s` to `path` as a VTK XML unstructured grid (ASCII).
///
/// Point data: `displacement` (m) and `velocity` (m/s) as 3-vectors (z = 0 in 2D). Cell
/// data: `stress` as a symmetric tensor in plain components, VTK order `XX, YY, ZZ, XY,
/// YZ, XZ` (2D: σxy = m₃/√2, YZ = XZ = 0; 3D: the Mandel shears over √2; Pa, tension
/// positive), `von_mises` (Pa), `pressure`
/// (−tr σ/3, Pa, compression positive), `principal_stress` (3 components `σ1 ≥ σ2 ≥ σ3`,
/// Pa, tension positive, [`principal_stresses`]) and `plastic_strain`. The time (s) is
/// stored as the `TimeValue` field. Numbers are written in Rust's shortest round-trip
/// form, so they read back exactly.
/// Cells are VTK triangles (5) and quadratic triangles (22) in 2D, tetrahedra (10) and
/// quadratic tetrahedra (24) in 3D.
pub fn write_vtu<const N: usize, const D: usize>(
    path: &Path,
    s: &FieldSnapshot<N, D>,
) -> Result<(), OutputError> {
    write_vtu_with(path, s, &FieldExtras::default())
}

/// [`write_vtu`] with the cell fields of `extras`: `strain` and `plastic_strain_increment`
/// as symmetric tensors in plain components like `stress` (tensor shear `εxy = m₃/√2`, not
/// the engineering `γxy = 2 εxy`; dimensionless, extension positive). Errors (`Invalid`,
/// nothing written): those of [`write_vtu`], an extra field without one entry per element
/// or with a non-finite value.
pub fn write_vtu_with<const N: usize, const D: usize>(
    path: &Path,
    s: &FieldSnapshot<N, D>,
    extras: &FieldExtras<D>,
) -> Result<(), OutputError> {
    let derived = s.validate()?;
    extras.validate(s.mesh.elements.len())?;
    let xml = vtu_string(s, extras, &derived);
    super::atomic::write(path, xml)
}

/// The piece of [`write_vtu_with`]'s file holding the elements `cells` (a range of
/// `s.mesh.elements`) and the nodes they use, renumbered in their order (a piece of a
/// `.pvtu`, [`super::write_pvtu`]); returns the XML written. Errors as
/// [`write_vtu_with`]'s, checked on the whole snapshot, and a range past its elements.
pub fn write_vtu_piece<const N: usize, const D: usize>(
    path: &Path,
    s: &FieldSnapshot<N, D>,
    extras: &FieldExtras<D>,
    cells: std::ops::Range<usize>,
) -> Result<String, OutputError> {
    let derived = s.validate()?;
    let n_elements = s.mesh.elements.len();
    extras.validate(n_elements)?;
    if cells.end > n_elements || cells.start > cells.end {
        return Err(OutputError::invalid(
            "cells",
            format!("{cells:?} is not a range of the {n_elements} elements"),
        ));
    }
    // Old node → new (usize::MAX: not in the piece), in ascending old order.
    let mut new_of = vec![usize::MAX; s.mesh.nodes.len()];
    for e in &s.mesh.elements[cells.clone()] {
        for &n in e {
            new_of[n] = 0;
        }
    }
    let mut kept = Vec::new();
    for (old, new) in new_of.iter_mut().enumerate() {
        if *new == 0 {
            *new = kept.len();
            kept.push(old);
        }
    }
    let pick = |v: &[[f64; N]]| -> Vec<[f64; N]> { kept.iter().map(|&n| v[n]).collect() };
    let (nodes, displacement, velocity) =
        (pick(s.mesh.nodes), pick(s.displacement), pick(s.velocity));
    let elements: Vec<Vec<usize>> = s.mesh.elements[cells.clone()]
        .iter()
        .map(|e| e.iter().map(|&n| new_of[n]).collect())
        .collect();
    let piece = FieldSnapshot {
        mesh: MeshView {
            nodes: &nodes,
            elements: &elements,
        },
        time: s.time,
        displacement: &displacement,
        velocity: &velocity,
        stress: &s.stress[cells.clone()],
        plastic_strain: &s.plastic_strain[cells.clone()],
        material: s.material.map(|m| &m[cells.clone()]),
        pore_pressure: s.pore_pressure.map(|p| &p[cells.clone()]),
    };
    let piece_extras = FieldExtras {
        strain: extras.strain.map(|e| &e[cells.clone()]),
        plastic_strain_increment: extras.plastic_strain_increment.map(|e| &e[cells.clone()]),
    };
    let xml = vtu_string(&piece, &piece_extras, &derived.slice(cells));
    super::atomic::write(path, &xml)?;
    Ok(xml)
}

fn vtu_string<const N: usize, const D: usize>(
    s: &FieldSnapshot<N, D>,
    extras: &FieldExtras<D>,
    derived: &Derived,
) -> String {
    let mesh = s.mesh;
    let mut x = String::with_capacity(64 * (mesh.nodes.len() * 3 + mesh.elements.len() * 4));
    begin_piece(&mut x, s.time, mesh.nodes.len(), mesh.elements.len());
    // Writing to a String cannot fail: the `fmt::Result`s are ignored on purpose.
    let _ = writeln!(x, r#"      <PointData Vectors="displacement">"#);
    vectors(&mut x, "displacement", s.displacement);
    vectors(&mut x, "velocity", s.velocity);
    let _ = writeln!(x, "      </PointData>");
    let _ = writeln!(
        x,
        r#"      <CellData Tensors="stress" Scalars="plastic_strain">"#
    );
    stress_and_invariants(&mut x, s.stress, derived);
    scalars(&mut x, "plastic_strain", s.plastic_strain);
    if let Some(p_w) = s.pore_pressure {
        scalars(&mut x, "pore_pressure", p_w);
        let effective: Vec<[f64; D]> = s
            .stress
            .iter()
            .zip(p_w)
            .map(|(m, p)| std::array::from_fn(|k| if k < 3 { m[k] + p } else { m[k] }))
            .collect();
        tensor(&mut x, "effective_stress", &effective);
    }
    if let Some(strain) = extras.strain {
        tensor(&mut x, "strain", strain);
    }
    if let Some(increment) = extras.plastic_strain_increment {
        tensor(&mut x, "plastic_strain_increment", increment);
    }
    if let Some(material) = s.material {
        indices(&mut x, "material", material);
    }
    let _ = writeln!(x, "      </CellData>");
    let cells: Vec<Vec<usize>> = mesh.elements.iter().map(|e| vtk_connectivity(e)).collect();
    points_and_cells(&mut x, mesh.nodes, &cells, |cell| match cell.len() {
        6 => VTK_QUADRATIC_TRIANGLE,
        4 => VTK_TETRA,
        10 => VTK_QUADRATIC_TETRA,
        _ => VTK_TRIANGLE,
    });
    end_piece(&mut x);
    x
}

/// An element's nodes in VTK's order: as Gmsh's, but a 10-node tetrahedron's last two
/// mid-edge nodes swapped (Gmsh edges 32, 31; VTK edges 13, 23).
fn vtk_connectivity(element: &[usize]) -> Vec<usize> {
    let mut cell = element.to_vec();
    if cell.len() == 10 {
        cell.swap(8, 9);
    }
    cell
}

/// XML header, `TimeValue` (s) as field data, and the opening `<Piece>` tag.
pub(super) fn begin_piece(x: &mut String, time: f64, n_points: usize, n_cells: usize) {
    let _ = writeln!(x, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        x,
        r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(x, "  <UnstructuredGrid>");
    let _ = writeln!(x, "    <FieldData>");
    let _ = writeln!(
        x,
        r#"      <DataArray type="Float64" Name="TimeValue" NumberOfTuples="1" format="ascii">"#
    );
    let _ = writeln!(x, "{time:e}");
    close_array(x, 6);
    let _ = writeln!(x, "    </FieldData>");
    let _ = writeln!(
        x,
        r#"    <Piece NumberOfPoints="{n_points}" NumberOfCells="{n_cells}">"#
    );
}

/// Closes what [`begin_piece`] opened.
pub(super) fn end_piece(x: &mut String) {
    let _ = writeln!(x, "    </Piece>");
    let _ = writeln!(x, "  </UnstructuredGrid>");
    let _ = writeln!(x, "</VTKFile>");
}

/// A 2- or 3-vector per entry, written as a 3-vector (z = 0 in 2D).
pub(super) fn vectors<const N: usize>(x: &mut String, name: &str, data: &[[f64; N]]) {
    open_array(x, "Float64", name, 3, 8);
    for v in data {
        write_point(x, v);
    }
    close_array(x, 8);
}

/// `x y z` (z = 0 for a point in the plane).
fn write_point(x: &mut String, v: &[f64]) {
    let _ = match v {
        [a, b] => writeln!(x, "{a:e} {b:e} 0"),
        [a, b, c, ..] => writeln!(x, "{a:e} {b:e} {c:e}"),
        _ => Ok(()),
    };
}

/// One integer per entry (`Int32`), e.g. a material index.
pub(super) fn indices(x: &mut String, name: &str, data: &[usize]) {
    open_array(x, "Int32", name, 1, 8);
    for i in data {
        let _ = writeln!(x, "{i}");
    }
    close_array(x, 8);
}

pub(super) fn scalars(x: &mut String, name: &str, data: &[f64]) {
    open_array(x, "Float64", name, 1, 8);
    for v in data {
        let _ = writeln!(x, "{v:e}");
    }
    close_array(x, 8);
}

/// `stress` as a symmetric tensor in plain components (VTK order `XX, YY, ZZ, XY, YZ, XZ`,
/// [`tensor_components`]), then its `von_mises`, `pressure` and `principal_stress`
/// (3 components, `σ1 ≥ σ2 ≥ σ3`), `derived` from [`derived`].
pub(super) fn stress_and_invariants<const D: usize>(
    x: &mut String,
    stress: &[[f64; D]],
    derived: &Derived,
) {
    tensor(x, "stress", stress);
    scalars(x, "von_mises", &derived.von_mises);
    scalars(x, "pressure", &derived.pressure);
    let _ = writeln!(
        x,
        r#"        <DataArray type="Float64" Name="principal_stress" NumberOfComponents="3" ComponentName0="1" ComponentName1="2" ComponentName2="3" format="ascii">"#
    );
    for [s1, s2, s3] in &derived.principal {
        let _ = writeln!(x, "{s1:e} {s2:e} {s3:e}");
    }
    close_array(x, 8);
}

/// A Mandel field (stress or strain) as a symmetric tensor in plain components.
fn tensor<const D: usize>(x: &mut String, name: &str, mandel: &[[f64; D]]) {
    let _ = writeln!(
        x,
        r#"        <DataArray type="Float64" Name="{name}" NumberOfComponents="6" ComponentName0="XX" ComponentName1="YY" ComponentName2="ZZ" ComponentName3="XY" ComponentName4="YZ" ComponentName5="XZ" format="ascii">"#
    );
    for m in mandel {
        let t = tensor_components(m);
        if D == 6 {
            let _ = writeln!(
                x,
                "{:e} {:e} {:e} {:e} {:e} {:e}",
                t[0], t[1], t[2], t[3], t[4], t[5]
            );
        } else {
            let _ = writeln!(x, "{:e} {:e} {:e} {:e} 0 0", t[0], t[1], t[2], t[3]);
        }
    }
    close_array(x, 8);
}

/// `<Points>` (z = 0 in 2D) and `<Cells>`: each cell's point ids, running offsets, VTK
/// types.
pub(super) fn points_and_cells<C: AsRef<[usize]>, const N: usize>(
    x: &mut String,
    points: &[[f64; N]],
    cells: &[C],
    cell_type: impl Fn(&[usize]) -> u8,
) {
    let _ = writeln!(x, "      <Points>");
    open_array(x, "Float64", "Points", 3, 8);
    for p in points {
        write_point(x, p);
    }
    close_array(x, 8);
    let _ = writeln!(x, "      </Points>");

    let _ = writeln!(x, "      <Cells>");
    open_array(x, "Int64", "connectivity", 1, 8);
    for cell in cells {
        let line: Vec<String> = cell.as_ref().iter().map(usize::to_string).collect();
        let _ = writeln!(x, "{}", line.join(" "));
    }
    close_array(x, 8);
    open_array(x, "Int64", "offsets", 1, 8);
    let mut offset = 0;
    for cell in cells {
        offset += cell.as_ref().len();
        let _ = writeln!(x, "{offset}");
    }
    close_array(x, 8);
    open_array(x, "UInt8", "types", 1, 8);
    for cell in cells {
        let _ = writeln!(x, "{}", cell_type(cell.as_ref()));
    }
    close_array(x, 8);
    let _ = writeln!(x, "      </Cells>");
}

fn open_array(x: &mut String, ty: &str, name: &str, components: usize, indent: usize) {
    let _ = writeln!(
        x,
        r#"{:indent$}<DataArray type="{ty}" Name="{name}" NumberOfComponents="{components}" format="ascii">"#,
        ""
    );
}

fn close_array(x: &mut String, indent: usize) {
    let _ = writeln!(x, "{:indent$}</DataArray>", "");
}
