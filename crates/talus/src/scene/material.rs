//! `[material]` (one material everywhere) or `[[material]]` (one per set of regions), and
//! `[[region]]`: the ground as layers (`docs/scenes.md`, 'Regions and materials').
use std::fmt;

use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use talus_bipotential::ConeFit;

/// What a material does past its elastic range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialModel {
    #[default]
    DruckerPrager,
    /// Never yields (a structure, a stiff layer): `young_modulus`, `poisson_ratio` and the
    /// densities only.
    Elastic,
}

impl MaterialModel {
    pub fn name(self) -> &'static str {
        match self {
            MaterialModel::DruckerPrager => "drucker_prager",
            MaterialModel::Elastic => "elastic",
        }
    }
}

/// The flow rule a Drucker-Prager material runs with (`flow`, `docs/scenes.md`, 'Regions and
/// materials').
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Flow {
    /// `friction_angle`, `cohesion` and `dilatancy_angle` as written.
    #[default]
    AsGiven,
    /// Davis's (1968) associated equivalent of them: `β = cos φ cos ψ / (1 − sin φ sin ψ)`,
    /// `c* = β c`, `tan φ* = β tan φ`, `ψ* = φ*`
    /// (`talus_bipotential::DruckerPragerParameters::davis_equivalent`).
    Davis,
}

impl Flow {
    /// Every choice, as written in a scene.
    pub const ALL: [Flow; 2] = [Flow::AsGiven, Flow::Davis];

    pub fn name(self) -> &'static str {
        match self {
            Flow::AsGiven => "as_given",
            Flow::Davis => "davis",
        }
    }

    /// The choice written `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// One material: Drucker-Prager parameters (Pa, degrees) or elastic ones, and the densities
/// (kg/m³): `density` is required for a dynamic analysis (the mass) and with `gravity`
/// (the weight), otherwise unused.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Required in a `[[material]]` list, where errors name it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The regions it fills (`[[region]]` names, or Gmsh physical surfaces); a single
    /// `[material]` without them fills the whole mesh.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<String>,
    #[serde(default)]
    pub model: MaterialModel,
    pub young_modulus: f64,
    pub poisson_ratio: f64,
    /// Drucker-Prager only (required there).
    #[serde(default)]
    pub friction_angle: Option<f64>,
    #[serde(default)]
    pub cohesion: Option<f64>,
    /// Default: associative (θ = φ).
    #[serde(default)]
    pub dilatancy_angle: Option<f64>,
    #[serde(default)]
    pub cone_fit: Option<ConeFit>,
    /// `"as_given"` (the default) or `"davis"` ([`Flow`]), Drucker-Prager only. Read as text
    /// so that a bad value is refused by `check::material`, naming `material.flow` or
    /// `material[k].flow` and its line; [`MaterialSpec::flow`] reads it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flow: Option<String>,
    /// Duvaut–Lions relaxation time τ (s), Drucker-Prager only; absent: rate-independent
    /// (`docs/scenes.md`, 'Regions and materials'). Checked by `check::material`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relaxation_time: Option<f64>,
    #[serde(default)]
    pub density: Option<f64>,
    /// Below a water table (kg/m³); default `density`.
    #[serde(default)]
    pub saturated_density: Option<f64>,
    /// Whether strength reduction (`[stability]`) weakens it; default true for
    /// Drucker-Prager, false for elastic.
    #[serde(default)]
    pub reduce: Option<bool>,
}

impl MaterialSpec {
    /// The cohesion (Pa); 0 for an elastic material or before it is checked.
    pub fn cohesion(&self) -> f64 {
        self.cohesion.unwrap_or(0.0)
    }

    /// The friction angle (degrees); 0 for an elastic material or before it is checked.
    pub fn friction_angle(&self) -> f64 {
        self.friction_angle.unwrap_or(0.0)
    }

    /// Its [`Flow`] (`AsGiven` when `flow` is absent), or `Err` with the unknown value.
    pub fn flow(&self) -> Result<Flow, &str> {
        match self.flow.as_deref() {
            None => Ok(Flow::AsGiven),
            Some(name) => Flow::from_name(name).ok_or(name),
        }
    }

    /// Whether strength reduction applies to it.
    pub fn reduced(&self) -> bool {
        self.reduce
            .unwrap_or(self.model == MaterialModel::DruckerPrager)
    }
}

/// The scene's materials: `[material]` (one, everywhere unless it names regions) or a
/// `[[material]]` list.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Materials {
    One(MaterialSpec),
    Many(Vec<MaterialSpec>),
}

impl Materials {
    /// Every material, in file order.
    pub fn all(&self) -> &[MaterialSpec] {
        match self {
            Materials::One(m) => std::slice::from_ref(m),
            Materials::Many(v) => v,
        }
    }

    pub fn all_mut(&mut self) -> &mut [MaterialSpec] {
        match self {
            Materials::One(m) => std::slice::from_mut(m),
            Materials::Many(v) => v,
        }
    }

    /// The field path of material `k`: `material` or `material[k]`.
    pub fn field(&self, k: usize) -> String {
        match self {
            Materials::One(_) => "material".into(),
            Materials::Many(_) => format!("material[{k}]"),
        }
    }

    /// The one material of a scene that has one (`[material]`, or a list of one).
    pub fn single(&self) -> Option<&MaterialSpec> {
        match self.all() {
            [m] => Some(m),
            _ => None,
        }
    }

    /// [`Materials::single`], mutably.
    pub fn single_mut(&mut self) -> Option<&mut MaterialSpec> {
        match self.all_mut() {
            [m] => Some(m),
            _ => None,
        }
    }
}

/// `[material]` as a table, `[[material]]` as an array of tables: each deserialized by
/// the same `MaterialSpec`, so an error keeps its key and line.
impl<'de> Deserialize<'de> for Materials {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct OneOrMany;
        impl<'de> Visitor<'de> for OneOrMany {
            type Value = Materials;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a [material] table or a [[material]] list of tables")
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Materials, A::Error> {
                MaterialSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(Materials::One)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Materials, A::Error> {
                Vec::<MaterialSpec>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(Materials::Many)
            }
        }
        deserializer.deserialize_any(OneOrMany)
    }
}

/// A named region: the elements whose centroid lies in `box` `[[x0, y0], [x1, y1]]` (m).
/// A Gmsh mesh's physical surfaces are regions under their own names without an entry.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct RegionSpec<V: super::SceneVector = [f64; 2]> {
    pub name: String,
    #[serde(rename = "box")]
    pub corners: [V; 2],
}
