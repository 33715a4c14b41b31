//! The frame of a map plot (a field in the x–y plane): title band, axes in m at equal
//! scale, and a viridis colour bar. Shared by the mesh field and the particle plots.
//! [`ColourScale`] decides which values the colours span: min to max, the top clipped at a
//! percentile, or one colour for a uniform field.
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
/// The title's line; each subtitle line adds `SUBTITLE_LINE`.
const TITLE_BAND: u32 = 60;
const SUBTITLE_LINE: u32 = 28;
const X_LABEL_AREA: u32 = 60;
const Y_LABEL_AREA: u32 = 80;
/// Font sizes tried, largest first, until a text fits its room.
const TITLE_FONTS: [u32; 5] = [30, 26, 22, 20, 18];
const SUBTITLE_FONTS: [u32; 4] = [20, 18, 16, 14];
const BAR_LABEL_FONTS: [u32; 4] = [20, 18, 16, 14];
/// The colour bar's name runs along the bar in at most this many columns, the first
/// centred this far from the bar area's left edge.
const BAR_LABEL_COLUMNS: usize = 2;
const BAR_LEFT: i32 = 14;
const TICK_FONTS: [u32; 4] = [18, 16, 14, 12];

/// A field spanning less than this fraction of its magnitude is drawn as uniform: in one
/// colour, with one label (round-off on a constant field is not a pattern).
const UNIFORM_SPAN: f64 = 1e-6;
/// A percentile clip is applied only when the values above it stretch the scale by more
/// than this fraction of the clipped range: a smooth field keeps its min-to-max scale.
const CLIP_WORTH: f64 = 0.1;

pub(super) type DynResult<T = ()> = Result<T, Box<dyn std::error::Error>>;

type Bitmap<'p> = BitMapBackend<'p>;

/// The `p`-th percentile (0–100) of `values`: linear between the order statistics at rank
/// `p/100 · (n − 1)` (NumPy's default). `NaN` for no values or `p` outside [0, 100]; NaN
/// values are sorted last.
fn percentile(values: &[f64], p: f64) -> f64 {
    if values.is_empty() || !(0.0..=100.0).contains(&p) {
        return f64::NAN;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = p / 100.0 * (sorted.len() - 1) as f64;
    let (i, f) = (rank.floor() as usize, rank - rank.floor());
    match sorted.get(i + 1) {
        Some(&next) if f > 0.0 => sorted[i] + f * (next - sorted[i]),
        _ => sorted[i],
    }
}

/// Which values a map's colours span, and how its colour bar is labelled.
///
/// ```
/// use talus::output::ColourScale;
/// // One spike among 0, 0.001, …, 0.999: the colours span the 99th percentile.
/// let mut v: Vec<f64> = (0..1000).map(|i| i as f64 / 1000.0).collect();
/// v.push(50.0);
/// let s = ColourScale::clipped(&v, 99.0);
/// assert!(s.hi < 1.0 && s.max == 50.0 && s.clipped_at == Some(99.0));
/// assert!(ColourScale::full(&[2.0, 2.0 + 1e-12]).is_uniform());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColourScale {
    /// Smallest and largest value of the field.
    pub min: f64,
    pub max: f64,
    /// The values the colours span, from the first colour to the last: `[min, max]`, or
    /// `[min, percentile]` when clipped (values above are drawn in the last colour).
    pub lo: f64,
    pub hi: f64,
    /// The percentile the top was clipped at, when it was.
    pub clipped_at: Option<f64>,
    /// Values closer than this (absolute, in the values' unit) are not told apart.
    pub resolution: f64,
}

impl ColourScale {
    /// Min to max of `values`: [`ColourScale::new`] without clipping or resolution.
    pub fn full(values: &[f64]) -> Self {
        Self::new(values, None, 0.0)
    }

    /// [`ColourScale::new`] clipped at `percentile`, without resolution.
    pub fn clipped(values: &[f64], percentile: f64) -> Self {
        Self::new(values, Some(percentile), 0.0)
    }

