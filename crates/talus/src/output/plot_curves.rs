//! Line plots for reports: the footing's load–settlement curve and the Newton
//! convergence history.
use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{prepare, significant, tick, FONT};
use super::colormap::viridis;
use super::OutputError;

const CURVE_SIZE: (u32, u32) = (1000, 700);
/// Residual plots draw at most this many steps, so that the lines stay distinguishable.
const MAX_DRAWN_STEPS: usize = 30;
const LINE_BLUE: RGBColor = RGBColor(31, 90, 160);
const WORST_RED: RGBColor = RGBColor(200, 30, 45);
const GRID: RGBColor = RGBColor(225, 225, 225);

/// Plots force against displacement as a PNG of 1000 × 700 px, forces per unit length
/// (plane strain): [`plot_force_displacement_with_unit`] in N/m.
pub fn plot_force_displacement(
    path: &Path,
    points: &[(f64, f64)],
    title: &str,
) -> Result<(), OutputError> {
    plot_force_displacement_with_unit(path, points, title, "N/m")
}

/// Plots force against displacement as a PNG of 1000 × 700 px.
///
/// `points` are `(displacement in m, force in force_unit)`, drawn as given (the caller
/// picks the sign, e.g. settlement positive downwards) in mm and in kilo`force_unit`:
/// the scene's `GeometryKind::force_unit()`, `"N/m"` in plane strain (kN/m on the plot),
/// `"N"` axisymmetric (kN). The peak `|force|` is marked and labelled. Errors (`Invalid`):
/// an empty or non-finite curve (`points`), a unit that is not newtons (`force_unit`).
pub fn plot_force_displacement_with_unit(
    path: &Path,
    points: &[(f64, f64)],
    title: &str,
    force_unit: &str,
) -> Result<(), OutputError> {
    super::atomic::through_temp(path, |tmp| {
        draw_plot_force_displacement(tmp, points, title, force_unit)
    })
}

/// The force axis's label for forces in `force_unit` (N or N per something), plotted in
/// kilonewtons: `"N/m"` → `"Force F [kN/m]"`, `"N"` → `"Force F [kN]"`.
pub fn force_axis_label(force_unit: &str) -> String {
    format!("Force F [{}]", kilo(force_unit))
}

/// `"N/m"` → `"kN/m"`.
fn kilo(force_unit: &str) -> String {
    format!("k{force_unit}")
}

fn draw_plot_force_displacement(
    path: &Path,
    points: &[(f64, f64)],
    title: &str,
    force_unit: &str,
) -> Result<(), OutputError> {
    if points.is_empty() {
        return Err(OutputError::invalid(
            "points",
            "the force–displacement curve is empty",
        ));
    }
    if let Some(i) = points
        .iter()
        .position(|(u, f)| !u.is_finite() || !f.is_finite())
    {
        return Err(OutputError::invalid(
            "points",
            format!("point {i} is not finite: {:?}", points[i]),
        ));
    }
    if !(force_unit == "N" || force_unit.starts_with("N/")) {
        return Err(OutputError::invalid(
            "force_unit",
            format!("{force_unit:?} is not a force in newtons (N, N/m)"),
        ));
    }
    prepare(path)?;
    // m → mm, N → kN
    let data: Vec<(f64, f64)> = points.iter().map(|&(u, f)| (u * 1e3, f * 1e-3)).collect();
    draw_force_displacement(path, &data, title, force_unit).map_err(|e| OutputError::plot(path, e))
}

