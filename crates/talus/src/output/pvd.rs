//! ParaView time collection (`.pvd`) listing one VTU file per time step.
use std::fmt::Write as _;
use std::path::Path;

use super::OutputError;

/// Writes a ParaView collection: one `<DataSet timestep=… file=…/>` per entry, in the given
/// order. Times are in s; file names are relative to the `.pvd` file's folder.
pub fn write_pvd(path: &Path, entries: &[(f64, String)]) -> Result<(), OutputError> {
    if entries.is_empty() {
        return Err(OutputError::invalid("entries", "no time steps to list"));
    }
    for (i, (t, file)) in entries.iter().enumerate() {
        if !t.is_finite() {
            return Err(OutputError::invalid(
                "entries",
                format!("time of entry {i} is not finite: {t}"),
            ));
        }
        if file.is_empty() {
            return Err(OutputError::invalid(
                "entries",
                format!("file name of entry {i} is empty"),
            ));
        }
    }
    let mut x = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(x, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        x,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(x, "  <Collection>");
    for (t, file) in entries {
        let _ = writeln!(
            x,
            r#"    <DataSet timestep="{t:e}" group="" part="0" file="{}"/>"#,
            xml_escape(file)
        );
    }
    let _ = writeln!(x, "  </Collection>");
    let _ = writeln!(x, "</VTKFile>");
    super::atomic::write(path, x)
}

/// File names go into an XML attribute (here and in `pvtu.rs`).
pub(super) fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}
