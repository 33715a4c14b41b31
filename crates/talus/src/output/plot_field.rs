//! A per-element field painted on the (optionally deformed) mesh, with a colour bar.
use std::collections::HashMap;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{prepare, significant, tick, FONT};
use super::colormap::{viridis, Normalize};
use super::mesh::{check_finite, check_finite_scalars, check_len, linear_pieces};
use super::{MeshView, OutputError};

const WIDTH: u32 = 1200;
const COLOUR_BAR_AREA: u32 = 190;
const MARGIN: u32 = 15;
const TITLE_BAND: u32 = 60;
const X_LABEL_AREA: u32 = 60;
const Y_LABEL_AREA: u32 = 80;
/// Element edges are drawn only when elements are at least this wide on the page.
const MIN_EDGE_SPACING_PX: f64 = 7.0;

/// Paints `values` (one per element, in the caller's units, named by `label`) on the mesh
/// as a PNG 1200 px wide, x and y in m at equal scale.
///
/// With `displacement = Some((u, k))` the mesh is drawn at `x + k·u` (u per node, m; k the
/// magnification) over the undeformed outline in grey. P2 elements are filled as 4
/// sub-triangles through their mid-edge nodes, so curved deformed edges are followed.
/// Colours: viridis between the field's min and max, shown by the colour bar. Errors
/// (`Invalid`): bad mesh, lengths that do not match, non-finite values or magnification.
pub fn plot_field_on_mesh(
    path: &Path,
    mesh: &MeshView,
    displacement: Option<(&[[f64; 2]], f64)>,
    values: &[f64],
    label: &str,
) -> Result<(), OutputError> {
    mesh.validate()?;
    check_len("values", values.len(), mesh.triangles.len(), "element")?;
    check_finite_scalars("values", values)?;
    let deformed: Vec<[f64; 2]> = match displacement {
        None => mesh.nodes.to_vec(),
        Some((u, k)) => {
            check_len("displacement", u.len(), mesh.nodes.len(), "node")?;
            check_finite("displacement", u)?;
            if !k.is_finite() {
                return Err(OutputError::invalid(
                    "magnification",
                    format!("is not finite: {k}"),
                ));
            }
            let moved: Vec<[f64; 2]> = mesh
                .nodes
                .iter()
                .zip(u)
                .map(|(x, u)| [x[0] + k * u[0], x[1] + k * u[1]])
                .collect();
            check_finite("displacement", &moved)?;
            moved
        }
    };
    let title = match displacement {
        Some((_, k)) => format!("{label} (deformed shape ×{})", tick(k)),
        None => label.to_string(),
    };
    prepare(path)?;
    let plot = FieldPlot {
        mesh,
        deformed: &deformed,
        undeformed_outline: displacement.is_some(),
        values,
        label,
        title: &title,
    };
    plot.draw(path).map_err(|e| OutputError::plot(path, e))
}

struct FieldPlot<'a> {
    mesh: &'a MeshView<'a>,
    deformed: &'a [[f64; 2]],
    undeformed_outline: bool,
    values: &'a [f64],
    label: &'a str,
    title: &'a str,
}

type DynResult = Result<(), Box<dyn std::error::Error>>;