fn draw_force_displacement(
    path: &Path,
    data: &[(f64, f64)],
    title: &str,
    force_unit: &str,
) -> Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::new(path, CURVE_SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    // Load–settlement curves are read from the origin: keep it in view.
    let x = padded_range(data.iter().map(|p| p.0).chain([0.0]));
    let y = padded_range(data.iter().map(|p| p.1).chain([0.0]));
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 30).into_font().style(FontStyle::Bold))
        .margin(20)
        .margin_right(40)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d(x, y)?;
    chart
        .configure_mesh()
        .light_line_style(GRID.mix(0.5))
        .bold_line_style(GRID)
        .x_desc("Displacement u [mm]")
        .y_desc(force_axis_label(force_unit))
        .axis_desc_style((FONT, 24))
        .label_style((FONT, 20))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;

    chart.draw_series(LineSeries::new(
        data.iter().copied(),
        LINE_BLUE.stroke_width(3),
    ))?;
    // Markers show where the load steps are, unless they would merge into a thick line.
    if data.len() <= 80 {
        chart.draw_series(data.iter().map(|&p| Circle::new(p, 4, LINE_BLUE.filled())))?;
    }

    let peak = data
        .iter()
        .copied()
        .fold(data[0], |a, b| if b.1.abs() > a.1.abs() { b } else { a });
    chart.draw_series([Circle::new(peak, 8, WORST_RED.stroke_width(3))])?;
    let text = format!(
        "peak {} {} at {} mm",
        significant(peak.1, 3),
        kilo(force_unit),
        significant(peak.0, 3)
    );
    let (px, py) = chart.backend_coord(&peak);
    let plot = chart.plotting_area().get_pixel_range();
    // Keep the annotation inside the plot: left of the peak when the peak is near the right edge.
    let right_side = px < (plot.0.start + plot.0.end) / 2 + (plot.0.end - plot.0.start) / 4;
    let anchor = if right_side {
        (px + 14, py + 22)
    } else {
        (px - 14, py + 22)
    };
    let hpos = if right_side { HPos::Left } else { HPos::Right };
    root.draw(&Text::new(
        text,
        anchor,
        (FONT, 20)
            .into_font()
            .color(&WORST_RED)
            .pos(Pos::new(hpos, VPos::Top)),
    ))?;
    root.present()?;
    Ok(())
}

/// Plots ‖F‖ per Newton iteration, one line per load step, on a log₁₀ axis, as a PNG of
/// 1000 × 700 px, with the `tolerance` as a dashed line.
///
/// `histories` are `(step number, residual norm per iteration)`, in the residual's own
/// units. With more than 30 steps, 29 evenly spaced ones are drawn plus the slowest (most
/// iterations, then largest final residual), which is highlighted. Exact zeros are drawn
/// one decade below the smallest positive value. Errors (`Invalid`): no histories, an
/// empty history, a negative or non-finite residual, a tolerance that is not finite and
/// positive.
pub fn plot_newton_residuals(
    path: &Path,
    histories: &[(usize, Vec<f64>)],
    tolerance: f64,
) -> Result<(), OutputError> {
    super::atomic::through_temp(path, |tmp| {
        draw_plot_newton_residuals(tmp, histories, tolerance)
    })
}

fn draw_plot_newton_residuals(
    path: &Path,
    histories: &[(usize, Vec<f64>)],
    tolerance: f64,
) -> Result<(), OutputError> {
    if histories.is_empty() {
        return Err(OutputError::invalid(
            "histories",
            "no Newton histories to plot",
        ));
    }
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(OutputError::invalid(
            "tolerance",
            format!("must be finite and positive, got {tolerance}"),
        ));
    }
    for (step, h) in histories {
        if h.is_empty() {
            return Err(OutputError::invalid(
                "histories",
                format!("the history of step {step} is empty"),
            ));
        }
        if let Some(i) = h.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
            return Err(OutputError::invalid(
                "histories",
                format!(
                    "step {step}, iteration {i}: residual {} is not finite and non-negative",
                    h[i]
                ),
            ));
        }
    }
    prepare(path)?;
    draw_newton_residuals(path, histories, tolerance).map_err(|e| OutputError::plot(path, e))
}

/// Indices into `histories` to draw, in step order, and the index of the slowest step.
fn pick_steps(histories: &[(usize, Vec<f64>)]) -> (Vec<usize>, usize) {
    let last = |h: &[f64]| h.last().copied().unwrap_or(0.0);
    let worst = (0..histories.len())
        .max_by(|&a, &b| {
            let (ha, hb) = (&histories[a].1, &histories[b].1);
            ha.len().cmp(&hb.len()).then(last(ha).total_cmp(&last(hb)))
        })
        .unwrap_or(0);
    let n = histories.len();
    let mut picked: Vec<usize> = if n <= MAX_DRAWN_STEPS {
        (0..n).collect()
    } else {
        let k = MAX_DRAWN_STEPS - 1;
        (0..k)
            .map(|i| (i * (n - 1) + (k - 1) / 2) / (k - 1))
            .collect()
    };
    picked.push(worst);
    picked.sort_unstable();
    picked.dedup();
    (picked, worst)
}

