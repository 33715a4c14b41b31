//! The speed/accuracy trade on the paper footing (`scenes/footing.toml`): Newton tolerance,
//! time step, mesh size and element order. Each run pushes the footing 1.5 mm (the plateau
//! starts at about 0.6 mm); the limit load is the force at the end. Writes
//! `docs/tradeoffs.md` and `docs/img/tradeoff_pareto.png`.
//!
//! ```sh
//! cargo run --release -p talus-studies --bin tradeoffs            # all runs (about 4 min)
//! cargo run --release -p talus-studies --bin tradeoffs -- --replot  # redraw from the last results
//! cargo run --release -p talus-studies --bin tradeoffs -- --only P1  # some runs, nothing written
//! ```
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;
use talus::model::fem::ReactionForce;
use talus::run::fem::run_scene;
use talus::run::RunOptions;
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
    /// CPU time of the process over the run (all threads), s.
    cpu: f64,
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
    // The cheap knobs set loose together, on the two finest P2 meshes.
    let fast = Study {
        title: "combined: tol 1e-8, and 30 steps of 0.05 mm (fast), P2 (reference P2 48×21)",
        runs: vec![
            (
                "fast 32×14".into(),
                Config {
                    tol: 1e-8,
                    h: 0.05,
                    steps: 30,
                    ..PAPER
                },
            ),
            (
                "fast 48×21".into(),
                Config {
                    tol: 1e-8,
                    h: 0.05,
                    steps: 30,
                    cells: [48, 21],
                    ..PAPER
                },
            ),
            (
                "tol 1e-8 48×21".into(),
                Config {
                    tol: 1e-8,
                    cells: [48, 21],
                    ..PAPER
                },
            ),
        ],
        reference: "P2 48×21".into(),
    };
    vec![tol, incr, rate, p2, p1, fast]
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
    let options = RunOptions::new(out.to_path_buf());
    let (start, cpu0) = (Instant::now(), cpu_seconds());
    let summary = run_scene(&scene, &options).unwrap_or_else(|e| panic!("{config:?}: {e}"));
    let seconds = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    let records = &summary.records;
    let force = records.last().expect("at least one step").reaction_force();
    let two_thirds = 2 * config.steps;
    let drift = if two_thirds.is_multiple_of(3) {
        (force - records[two_thirds / 3 - 1].reaction_force()) / force
    } else {
        f64::NAN
    };
    Outcome {
        seconds,
        cpu,
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

/// utime + stime of this process from /proc (Linux; NaN elsewhere).
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the command name (which is in parentheses): state is field 3.
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<f64> = rest
        .split_whitespace()
        .map(|w| w.parse().unwrap_or(f64::NAN))
        .collect();
    // utime, stime are fields 14 and 15, in clock ticks of 1/100 s.
    (f[11] + f[12]) / 100.0
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
            "{:e} {:e} {} {:e} {} {} {} {:e} {:e} {:e} {} {} {} {} {:e}",
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
            o.points,
            o.cpu
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
                cpu: f(14),
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
    let total_cpu: f64 = results.iter().map(|(_, o)| o.cpu).sum();
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
    let mut points: Vec<Point> = Vec::new();
    for (k, s) in studies.iter().enumerate() {
        let reference = outcome(&config_of(&s.reference)).force;
        let _ = writeln!(md, "\n### {}\n", s.title);
        let _ = writeln!(
            md,
            "| run | steps | h (s) | v (mm/s) | Gauss pts | wall s | CPU s | F (kN/m) | rel. error | drift | Newton max / total |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
        for (label, c) in &s.runs {
            let o = outcome(c);
            let err = ((o.force - reference) / reference).abs();
            let err_text = if *label == s.reference {
                "ref.".to_string()
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
                format!("{:.0e}", o.drift)
            };
            let _ = writeln!(
                md,
                "| {label}{paper} | {} | {} | {} | {} | {:.2} | {:.2} | {:.3} | {err_text} | {drift} | {} / {}{halved} |",
                c.steps,
                g(c.h),
                g(c.velocity * 1e3),
                o.points,
                o.seconds,
                o.cpu,
                o.force * 1e-3,
                o.max_its,
                o.total_its
            );
            if err > 0.0 {
                points.push((k, label.clone(), o.seconds, err, c == &PAPER));
            }
        }
    }
    println!(
        "{md}\ntotal run time {total:.0} s ({total_cpu:.0} s CPU; this process {:.0} s)",
        start.elapsed().as_secs_f64()
    );

    // Observed order in mesh size: F(n) = F∞ + C n^-p fitted to each order's meshes (n = cells
    // in x), and Richardson on the nested P1 meshes 16, 32, 64.
    let mut orders = String::new();
    for s in &studies[3..5] {
        let data: Vec<(f64, f64)> = s
            .runs
            .iter()
            .map(|(_, c)| (c.cells[0] as f64, outcome(c).force))
            .collect();
        let (p, limit, rms) = fit_order(&data);
        let (n, finest) = data[data.len() - 1];
        let _ =
            writeln!(
            orders,
            "| {} | fit over nx = {} | {p:.2} | {:.2} | {:.1e} | {:.2} kN/m at nx = {n} ({:.1e}) |",
            &s.runs[0].0[..2],
            data.iter().map(|d| d.0.to_string()).collect::<Vec<_>>().join(", "),
            limit * 1e-3,
            rms / limit,
            finest * 1e-3,
            ((finest - limit) / limit).abs()
        );
    }
    let f = |nx: usize, ny: usize| {
        outcome(&Config {
            cells: [nx, ny],
            p2: false,
            ..PAPER
        })
        .force
    };
    let (a, b, c) = (f(16, 7), f(32, 14), f(64, 28));
    let ratio = (a - b) / (b - c);
    if ratio > 1.0 {
        let p = ratio.log2();
        let limit = c + (c - b) / (2f64.powf(p) - 1.0);
        let _ = writeln!(
            orders,
            "| P1 | Richardson, nx = 16, 32, 64 (nested) | {p:.2} | {:.2} | – | {:.2} kN/m at nx = 64 ({:.1e}) |",
            limit * 1e-3,
            c * 1e-3,
            ((c - limit) / limit).abs()
        );
    }
    println!("{orders}");

    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs");
    let png = docs.join("img/tradeoff_pareto.png");
    plot(&png, &studies, &points).expect("draw the Pareto plot");
    let doc = DOC
        .replace("{TABLES}", md.trim())
        .replace("{ORDERS}", orders.trim())
        .replace("{TOTAL}", &format!("{total:.0}"))
        .replace("{CPU}", &format!("{total_cpu:.0}"));
    std::fs::write(docs.join("tradeoffs.md"), doc).expect("write docs/tradeoffs.md");
    println!(
        "wrote {} and {}",
        docs.join("tradeoffs.md").display(),
        png.display()
    );
}

/// Least squares F = F∞ + C n^-p over p ∈ [0.2, 4]: (p, F∞, rms misfit).
fn fit_order(data: &[(f64, f64)]) -> (f64, f64, f64) {
    let mut best = (f64::NAN, f64::NAN, f64::INFINITY);
    for k in 20..=400 {
        let p = k as f64 / 100.0;
        let xs: Vec<f64> = data.iter().map(|d| d.0.powf(-p)).collect();
        let m = data.len() as f64;
        let (mx, my) = (
            xs.iter().sum::<f64>() / m,
            data.iter().map(|d| d.1).sum::<f64>() / m,
        );
        let sxy: f64 = xs
            .iter()
            .zip(data)
            .map(|(x, d)| (x - mx) * (d.1 - my))
            .sum();
        let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
        let slope = sxy / sxx;
        let limit = my - slope * mx;
        let sse: f64 = xs
            .iter()
            .zip(data)
            .map(|(x, d)| (limit + slope * x - d.1).powi(2))
            .sum();
        let rms = (sse / m).sqrt();
        if rms < best.2 {
            best = (p, limit, rms);
        }
    }
    best
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 90, 160),
    RGBColor(230, 120, 20),
    RGBColor(40, 150, 60),
    RGBColor(200, 30, 45),
    RGBColor(130, 60, 170),
    RGBColor(0, 140, 150),
];

