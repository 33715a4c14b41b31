//! A per-element field painted on the (optionally deformed) mesh, with a colour bar.
use std::collections::HashMap;
use std::path::Path;

use plotters::prelude::*;

use super::canvas::{prepare, tick};
use super::map_frame::{BBox, ColourScale, DynResult, MapFrame};
use super::mesh::{check_finite, check_finite_scalars, check_len, linear_pieces};
use super::{MeshView, OutputError};

/// Element edges are drawn only when elements are at least this wide on the page.
const MIN_EDGE_SPACING_PX: f64 = 7.0;

/// The text around a field map and its colour scale ([`plot_field_map`]).
#[derive(Debug, Clone, Copy)]
pub struct FieldMap<'a> {
    /// Above the plot, in bold (e.g. the scene's title).
    pub title: &'a str,
    /// Under the title: what is drawn and when (e.g. `"cumulative plastic strain at
    /// footing settlement 3 mm, load 195 kN/m"`).
    pub subtitle: Option<&'a str>,
    /// Along the colour bar: the value's name and unit.
    pub label: &'a str,
    /// Clips the top of the colour scale at this percentile (0–100] of the values when
    /// the values above it stretch the scale by more than 10 % ([`ColourScale::clipped`]):
    /// a singular peak, such as a footing's corner, then does not swamp the rest. The
    /// picture says so under the title, with the maximum. `None`: min to max.
    pub clip_percentile: Option<f64>,
    /// Values closer than this (absolute, in the values' unit) are not told apart: a field
    /// within it is drawn in one colour with one label ([`ColourScale::new`]). 0: only
    /// round-off relative to the values' magnitude.
    pub resolution: f64,
}

/// Paints `values` (one per element, in the caller's units, named by `label` on the colour
/// bar) on the mesh as a PNG 1200 px wide under `title`, x and y in m at equal scale.
/// The colours span min to max: [`plot_field_map`] with no subtitle and no clipping.
///
/// With `displacement = Some((u, k))` the mesh is drawn at `x + k·u` (u per node, m; k the
/// magnification) over the undeformed outline in grey. P2 elements are filled as 4
/// sub-triangles through their mid-edge nodes, so curved deformed edges are followed.
/// Errors (`Invalid`): bad mesh, lengths that do not match, non-finite values or
/// magnification.
pub fn plot_field_on_mesh(
    path: &Path,
    mesh: &MeshView,
    displacement: Option<(&[[f64; 2]], f64)>,
    values: &[f64],
    title: &str,
    label: &str,
) -> Result<(), OutputError> {
    let map = FieldMap {
        title,
        subtitle: None,
        label,
        clip_percentile: None,
        resolution: 0.0,
    };
    plot_field_map(path, mesh, displacement, values, &map)
}

/// Paints `values` (one per element) on the mesh as a PNG 1200 px wide, x and y in m at
/// equal scale, with the title, subtitle, colour-bar label and colour scale of `map`.
///
/// Colours: viridis over the scale of [`ColourScale`] (min to max, or clipped at
/// `map.clip_percentile`), shown by the colour bar; a uniform field (constant to a
/// millionth of its magnitude or to `map.resolution`) is drawn in one colour with one
/// label giving its value.
/// `displacement` as for [`plot_field_on_mesh`]. Errors (`Invalid`): those of
/// [`plot_field_on_mesh`], a `clip_percentile` outside (0, 100], a negative or non-finite
/// `resolution`.
pub fn plot_field_map(
    path: &Path,
    mesh: &MeshView,
    displacement: Option<(&[[f64; 2]], f64)>,
    values: &[f64],
    map: &FieldMap,
) -> Result<(), OutputError> {
    super::atomic::through_temp(path, |tmp| {
        draw_plot_field_map(tmp, mesh, displacement, values, map)
    })
}

fn draw_plot_field_map(
    path: &Path,
    mesh: &MeshView,
    displacement: Option<(&[[f64; 2]], f64)>,
    values: &[f64],
    map: &FieldMap,
) -> Result<(), OutputError> {
    mesh.validate()?;
    check_len("values", values.len(), mesh.elements.len(), "element")?;
    check_finite_scalars("values", values)?;
    if !(map.resolution.is_finite() && map.resolution >= 0.0) {
        return Err(OutputError::invalid(
            "resolution",
            format!("must be finite and non-negative, got {}", map.resolution),
        ));
    }
    if let Some(p) = map.clip_percentile {
        if !(p > 0.0 && p <= 100.0) {
            return Err(OutputError::invalid(
                "clip_percentile",
                format!("must be in (0, 100], got {p}"),
            ));
        }
    }
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
        Some((_, k)) => format!("{} (deformed shape ×{})", map.title, tick(k)),
        None => map.title.to_string(),
    };
    let scale = ColourScale::new(values, map.clip_percentile, map.resolution);
    let subtitles: Vec<String> = map
        .subtitle
        .map(str::to_string)
        .into_iter()
        .chain(scale.note())
        .collect();
    prepare(path)?;
    let plot = FieldPlot {
        mesh,
        deformed: &deformed,
        undeformed_outline: displacement.is_some(),
        values,
        label: map.label,
        title: &title,
        subtitles: &subtitles,
        scale,
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
    subtitles: &'a [String],
    scale: ColourScale,
}

impl FieldPlot<'_> {
    fn draw(&self, path: &Path) -> DynResult {
        let used = used_nodes(self.mesh);
        let mut bbox = BBox::of(used.iter().map(|&n| self.deformed[n]));
        if self.undeformed_outline {
            bbox = bbox.union(&BBox::of(used.iter().map(|&n| self.mesh.nodes[n])));
        }
        let bbox = bbox.padded();

        let mut frame = MapFrame::new(path, &bbox, self.title, self.subtitles)?;
        let chart = &mut frame.chart;
        let fills = self
            .mesh
            .elements
            .iter()
            .zip(self.values)
            .flat_map(|(tri, &v)| {
                let colour = self.scale.colour(v);
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

        let (pw, ph) = frame.plot_px;
        let element_px = (pw * ph / self.mesh.elements.len() as f64).sqrt();
        if element_px >= MIN_EDGE_SPACING_PX {
            let edge = RGBColor(30, 30, 30).mix(0.35);
            for tri in self.mesh.elements {
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

        frame.finish(&self.scale, self.label)
    }
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
    for tri in mesh.elements {
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
    let mut used: Vec<usize> = mesh.elements.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    used
}