    /// The scale of `values` (finite, not empty).
    ///
    /// With `clip_percentile = Some(p)`, min to the `p`-th percentile of `values` when the
    /// values above it would stretch the scale by more than 10 % of that range (a singular
    /// peak, e.g. at a footing's corner); otherwise, and without, min to max. A field
    /// uniform below the percentile keeps its full range, so that a lone peak stays
    /// visible. The field is uniform ([`ColourScale::is_uniform`]) when its span is within
    /// a millionth of its magnitude or within `resolution` (e.g. the round-off of a plastic
    /// strain that is zero).
    pub fn new(values: &[f64], clip_percentile: Option<f64>, resolution: f64) -> Self {
        let n = Normalize::of(values);
        let full = Self {
            min: n.min,
            max: n.max,
            lo: n.min,
            hi: n.max,
            clipped_at: None,
            resolution: resolution.max(0.0),
        };
        let Some(percentile) = clip_percentile else {
            return full;
        };
        let p = self::percentile(values, percentile);
        let clipped = Self {
            hi: p,
            clipped_at: Some(percentile),
            ..full
        };
        if p.is_finite() && !clipped.is_uniform() && full.max - p > CLIP_WORTH * (p - full.min) {
            clipped
        } else {
            full
        }
    }

    /// The colours would span less than a millionth of the values' magnitude, less than
    /// the resolution, or nothing: one colour, one label.
    pub fn is_uniform(&self) -> bool {
        let span = self.hi - self.lo;
        span <= UNIFORM_SPAN * self.lo.abs().max(self.hi.abs()) || span <= self.resolution
    }

    /// Where `v` falls on the colour map, in [0, 1]: clamped to the span; 0.5 for a
    /// uniform scale.
    pub fn t(&self, v: f64) -> f64 {
        if self.is_uniform() {
            return 0.5;
        }
        Normalize {
            min: self.lo,
            max: self.hi,
        }
        .t(v)
        .clamp(0.0, 1.0)
    }

    pub(super) fn colour(&self, v: f64) -> RGBColor {
        viridis(self.t(v))
    }

    /// The colour bar's labelled values and their text: one `"… (uniform)"` label for a
    /// uniform scale; otherwise the ends (`"(min)"`, `"(max)"`, or `"≥ …"` at a clipped
    /// top) and round values in between, with enough digits that no two read the same.
    pub fn ticks(&self) -> Vec<(f64, String)> {
        if self.is_uniform() {
            let v = 0.5 * (self.lo + self.hi);
            // Within the resolution of zero is zero (round-off of a zero plastic strain).
            let v = if v.abs() <= self.resolution { 0.0 } else { v };
            return vec![(v, format!("{} (uniform)", significant(v, 3)))];
        }
        let range = self.hi - self.lo;
        let step = nice_step(range / 4.0);
        // Digits down to the step's own (2.5 × 10ᵏ needs one more), at least 3.
        let magnitude = self.lo.abs().max(self.hi.abs());
        let mantissa = step / 10f64.powf(step.log10().floor());
        let digits = magnitude.log10().floor() - step.log10().floor()
            + 1.0
            + if (mantissa - 2.5).abs() < 1e-9 {
                1.0
            } else {
                0.0
            };
        let digits = (digits as usize).clamp(3, 12);
        // Values within 10⁻⁶ of the range from zero are zero (e.g. 6.5e-75 of plastic strain).
        let show = |v: f64| {
            if v.abs() <= 1e-6 * range {
                "0".to_string()
            } else {
                significant(v, digits)
            }
        };
        let mut ticks = vec![(self.lo, format!("{} (min)", show(self.lo)))];
        let top = match self.clipped_at {
            Some(_) => format!("≥ {}", show(self.hi)),
            None => format!("{} (max)", show(self.hi)),
        };
        // Round values in between, kept clear of the end labels.
        let mut k = (self.lo / step).ceil();
        while k * step <= self.hi {
            let v = k * step;
            let t = self.t(v);
            if t > 0.08 && t < 0.92 {
                ticks.push((v, show(v)));
            }
            k += 1.0;
        }
        ticks.push((self.hi, top));
        ticks
    }

