use std::path::PathBuf;

use super::dimension::three_d_key;
use super::source::{error_near, Locate, SceneDocument};
use super::{MpmSceneSpec, SceneError, SceneVector};

/// A parsed MPM scene (2D).
pub type MpmScene = SceneDocument<MpmSceneSpec>;

/// A parsed 3D MPM scene (`[analysis] geometry = "3d"`, `docs/3d-mpm.md`).
pub type MpmScene3 = SceneDocument<MpmSceneSpec<[f64; 3]>>;

impl<V: SceneVector> SceneDocument<MpmSceneSpec<V>> {
    /// An error at `field` (`wall[1].friction`), with the line where it stands, or where
    /// it belongs when it is missing.
    pub fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_near(&self.source, self.path.as_ref(), field, message.into())
    }
}

impl<V: SceneVector> Locate for SceneDocument<MpmSceneSpec<V>> {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_near(&self.source, self.path.as_ref(), field, message.into())
    }
}

/// Reads an MPM scene of `V::DIM` dimensions: the keys and vector lengths of the other
/// dimension are refused by name ([`check_dimension`]) before the schema is read.
pub(super) fn parse_mpm<V: SceneVector>(
    source: &str,
    path: Option<PathBuf>,
) -> Result<SceneDocument<MpmSceneSpec<V>>, SceneError> {
    check_dimension(source, path.as_ref(), V::DIM)?;
    SceneDocument::parse(source, path)
}

/// The vectors of an MPM scene and how many points each holds (1, or 2 corners).
const VECTORS: [(&str, &str, usize); 10] = [
    ("", "gravity", 1),
    ("grid", "origin", 1),
    ("grid", "cells", 1),
    ("body", "rectangle", 2),
    ("body", "box", 2),
    ("prescribed", "region", 2),
    ("prescribed", "velocity", 1),
    ("surface_load", "region", 2),
    ("surface_load", "traction", 1),
    ("monitor", "point", 1),
];

/// Refuses in an MPM scene of `dim` dimensions (its source) a vector of the other
/// dimension (`gravity = [0, -9.81]` in 3D, `[grid] cells` of 3 in 2D), a uniform initial
/// stress of the other dimension (4 components in 3D, 6 in 2D) and the keys of
/// the other dimension: in 2D `box`, `cylinder`, `velocity_z`, a wall on `back`/`front`;
/// in 3D `rectangle`. Each error names the field (`body[0].box`) and its line. What the
/// schema refuses anyway (a bad TOML) is left to it.
pub fn check_dimension(source: &str, path: Option<&PathBuf>, dim: usize) -> Result<(), SceneError> {
    let Ok(table) = toml::from_str::<toml::Table>(source) else {
        return Ok(());
    };
    let at = |field: &str, message: String| error_near(source, path, field, message);
    let three_d = dim == 3;
    let located = |field: String| Located {
        source,
        path,
        field,
    };
    // The tables each vector sits in: the scene itself, [grid], each [[body]], ...
    for (section, key, points) in VECTORS {
        let tables: Vec<(String, &toml::Table)> = if section.is_empty() {
            vec![(String::new(), &table)]
        } else if let Some(t) = table.get(section).and_then(|v| v.as_table()) {
            vec![(format!("{section}."), t)]
        } else if let Some(items) = table.get(section).and_then(|v| v.as_array()) {
            (items.iter().enumerate())
                .filter_map(|(k, v)| v.as_table().map(|t| (format!("{section}[{k}]."), t)))
                .collect()
        } else {
            Vec::new()
        };
        for (prefix, t) in tables {
            let Some(value) = t.get(key) else { continue };
            let field = format!("{prefix}{key}");
            let vectors: Vec<&toml::Value> = match (points, value.as_array()) {
                (1, _) => vec![value],
                (_, Some(corners)) => corners.iter().collect(),
                _ => continue,
            };
            for v in vectors {
                let Some(n) = v.as_array().map(Vec::len) else {
                    continue;
                };
                if n != dim && (n == 2 || n == 3) {
                    let (this, hint) = if three_d {
                        ("3D", "[x, y, z]")
                    } else {
                        (
                            "2D",
                            "[x, y]; [analysis] geometry = \"3d\" makes a scene 3D",
                        )
                    };
                    return Err(at(
                        &field,
                        format!(
                            "{} has {n} components: the vectors of a {this} MPM scene have \
                             {dim} ({hint})",
                            toml::Value::Array(v.as_array().cloned().unwrap_or_default())
                        ),
                    ));
                }
            }
        }
    }
    super::dimension::stress_components(&table, three_d, "MPM", &at)?;
    let items = |section: &str| -> Vec<toml::Table> {
        (table.get(section).and_then(|v| v.as_array()))
            .map(|a| (a.iter()).filter_map(|v| v.as_table().cloned()).collect())
            .unwrap_or_default()
    };
    for (k, body) in items("body").iter().enumerate() {
        if three_d {
            if body.contains_key("rectangle") {
                return Err(at(
                    &format!("body[{k}].rectangle"),
                    "is 2D: a body of a 3D scene is a `box = [[x0, y0, z0], [x1, y1, z1]]` \
                     or a `cylinder = {{ centre = [xc, zc], base, radius, height }}`"
                        .into(),
                ));
            }
        } else {
            for key in ["box", "cylinder"] {
                if body.contains_key(key) {
                    return Err(
                        located(format!("body[{k}].{key}")).three_d(&format!("a body `{key}`"))
                    );
                }
            }
        }
    }
    if !three_d {
        for (k, p) in items("prescribed").iter().enumerate() {
            if p.contains_key("velocity_z") {
                return Err(located(format!("prescribed[{k}].velocity_z")).three_d("z"));
            }
        }
        for (k, w) in items("wall").iter().enumerate() {
            if let Some(side @ ("back" | "front")) = w.get("side").and_then(|s| s.as_str()) {
                return Err(located(format!("wall[{k}].side"))
                    .three_d(&format!("side = \"{side}\", a face of constant z,")));
            }
        }
    }
    Ok(())
}

/// A field of a scene source, for [`three_d_key`].
struct Located<'a> {
    source: &'a str,
    path: Option<&'a PathBuf>,
    field: String,
}

impl Locate for Located<'_> {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_near(self.source, self.path, field, message.into())
    }
}

impl Located<'_> {
    fn three_d(&self, what: &str) -> SceneError {
        three_d_key(self, &self.field, what)
    }
}