/// (study, label, wall seconds, relative error, is the paper setting).
type Point = (usize, String, f64, f64, bool);

fn marker<DB: DrawingBackend>(k: usize, colour: RGBColor) -> DynElement<'static, DB, (i32, i32)> {
    let fill = colour.filled();
    match k {
        0 => Circle::new((0, 0), 7, fill).into_dyn(),
        1 => TriangleMarker::new((0, 0), 9, fill).into_dyn(),
        2 => Cross::new((0, 0), 7, colour.stroke_width(3)).into_dyn(),
        3 => Rectangle::new([(-6, -6), (6, 6)], fill).into_dyn(),
        5 => Circle::new((0, 0), 8, colour.stroke_width(3)).into_dyn(),
        _ => Rectangle::new([(-6, -6), (6, 6)], colour.stroke_width(2)).into_dyn(),
    }
}

fn plot(
    path: &Path,
    studies: &[Study],
    points: &[Point],
) -> Result<(), Box<dyn std::error::Error>> {
    for (style, bytes) in [
        (FontStyle::Normal, dejavu::sans::regular()),
        (FontStyle::Bold, dejavu::sans::bold()),
    ] {
        plotters::style::register_font("sans-serif", style, bytes).map_err(|_| "font")?;
    }
    let at = |p: &Point| (p.2, p.3);
    let range = |f: &dyn Fn(&Point) -> f64| {
        points
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(f(p)), b.max(f(p))))
    };
    let (x0, x1) = range(&|p| p.2);
    let (y0, y1) = range(&|p| p.3);
    // Room below the points for the legend.
    let y0 = 10f64.powf((y0.log10() - 2.3).floor());
    let root = BitMapBackend::new(path, (1400, 950)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Footing limit load: error against wall time, one knob varied at a time",
            ("sans-serif", 30).into_font().style(FontStyle::Bold),
        )
        .margin(20)
        .margin_right(40)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d(
            (x0 / 1.4..x1 * 2.2)
                .log_scale()
                .with_key_points(vec![0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0]),
            (y0..y1 * 2.5).log_scale(),
        )?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_labels(12)
        .y_labels(12)
        .x_desc("wall time of the run [s] (log scale)")
        .y_desc("relative error of the limit load (log scale)")
        .axis_desc_style(("sans-serif", 24))
        .label_style(("sans-serif", 20))
        .x_label_formatter(&|v| g(*v))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    // Labels go to the first free place around their point (pixel boxes).
    let pixels: Vec<(i32, i32)> = points.iter().map(|p| chart.backend_coord(&at(p))).collect();
    let mut taken: Vec<[i32; 4]> = pixels
        .iter()
        .map(|&(x, y)| [x - 9, y - 9, x + 9, y + 9])
        .collect();
    let overlaps =
        |a: &[i32; 4], b: &[i32; 4]| a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
    let mut labels = Vec::new();
    for (k, s) in studies.iter().enumerate() {
        let colour = COLOURS[k];
        let mine: Vec<&Point> = points.iter().filter(|p| p.0 == k).collect();
        // Lines join the settings of one knob (the combined runs are not a sequence).
        let line = if k < 5 { mine.len() } else { 0 };
        chart.draw_series(LineSeries::new(
            mine.iter().take(line).map(|p| at(p)),
            colour.mix(0.35).stroke_width(2),
        ))?;
        chart
            .draw_series(
                mine.iter()
                    .map(|p| EmptyElement::at(at(p)) + marker(k, colour)),
            )?
            .label(s.title)
            .legend(move |(x, y)| EmptyElement::at((x + 10, y)) + marker(k, colour));
        for (p, &(x, y)) in points.iter().zip(&pixels).filter(|(p, _)| p.0 == k) {
            let w = p.1.chars().count() as i32 * 9;
            let spots = [
                (10, -22),
                (10, 4),
                (-10 - w, -22),
                (-10 - w, 4),
                (-w / 2, -32),
                (-w / 2, 12),
            ];
            let spot = spots
                .iter()
                .map(|&(dx, dy)| [x + dx, y + dy, x + dx + w, y + dy + 18])
                .find(|b| !taken.iter().any(|t| overlaps(b, t)))
                .unwrap_or([x + 10, y - 22, x + 10 + w, y - 4]);
            taken.push(spot);
            labels.push((p.1.clone(), (spot[0], spot[1]), colour));
        }
    }
    chart
        .draw_series(
            points
                .iter()
                .filter(|p| p.4)
                .map(|p| EmptyElement::at(at(p)) + Circle::new((0, 0), 13, BLACK.stroke_width(2))),
        )?
        .label("paper setting (P2 32×14, tol 1e-12, h = 1e-2 s, Δu = 0.01 mm)")
        .legend(|(x, y)| Circle::new((x + 10, y), 9, BLACK.stroke_width(2)));
    for (text, spot, colour) in labels {
        root.draw(&Text::new(
            text,
            spot,
            ("sans-serif", 17).into_font().color(&colour),
        ))?;
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

The paper footing (`scenes/footing.toml`, [footing.md](footing.md)) with one knob changed at
a time: the Newton tolerance, the displacement increment per step, the time step at a fixed
increment, the mesh size and the element order; then the cheap knobs set loose together.
Reproduce with `cargo run --release -p talus-studies --bin tradeoffs`: 26 runs one after another,
{TOTAL} s of wall time ({CPU} s CPU: the solver runs on one thread, so the times below are
not inflated by other jobs on the 2-core machine; repeated runs agree to about 10 %, 25 %
at worst).

**Limit load.** Every run pushes the footing 1.5 mm instead of 3 mm (the plateau starts at
about 0.6 mm) and the limit load is the reaction at the end. *Drift* is
`(F(1.5 mm) − F(1.0 mm)) / F(1.5 mm)`: 4e-4 on the paper run, 6e-4 on the finest mesh, so
the plateau is reached. It is not perfectly flat: the paper run still gains 2e-4 from 1.5 to
3 mm (195.24 → 195.28 kN/m). That is the precision to which "the limit load" is defined;
smaller errors below compare discrete solutions at the same 1.5 mm.

**References.** Each knob is measured against its own most accurate run, every other setting
at the paper's value:
- tolerance: 1e-12 (the default);
- increment: Δu = 0.0025 mm (600 steps). The error falls about linearly with Δu (implicit
  Euler), so the reference's own error is about 1e-6;
- h at a fixed increment: h = 1 s, where inertia (forces ~ M Δu / h²) is smallest;
- mesh, both orders: the finest P2 mesh that runs, 48 × 21 cells. P2 64 × 28 does not finish
  in minutes: from about 0.4 mm on, most steps stop at 50 Newton iterations or on a failed
  line search and are halved up to three times, 5 to 40 s per step (46 steps in 200 s at
  tolerance 1e-8, 42 in 150 s at h = 1 s).

Meshes are uniform in x (the footing edges ±0.25 m are nodes) and graded in y with the same
geometry at every size (ratio 1.1^(14/ny) per cell), so 16 × 7, 32 × 14 and 48 × 21 are
similar meshes and 16 × 7 ⊂ 32 × 14 ⊂ 64 × 28 are nested.

**The time step.** At the paper's 1 mm/s an h of 1e-4 s would take 15 000 steps for 1.5 mm
(about 10 minutes). h enters twice: through the displacement increment Δu = v·h (how far
implicit Euler jumps along the plastic path) and through inertia. The two are measured
apart: the increment at v = 1 mm/s (h from 0.5 s to 2.5e-3 s, 3 to 600 steps), and h from
1 s to 1e-4 s at a fixed 150 steps of 0.01 mm, the velocity set to 0.01 mm / h (0.01 mm/s
to 0.1 m/s).

## Results

Wall s, CPU s: the whole `run_scene` (model, K₀ state, all steps). F: reaction at 1.5 mm.
Newton: the most iterations a single step took, the total over the run, and the steps that
had to be halved.

{TABLES}

![Pareto plot: relative error against seconds](img/tradeoff_pareto.png)

The plot leaves out the references (error 0). Each colour varies one knob from the paper
setting (ringed); the errors of different knobs are against different references but add
up: a run's error is about the sum of its knobs' errors.

## Observed order in mesh size

F(n) = F∞ + C n⁻ᵖ fitted by least squares to each element order's meshes (n = cells in x,
mesh size 2 m / n), and Richardson's estimate on the three nested P1 meshes. The last column
is the finest mesh's distance to the extrapolated F∞.

