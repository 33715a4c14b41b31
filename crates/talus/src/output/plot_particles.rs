//! Material points as filled squares coloured by a value, with a colour bar.
use std::path::Path;

use plotters::prelude::*;

use super::canvas::prepare;
use super::map_frame::{BBox, ColourScale, DynResult, MapFrame};
use super::mesh::{check_finite, check_finite_scalars, check_finite_value, check_len};
use super::spacing::mean_spacing;
use super::OutputError;

/// A particle is never drawn smaller than this, so a sparse cloud stays visible.
const MIN_MARKER_PX: f64 = 2.0;
/// Marker side, as a fraction of the window's larger side, when no spacing can be measured
/// (a single particle, or all at one position).
const LONE_MARKER: f64 = 0.02;

/// How [`plot_particles`] frames and draws the particles. Lengths in m.
#[derive(Debug, Clone, Copy)]
pub struct ParticlePlot<'a> {
    /// Above the plot.
    pub title: &'a str,
    /// Along the colour bar: the value's name and unit.
    pub value_label: &'a str,
    /// `[[xmin, ymin], [xmax, ymax]]` of the plotted window (widened to equal scale);
    /// `None` fits the particles (and the floor), with a 3 % margin.
    pub bounds: Option<[[f64; 2]; 2]>,
    /// Side of a particle's square; `None` uses the mean nearest-neighbour spacing, so
    /// particles on a lattice tile the plot.
    pub marker_size: Option<f64>,
    /// Draws the ground as a horizontal line at this y.
    pub floor: Option<f64>,
}

/// Draws particles at `position` (m) as filled squares coloured by `value` (one per
/// particle, in the caller's units) as a PNG 1200 px wide, x and y at equal scale.
///
/// Colours: viridis between the min and max of `value` (a uniform value, constant to a
/// millionth, is drawn in the middle colour with one label), shown by the colour bar. Squares are drawn in the given order and
/// clipped to the window; each is at least 2 px wide. Errors (`Invalid`, nothing drawn):
/// no particles, `value` not one per particle, non-finite input, `bounds` not ordered,
/// `marker_size` not positive.
pub fn plot_particles(
    path: &Path,
    position: &[[f64; 2]],
    value: &[f64],
    view: ParticlePlot,
) -> Result<(), OutputError> {
    super::atomic::through_temp(path, |tmp| draw_plot_particles(tmp, position, value, view))
}

fn draw_plot_particles(
    path: &Path,
    position: &[[f64; 2]],
    value: &[f64],
    view: ParticlePlot,
) -> Result<(), OutputError> {
    if position.is_empty() {
        return Err(OutputError::invalid("position", "there are no particles"));
    }
    check_len("value", value.len(), position.len(), "particle")?;
    check_finite("position", position)?;
    check_finite_scalars("value", value)?;
    if let Some(y) = view.floor {
        check_finite_value("floor", y)?;
    }
    if let Some(s) = view.marker_size {
        if !(s.is_finite() && s > 0.0) {
            return Err(OutputError::invalid(
                "marker_size",
                format!("is not a positive length: {s}"),
            ));
        }
    }
    let spacing = view.marker_size.or_else(|| mean_spacing(position));
    let (window, field) = match view.bounds {
        Some(b) => {
            check_finite("bounds", &b)?;
            if !(b[0][0] < b[1][0] && b[0][1] < b[1][1]) {
                return Err(OutputError::invalid(
                    "bounds",
                    format!("{b:?} is not [[xmin, ymin], [xmax, ymax]] with min < max"),
                ));
            }
            let window = BBox {
                x: (b[0][0], b[1][0]),
                y: (b[0][1], b[1][1]),
            };
            (window, "bounds")
        }
        None => {
            let mut fit = BBox::of(position.iter().copied()).grown(0.5 * spacing.unwrap_or(0.0));
            if let Some(y) = view.floor {
                fit.y = (fit.y.0.min(y), fit.y.1.max(y));
            }
            (fit.padded(), "position")
        }
    };
    if !(window.width().is_finite() && window.height().is_finite()) {
        return Err(OutputError::invalid(
            field,
            format!("the plotted window {window:?} is too large"),
        ));
    }
    prepare(path)?;
    let marker = spacing.unwrap_or(LONE_MARKER * window.width().max(window.height()));
    draw(path, position, value, &view, &window, marker).map_err(|e| OutputError::plot(path, e))
}

fn draw(
    path: &Path,
    position: &[[f64; 2]],
    value: &[f64],
    view: &ParticlePlot,
    window: &BBox,
    marker: f64,
) -> DynResult {
    let mut frame = MapFrame::new(path, window, view.title, &[])?;
    let ((x0, x1), (y0, y1)) = (frame.x_range, frame.y_range);
    let metres_per_px = (x1 - x0) / frame.plot_px.0;
    let half = 0.5 * marker.max(MIN_MARKER_PX * metres_per_px);
    let scale = ColourScale::full(value);
    let squares = position.iter().zip(value).filter_map(|(p, &v)| {
        let (a, b) = ((p[0] - half).max(x0), (p[0] + half).min(x1));
        let (c, d) = ((p[1] - half).max(y0), (p[1] + half).min(y1));
        (a < b && c < d).then(|| Rectangle::new([(a, c), (b, d)], scale.colour(v).filled()))
    });
    frame.chart.draw_series(squares)?;
    if let Some(y) = view.floor.filter(|y| (y0..=y1).contains(y)) {
        frame.chart.draw_series([PathElement::new(
            vec![(x0, y), (x1, y)],
            BLACK.stroke_width(2),
        )])?;
    }
    frame.finish(&scale, view.value_label)
}
