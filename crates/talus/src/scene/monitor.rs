//! `[[monitor]]`: a point whose displacement and velocity go to `history.csv` and
//! `summary.json`, and the rule that every named result gets its own CSV columns.
use serde::{Deserialize, Serialize};

/// A monitored point (m): the nearest node (FEM) or the grid-interpolated value (MPM).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct MonitorSpec<V: super::SceneVector = [f64; 2]> {
    pub name: String,
    pub point: V,
}

/// The columns a monitor adds to `history.csv`, in order (2D and MPM).
pub const MONITOR_COLUMNS: [&str; 4] = ["ux", "uy", "vx", "vy"];
/// The columns a monitor adds to a 3D run's `history.csv`, in order.
pub const MONITOR_COLUMNS_3D: [&str; 6] = ["ux", "uy", "uz", "vx", "vy", "vz"];

/// A monitor's columns with `components` displacement and velocity components (2 or 3).
pub fn monitor_columns(components: usize) -> &'static [&'static str] {
    match components {
        3 => &MONITOR_COLUMNS_3D,
        _ => &MONITOR_COLUMNS,
    }
}
/// The columns a named boundary adds: the first two in 2D (and MPM), all three in 3D.
pub const REACTION_COLUMNS: [&str; 3] = ["fx", "fy", "fz"];

/// Why a name cannot head CSV columns: empty, or holding a character a CSV reader would
/// split or quote on.
pub fn bad_name(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        Some("must not be empty")
    } else if name
        .chars()
        .any(|c| c == ',' || c == '"' || c.is_whitespace() || c.is_control())
    {
        Some("must not hold commas, quotes or spaces (it names history.csv columns)")
    } else {
        None
    }
}

/// The first column of `extra` that repeats one of `base` or an earlier one of `extra`,
/// with the index of the entry (of `extra`) that made it.
pub fn first_duplicate<'a>(
    base: &[&str],
    extra: &'a [(usize, String)],
) -> Option<&'a (usize, String)> {
    extra.iter().enumerate().find_map(|(k, e)| {
        let repeated = base.contains(&e.1.as_str()) || extra[..k].iter().any(|o| o.1 == e.1);
        repeated.then_some(e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_that_would_break_the_csv_are_refused() {
        assert!(bad_name("footing").is_none());
        assert!(bad_name("crest_1").is_none());
        for bad in ["", "a,b", "a b", "\"a\"", "a\n"] {
            assert!(bad_name(bad).is_some(), "{bad:?}");
        }
    }

    #[test]
    fn a_repeated_column_is_found_with_its_entry() {
        let extra = vec![(0, "a_fx".to_string()), (3, "b_ux".to_string())];
        assert_eq!(first_duplicate(&["step", "time"], &extra), None);
        assert_eq!(
            first_duplicate(&["b_ux"], &extra),
            Some(&(3, "b_ux".to_string()))
        );
        let twice = vec![(0, "a_ux".to_string()), (1, "a_ux".to_string())];
        assert_eq!(first_duplicate(&[], &twice), Some(&(1, "a_ux".to_string())));
    }
}
