//! What every PNG plot needs before drawing: a registered font and a writable file.
use std::path::Path;
use std::sync::OnceLock;

use plotters::style::FontStyle;

use super::OutputError;

/// The family every plot draws text with (DejaVu Sans, embedded by the `dejavu` crate).
pub(crate) const FONT: &str = "sans-serif";

/// With plotters' `ab_glyph` feature no system font is looked up: text fails unless a
/// font was registered first. Registration happens once per process.
pub(crate) fn ensure_fonts(path: &Path) -> Result<(), OutputError> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            let fonts = [
                (FontStyle::Normal, dejavu::sans::regular()),
                (FontStyle::Bold, dejavu::sans::bold()),
                (FontStyle::Italic, dejavu::sans::oblique()),
                (FontStyle::Oblique, dejavu::sans::oblique()),
            ];
            for (style, bytes) in fonts {
                plotters::style::register_font(FONT, style, bytes)
                    .map_err(|_| format!("DejaVu Sans ({}) is not a valid font", style.as_str()))?;
            }
            Ok(())
        })
        .clone()
        .map_err(|message| OutputError::plot(path, message))
}

/// Creates (truncates) the file so that a missing folder or a read-only location is an
/// `Io` error naming the path, rather than an opaque encoder error after all the drawing.
pub(crate) fn prepare(path: &Path) -> Result<(), OutputError> {
    ensure_fonts(path)?;
    std::fs::File::create(path)
        .map(drop)
        .map_err(|e| OutputError::io(path, e))
}

/// Axis tick text without float noise (`0.30000000000000004` → `0.3`).
pub(crate) fn tick(v: f64) -> String {
    // Tick positions are computed in floating point: a zero comes out as ±1e-16.
    if v.abs() < 1e-12 {
        return "0".into();
    }
    significant(v, 4)
}

/// `v` to `digits` significant digits, trailing zeros dropped; scientific notation outside
/// [10⁻³, 10⁵).
pub(crate) fn significant(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{:.*e}", digits.saturating_sub(1), v);
        // 1.500e5 → 1.5e5
        return match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        };
    }
    let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