| order | data | p | F∞ (kN/m) | rms misfit / F∞ | finest mesh |
|---|---|---|---|---|---|
{ORDERS}

The data do not give a convergence order. P2 is not monotone: the paper's 32 × 14 (195.2
kN/m) lies below both finer meshes (201.3, 198.7), so its 1.8 % "error" against 48 × 21 is
partly luck, and the fitted p ≈ 1.8 leaves a misfit of 2 %, as large as the differences it
should explain (the usual suspect is how the shear bands cross the structured triangles,
which changes from mesh to mesh). P1 decreases monotonically, but not yet at an asymptotic
rate: Richardson on 16/32/64 gives p ≈ 2 and 205.5 kN/m, and the next mesh (96 × 42,
205.1 kN/m) already falls below that. The two orders extrapolate to 193 and 202 kN/m. On
these meshes the discrete limit load is known to about ±3 %, and every other knob is far
below that.

## What to choose

The mesh is the error. At the paper setting the increment costs 4e-6 and h 4e-8 (the
tolerance, 1e-12, is the reference), against 2 % for the mesh. From about 1.5 s on, P2 is
2 to 8 times more accurate than P1 for the same time: P1 needs 96 × 42 (8064 points,
twice the time of P2 32 × 14) to come within 3 % of P2 48 × 21, the constant-strain
triangle being over-stiff in the plastic flow. So:

