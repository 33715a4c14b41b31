//! The frame of a map plot (a field in the x–y plane): title band, axes in m at equal
//! scale, and a viridis colour bar. Shared by the mesh field and the particle plots.
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{significant, tick, FONT};
use super::colormap::{viridis, Normalize};

const WIDTH: u32 = 1200;
const COLOUR_BAR_AREA: u32 = 190;
const MARGIN: u32 = 15;
const TITLE_BAND: u32 = 60;
const X_LABEL_AREA: u32 = 60;
const Y_LABEL_AREA: u32 = 80;

pub(super) type DynResult<T = ()> = Result<T, Box<dyn std::error::Error>>;

type Bitmap<'p> = BitMapBackend<'p>;

/// A map 1200 px wide whose axes and title are drawn; the caller paints on `chart`, then
/// calls [`MapFrame::finish`].
pub(super) struct MapFrame<'p> {
    root: DrawingArea<Bitmap<'p>, Shift>,
    bar: DrawingArea<Bitmap<'p>, Shift>,
    pub chart: ChartContext<'p, Bitmap<'p>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    /// Size of the plotting area, px.
    pub plot_px: (f64, f64),
    /// The x and y ranges of the plotting area, m (`window` widened to equal scale).
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
}

impl<'p> MapFrame<'p> {
    /// Sizes the image so that `window` (m) fills the plotting area at equal scale (height
    /// from the aspect ratio, clamped to 250–1000 px), draws `title` and the axes.
    pub fn new(path: &'p Path, window: &BBox, title: &str) -> DynResult<Self> {
        // Height from the aspect ratio; ranges are then widened to equal scale exactly.
        let plot_w = (WIDTH - COLOUR_BAR_AREA - 2 * MARGIN - Y_LABEL_AREA) as f64;
        let plot_h = (plot_w * window.height() / window.width()).clamp(250.0, 1000.0);
        let height = plot_h as u32 + 2 * MARGIN + X_LABEL_AREA + TITLE_BAND;

        let root = BitMapBackend::new(path, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE)?;
        // The title gets its own band: `titled` puts the glyph tops on the image edge.
        let (head, body) = root.split_vertically(TITLE_BAND);
        let (head_w, _) = head.dim_in_pixel();
        head.draw(&Text::new(
            title.to_string(),
            (head_w as i32 / 2, TITLE_BAND as i32 / 2 + 4),
            (FONT, 30)
                .into_font()
                .style(FontStyle::Bold)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
        let (main, bar) = body.split_horizontally(WIDTH - COLOUR_BAR_AREA);

        let (w, h) = main.dim_in_pixel();
        let pw = f64::from(w - 2 * MARGIN - Y_LABEL_AREA);
        let ph = f64::from(h - 2 * MARGIN - X_LABEL_AREA);
        let scale = (window.width() / pw).max(window.height() / ph); // m per pixel
        let (cx, cy) = window.centre();
        let xr = (cx - 0.5 * scale * pw, cx + 0.5 * scale * pw);
        let yr = (cy - 0.5 * scale * ph, cy + 0.5 * scale * ph);

        let mut chart = ChartBuilder::on(&main)
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x [m]")
            .y_desc("y [m]")
            .axis_desc_style((FONT, 22))
            .label_style((FONT, 18))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .draw()?;
        Ok(Self {
            root,
            bar,
            chart,
            plot_px: (pw, ph),
            x_range: xr,
            y_range: yr,
        })
    }

    /// Draws the colour bar of `norm` named `label`, then writes the PNG.
    pub fn finish(self, norm: Normalize, label: &str) -> DynResult {
        let top = (MARGIN as i32) + 10;
        let bottom = (MARGIN + self.plot_px.1 as u32) as i32 + (MARGIN as i32) - 10;
        draw_colour_bar(&self.bar, norm, top, bottom, label)?;
        self.root.present()?;
        Ok(())
    }
}

fn draw_colour_bar(
    bar: &DrawingArea<Bitmap, Shift>,
    norm: Normalize,
    top: i32,
    bottom: i32,
    label: &str,
) -> DynResult {
    let (x0, x1) = (20, 50);
    let span = (bottom - top).max(1);
    for py in top..bottom {
        let t = f64::from(bottom - 1 - py) / f64::from(span - 1).max(1.0);
        bar.draw(&Rectangle::new(
            [(x0, py), (x1, py + 1)],
            viridis(t).filled(),
        ))?;
    }
    bar.draw(&Rectangle::new(
        [(x0, top), (x1, bottom)],
        BLACK.stroke_width(1),
    ))?;
    let style = (FONT, 18).into_font().color(&BLACK);
    let label_at = |value: f64, text: String| -> DynResult {
        let py = bottom - (norm.t(value) * f64::from(span)).round() as i32;
        bar.draw(&PathElement::new(vec![(x1, py), (x1 + 6, py)], BLACK))?;
        bar.draw(&Text::new(
            text,
            (x1 + 10, py),
            style.pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        Ok(())
    };
    let range = norm.max - norm.min;
    // Values within 10⁻⁶ of the range from zero are zero (e.g. 6.5e-75 of plastic strain).
    let show = |v: f64| {
        if v.abs() <= 1e-6 * range {
            "0".to_string()
        } else {
            significant(v, 3)
        }
    };
    if range > 0.0 {
        label_at(norm.min, format!("{} (min)", show(norm.min)))?;
        label_at(norm.max, format!("{} (max)", show(norm.max)))?;
        // Round values in between, kept clear of the min/max labels.
        let step = nice_step(range / 4.0);
        let mut k = (norm.min / step).ceil();
        while k * step <= norm.max {
            let v = k * step;
            let t = norm.t(v);
            if t > 0.08 && t < 0.92 {
                label_at(v, show(v))?;
            }
            k += 1.0;
        }
    } else {
        label_at(norm.min, format!("{} (constant)", significant(norm.min, 3)))?;
    }
    // The field's name runs along the bar, so a long label does not need a wide margin.
    let (w, _) = bar.dim_in_pixel();
    bar.draw(&Text::new(
        label.to_string(),
        (w as i32 - 12, (top + bottom) / 2),
        (FONT, 20)
            .into_font()
            .transform(FontTransform::Rotate270)
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center)),
    ))?;
    Ok(())
}

/// The round step (1, 2, 2.5 or 5 × 10ᵏ) nearest above `raw`.
fn nice_step(raw: f64) -> f64 {
    let decade = 10f64.powf(raw.log10().floor());
    let m = raw / decade;
    let nice = [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .find(|&n| n >= m - 1e-9)
        .unwrap_or(10.0);
    nice * decade
}

/// An axis-aligned box in the x–y plane, m.
#[derive(Debug, Clone, Copy)]
pub(super) struct BBox {
    pub x: (f64, f64),
    pub y: (f64, f64),
}

impl BBox {
    pub fn of(points: impl Iterator<Item = [f64; 2]>) -> Self {
        points.fold(
            Self {
                x: (f64::INFINITY, f64::NEG_INFINITY),
                y: (f64::INFINITY, f64::NEG_INFINITY),
            },
            |b, p| Self {
                x: (b.x.0.min(p[0]), b.x.1.max(p[0])),
                y: (b.y.0.min(p[1]), b.y.1.max(p[1])),
            },
        )
    }

    pub fn union(&self, o: &Self) -> Self {
        Self {
            x: (self.x.0.min(o.x.0), self.x.1.max(o.x.1)),
            y: (self.y.0.min(o.y.0), self.y.1.max(o.y.1)),
        }
    }

    /// The box grown by `d` on every side.
    pub fn grown(&self, d: f64) -> Self {
        Self {
            x: (self.x.0 - d, self.x.1 + d),
            y: (self.y.0 - d, self.y.1 + d),
        }
    }

    /// 3 % of the larger side around the content, so the boundary line is not clipped; a
    /// degenerate (zero-area) box gets a unit size.
    pub fn padded(&self) -> Self {
        let size = (self.x.1 - self.x.0).max(self.y.1 - self.y.0);
        self.grown(if size > 0.0 { 0.03 * size } else { 0.5 })
    }

    pub fn width(&self) -> f64 {
        self.x.1 - self.x.0
    }

    pub fn height(&self) -> f64 {
        self.y.1 - self.y.0
    }

    pub fn centre(&self) -> (f64, f64) {
        (0.5 * (self.x.0 + self.x.1), 0.5 * (self.y.0 + self.y.1))
    }
}