fn superscript(k: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::from("10");
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

fn draw_newton_residuals(
    path: &Path,
    histories: &[(usize, Vec<f64>)],
    tolerance: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let (picked, worst) = pick_steps(histories);
    let min_positive = histories
        .iter()
        .flat_map(|(_, h)| h.iter().copied())
        .filter(|&r| r > 0.0)
        .fold(tolerance, f64::min);
    let floor = min_positive.log10() - 1.0;
    let lg = |r: f64| if r > 0.0 { r.log10() } else { floor };

    let logs = picked
        .iter()
        .flat_map(|&i| histories[i].1.iter().map(|&r| lg(r)));
    let lo = logs.clone().fold(lg(tolerance), f64::min).floor();
    let hi = logs.fold(lg(tolerance), f64::max).ceil();
    let (lo, hi) = if hi - lo < 1.0 {
        (lo - 1.0, hi + 1.0)
    } else {
        (lo, hi)
    };
    let max_iter = picked
        .iter()
        .map(|&i| histories[i].1.len())
        .max()
        .unwrap_or(1)
        .max(2) as i32
        - 1;

    let root = BitMapBackend::new(path, CURVE_SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let title = if picked.len() < histories.len() {
        format!(
            "Newton convergence ({} of {} steps shown)",
            picked.len(),
            histories.len()
        )
    } else {
        let n = histories.len();
        format!(
            "Newton convergence ({n} step{})",
            if n == 1 { "" } else { "s" }
        )
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 30).into_font().style(FontStyle::Bold))
        .margin(20)
        .margin_right(40)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d(0..max_iter, lo..hi)?;
    chart
        .configure_mesh()
        .light_line_style(GRID.mix(0.5))
        .bold_line_style(GRID)
        .x_desc("Newton iteration")
        .y_desc("relative residual ‖F‖∞ / max(1, ‖σ‖∞)")
        .axis_desc_style((FONT, 24))
        .label_style((FONT, 20))
        .x_labels((max_iter + 1).min(20) as usize)
        .y_labels((hi - lo) as usize + 1)
        .y_label_formatter(&|v| {
            // Label decades only: an in-between tick at 10^-7.5 would read as noise.
            if (v - v.round()).abs() < 1e-9 {
                superscript(v.round() as i32)
            } else {
                String::new()
            }
        })
        .draw()?;

    let denom = (picked.len().max(2) - 1) as f64;
    for (rank, &i) in picked.iter().enumerate() {
        if i == worst {
            continue;
        }
        // Early steps dark purple, late steps green: yellow is kept off a white page.
        let colour = viridis(0.8 * rank as f64 / denom);
        let (step, h) = (&histories[i].0, &histories[i].1);
        let series = chart.draw_series(LineSeries::new(
            h.iter().enumerate().map(|(k, &r)| (k as i32, lg(r))),
            colour.stroke_width(2),
        ))?;
        if rank == 0 || rank == picked.len() - 1 {
            series.label(format!("step {step}")).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 30, y)], colour.stroke_width(3))
            });
        }
        chart.draw_series(
            h.iter()
                .enumerate()
                .map(|(k, &r)| Circle::new((k as i32, lg(r)), 3, colour.filled())),
        )?;
    }
    let (step, h) = (&histories[worst].0, &histories[worst].1);
    chart
        .draw_series(LineSeries::new(
            h.iter().enumerate().map(|(k, &r)| (k as i32, lg(r))),
            WORST_RED.stroke_width(3),
        ))?
        .label(if histories.len() == 1 {
            format!("step {step} ({} iterations)", h.len() - 1)
        } else {
            format!("slowest: step {step} ({} iterations)", h.len() - 1)
        })
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], WORST_RED.stroke_width(3)));
    chart.draw_series(
        h.iter()
            .enumerate()
            .map(|(k, &r)| Circle::new((k as i32, lg(r)), 4, WORST_RED.filled())),
    )?;

    let t = tolerance.log10();
    chart
        .draw_series(DashedLineSeries::new(
            [(0, t), (max_iter, t)],
            12,
            8,
            BLACK.stroke_width(2),
        ))?
        .label(format!("tolerance {tolerance:.0e}"))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 12, y)], BLACK.stroke_width(2)));

    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FONT, 20))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.5))
        .draw()?;
    root.present()?;
    Ok(())
}

/// `[min, max]` of the values, widened by 5 % (or by 1 for a single value).
fn padded_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let pad = if hi > lo { 0.05 * (hi - lo) } else { 1.0 };
    (lo - pad)..(hi + pad)
}