    /// What a clipped scale leaves out, for the picture: `"colours clipped at the 99th
    /// percentile (0.0234), max = 0.0672"`; `None` when not clipped.
    pub fn note(&self) -> Option<String> {
        let p = self.clipped_at?;
        Some(format!(
            "colours clipped at the {} percentile ({}), max = {}",
            ordinal(p),
            significant(self.hi, 3),
            significant(self.max, 3)
        ))
    }
}

/// `99` → `99th`, `92.5` → `92.5th`, `1` → `1st`.
fn ordinal(p: f64) -> String {
    let text = significant(p, 4);
    let suffix = if text.contains('.') {
        "th"
    } else {
        match (p as u64 % 100, p as u64 % 10) {
            (11..=13, _) => "th",
            (_, 1) => "st",
            (_, 2) => "nd",
            (_, 3) => "rd",
            _ => "th",
        }
    };
    format!("{text}{suffix}")
}

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
    /// from the aspect ratio, clamped to 250–1000 px), draws `title` (bold), the
    /// `subtitles` under it (one line each; a line too long for the width is drawn in a
    /// smaller font) and the axes.
    pub fn new(
        path: &'p Path,
        window: &BBox,
        title: &str,
        subtitles: &[String],
    ) -> DynResult<Self> {
        // Height from the aspect ratio; ranges are then widened to equal scale exactly.
        let plot_w = (WIDTH - COLOUR_BAR_AREA - 2 * MARGIN - Y_LABEL_AREA) as f64;
        let plot_h = (plot_w * window.height() / window.width()).clamp(250.0, 1000.0);
        let band = TITLE_BAND + SUBTITLE_LINE * subtitles.len() as u32;
        let height = plot_h as u32 + 2 * MARGIN + X_LABEL_AREA + band;

        let root = BitMapBackend::new(path, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE)?;
        // The title gets its own band: `titled` puts the glyph tops on the image edge.
        let (head, body) = root.split_vertically(band);
        let (head_w, _) = head.dim_in_pixel();
        let room = head_w.saturating_sub(2 * MARGIN);
        let size = fitting_font(&head, title, &TITLE_FONTS, room, true)?;
        head.draw(&Text::new(
            title.to_string(),
            (head_w as i32 / 2, TITLE_BAND as i32 / 2 + 4),
            (FONT, size)
                .into_font()
                .style(FontStyle::Bold)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
        for (i, line) in subtitles.iter().enumerate() {
            let size = fitting_font(&head, line, &SUBTITLE_FONTS, room, false)?;
            let y = TITLE_BAND as i32 - 6 + (SUBTITLE_LINE as i32) * i as i32;
            head.draw(&Text::new(
                line.clone(),
                (head_w as i32 / 2, y + SUBTITLE_LINE as i32 / 2),
                (FONT, size)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            ))?;
        }
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

    /// Draws the colour bar of `scale` named `label`, then writes the PNG.
    pub fn finish(self, scale: &ColourScale, label: &str) -> DynResult {
        let top = (MARGIN as i32) + 10;
        let bottom = (MARGIN + self.plot_px.1 as u32) as i32 + (MARGIN as i32) - 10;
        draw_colour_bar(&self.bar, scale, top, bottom, label)?;
        self.root.present()?;
        Ok(())
    }
}

/// The largest of `sizes` (the last if none) at which `text` is at most `room` px wide.
fn fitting_font(
    area: &DrawingArea<Bitmap, Shift>,
    text: &str,
    sizes: &[u32],
    room: u32,
    bold: bool,
) -> DynResult<u32> {
    for &size in sizes {
        let font = (FONT, size).into_font();
        let font = if bold {
            font.style(FontStyle::Bold)
        } else {
            font
        };
        let (w, _) = area.estimate_text_size(text, &font.into())?;
        if w <= room {
            return Ok(size);
        }
    }
    Ok(sizes.last().copied().unwrap_or(14))
}

/// `text` broken at spaces into lines at most `room` px wide in `font` (a word longer
/// than `room` gets a line of its own).
fn wrap(
    area: &DrawingArea<Bitmap, Shift>,
    text: &str,
    font: &FontDesc,
    room: u32,
) -> DynResult<Vec<String>> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        if let Some(last) = lines.last_mut() {
            let joined = format!("{last} {word}");
            if area.estimate_text_size(&joined, &font.clone().into())?.0 <= room {
                *last = joined;
                continue;
            }
        }
        lines.push(word.to_string());
    }
    Ok(lines)
}

