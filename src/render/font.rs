//! A tiny 3x5 bitmap font for the digits and signs of numeric labels.

use image::RgbImage;

/// Glyph width in font pixels.
pub(crate) const GLYPH_WIDTH: u32 = 3;
/// Glyph height in font pixels.
pub(crate) const GLYPH_HEIGHT: u32 = 5;
/// Blank columns between glyphs, in font pixels.
const SPACING: u32 = 1;

/// The rows of a glyph, top first; bit 2 is the left column, bit 0 the right.
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [0b111, 0b101, 0b101, 0b101, 0b111],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b011, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b010, 0b010, 0b010],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '.' => [0b000, 0b000, 0b000, 0b000, 0b010],
        'e' => [0b000, 0b111, 0b111, 0b100, 0b111],
        '-' => [0b000, 0b000, 0b111, 0b000, 0b000],
        '+' => [0b000, 0b010, 0b111, 0b010, 0b000],
        ' ' => [0; 5],
        _ => return None,
    })
}

/// The width in image pixels of `text` drawn at `scale`.
pub(crate) fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    (n * (GLYPH_WIDTH + SPACING)).saturating_sub(SPACING) * scale
}

/// Draws `text` with its top-left corner at `(x, y)`, each font pixel a
/// `scale` x `scale` square. Characters without a glyph are drawn as blanks;
/// pixels outside the image are skipped.
pub(crate) fn draw_text(
    img: &mut RgbImage,
    x: i64,
    y: i64,
    scale: u32,
    text: &str,
    colour: [u8; 3],
) {
    let s = i64::from(scale);
    for (i, c) in text.chars().enumerate() {
        let Some(rows) = glyph(c) else {
            continue;
        };
        let left = x + i as i64 * i64::from(GLYPH_WIDTH + SPACING) * s;
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..GLYPH_WIDTH {
                if bits & (0b100 >> col) == 0 {
                    continue;
                }
                let (gx, gy) = (left + i64::from(col) * s, y + r as i64 * s);
                fill_rect(img, gx, gy, s, s, colour);
            }
        }
    }
}

/// Fills the rectangle `[x, x + w) x [y, y + h)`, clipped to the image.
pub(crate) fn fill_rect(img: &mut RgbImage, x: i64, y: i64, w: i64, h: i64, colour: [u8; 3]) {
    let x0 = x.max(0);
    let y0 = y.max(0);
    let x1 = (x + w).min(i64::from(img.width()));
    let y1 = (y + h).min(i64::from(img.height()));
    for py in y0..y1 {
        for px in x0..x1 {
            img.put_pixel(px as u32, py as u32, image::Rgb(colour));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_label_character_has_a_glyph() {
        for c in "0123456789.e-+".chars() {
            let g = glyph(c).unwrap();
            assert!(g.iter().any(|&r| r != 0), "{c} is blank");
            assert!(g.iter().all(|&r| r < 8));
        }
        // Distinct digits look distinct.
        let digits: Vec<_> = "0123456789".chars().map(|c| glyph(c).unwrap()).collect();
        for i in 0..10 {
            for j in 0..i {
                assert_ne!(digits[i], digits[j], "{i} and {j}");
            }
        }
    }

    #[test]
    fn draws_scaled_glyphs_in_place() {
        let mut img = RgbImage::new(20, 12);
        draw_text(&mut img, 1, 1, 2, "-1", [255, 0, 0]);
        // '-' occupies font row 2, columns 0..3: image rows 5..7, columns 1..7.
        assert_eq!(img.get_pixel(1, 5).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(6, 6).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(1, 4).0, [0, 0, 0]);
        // '1' starts 4 font pixels (8 image pixels) further right; its top row is
        // the middle column only.
        assert_eq!(img.get_pixel(11, 1).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(9, 1).0, [0, 0, 0]);
        assert_eq!(text_width("-1", 2), 14);
        // Clipped, not panicking, at the border.
        draw_text(&mut img, 18, 10, 3, "88", [1, 1, 1]);
    }
}
