//! Output writers: VTU/PVD read back by a small parser, PNGs checked down to the pixels
//! (decoded by the minimal inflate in `common`; `image` is not a dependency of this crate).
use crate::common;
use std::f64::consts::SQRT_2;
use std::path::{Path, PathBuf};

use common::{array, attr, distinct_colours, field_of, read_png};
use talus::output::{
    plot_field_on_mesh, plot_force_displacement, plot_newton_residuals, von_mises, write_pvd,
    write_vtu, FieldSnapshot, MeshView, OutputError,
};

fn out_dir(name: &str) -> PathBuf {
    common::target_tmp_dir("output_files", name)
}

// A value with all 17 significant digits in play, to catch any rounding on the way.
const AWKWARD: f64 = -1.234_567_890_123_456_7e5;

#[test]
fn vtu_p1_two_triangles_round_trips_exactly() {
    let nodes = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0 / 3.0]];
    let triangles = vec![vec![0, 1, 2], vec![0, 2, 3]];
    let displacement = [
        [1e-3, -2e-3],
        [0.1 + 0.2, 0.0],
        [AWKWARD, 1e-300],
        [-0.0, 7.0],
    ];
    let velocity = [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0], [7.0, 8.0]];
    let stress = [
        [AWKWARD, -2.5e4, 1.0 / 3.0, 1e4],
        [-1e5, -2e5, -1.5e5, -3.3e3],
    ];
    let plastic = [0.0, 0.012_345_678_901_234_5];
    let s = FieldSnapshot {
        mesh: MeshView {
            nodes: &nodes,
            elements: &triangles,
        },
        time: 0.125,
        displacement: &displacement,
        velocity: &velocity,
        stress: &stress,
        plastic_strain: &plastic,
        material: None,
        pore_pressure: None,
    };
    let path = out_dir("vtu").join("p1.vtu");
    write_vtu(&path, &s).unwrap();
    let xml = std::fs::read_to_string(&path).unwrap();

    assert_eq!(attr(&xml, "NumberOfPoints"), "4");
    assert_eq!(attr(&xml, "NumberOfCells"), "2");
    assert_eq!(array(&xml, "types"), [5.0, 5.0]);
    assert_eq!(array(&xml, "connectivity"), [0.0, 1.0, 2.0, 0.0, 2.0, 3.0]);
    assert_eq!(array(&xml, "offsets"), [3.0, 6.0]);
    assert_eq!(array(&xml, "TimeValue"), [0.125]);

    let points = array(&xml, "Points");
    let u = array(&xml, "displacement");
    for (i, (x, d)) in nodes.iter().zip(&displacement).enumerate() {
        assert_eq!(points[3 * i..3 * i + 3], [x[0], x[1], 0.0]);
        assert_eq!(u[3 * i..3 * i + 3], [d[0], d[1], 0.0]);
    }
    assert_eq!(array(&xml, "velocity")[9..12], [7.0, 8.0, 0.0]);

    let sigma = array(&xml, "stress");
    assert_eq!(sigma.len(), 12);
    for (e, m) in stress.iter().enumerate() {
        // VTK symmetric-tensor order XX, YY, ZZ, XY, YZ, XZ; σxy = m₃/√2.
        assert_eq!(
            sigma[6 * e..6 * e + 6],
            [m[0], m[1], m[2], m[3] / SQRT_2, 0.0, 0.0]
        );
    }
    assert_eq!(
        array(&xml, "pressure"),
        stress.map(|m| -(m[0] + m[1] + m[2]) / 3.0)
    );
    assert_eq!(array(&xml, "von_mises"), stress.map(|m| von_mises(&m)));
    assert_eq!(array(&xml, "plastic_strain"), plastic);
    assert!(!xml.contains("NaN") && !xml.contains("inf"));
}

