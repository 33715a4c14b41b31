//! Parallel VTU (`docs/distributed.md`, 'Outputs'): a snapshot written as pieces (one per
//! MPI rank, here written in one process) and their `.pvtu` hold what the whole VTU holds.
//!
//! - The tetrahedral block (48 P2 tetrahedra) in 3 pieces: every element is in one piece,
//!   in order, with the same corner coordinates, stress, plastic strain and material as
//!   in the whole file, and its nodes' displacements; a piece holds only its elements'
//!   nodes.
//! - The `.pvtu` declares exactly the arrays each piece holds (name, type, components)
//!   and lists the pieces' files.
//! - 10 particles in 4 pieces: each particle once, in order, with its values.
//! - A range outside the elements or particles is refused naming the field.
use crate::common;
use std::path::{Path, PathBuf};

use common::{array, attr, field_of, target_tmp_dir};
use talus::output::{
    piece_range, write_particle_vtu_piece, write_particle_vtu_with, write_pvtu, write_vtu_piece,
    write_vtu_with, FieldExtras, FieldSnapshot, MeshView, ParticleExtras, ParticleSnapshot,
};
use talus_fem::{ElementOrder, TetrahedralMesh};

fn dir(name: &str) -> PathBuf {
    let dir = target_tmp_dir("parallel_vtu", name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The `(Name, type, NumberOfComponents)` of the arrays of `<section>` in `xml`.
fn declared(xml: &str, section: &str) -> Vec<(String, String, String)> {
    let start = xml
        .find(&format!("<{section}"))
        .unwrap_or_else(|| panic!("no {section}"));
    let end = start + xml[start..].find(&format!("</{section}>")).unwrap();
    xml[start..end]
        .lines()
        .filter(|l| l.contains("DataArray "))
        .map(|l| {
            (
                attr(l, "Name"),
                attr(l, "type"),
                attr(l, "NumberOfComponents"),
            )
        })
        .collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn pieces_of_a_tetrahedral_block_hold_the_whole_snapshot() {
    let mesh = TetrahedralMesh::block(
        &[0.0, 0.5, 1.0],
        &[0.0, 1.0],
        &[0.0, 0.5, 1.0],
        ElementOrder::P2,
    )
    .unwrap();
    let n = mesh.tetrahedra.len();
    let u: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|x| [x[0], 2.0 * x[1], x[0] * x[2]])
        .collect();
    let v: Vec<[f64; 3]> = mesh.nodes.iter().map(|x| [x[2], 0.0, -x[1]]).collect();
    let stress: Vec<[f64; 6]> = (0..n)
        .map(|e| std::array::from_fn(|k| -1.0e3 * (e as f64 + 1.0) + k as f64))
        .collect();
    let plastic: Vec<f64> = (0..n).map(|e| 1e-3 * e as f64).collect();
    let material: Vec<usize> = (0..n).map(|e| e % 3).collect();
    let strain: Vec<[f64; 6]> = (0..n).map(|e| [1e-4 * e as f64; 6]).collect();
    let snapshot = FieldSnapshot {
        mesh: MeshView {
            nodes: &mesh.nodes,
            elements: &mesh.tetrahedra,
        },
        time: 0.25,
        displacement: &u,
        velocity: &v,
        stress: &stress,
        plastic_strain: &plastic,
        material: Some(&material),
        pore_pressure: None,
    };
    let extras = FieldExtras {
        strain: Some(&strain),
        plastic_strain_increment: None,
    };
    let dir = dir("block");
    write_vtu_with(&dir.join("whole.vtu"), &snapshot, &extras).unwrap();
    let whole = read(&dir.join("whole.vtu"));
    let pieces = 3;
    let mut names = Vec::new();
    let mut first_xml = String::new();
    for p in 0..pieces {
        let name = format!("piece_{p}.vtu");
        let xml = write_vtu_piece(
            &dir.join(&name),
            &snapshot,
            &extras,
            piece_range(n, p, pieces),
        )
        .unwrap();
        assert_eq!(xml, read(&dir.join(&name)), "the XML returned is the file");
        if p == 0 {
            first_xml = xml;
        }
        names.push(name);
    }
    write_pvtu(&dir.join("block.pvtu"), &first_xml, &names).unwrap();

    // Element by element, in order: corners, cell values and nodal displacements.
    let whole_points = array(&whole, "Points");
    let whole_conn = array(&whole, "connectivity");
    let whole_u = array(&whole, "displacement");
    let (whole_stress, whole_plastic, whole_material) = (
        array(&whole, "stress"),
        array(&whole, "plastic_strain"),
        array(&whole, "material"),
    );
    let mut e = 0;
    for name in &names {
        let xml = read(&dir.join(name));
        let cells: usize = attr(&xml, "NumberOfCells").parse().unwrap();
        let points: usize = attr(&xml, "NumberOfPoints").parse().unwrap();
        let (conn, pts, disp) = (
            array(&xml, "connectivity"),
            array(&xml, "Points"),
            array(&xml, "displacement"),
        );
        let (stress, plastic, mat) = (
            array(&xml, "stress"),
            array(&xml, "plastic_strain"),
            array(&xml, "material"),
        );
        let mut used = vec![false; points];
        for c in 0..cells {
            for k in 0..10 {
                let local = conn[10 * c + k] as usize;
                let global = whole_conn[10 * (e + c) + k] as usize;
                used[local] = true;
                assert_eq!(
                    pts[3 * local..3 * local + 3],
                    whole_points[3 * global..3 * global + 3]
                );
                assert_eq!(
                    disp[3 * local..3 * local + 3],
                    whole_u[3 * global..3 * global + 3]
                );
            }
            assert_eq!(
                stress[6 * c..6 * c + 6],
                whole_stress[6 * (e + c)..6 * (e + c) + 6]
            );
            assert_eq!(plastic[c], whole_plastic[e + c]);
            assert_eq!(mat[c], whole_material[e + c]);
        }
        assert!(
            used.iter().all(|&u| u),
            "{name}: a node no element of the piece uses"
        );
        for section in ["PointData", "CellData"] {
            assert_eq!(
                declared(&xml, section),
                declared(&whole, section),
                "{name} {section}"
            );
        }
        e += cells;
    }
    assert_eq!(e, n, "every element in one piece");

    // The .pvtu: the pieces' arrays, and the pieces.
    let pvtu = read(&dir.join("block.pvtu"));
    assert!(pvtu.contains(r#"type="PUnstructuredGrid""#));
    for (section, parallel) in [
        ("PointData", "PPointData"),
        ("CellData", "PCellData"),
        ("Points", "PPoints"),
    ] {
        let want: Vec<_> = declared(&first_xml, section)
            .into_iter()
            .map(|(_, t, c)| (t, c))
            .collect();
        let got: Vec<_> = declared(&pvtu, parallel)
            .into_iter()
            .map(|(_, t, c)| (t, c))
            .collect();
        assert_eq!(got, want, "{parallel}");
    }
    for name in [
        "displacement",
        "velocity",
        "stress",
        "von_mises",
        "strain",
        "material",
    ] {
        assert!(
            pvtu.contains(&format!(r#"Name="{name}""#)),
            "{name} in the .pvtu"
        );
    }
    let sources: Vec<&str> = pvtu
        .lines()
        .filter_map(|l| l.trim().strip_prefix(r#"<Piece Source=""#))
        .map(|l| &l[..l.find('"').unwrap()])
        .collect();
    assert_eq!(sources, names);

    // A range past the elements.
    let err = write_vtu_piece(&dir.join("bad.vtu"), &snapshot, &extras, n - 1..n + 1).unwrap_err();
    assert_eq!(field_of(err), "cells");
}

#[test]
fn pieces_of_particles_hold_every_particle_once() {
    let n = 10;
    let position: Vec<[f64; 2]> = (0..n).map(|i| [i as f64, 0.5 * i as f64]).collect();
    let velocity: Vec<[f64; 2]> = (0..n).map(|i| [0.1 * i as f64, -1.0]).collect();
    let volume = vec![1e-4; n];
    let mass: Vec<f64> = (0..n).map(|i| 0.15 + i as f64).collect();
    let stress: Vec<[f64; 4]> = (0..n).map(|i| [-(i as f64), -2.0, -3.0, 0.5]).collect();
    let plastic = vec![0.0; n];
    let material: Vec<usize> = (0..n).map(|i| i % 2).collect();
    let snapshot = ParticleSnapshot {
        time: 1.0,
        position: &position,
        velocity: &velocity,
        volume: &volume,
        mass: &mass,
        stress: &stress,
        plastic_strain: &plastic,
    };
    let extras = ParticleExtras {
        displacement: None,
        material: Some(&material),
    };
    let dir = dir("particles");
    write_particle_vtu_with(&dir.join("whole.vtu"), &snapshot, &extras).unwrap();
    let whole = read(&dir.join("whole.vtu"));
    let (mut points, mut masses) = (Vec::new(), Vec::new());
    for p in 0..4 {
        let xml = write_particle_vtu_piece(
            &dir.join(format!("piece_{p}.vtu")),
            &snapshot,
            &extras,
            piece_range(n, p, 4),
        )
        .unwrap();
        assert_eq!(declared(&xml, "PointData"), declared(&whole, "PointData"));
        points.extend(array(&xml, "Points"));
        masses.extend(array(&xml, "mass"));
    }
    assert_eq!(points, array(&whole, "Points"));
    assert_eq!(masses, array(&whole, "mass"));
    let err = write_particle_vtu_piece(&dir.join("bad.vtu"), &snapshot, &extras, 3..3).unwrap_err();
    assert_eq!(field_of(err), "particles");
}
