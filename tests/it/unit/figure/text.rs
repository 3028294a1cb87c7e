//! Unit tests of `figure::text` (`src/figure/text.rs`).

use ab_glyph::{Font, PxScale, ScaleFont};
use isola::figure::text::face;

#[test]
fn a_scale_of_the_height_gives_the_em_asked() {
    let f = face();
    let em = 20.0f32;
    let units = f.units_per_em().unwrap();
    let scale = PxScale::from(em * f.height_unscaled() / units);
    let scaled = f.as_scaled(scale);
    let advance = scaled.h_advance(f.glyph_id('0'));
    let expected = em * f.h_advance_unscaled(f.glyph_id('0')) / units;
    assert!((advance - expected).abs() < 1e-3, "{advance} {expected}");
}