#[test]
fn vtu_p2_triangle_is_quadratic_and_pure_shear_gives_sqrt3_tau() {
    // Gmsh order: corners, then mid-edges 01, 12, 20 (same as VTK_QUADRATIC_TRIANGLE).
    let nodes = [
        [0.0, 0.0],
        [2.0, 0.0],
        [0.0, 2.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
    ];
    let triangles = vec![vec![0, 1, 2, 3, 4, 5]];
    let zero = [[0.0; 2]; 6];
    let tau = 37.5e3;
    let stress = [[0.0, 0.0, 0.0, SQRT_2 * tau]];
    let s = FieldSnapshot {
        mesh: MeshView {
            nodes: &nodes,
            elements: &triangles,
        },
        time: 2.0,
        displacement: &zero,
        velocity: &zero,
        stress: &stress,
        plastic_strain: &[0.5],
        material: None,
        pore_pressure: None,
    };
    let path = out_dir("vtu").join("p2.vtu");
    write_vtu(&path, &s).unwrap();
    let xml = std::fs::read_to_string(&path).unwrap();
    assert_eq!(attr(&xml, "NumberOfPoints"), "6");
    assert_eq!(attr(&xml, "NumberOfCells"), "1");
    assert_eq!(array(&xml, "types"), [22.0]);
    assert_eq!(array(&xml, "connectivity"), [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(array(&xml, "offsets"), [6.0]);
    let sigma = array(&xml, "stress");
    assert!((sigma[3] - tau).abs() <= 1e-12 * tau, "σxy = {}", sigma[3]);
    let vm = array(&xml, "von_mises")[0];
    assert!(
        (vm - 3f64.sqrt() * tau).abs() <= 1e-12 * tau,
        "von Mises {vm}"
    );
    assert_eq!(array(&xml, "pressure"), [0.0]);
}

#[test]
fn pvd_lists_files_with_times() {
    let entries: Vec<(f64, String)> = (0..4)
        .map(|i| (0.1 * i as f64, format!("step_{i:04}.vtu")))
        .chain([(1.0 / 3.0, "odd&name.vtu".to_string())])
        .collect();
    let path = out_dir("pvd").join("run.pvd");
    write_pvd(&path, &entries).unwrap();
    let xml = std::fs::read_to_string(&path).unwrap();
    assert!(xml.contains(r#"<VTKFile type="Collection""#));
    let sets: Vec<(f64, String)> = xml
        .lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| (attr(l, "timestep").parse().unwrap(), attr(l, "file")))
        .collect();
    assert_eq!(sets.len(), entries.len());
    for ((t, f), (t0, f0)) in sets.iter().zip(&entries) {
        assert_eq!(t, t0);
        assert_eq!(f.replace("&amp;", "&"), *f0);
    }
    assert!(xml.contains("odd&amp;name.vtu"));
}

// ---------------------------------------------------------------- PNG plots

/// Half of a strip-footing domain, 6 m × 4 m, P2, with the footing at the top left.
fn footing_mesh(nx: usize, ny: usize) -> (Vec<[f64; 2]>, Vec<Vec<usize>>) {
    let (w, h) = (6.0, 4.0);
    let (cols, rows) = (2 * nx + 1, 2 * ny + 1);
    let nodes = (0..rows)
        .flat_map(|j| {
            (0..cols).map(move |i| {
                [
                    w * i as f64 / (cols - 1) as f64,
                    -h + h * j as f64 / (rows - 1) as f64,
                ]
            })
        })
        .collect();
    let id = |i: usize, j: usize| j * cols + i;
    let mut triangles = Vec::new();
    for cy in 0..ny {
        for cx in 0..nx {
            let (i, j) = (2 * cx, 2 * cy);
            triangles.push(vec![
                id(i, j),
                id(i + 2, j),
                id(i + 2, j + 2),
                id(i + 1, j),
                id(i + 2, j + 1),
                id(i + 1, j + 1),
            ]);
            triangles.push(vec![
                id(i, j),
                id(i + 2, j + 2),
                id(i, j + 2),
                id(i + 1, j + 1),
                id(i + 1, j + 2),
                id(i, j + 1),
            ]);
        }
    }
    (nodes, triangles)
}

/// A settlement bowl under the footing (|x| < 1 m) and a Prandtl-like band of plastic
/// strain: made-up fields with the look of the real thing.
fn footing_fields(nodes: &[[f64; 2]], triangles: &[Vec<usize>]) -> (Vec<[f64; 2]>, Vec<f64>) {
    let u = nodes
        .iter()
        .map(|&[x, y]| {
            let bowl = (-(x * x + y * y) / 2.5).exp();
            [
                0.01 * x * bowl * (y + 4.0) / 4.0,
                -0.03 * bowl * (y + 4.0) / 4.0,
            ]
        })
        .collect();
    let strain = triangles
        .iter()
        .map(|t| {
            let c = [0, 1, 2].map(|k| nodes[t[k]]);
            let (x, y) = (
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            );
            // Prandtl: active wedge under the footing, then a fan around its edge (1, 0).
            let r = ((x - 1.0).powi(2) + y * y).sqrt();
            let fan = (-((r - 1.0) / 0.18).powi(2)).exp() * f64::from(u8::from(y < 0.0));
            let wedge = (-((y + x) / 0.12).powi(2)).exp() * f64::from(u8::from(x < 1.0));
            0.08 * fan.max(wedge) + 0.02 * (-(x * x + y * y) / 0.5).exp()
        })
        .collect();
    (u, strain)
}

fn examples_dir() -> Option<PathBuf> {
    std::env::var_os("TALUS_OUTPUT_EXAMPLES").map(PathBuf::from)
}

fn keep_example(path: &Path) {
    if let Some(dir) = examples_dir() {
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(path, dir.join(path.file_name().unwrap())).unwrap();
    }
}

#[test]
fn force_displacement_png() {
    // Hyperbolic approach to the Prandtl load (2 + π) c B with c = 10 kPa, B = 2 m.
    let qu = (2.0 + std::f64::consts::PI) * 10e3 * 2.0;
    let points: Vec<(f64, f64)> = (0..=40)
        .map(|i| {
            let u = 1e-3 * i as f64;
            (u, qu * u / (u + 2.5e-3))
        })
        .collect();
    let path = out_dir("png").join("force_displacement.png");
    plot_force_displacement(&path, &points, "Strip footing: load–settlement").unwrap();
    let png = read_png(&path);
    assert_eq!((png.width, png.height), (1000, 700));
    assert!(distinct_colours(&png) > 10);
    keep_example(&path);
}

#[test]
fn newton_residuals_png() {
    let tol = 1e-8;
    let histories: Vec<(usize, Vec<f64>)> = (1..=120)
        .map(|step| {
            // Linear phase, then quadratic; step 97 struggles.
            let mut r = vec![1e2 * (1.0 + step as f64 / 30.0)];
            let slow = if step == 97 { 8 } else { step / 40 };
            for k in 0.. {
                let last = *r.last().unwrap();
                if last < tol {
                    break;
                }
                r.push(if k < slow {
                    0.4 * last
                } else {
                    3e-4 * last * last.max(1e-2).sqrt()
                });
            }
            (step, r)
        })
        .collect();
    let path = out_dir("png").join("newton_residuals.png");
    plot_newton_residuals(&path, &histories, tol).unwrap();
    let png = read_png(&path);
    assert_eq!((png.width, png.height), (1000, 700));
    assert!(distinct_colours(&png) > 10);
    keep_example(&path);

    // An exact zero residual is drawn, not rejected.
    let path = out_dir("png").join("newton_zero.png");
    plot_newton_residuals(&path, &[(1, vec![1.0, 1e-6, 0.0])], tol).unwrap();
    assert_eq!(read_png(&path).width, 1000);
}

#[test]
fn field_on_deformed_p2_mesh_png() {
    let (nodes, triangles) = footing_mesh(36, 24);
    let (u, strain) = footing_fields(&nodes, &triangles);
    let mesh = MeshView {
        nodes: &nodes,
        elements: &triangles,
    };
    let path = out_dir("png").join("field_plastic_strain.png");
    plot_field_on_mesh(
        &path,
        &mesh,
        Some((&u, 10.0)),
        &strain,
        "Footing at t = 3 s",
        "Equivalent plastic strain [-]",
    )
    .unwrap();
    let png = read_png(&path);
    assert_eq!(png.width, 1200);
    assert!(png.height > 300, "height {}", png.height);
    assert!(
        distinct_colours(&png) > 50,
        "{} colours",
        distinct_colours(&png)
    );
    // Both ends of the colour map are painted (viridis dark purple and yellow).
    let near = |p: &[u8; 3], q: [u8; 3]| p.iter().zip(q).all(|(a, b)| a.abs_diff(b) <= 3);
    assert!(png.rgb.iter().any(|p| near(p, [0x44, 0x01, 0x54])));
    assert!(png.rgb.iter().any(|p| near(p, [0xfd, 0xe7, 0x25])));
    keep_example(&path);
}

#[test]
fn field_on_undeformed_p1_mesh_png() {
    let nodes = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
    let triangles = vec![vec![0, 1, 2], vec![0, 2, 3]];
    let mesh = MeshView {
        nodes: &nodes,
        elements: &triangles,
    };
    let path = out_dir("png").join("field_p1.png");
    plot_field_on_mesh(
        &path,
        &mesh,
        None,
        &[-150e3, -20e3],
        "title",
        "Pressure p [Pa]",
    )
    .unwrap();
    let png = read_png(&path);
    assert_eq!(png.width, 1200);
    assert!(distinct_colours(&png) > 3);
    // A constant field is drawn too (one colour, mid-scale).
    plot_field_on_mesh(&path, &mesh, None, &[1.0, 1.0], "title", "constant").unwrap();
}

// ---------------------------------------------------------------- bad inputs

#[test]
fn bad_inputs_name_the_field_and_write_nothing() {
    let dir = out_dir("bad");
    let nodes = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let triangles = vec![vec![0, 1, 2]];
    let mesh = MeshView {
        nodes: &nodes,
        elements: &triangles,
    };
    let zero = [[0.0; 2]; 3];
    let good = FieldSnapshot {
        mesh,
        time: 0.0,
        displacement: &zero,
        velocity: &zero,
        stress: &[[0.0; 4]],
        plastic_strain: &[0.0],
        material: None,
        pore_pressure: None,
    };
    let vtu = dir.join("bad.vtu");
    let _ = std::fs::remove_file(&vtu);

    let short = [[0.0; 2]; 2];
    let cases: [(FieldSnapshot, &str); 6] = [
        (
            FieldSnapshot {
                displacement: &short,
                ..good
            },
            "displacement",
        ),
        (
            FieldSnapshot {
                velocity: &short,
                ..good
            },
            "velocity",
        ),
        (
            FieldSnapshot {
                stress: &[[0.0, f64::NAN, 0.0, 0.0]],
                ..good
            },
            "stress",
        ),
        (
            FieldSnapshot {
                stress: &[[0.0; 4], [0.0; 4]],
                ..good
            },
            "stress",
        ),
        (
            FieldSnapshot {
                plastic_strain: &[f64::INFINITY],
                material: None,
                pore_pressure: None,
                ..good
            },
            "plastic_strain",
        ),
        (
            FieldSnapshot {
                time: f64::NAN,
                ..good
            },
            "time",
        ),
    ];
    for (snapshot, field) in cases {
        assert_eq!(field_of(write_vtu(&vtu, &snapshot).unwrap_err()), field);
        assert!(!vtu.exists(), "a file was written for bad `{field}`");
    }
    let wrong_index = vec![vec![0, 1, 7]];
    let bad_mesh = FieldSnapshot {
        mesh: MeshView {
            nodes: &nodes,
            elements: &wrong_index,
        },
        ..good
    };
    assert_eq!(
        field_of(write_vtu(&vtu, &bad_mesh).unwrap_err()),
        "mesh.elements"
    );
    let nan_node = [[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]];
    let bad_nodes = FieldSnapshot {
        mesh: MeshView {
            nodes: &nan_node,
            elements: &triangles,
        },
        ..good
    };
    assert_eq!(
        field_of(write_vtu(&vtu, &bad_nodes).unwrap_err()),
        "mesh.nodes"
    );

    let pvd = dir.join("bad.pvd");
    assert_eq!(field_of(write_pvd(&pvd, &[]).unwrap_err()), "entries");
    assert_eq!(
        field_of(write_pvd(&pvd, &[(f64::NAN, "a.vtu".into())]).unwrap_err()),
        "entries"
    );

    let png = dir.join("bad.png");
    let _ = std::fs::remove_file(&png);
    let err = plot_force_displacement(&png, &[], "empty").unwrap_err();
    assert!(err.to_string().contains("empty"), "{err}");
    assert_eq!(field_of(err), "points");
    assert_eq!(
        field_of(plot_force_displacement(&png, &[(0.0, 1.0), (f64::NAN, 2.0)], "t").unwrap_err()),
        "points"
    );
    assert_eq!(
        field_of(plot_newton_residuals(&png, &[], 1e-8).unwrap_err()),
        "histories"
    );
    assert_eq!(
        field_of(plot_newton_residuals(&png, &[(3, vec![])], 1e-8).unwrap_err()),
        "histories"
    );
    assert_eq!(
        field_of(plot_newton_residuals(&png, &[(3, vec![1.0, f64::NAN])], 1e-8).unwrap_err()),
        "histories"
    );
    assert_eq!(
        field_of(plot_newton_residuals(&png, &[(3, vec![1.0])], 0.0).unwrap_err()),
        "tolerance"
    );
    assert_eq!(
        field_of(plot_field_on_mesh(&png, &mesh, None, &[1.0, 2.0], "t", "v").unwrap_err()),
        "values"
    );
    assert_eq!(
        field_of(plot_field_on_mesh(&png, &mesh, None, &[f64::NAN], "t", "v").unwrap_err()),
        "values"
    );
    assert_eq!(
        field_of(
            plot_field_on_mesh(&png, &mesh, Some((&short, 1.0)), &[1.0], "t", "v").unwrap_err()
        ),
        "displacement"
    );
    assert_eq!(
        field_of(
            plot_field_on_mesh(&png, &mesh, Some((&zero, f64::NAN)), &[1.0], "t", "v").unwrap_err()
        ),
        "magnification"
    );
    assert!(!png.exists(), "a PNG was written for bad input");

    // A folder that does not exist is an Io error naming the path.
    let missing = dir.join("no_such_folder").join("x.png");
    match plot_force_displacement(&missing, &[(0.0, 0.0), (1e-3, 1e3)], "t") {
        Err(OutputError::Io { path, .. }) => assert_eq!(path, missing),
        other => panic!("expected Io, got {other:?}"),
    }
}
