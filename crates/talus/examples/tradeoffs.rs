//! The speed/accuracy trade on the paper footing (`scenes/footing.toml`): Newton tolerance,
//! time step, mesh size and element order. Each run pushes the footing 1.5 mm (the plateau
//! starts at about 0.6 mm); the limit load is the force at the end. Writes
//! `docs/tradeoffs.md` and `docs/img/tradeoff_pareto.png`.
//!
//! ```sh
//! cargo run --release -p talus --example tradeoffs            # all runs (about 4 min)
//! cargo run --release -p talus --example tradeoffs -- --replot  # redraw from the last results
//! cargo run --release -p talus --example tradeoffs -- --only P1  # some runs, nothing written
//! ```
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;
use talus::run::{run_scene, RunOptions};
use talus::scene::{builtin_footing, MeshSpec, Order};

/// Total footing displacement of every run (m).
const TOTAL: f64 = 1.5e-3;
/// The paper's velocity (m/s) and step (s).
const V_PAPER: f64 = 1e-3;
const H_PAPER: f64 = 1e-2;

#[derive(Clone, Copy, PartialEq, Debug)]
struct Config {
    tol: f64,
    h: f64,
    steps: usize,
    velocity: f64,
    cells: [usize; 2],
    p2: bool,
}

const PAPER: Config = Config {
    tol: 1e-12,
    h: H_PAPER,
    steps: 150,
    velocity: V_PAPER,
    cells: [32, 14],
    p2: true,
};

#[derive(Clone, Debug)]
struct Outcome {
    seconds: f64,
    force: f64,
    /// (F(1.5 mm) − F(1.0 mm)) / F(1.5 mm); NaN when no step ends at 1.0 mm.
    drift: f64,
    max_its: usize,
    total_its: usize,
    halved: usize,
    points: usize,
}

/// One study: a knob, its runs (label, config) and the label of its reference.
struct Study {
    title: &'static str,
    runs: Vec<(String, Config)>,
    reference: String,
}

fn studies() -> Vec<Study> {
    let tols = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12];
    let tol = Study {
        title: "Newton tolerance (paper mesh, h = 1e-2 s, 150 steps)",
        runs: tols
            .iter()
            .map(|&t| (format!("tol {t:.0e}"), Config { tol: t, ..PAPER }))
            .collect(),
        reference: "tol 1e-12".into(),
    };
    // Δu = v h at the paper's velocity: the number of steps is TOTAL / Δu.
    let hs = [0.5, 0.1, 0.05, 0.01, 0.005, 0.0025];
    let incr = Study {
        title: "displacement increment Δu = v·h (v = 1 mm/s, h = Δu / v)",
        runs: hs
            .iter()
            .map(|&h| {
                let steps = (TOTAL / (V_PAPER * h)).round() as usize;
                (
                    format!("Δu {}", g(V_PAPER * h * 1e3) + " mm"),
                    Config { h, steps, ..PAPER },
                )
            })
            .collect(),
        reference: "Δu 0.0025 mm".into(),
    };
    // h alone: 150 steps of Δu = 0.01 mm each, the velocity set to Δu / h.
    let hs = [1.0, 0.1, 0.01, 1e-3, 1e-4];
    let rate = Study {
        title: "time step h at fixed Δu = 0.01 mm (150 steps, v = Δu / h)",
        runs: hs
            .iter()
            .map(|&h| {
                let velocity = TOTAL / (150.0 * h);
                (
                    format!("h {h:.0e}"),
                    Config {
                        h,
                        velocity,
                        ..PAPER
                    },
                )
            })
            .collect(),
        reference: "h 1e0".into(),
    };
    let mesh = |p2: bool, cells: &[[usize; 2]]| {
        cells
            .iter()
            .map(|&c| {
                let order = if p2 { "P2" } else { "P1" };
                (
                    format!("{order} {}×{}", c[0], c[1]),
                    Config {
                        cells: c,
                        p2,
                        ..PAPER
                    },
                )
            })
            .collect::<Vec<_>>()
    };
    let p2 = Study {
        title: "mesh, P2 (reference P2 48×21)",
        runs: mesh(true, &[[16, 7], [24, 10], [32, 14], [40, 18], [48, 21]]),
        reference: "P2 48×21".into(),
    };
    let p1 = Study {
        title: "mesh, P1 (reference P2 48×21)",
        runs: mesh(false, &[[16, 7], [32, 14], [48, 21], [64, 28], [96, 42]]),
        reference: "P2 48×21".into(),
    };
    vec![tol, incr, rate, p2, p1]
}