- **Elements**: P2, on the finest mesh you can afford. Past 48 × 21 cells Newton itself
  becomes the limit (see the references above).
- **Tolerance**: 1e-8. It changes the limit load by 2e-8 and saves a third of the time
  (1e-12 → 1e-8: 421 → 279 Newton iterations on the paper mesh, 552 → 394 on 48 × 21).
  1e-6 is the fastest (error 1e-6). Do not go to 1e-4: a loose step presumably spoils the next step's
  predictor, and the run is slower (566 iterations, up to 22 per step) for no gain.
- **Increment**: for the limit load alone, 15 to 30 steps over the settlement (Δu = 0.1 to
  0.05 mm, a tenth of the displacement to the plateau): 4e-5 to 2e-5 for a third of the
  time of 150 steps. Keep more steps for the shape of the curve before the plateau, and on
  fine meshes, where large increments cost Newton iterations and halvings: on 48 × 21, 30
  steps of 0.05 mm needed up to 46 iterations a step and two halvings, and took longer
  (23 s) than 150 steps at the same tolerance (18 s).
- **h**: for a quasi-static footing take h large, v = Δu / h small: h ≥ 1e-2 s (v ≤ 1 mm/s)
  is quasi-static to 4e-8. At h = 1e-3 s (v = 1 cm/s) inertia shows (2e-5, more Newton
  iterations); at h = 1e-4 s (v = 0.1 m/s) the run is dynamic: the force oscillates (drift
  −0.5) and ends 25 % low.
"#;