impl FieldPlot<'_> {
    fn draw(&self, path: &Path) -> DynResult {
        let used = used_nodes(self.mesh);
        let mut bbox = BBox::of(used.iter().map(|&n| self.deformed[n]));
        if self.undeformed_outline {
            bbox = bbox.union(&BBox::of(used.iter().map(|&n| self.mesh.nodes[n])));
        }
        let bbox = bbox.padded();

        // Height from the aspect ratio; ranges are then widened to equal scale exactly.
        let plot_w = (WIDTH - COLOUR_BAR_AREA - 2 * MARGIN - Y_LABEL_AREA) as f64;
        let plot_h = (plot_w * bbox.height() / bbox.width()).clamp(250.0, 1000.0);
        let height = plot_h as u32 + 2 * MARGIN + X_LABEL_AREA + TITLE_BAND;

        let root = BitMapBackend::new(path, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE)?;
        // The title gets its own band: `titled` puts the glyph tops on the image edge.
        let (head, body) = root.split_vertically(TITLE_BAND);
        let (head_w, _) = head.dim_in_pixel();
        head.draw(&Text::new(
            self.title.to_string(),
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
        let scale = (bbox.width() / pw).max(bbox.height() / ph); // m per pixel
        let (cx, cy) = bbox.centre();
        let xr = (cx - 0.5 * scale * pw)..(cx + 0.5 * scale * pw);
        let yr = (cy - 0.5 * scale * ph)..(cy + 0.5 * scale * ph);

        let mut chart = ChartBuilder::on(&main)
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(xr, yr)?;
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

        let norm = Normalize::of(self.values);
        let fills = self
            .mesh
            .triangles
            .iter()
            .zip(self.values)
            .flat_map(|(tri, &v)| {
                let colour = viridis(norm.t(v));
                linear_pieces(tri).into_iter().map(move |p| (p, colour))
            });
        for (piece, colour) in fills {
            let pts: Vec<(f64, f64)> = piece
                .iter()
                .map(|&n| (self.deformed[n][0], self.deformed[n][1]))
                .collect();
            chart.draw_series([Polygon::new(pts.clone(), colour.filled())])?;
            // The scan-line fill leaves hairline gaps between neighbours: stroke the edges too.
            let mut closed = pts;
            closed.push(closed[0]);
            chart.draw_series([PathElement::new(closed, colour.stroke_width(1))])?;
        }

        let element_px = (pw * ph / self.mesh.triangles.len() as f64).sqrt();
        if element_px >= MIN_EDGE_SPACING_PX {
            let edge = RGBColor(30, 30, 30).mix(0.35);
            for tri in self.mesh.triangles {
                chart.draw_series([PathElement::new(
                    element_outline(tri, self.deformed),
                    edge.stroke_width(1),
                )])?;
            }
        }
        let boundary = boundary_edges(self.mesh);
        if self.undeformed_outline {
            let grey = RGBColor(120, 120, 120);
            for e in &boundary {
                let pts = e
                    .iter()
                    .map(|&n| (self.mesh.nodes[n][0], self.mesh.nodes[n][1]));
                chart.draw_series([PathElement::new(
                    pts.collect::<Vec<_>>(),
                    grey.stroke_width(1),
                )])?;
            }
        }
        for e in &boundary {
            let pts = e
                .iter()
                .map(|&n| (self.deformed[n][0], self.deformed[n][1]));
            chart.draw_series([PathElement::new(
                pts.collect::<Vec<_>>(),
                BLACK.stroke_width(2),
            )])?;
        }

        let (top, bottom) = (
            (MARGIN as i32) + 10,
            (MARGIN + ph as u32) as i32 + (MARGIN as i32) - 10,
        );
        self.draw_colour_bar(&bar, norm, top, bottom)?;
        root.present()?;
        Ok(())
    }

    fn draw_colour_bar(
        &self,
        bar: &DrawingArea<BitMapBackend, Shift>,
        norm: Normalize,
        top: i32,
        bottom: i32,
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
            self.label.to_string(),
            (w as i32 - 12, (top + bottom) / 2),
            (FONT, 20)
                .into_font()
                .transform(FontTransform::Rotate270)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
        Ok(())
    }
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

/// Corner → (mid-edge →) corner path around one element.
fn element_outline(tri: &[usize], x: &[[f64; 2]]) -> Vec<(f64, f64)> {
    let order: &[usize] = if tri.len() == 6 {
        &[0, 3, 1, 4, 2, 5, 0]
    } else {
        &[0, 1, 2, 0]
    };
    order
        .iter()
        .map(|&i| (x[tri[i]][0], x[tri[i]][1]))
        .collect()
}

/// Edges used by one element only, as node paths (with the mid-edge node for P2).
fn boundary_edges(mesh: &MeshView) -> Vec<Vec<usize>> {
    let mut count: HashMap<(usize, usize), (usize, Vec<usize>)> = HashMap::new();
    for tri in mesh.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let path = if tri.len() == 6 {
                vec![a, tri[3 + k], b]
            } else {
                vec![a, b]
            };
            count
                .entry((a.min(b), a.max(b)))
                .and_modify(|e| e.0 += 1)
                .or_insert((1, path));
        }
    }
    let mut edges: Vec<Vec<usize>> = count
        .into_values()
        .filter(|(c, _)| *c == 1)
        .map(|(_, p)| p)
        .collect();
    edges.sort_unstable(); // deterministic drawing order
    edges
}

fn used_nodes(mesh: &MeshView) -> Vec<usize> {
    let mut used: Vec<usize> = mesh.triangles.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    used
}

#[derive(Debug, Clone, Copy)]
struct BBox {
    x: (f64, f64),
    y: (f64, f64),
}

impl BBox {
    fn of(points: impl Iterator<Item = [f64; 2]>) -> Self {
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

    fn union(&self, o: &Self) -> Self {
        Self {
            x: (self.x.0.min(o.x.0), self.x.1.max(o.x.1)),
            y: (self.y.0.min(o.y.0), self.y.1.max(o.y.1)),
        }
    }

    /// 3 % of the larger side around the mesh, so the boundary line is not clipped; a
    /// degenerate (zero-area) box gets a unit size.
    fn padded(&self) -> Self {
        let size = (self.x.1 - self.x.0).max(self.y.1 - self.y.0);
        let pad = if size > 0.0 { 0.03 * size } else { 0.5 };
        Self {
            x: (self.x.0 - pad, self.x.1 + pad),
            y: (self.y.0 - pad, self.y.1 + pad),
        }
    }

    fn width(&self) -> f64 {
        self.x.1 - self.x.0
    }

    fn height(&self) -> f64 {
        self.y.1 - self.y.0
    }

    fn centre(&self) -> (f64, f64) {
        (0.5 * (self.x.0 + self.x.1), 0.5 * (self.y.0 + self.y.1))
    }
}
