//! Parallel VTU: one snapshot as pieces, each written by one MPI rank
//! (`docs/distributed.md`, 'Outputs'), and the `.pvtu` that gathers them for ParaView.
use std::fmt::Write as _;
use std::ops::Range;
use std::path::Path;

use super::OutputError;

/// The items (cells, particles) of piece `piece` of `pieces`: contiguous ranges of about
/// `n / pieces`, the first ones a cell longer when `pieces` does not divide `n`; the
/// first piece is empty only when `n` is 0.
pub fn piece_range(n: usize, piece: usize, pieces: usize) -> Range<usize> {
    let pieces = pieces.max(1);
    (n * piece).div_ceil(pieces)..(n * (piece + 1)).div_ceil(pieces).min(n)
}

/// Writes the `.pvtu` at `path` listing `pieces` (paths relative to its folder), with the
/// arrays each piece holds, as declared in `piece_xml` (one of them, as written: every
/// piece of a snapshot holds the same arrays).
pub fn write_pvtu(path: &Path, piece_xml: &str, pieces: &[String]) -> Result<(), OutputError> {
    let mut x = String::new();
    // Writing to a String cannot fail: the `fmt::Result`s are ignored on purpose.
    let _ = writeln!(x, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        x,
        r#"<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(x, r#"  <PUnstructuredGrid GhostLevel="0">"#);
    for (section, parallel) in [
        ("PointData", "PPointData"),
        ("CellData", "PCellData"),
        ("Points", "PPoints"),
    ] {
        let Some(body) = section_body(piece_xml, section) else {
            continue;
        };
        let attributes = body.0.trim();
        let _ = writeln!(
            x,
            "    <{parallel}{}{attributes}>",
            if attributes.is_empty() { "" } else { " " }
        );
        for line in body.1.lines().map(str::trim) {
            if let Some(rest) = line.strip_prefix("<DataArray ") {
                let declared = rest.trim_end_matches('>').replace(r#" format="ascii""#, "");
                let _ = writeln!(x, "      <PDataArray {declared}/>");
            }
        }
        let _ = writeln!(x, "    </{parallel}>");
    }
    for piece in pieces {
        let _ = writeln!(
            x,
            r#"    <Piece Source="{}"/>"#,
            super::pvd::xml_escape(piece)
        );
    }
    let _ = writeln!(x, "  </PUnstructuredGrid>");
    let _ = writeln!(x, "</VTKFile>");
    super::atomic::write(path, x)
}

/// The attributes of `<section …>` and the text up to `</section>` in `xml`.
fn section_body<'a>(xml: &'a str, section: &str) -> Option<(&'a str, &'a str)> {
    let open = format!("<{section}");
    let start = xml
        .find(&format!("{open}>"))
        .or_else(|| xml.find(&format!("{open} ")))?;
    let after = start + open.len();
    let tag_end = after + xml[after..].find('>')?;
    let close = tag_end + xml[tag_end..].find(&format!("</{section}>"))?;
    Some((&xml[after..tag_end], &xml[tag_end + 1..close]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every item is in exactly one piece, in order; piece sizes differ by at most one.
    #[test]
    fn pieces_cover_the_items_once() {
        for n in [0, 1, 2, 5, 7, 100] {
            for pieces in 1..=4 {
                let ranges: Vec<_> = (0..pieces).map(|p| piece_range(n, p, pieces)).collect();
                assert_eq!(ranges[0].start, 0);
                assert_eq!(ranges[pieces - 1].end, n);
                for w in ranges.windows(2) {
                    assert_eq!(w[0].end, w[1].start, "{n} in {pieces}");
                }
                let lens: Vec<usize> = ranges.iter().map(|r| r.len()).collect();
                let (lo, hi) = (lens.iter().min().unwrap(), lens.iter().max().unwrap());
                assert!(hi - lo <= 1, "{n} in {pieces}: {lens:?}");
                assert!(n == 0 || !ranges[0].is_empty());
            }
        }
    }
}