/// Shortest decimal text of a positive number (0.5, 0.01, 1e-4 …).
fn g(v: f64) -> String {
    if (1e-3..1e4).contains(&v.abs()) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

fn run(config: &Config, out: &Path) -> Outcome {
    let mut scene = builtin_footing();
    let spec = &mut scene.spec;
    spec.time.step = config.h;
    spec.time.steps = config.steps;
    spec.solver.tolerance = config.tol;
    let footing = spec
        .boundary
        .iter_mut()
        .find(|b| b.name.as_deref() == Some("footing"))
        .expect("the paper footing has a boundary named footing");
    footing.velocity = [0.0, -config.velocity];
    if let MeshSpec::Rectangle {
        cells,
        order,
        ratio,
        ..
    } = &mut spec.mesh
    {
        // The same geometric grading at every size: 1.1 per cell over 14 cells.
        ratio[1] = 1.1f64.powf(14.0 / config.cells[1] as f64);
        *cells = config.cells;
        *order = if config.p2 { Order::P2 } else { Order::P1 };
    }
    let options = RunOptions {
        out_dir: out.to_path_buf(),
        progress: false,
        write_fields: false,
    };
    let start = Instant::now();
    let summary = run_scene(&scene, &options).unwrap_or_else(|e| panic!("{config:?}: {e}"));
    let seconds = start.elapsed().as_secs_f64();
    let records = &summary.records;
    let force = records.last().expect("at least one step").reaction_force;
    let two_thirds = 2 * config.steps;
    let drift = if two_thirds % 3 == 0 {
        (force - records[two_thirds / 3 - 1].reaction_force) / force
    } else {
        f64::NAN
    };
    Outcome {
        seconds,
        force,
        drift,
        max_its: records
            .iter()
            .map(|r| r.max_newton_iterations)
            .max()
            .unwrap_or(0),
        total_its: records.iter().map(|r| r.newton_iterations).sum(),
        halved: records.iter().filter(|r| r.substeps > 1).count(),
        points: summary.final_state.plastic_strain.len(),
    }
}

type Results = Vec<(Config, Outcome)>;

fn cache_path() -> PathBuf {
    std::env::temp_dir().join("talus_tradeoffs/results.txt")
}

fn save(results: &Results) {
    let mut s = String::new();
    for (c, o) in results {
        let _ = writeln!(
            s,
            "{:e} {:e} {} {:e} {} {} {} {:e} {:e} {:e} {} {} {} {}",
            c.tol,
            c.h,
            c.steps,
            c.velocity,
            c.cells[0],
            c.cells[1],
            c.p2,
            o.seconds,
            o.force,
            o.drift,
            o.max_its,
            o.total_its,
            o.halved,
            o.points
        );
    }
    std::fs::write(cache_path(), s).expect("write the results cache");
}

fn load() -> Results {
    let text =
        std::fs::read_to_string(cache_path()).expect("no cached results: run without --replot");
    text.lines()
        .map(|l| {
            let w: Vec<&str> = l.split(' ').collect();
            let f = |i: usize| w[i].parse::<f64>().expect("number");
            let u = |i: usize| w[i].parse::<usize>().expect("integer");
            let c = Config {
                tol: f(0),
                h: f(1),
                steps: u(2),
                velocity: f(3),
                cells: [u(4), u(5)],
                p2: w[6] == "true",
            };
            let o = Outcome {
                seconds: f(7),
                force: f(8),
                drift: f(9),
                max_its: u(10),
                total_its: u(11),
                halved: u(12),
                points: u(13),
            };
            (c, o)
        })
        .collect()
}

fn main() {
    let studies = studies();
    let work = std::env::temp_dir().join("talus_tradeoffs");
    std::fs::create_dir_all(&work).expect("create the work folder");
    let start = Instant::now();
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--only") {
        // A quick look at some runs (labels containing the text); nothing is written.
        let want = args.get(i + 1).map_or("", |s| s.as_str());
        for (label, config) in studies.iter().flat_map(|s| s.runs.iter()) {
            if label.contains(want) {
                let o = run(config, &work.join("run"));
                eprintln!("{label:>14}: {o:?}");
            }
        }
        return;
    }
    let results: Results = if std::env::args().any(|a| a == "--replot") {
        load()
    } else {
        // Each distinct configuration runs once (the paper's one is in every study).
        let mut results: Results = Vec::new();
        for (label, config) in studies.iter().flat_map(|s| s.runs.iter()) {
            if results.iter().any(|(c, _)| c == config) {
                continue;
            }
            let o = run(config, &work.join("run"));
            eprintln!(
                "{label:>14}: {:7.2} s  F = {:.6} kN/m  max its {}",
                o.seconds,
                o.force * 1e-3,
                o.max_its
            );
            results.push((*config, o));
        }
        save(&results);
        results
    };
    let total: f64 = results.iter().map(|(_, o)| o.seconds).sum();
    let outcome = |c: &Config| &results.iter().find(|(r, _)| r == c).expect("ran").1;
    let config_of = |label: &str| {
        studies
            .iter()
            .flat_map(|s| s.runs.iter())
            .find(|(l, _)| l == label)
            .expect("reference label")
            .1
    };

    // Tables, and the points of the Pareto plot: (study, label, seconds, error).
    let mut md = String::new();
    let mut points: Vec<(usize, String, f64, f64)> = Vec::new();
    for (k, s) in studies.iter().enumerate() {
        let reference = outcome(&config_of(&s.reference)).force;
        let _ = writeln!(md, "\n### {}\n", s.title);
        let _ = writeln!(
            md,
            "| run | steps | h (s) | v (mm/s) | Gauss points | seconds | F (kN/m) | rel. error | plateau drift | max / total Newton its |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
        for (label, c) in &s.runs {
            let o = outcome(c);
            let err = ((o.force - reference) / reference).abs();
            let err_text = if *label == s.reference {
                "reference".to_string()
            } else if err == 0.0 {
                "0".to_string()
            } else {
                format!("{err:.1e}")
            };
            let paper = if c == &PAPER { " (paper)" } else { "" };
            let halved = if o.halved > 0 {
                format!(", {} halved", o.halved)
            } else {
                String::new()
            };
            let drift = if o.drift.is_nan() {
                "–".to_string()
            } else {
                format!("{:.1e}", o.drift)
            };
            let _ = writeln!(
                md,
                "| {label}{paper} | {} | {} | {} | {} | {:.2} | {:.3} | {err_text} | {drift} | {} / {}{halved} |",
                c.steps,
                g(c.h),
                g(c.velocity * 1e3),
                o.points,
                o.seconds,
                o.force * 1e-3,
                o.max_its,
                o.total_its
            );
            if err > 0.0 {
                points.push((k, label.clone(), o.seconds, err));
            }
        }
    }
    println!(
        "{md}\ntotal run time {total:.0} s (wall {:.0} s)",
        start.elapsed().as_secs_f64()
    );

    // Observed order in mesh size: Richardson on the nested 16, 32, 64 meshes.
    let mut orders = String::new();
    for p2 in [true, false] {
        let f = |nx: usize| {
            let c = Config {
                cells: [nx, nx * 7 / 16],
                p2,
                ..PAPER
            };
            outcome(&c).force
        };
        let (a, b, c) = (f(16), f(32), f(64));
        let ratio = (a - b) / (b - c);
        let name = if p2 { "P2" } else { "P1" };
        if ratio > 1.0 {
            let p = ratio.log2();
            let limit = c + (c - b) / (2f64.powf(p) - 1.0);
            let _ = writeln!(
                orders,
                "| {name} | {:.3} | {:.3} | {:.3} | {ratio:.2} | {p:.2} | {:.2} |",
                a * 1e-3,
                b * 1e-3,
                c * 1e-3,
                limit * 1e-3
            );
        } else {
            let _ = writeln!(
                orders,
                "| {name} | {:.3} | {:.3} | {:.3} | {ratio:.2} | – (not monotone) | – |",
                a * 1e-3,
                b * 1e-3,
                c * 1e-3
            );
        }
    }
    println!("{orders}");

    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs");
    let png = docs.join("img/tradeoff_pareto.png");
    plot(&png, &studies, &points).expect("draw the Pareto plot");
    let doc = DOC
        .replace("{TABLES}", md.trim())
        .replace("{ORDERS}", orders.trim())
        .replace("{TOTAL}", &format!("{total:.0}"));
    std::fs::write(docs.join("tradeoffs.md"), doc).expect("write docs/tradeoffs.md");
    println!(
        "wrote {} and {}",
        docs.join("tradeoffs.md").display(),
        png.display()
    );
}

const COLOURS: [RGBColor; 5] = [
    RGBColor(31, 90, 160),
    RGBColor(230, 120, 20),
    RGBColor(40, 150, 60),
    RGBColor(200, 30, 45),
    RGBColor(130, 60, 170),
];

fn plot(
    path: &Path,
    studies: &[Study],
    points: &[(usize, String, f64, f64)],
) -> Result<(), Box<dyn std::error::Error>> {
    for (style, bytes) in [
        (FontStyle::Normal, dejavu::sans::regular()),
        (FontStyle::Bold, dejavu::sans::bold()),
    ] {
        plotters::style::register_font("sans-serif", style, bytes).map_err(|_| "font")?;
    }
    let lg = |v: f64| v.log10();
    let (x0, x1) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(lg(p.2)), b.max(lg(p.2)))
    });
    let (y0, y1) = points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(lg(p.3)), b.max(lg(p.3)))
    });
    let root = BitMapBackend::new(path, (1400, 950)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Footing limit load: error against wall time, one knob at a time",
            ("sans-serif", 30).into_font().style(FontStyle::Bold),
        )
        .margin(20)
        .margin_right(40)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d(
            (x0 - 0.1).floor()..(x1 + 0.25).ceil(),
            (y0 - 0.3).floor()..(y1 + 0.3).ceil(),
        )?;
    let decade = |v: &f64| {
        if (v - v.round()).abs() < 1e-9 {
            format!("1e{}", v.round() as i32)
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_desc("wall time of the run [s]")
        .y_desc("relative error of the limit load")
        .axis_desc_style(("sans-serif", 24))
        .label_style(("sans-serif", 20))
        .x_label_formatter(&|v| {
            let s = decade(v);
            if s.is_empty() {
                s
            } else {
                g(10f64.powf(*v))
            }
        })
        .y_label_formatter(&decade)
        .draw()?;
    for (k, s) in studies.iter().enumerate() {
        let colour = COLOURS[k];
        let mine: Vec<_> = points.iter().filter(|p| p.0 == k).collect();
        chart.draw_series(LineSeries::new(
            mine.iter().map(|p| (lg(p.2), lg(p.3))),
            colour.mix(0.35).stroke_width(2),
        ))?;
        chart
            .draw_series(mine.iter().map(|p| {
                let at = (lg(p.2), lg(p.3));
                let style = colour.filled();
                let marker: DynElement<_, _> = match k {
                    0 => Circle::new((0, 0), 7, style).into_dyn(),
                    1 => TriangleMarker::new((0, 0), 9, style).into_dyn(),
                    2 => Cross::new((0, 0), 7, colour.stroke_width(3)).into_dyn(),
                    3 => Rectangle::new([(-6, -6), (6, 6)], style).into_dyn(),
                    _ => Rectangle::new([(-6, -6), (6, 6)], colour.stroke_width(2)).into_dyn(),
                };
                let text =
                    p.1.split_once(' ')
                        .map_or(p.1.as_str(), |t| t.1)
                        .to_string();
                EmptyElement::at(at)
                    + marker
                    + Text::new(
                        text,
                        (9, -20),
                        ("sans-serif", 16).into_font().color(&colour),
                    )
            }))?
            .label(s.title)
            .legend(move |(x, y)| Circle::new((x + 10, y), 6, colour.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .label_font(("sans-serif", 18))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.5))
        .draw()?;
    root.present()?;
    Ok(())
}

const DOC: &str = r#"# Speed against accuracy on the footing

The paper footing (`scenes/footing.toml`, [docs/footing.md](footing.md)) with one knob
changed at a time: the Newton tolerance, the displacement increment per step, the time step
at a fixed increment, the mesh size and the element order. Reproduce with
`cargo run --release -p talus --example tradeoffs` (all runs one after another, {TOTAL} s of
run time on the 2-core machine shared with other jobs, so the seconds are good to about 20 %).

**Limit load.** Every run pushes the footing 1.5 mm instead of 3 mm (the plateau starts at
about 0.6 mm) and the limit load is the reaction at the end. *Plateau drift* is
`(F(1.5 mm) − F(1.0 mm)) / F(1.5 mm)`: a few 1e-4 on the reference runs, so the plateau is
reached; the force still creeps up by 2e-4 between 1.5 and 3 mm on the paper run (195.24 →
195.28 kN/m), which is the precision to which "the limit load" itself is defined.
Errors below that are differences between discrete solutions, not errors of the limit load.

**References.** Each knob is measured against its own finest run, every other setting at the
paper's value: tolerance 1e-12; the smallest increment Δu = 0.001 mm (1500 steps); for h at
fixed increment the largest h (1 s: the quasi-static limit, the inertia `h² B M⁻¹ Bᵀ` is
smallest there); for both element orders the finest P2 mesh, 64 × 28 cells. Meshes are
uniform in x (the footing edges are nodes), graded in y with the same geometric ratio at
every size (1.1^(14/ny) per cell), so 16 × 7 ⊂ 32 × 14 ⊂ 64 × 28 are nested.

**The time step.** At the paper's 1 mm/s an h of 1e-4 s would take 15 000 steps for 1.5 mm
(about 8 minutes). h enters the scheme twice: through the displacement increment Δu = v·h
(how far implicit Euler jumps along the plastic path), and through inertia (`W = S + h² B M⁻¹
Bᵀ`, an impulse `M Δv / h` when the footing starts). The two are measured separately: the
increment at v = 1 mm/s (h from 0.5 s to 1e-3 s, 3 to 1500 steps), and h from 1 s to 1e-4 s
at a fixed 150 steps of 0.01 mm, the velocity set to 0.01 mm / h (1e-5 to 0.1 m/s).

## Results

Seconds: wall time of `run_scene` (model build, K₀ state, all steps). F: reaction at 1.5 mm.
Newton its: the most a single step took, and the sum over the run.

{TABLES}

![Pareto plot: relative error against seconds](img/tradeoff_pareto.png)

The plot leaves out the references (error 0). Each colour varies one knob from the paper
setting; the errors of different knobs are against different references, but they add up:
a run's error is about the sum of its knobs' errors.

## Observed order in mesh size

From the nested 16 × 7, 32 × 14, 64 × 28 meshes (F in kN/m): ratio =
(F₁₆ − F₃₂) / (F₃₂ − F₆₄), observed order p = log₂ ratio, Richardson limit
F₆₄ + (F₆₄ − F₃₂) / (2ᵖ − 1).

| order | F 16×7 | F 32×14 | F 64×28 | ratio | p | extrapolated |
|---|---|---|---|---|---|---|
{ORDERS}

{DISCUSSION}
"#;
