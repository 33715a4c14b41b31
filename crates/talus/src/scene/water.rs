//! `[water]`: a drained water table (`docs/scenes.md`, 'Water'): a horizontal `level` or a
//! piecewise-linear `phreatic` line, and the pore pressure below it. No consolidation and
//! no seepage: the pore pressure is hydrostatic under the line, zero above (no suction).
use serde::{Deserialize, Serialize};

use super::source::Locate;
use super::SceneError;

/// The unit weight of water (N/m³) when the scene gives none.
pub const WATER_UNIT_WEIGHT: f64 = 9810.0;

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WaterSpec {
    /// y of a horizontal water table (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<f64>,
    /// `[[x0, y0], [x1, y1], ...]` (m), x increasing; constant beyond its ends.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phreatic: Option<Vec<[f64; 2]>>,
    /// γ_w (N/m³) at full gravity; default 9810.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit_weight: Option<f64>,
}

/// A checked water table.
#[derive(Debug, Clone, PartialEq)]
pub struct WaterTable {
    /// The phreatic line, x strictly increasing (one point: a level).
    line: Vec<[f64; 2]>,
    pub unit_weight: f64,
}

impl WaterTable {
    /// The spec at `field` (`water`, or a stage's `stage[k].water`), checked.
    pub fn try_new(scene: &impl Locate, field: &str, spec: &WaterSpec) -> Result<Self, SceneError> {
        let unit_weight = spec.unit_weight.unwrap_or(WATER_UNIT_WEIGHT);
        if !(unit_weight.is_finite() && unit_weight > 0.0) {
            return Err(scene.error(
                &format!("{field}.unit_weight"),
                format!("{unit_weight} N/m³ must be finite and > 0"),
            ));
        }
        let line = match (spec.level, &spec.phreatic) {
            (Some(level), None) => {
                if !level.is_finite() {
                    return Err(scene.error(
                        &format!("{field}.level"),
                        format!("{level} m must be finite"),
                    ));
                }
                vec![[0.0, level]]
            }
            (None, Some(points)) => {
                let at = format!("{field}.phreatic");
                if points.is_empty() {
                    return Err(scene.error(&at, "is empty: give [[x0, y0], [x1, y1], ...]"));
                }
                for (k, p) in points.iter().enumerate() {
                    if !p.iter().all(|v| v.is_finite()) {
                        return Err(scene.error(&at, format!("point {k} = {p:?} must be finite")));
                    }
                    if k > 0 && p[0] <= points[k - 1][0] {
                        return Err(scene.error(
                            &at,
                            format!(
                                "x must increase strictly: point {k} = {p:?} after {:?}",
                                points[k - 1]
                            ),
                        ));
                    }
                }
                points.clone()
            }
            (Some(_), Some(_)) => {
                return Err(scene.error(
                    &format!("{field}.phreatic"),
                    "give either `level` or `phreatic`, not both",
                ))
            }
            (None, None) => {
                return Err(scene.error(
                    field,
                    "give the water table: `level = y` or `phreatic = [[x0, y0], ...]`",
                ))
            }
        };
        Ok(Self { line, unit_weight })
    }

    /// The phreatic line's height at `x` (m): linear between its points, constant beyond.
    pub fn height(&self, x: f64) -> f64 {
        let (first, last) = (self.line[0], self.line[self.line.len() - 1]);
        if x <= first[0] {
            return first[1];
        }
        if x >= last[0] {
            return last[1];
        }
        let k = self.line.partition_point(|p| p[0] < x);
        let (a, b) = (self.line[k - 1], self.line[k]);
        a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
    }

    /// `p_w = γ_w · max(0, y_phreatic(x) − y)` (Pa, compression positive) at `[x, y]` or,
    /// in 3D, `[x, y, z]`: the phreatic surface is the line's extrusion along z.
    pub fn pore_pressure(&self, at: impl AsRef<[f64]>) -> f64 {
        let at = at.as_ref();
        self.unit_weight * (self.height(at[0]) - at[1]).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_phreatic_line_is_linear_between_its_points_and_flat_beyond() {
        let t = WaterTable {
            line: vec![[0.0, 2.0], [10.0, 7.0]],
            unit_weight: 10.0,
        };
        assert_eq!(t.height(-5.0), 2.0);
        assert_eq!(t.height(4.0), 4.0);
        assert_eq!(t.height(20.0), 7.0);
        assert_eq!(t.pore_pressure([4.0, 1.0]), 30.0);
        assert_eq!(
            t.pore_pressure([4.0, 5.0]),
            0.0,
            "no suction above the line"
        );
    }
}