fn draw_colour_bar(
    bar: &DrawingArea<Bitmap, Shift>,
    scale: &ColourScale,
    top: i32,
    bottom: i32,
    label: &str,
) -> DynResult {
    // The field's name runs up the bar's left side, in one or two columns and the largest
    // font that fits the bar's height, so that a long label is never cut off.
    let room = (bottom - top).max(1) as u32;
    let mut columns = Vec::new();
    let mut size = BAR_LABEL_FONTS[BAR_LABEL_FONTS.len() - 1];
    for &s in &BAR_LABEL_FONTS {
        columns = wrap(bar, label, &(FONT, s).into_font(), room)?;
        size = s;
        if columns.len() <= BAR_LABEL_COLUMNS {
            break;
        }
    }
    let column_px = size as i32 + 4;
    for (i, line) in columns.iter().enumerate() {
        bar.draw(&Text::new(
            line.clone(),
            (BAR_LEFT + column_px * i as i32, (top + bottom) / 2),
            (FONT, size)
                .into_font()
                .transform(FontTransform::Rotate270)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
    }
    let x0 = BAR_LEFT + column_px * columns.len().max(1) as i32 - column_px / 2 + 8;
    let x1 = x0 + 30;

    let span = (bottom - top).max(1);
    for py in top..bottom {
        let t = if scale.is_uniform() {
            0.5
        } else {
            f64::from(bottom - 1 - py) / f64::from(span - 1).max(1.0)
        };
        bar.draw(&Rectangle::new(
            [(x0, py), (x1, py + 1)],
            viridis(t).filled(),
        ))?;
    }
    bar.draw(&Rectangle::new(
        [(x0, top), (x1, bottom)],
        BLACK.stroke_width(1),
    ))?;
    if scale.clipped_at.is_some() {
        // A clipped top: the last colour continues as an arrow head (more above).
        let head = vec![(x0, top), ((x0 + x1) / 2, top - 14), (x1, top)];
        bar.draw(&Polygon::new(head.clone(), viridis(1.0).filled()))?;
        let mut outline = head;
        outline.push((x0, top));
        bar.draw(&PathElement::new(outline, BLACK.stroke_width(1)))?;
    }

    // Tick texts in the largest font that fits right of the bar.
    let ticks = scale.ticks();
    let (w, _) = bar.dim_in_pixel();
    let text_room = (w as i32 - (x1 + 10) - 4).max(1) as u32;
    let mut tick_size = TICK_FONTS[TICK_FONTS.len() - 1];
    for &s in &TICK_FONTS {
        let font: TextStyle = (FONT, s).into_font().into();
        let mut widest = 0;
        for (_, text) in &ticks {
            widest = widest.max(bar.estimate_text_size(text, &font)?.0);
        }
        tick_size = s;
        if widest <= text_room {
            break;
        }
    }
    let style = (FONT, tick_size).into_font().color(&BLACK);
    let at = |value: f64| {
        if scale.is_uniform() {
            (top + bottom) / 2
        } else {
            bottom - (scale.t(value) * f64::from(span)).round() as i32
        }
    };
    // The ends come first and last; a round value too close to an end is left out.
    let ends = [ticks.first(), ticks.last()].map(|t| t.map(|t| at(t.0)));
    let clearance = tick_size as i32 + 8;
    for (i, (value, text)) in ticks.iter().enumerate() {
        let py = at(*value);
        let end = i == 0 || i + 1 == ticks.len();
        if !end && ends.iter().flatten().any(|&e| (e - py).abs() < clearance) {
            continue;
        }
        bar.draw(&PathElement::new(vec![(x1, py), (x1 + 6, py)], BLACK))?;
        bar.draw(&Text::new(
            text.clone(),
            (x1 + 10, py),
            style.pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
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
