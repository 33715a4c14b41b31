//! Particle outputs (MPM): the VTU read back by the small parser of `common`, the PNG map
//! checked down to the pixels, bad inputs rejected with the field named.
use crate::common;
use std::f64::consts::SQRT_2;
use std::path::PathBuf;

use common::{array, attr, distinct_colours, field_of, read_png, Png};
use talus::output::{plot_particles, write_particle_vtu, ParticlePlot, ParticleSnapshot};

fn out_dir(name: &str) -> PathBuf {
    common::target_tmp_dir("particle_outputs", name)
}

// ---------------------------------------------------------------- VTU

/// Plain components (xx, yy, zz, xy) → Mandel (xx, yy, zz, √2 xy).
fn mandel(s: [f64; 4]) -> [f64; 4] {
    [s[0], s[1], s[2], SQRT_2 * s[3]]
}

/// Von Mises from plain components, written independently of the Mandel form.
fn von_mises_plain(s: [f64; 4]) -> f64 {
    let [xx, yy, zz, xy] = s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * xy * xy).sqrt()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

#[test]
fn particle_vtu_has_one_vertex_per_particle_and_plain_stress_components() {
    let position = [[0.1, 0.2], [-1.5, 1.0 / 3.0], [2.0, 0.0]];
    let velocity = [[1.0, -2.0], [0.0, 0.5], [-1e-3, 7.0]];
    let volume = [0.01, 0.02, 0.015];
    let mass = [18.0, 36.0, 27.0];
    // Plain components xx, yy, zz, xy in Pa: compression with shear, pure shear, tension.
    let plain = [
        [-1e5, -2e5, -1.5e5, 3e4],
        [0.0, 0.0, 0.0, -4.5e4],
        [1.0e3, 2.5e3, -7.0e2, 1.2e3],
    ];
    let stress = plain.map(mandel);
    let plastic = [0.0, 0.25, 1e-3];
    let s = ParticleSnapshot {
        time: 0.375,
        position: &position,
        velocity: &velocity,
        volume: &volume,
        mass: &mass,
        stress: &stress,
        plastic_strain: &plastic,
    };
    let path = out_dir("vtu").join("particles.vtu");
    write_particle_vtu(&path, &s).unwrap();
    let xml = std::fs::read_to_string(&path).unwrap();

    assert!(xml.contains(r#"<VTKFile type="UnstructuredGrid""#));
    assert_eq!(attr(&xml, "NumberOfPoints"), "3");
    assert_eq!(attr(&xml, "NumberOfCells"), "3");
    assert_eq!(array(&xml, "types"), [1.0; 3], "VTK_VERTEX is 1");
    assert_eq!(array(&xml, "connectivity"), [0.0, 1.0, 2.0]);
    assert_eq!(array(&xml, "offsets"), [1.0, 2.0, 3.0]);
    assert_eq!(array(&xml, "TimeValue"), [0.375]);

    let points = array(&xml, "Points");
    let v = array(&xml, "velocity");
    assert_eq!((points.len(), v.len()), (9, 9));
    for i in 0..3 {
        assert_eq!(
            points[3 * i..3 * i + 3],
            [position[i][0], position[i][1], 0.0]
        );
        assert_eq!(v[3 * i..3 * i + 3], [velocity[i][0], velocity[i][1], 0.0]);
    }
    assert_eq!(array(&xml, "volume"), volume);
    assert_eq!(array(&xml, "mass"), mass);
    assert_eq!(array(&xml, "plastic_strain"), plastic);

    // Symmetric tensor, VTK order XX, YY, ZZ, XY, YZ, XZ, back in plain components.
    let sigma = array(&xml, "stress");
    assert_eq!(sigma.len(), 18);
    for (p, s) in plain.iter().enumerate() {
        let written = &sigma[6 * p..6 * p + 6];
        let expected = [s[0], s[1], s[2], s[3], 0.0, 0.0];
        for (c, (w, e)) in written.iter().zip(expected).enumerate() {
            assert!(close(*w, e), "particle {p} component {c}: {w} vs {e}");
        }
    }
    // The first particle by hand: p = 150 kPa, q = √(7.5e9 + 3·9e8) = √1.02e10 Pa.
    let vm = array(&xml, "von_mises");
    let p = array(&xml, "pressure");
    assert!(close(p[0], 1.5e5), "pressure {}", p[0]);
    assert!(close(vm[0], 1.02e10_f64.sqrt()), "von Mises {}", vm[0]);
    assert!(close(vm[1], 3f64.sqrt() * 4.5e4), "pure shear: {}", vm[1]);
    for (i, s) in plain.iter().enumerate() {
        assert!(
            close(vm[i], von_mises_plain(*s)),
            "von Mises {i}: {}",
            vm[i]
        );
        assert!(
            close(p[i], -(s[0] + s[1] + s[2]) / 3.0),
            "pressure {i}: {}",
            p[i]
        );
    }

    // Everything is point data (there are no cell fields for particles).
    let point_data = &xml[xml.find("<PointData").unwrap()..xml.find("</PointData>").unwrap()];
    for name in [
        "velocity",
        "volume",
        "mass",
        "stress",
        "von_mises",
        "pressure",
    ] {
        assert!(point_data.contains(&format!("Name=\"{name}\"")), "{name}");
    }
    assert!(point_data.contains(r#"Tensors="stress""#));
    assert!(!xml.contains("<CellData"));
    assert!(!xml.contains("NaN") && !xml.contains("inf"));
}

#[test]
fn bad_particle_inputs_name_the_field_and_write_nothing() {
    let dir = out_dir("bad");
    let two = [[0.0, 0.0], [1.0, 0.0]];
    let good = ParticleSnapshot {
        time: 0.0,
        position: &two,
        velocity: &two,
        volume: &[1.0, 1.0],
        mass: &[1.0, 1.0],
        stress: &[[0.0; 4]; 2],
        plastic_strain: &[0.0, 0.0],
    };
    let vtu = dir.join("bad.vtu");
    let _ = std::fs::remove_file(&vtu);
    write_particle_vtu(&vtu, &good).unwrap();
    std::fs::remove_file(&vtu).unwrap();

    let nan_position = [[0.0, 0.0], [f64::NAN, 0.0]];
    let nan_stress = [[0.0; 4], [-1e5, -1e5, f64::NAN, 0.0]];
    let cases: [(ParticleSnapshot, &str, &str); 9] = [
        (
            ParticleSnapshot {
                velocity: &two[..1],
                ..good
            },
            "velocity",
            "1 entries",
        ),
        (
            ParticleSnapshot {
                mass: &[1.0; 3],
                ..good
            },
            "mass",
            "3 entries",
        ),
        (
            ParticleSnapshot {
                stress: &[[0.0; 4]],
                ..good
            },
            "stress",
            "1 entries",
        ),
        (
            ParticleSnapshot {
                position: &nan_position,
                ..good
            },
            "position",
            "NaN",
        ),
        (
            ParticleSnapshot {
                stress: &nan_stress,
                ..good
            },
            "stress",
            "NaN",
        ),
        (
            ParticleSnapshot {
                volume: &[1.0, f64::INFINITY],
                ..good
            },
            "volume",
            "inf",
        ),
        (
            ParticleSnapshot {
                plastic_strain: &[f64::NAN, 0.0],
                ..good
            },
            "plastic_strain",
            "NaN",
        ),
        (
            ParticleSnapshot {
                time: f64::NAN,
                ..good
            },
            "time",
            "NaN",
        ),
        (
            ParticleSnapshot {
                position: &[],
                velocity: &[],
                volume: &[],
                mass: &[],
                stress: &[],
                plastic_strain: &[],
                ..good
            },
            "position",
            "no particles",
        ),
    ];
    for (snapshot, field, bad) in cases {
        let err = write_particle_vtu(&vtu, &snapshot).unwrap_err();
        let message = err.to_string();
        assert_eq!(field_of(err), field);
        assert!(message.contains(bad), "`{field}`: {message}");
        assert!(!vtu.exists(), "a file was written for bad `{field}`");
    }

    let png = dir.join("bad.png");
    let _ = std::fs::remove_file(&png);
    let view = ParticlePlot {
        title: "bad",
        value_label: "v",
        bounds: None,
        marker_size: None,
        floor: None,
    };
    let plot = |position: &[[f64; 2]], value: &[f64], view: ParticlePlot| {
        let err = plot_particles(&png, position, value, view).unwrap_err();
        let message = err.to_string();
        (field_of(err), message)
    };
    let cases = [
        (plot(&two, &[1.0], view), "value", "1 entries"),
        (plot(&nan_position, &[1.0, 2.0], view), "position", "NaN"),
        (plot(&two, &[1.0, f64::NAN], view), "value", "NaN"),
        (plot(&[], &[], view), "position", "no particles"),
        (
            plot(
                &two,
                &[1.0, 2.0],
                ParticlePlot {
                    bounds: Some([[1.0, 0.0], [0.0, 1.0]]),
                    ..view
                },
            ),
            "bounds",
            "[[1.0, 0.0], [0.0, 1.0]]",
        ),
        (
            plot(
                &two,
                &[1.0, 2.0],
                ParticlePlot {
                    marker_size: Some(0.0),
                    ..view
                },
            ),
            "marker_size",
            "0",
        ),
        (
            plot(
                &two,
                &[1.0, 2.0],
                ParticlePlot {
                    floor: Some(f64::NAN),
                    ..view
                },
            ),
            "floor",
            "NaN",
        ),
    ];
    for ((field, message), expected, bad) in cases {
        assert_eq!(field, expected, "{message}");
        assert!(message.contains(bad), "`{field}`: {message}");
        assert!(!png.exists(), "a PNG was written for bad `{field}`");
    }
}

// ---------------------------------------------------------------- PNG

/// Plotting area of a 1200 px map: left edge after the 15 px margin and the 80 px y-label
/// area, top edge after the 60 px title band and the 15 px margin; 900 px wide.
const PLOT_LEFT: f64 = 95.0;
const PLOT_TOP: f64 = 75.0;
const PLOT_WIDTH: f64 = 900.0;

/// The pixel at (x, y) m of a map whose window starts at `x0` and ends at `y1`, with
/// `scale` m per pixel.
fn pixel(png: &Png, (x0, y1, scale): (f64, f64, f64), x: f64, y: f64) -> [u8; 3] {
    let px = (PLOT_LEFT + (x - x0) / scale).round() as usize;
    let py = (PLOT_TOP + (y1 - y) / scale).round() as usize;
    png.rgb[py * png.width as usize + px]
}

fn near(p: [u8; 3], q: [u8; 3]) -> bool {
    p.iter().zip(q).all(|(a, b)| a.abs_diff(b) <= 3)
}

/// Pixels of colour `c` left of the colour bar (whose 190 px band has every colour).
fn count_left_of_bar(png: &Png, c: [u8; 3]) -> usize {
    let w = png.width as usize;
    (0..png.rgb.len())
        .filter(|&k| k % w < w - 190 && near(png.rgb[k], c))
        .count()
}

const WHITE: [u8; 3] = [255, 255, 255];
const VIRIDIS_MIN: [u8; 3] = [0x44, 0x01, 0x54];
const VIRIDIS_MID: [u8; 3] = [0x21, 0x91, 0x8c];
const VIRIDIS_MAX: [u8; 3] = [0xfd, 0xe7, 0x25];

/// A 9 × 5 lattice, spacing 0.25 m, centres in [0.5, 2.5] × [0.25, 1.25]; value = x.
fn lattice() -> (Vec<[f64; 2]>, Vec<f64>) {
    let position: Vec<[f64; 2]> = (0..5)
        .flat_map(|j| (0..9).map(move |i| [0.5 + 0.25 * i as f64, 0.25 + 0.25 * j as f64]))
        .collect();
    let value = position.iter().map(|p| p[0]).collect();
    (position, value)
}

#[test]
fn particle_png_in_a_window_tiles_the_lattice_at_equal_scale() {
    let (position, value) = lattice();
    let path = out_dir("png").join("lattice.png");
    let view = ParticlePlot {
        title: "Lattice coloured by x",
        value_label: "x [m]",
        bounds: Some([[0.0, 0.0], [4.0, 2.0]]),
        marker_size: None,
        floor: Some(0.05),
    };
    plot_particles(&path, &position, &value, view).unwrap();
    let png = read_png(&path);
    // A 4 m × 2 m window on the 900 px plot width: 450 px high, + 150 px of frame.
    assert_eq!((png.width, png.height), (1200, 600));
    let frame = (0.0, 2.0, 4.0 / PLOT_WIDTH);

    // Both ends of the colour map, at the first and last columns of particles.
    assert!(near(pixel(&png, frame, 0.5, 0.75), VIRIDIS_MIN));
    assert!(near(pixel(&png, frame, 2.5, 0.75), VIRIDIS_MAX));
    // The particles' squares (side = mean spacing, 0.25 m) tile [0.375, 2.625] ×
    // [0.125, 1.375] without gaps, and nothing is drawn past them.
    let mut inside = Vec::new();
    for i in 0..=80 {
        for j in 0..=40 {
            let (x, y) = (
                0.4 + 2.2 * f64::from(i) / 80.0,
                0.15 + 1.2 * f64::from(j) / 40.0,
            );
            inside.push(pixel(&png, frame, x, y));
        }
    }
    assert!(
        inside.iter().all(|&p| p != WHITE),
        "a gap between particles"
    );
    let colours: std::collections::HashSet<_> = inside.iter().collect();
    assert!(
        colours.len() >= 9,
        "{} colours in the particle area",
        colours.len()
    );
    for (x, y) in [
        (0.3, 0.75),
        (2.7, 0.75),
        (1.5, 1.45),
        (3.5, 1.0),
        (1.5, 1.9),
    ] {
        assert_eq!(pixel(&png, frame, x, y), WHITE, "at ({x}, {y})");
    }
    // Equal scale: the first column (one colour) is 5 squares high and 1 square wide.
    let run = |dx: f64, dy: f64| {
        (0..2000)
            .map(|k| {
                pixel(
                    &png,
                    frame,
                    0.5 + dx * f64::from(k),
                    0.75 + dy * f64::from(k),
                )
            })
            .take_while(|&p| near(p, VIRIDIS_MIN))
            .count() as f64
    };
    let step = frame.2 / 2.0;
    let (width_px, height_px) = (
        run(step, 0.0) + run(-step, 0.0),
        run(0.0, step) + run(0.0, -step),
    );
    assert!(
        (width_px / 2.0 - 0.25 / frame.2).abs() <= 2.0,
        "square {width_px} half-px wide"
    );
    assert!(
        (height_px / width_px - 5.0).abs() < 0.2,
        "{height_px} / {width_px}"
    );
    // The floor: a dark line at y = 0.05 m, away from the particles.
    let floor_row = (-3..=3).map(|k| pixel(&png, frame, 3.5, 0.05 + f64::from(k) * frame.2));
    assert!(
        floor_row.into_iter().any(|p| p.iter().all(|&c| c < 80)),
        "no floor line"
    );
}

#[test]
fn particle_png_fits_a_heap_and_draws_constant_and_single_particles() {
    // A heap: rows of particles, 0.1 m apart, narrowing upwards; value like a plastic strain.
    let mut position = Vec::new();
    for j in 0..20 {
        for i in 0..(80 - 4 * j) {
            position.push([
                0.05 + 0.2 * f64::from(j) + 0.1 * f64::from(i),
                0.05 + 0.1 * f64::from(j),
            ]);
        }
    }
    let value: Vec<f64> = position
        .iter()
        .map(|p| 0.1 * (-((p[0] - 4.0 - p[1]).powi(2)) / 0.3).exp())
        .collect();
    let path = out_dir("png").join("heap.png");
    let view = ParticlePlot {
        title: "Heap: equivalent plastic strain",
        value_label: "plastic strain [-]",
        bounds: None,
        marker_size: None,
        floor: Some(0.0),
    };
    plot_particles(&path, &position, &value, view).unwrap();
    let png = read_png(&path);
    // Squares of 0.1 m (the spacing) fill [0, 8] × [0, 2]; with 3 % of 8 m around, the
    // window is 8.48 m × 2.48 m, so the plot is 900 × 263 px at equal scale.
    assert_eq!((png.width, png.height), (1200, 263 + 150));
    assert!(
        distinct_colours(&png) > 30,
        "{} colours",
        distinct_colours(&png)
    );
    assert!(count_left_of_bar(&png, VIRIDIS_MIN) > 1000);
    assert!(count_left_of_bar(&png, VIRIDIS_MAX) > 100);

    // A constant value is drawn in the middle colour (no division by a zero range).
    let path = out_dir("png").join("constant.png");
    plot_particles(&path, &position, &vec![3.0; position.len()], view).unwrap();
    let png = read_png(&path);
    let mid = count_left_of_bar(&png, VIRIDIS_MID);
    assert!(mid > 10_000, "{mid} pixels of the middle colour");
    assert_eq!(count_left_of_bar(&png, VIRIDIS_MIN), 0);

    // One particle: no spacing to measure, still a visible square.
    let path = out_dir("png").join("single.png");
    plot_particles(
        &path,
        &[[1.0, 2.0]],
        &[0.5],
        ParticlePlot {
            floor: None,
            ..view
        },
    )
    .unwrap();
    let png = read_png(&path);
    let mid = count_left_of_bar(&png, VIRIDIS_MID);
    assert!(mid > 50, "{mid} pixels of the single particle");
}
