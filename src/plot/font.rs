//! The one font of every figure: DejaVu Sans, embedded in the binary (`assets/fonts/`,
//! Bitstream Vera licence) and registered with plotters' pure-Rust `ab_glyph` text path, so
//! that no system font library (fontconfig, freetype) is needed.

use plotters::style::FontStyle;
use std::sync::OnceLock;

/// The font file (DejaVu Sans 2.37).
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The family name figures ask for.
pub const FAMILY: &str = "sans-serif";

/// Registers the embedded font under [`FAMILY`] for every style (once per process).
/// Returns false if the font could not be parsed, which would be a broken build.
pub fn ensure_registered() -> bool {
    static DONE: OnceLock<bool> = OnceLock::new();
    *DONE.get_or_init(|| {
        [
            FontStyle::Normal,
            FontStyle::Bold,
            FontStyle::Italic,
            FontStyle::Oblique,
        ]
        .into_iter()
        .all(|style| plotters::style::register_font(FAMILY, style, DEJAVU_SANS).is_ok())
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn embedded_font_parses() {
        assert!(super::ensure_registered(), "DejaVuSans.ttf did not parse");
    }
}
