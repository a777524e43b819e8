//! Pictures of many cells as a raster inside the SVG: a mesh or a deformed body of tens of
//! thousands of cells written as vector paths takes megabytes (every cell a path segment), while
//! at the size it is shown most cells are narrower than a pixel. Above [`RASTER_MIN_CELLS`] cells
//! the figures paint the cells into a [`Raster`] of one pixel per SVG pixel and embed it as a
//! PNG (`<image href="data:image/png;base64,…">`), so that the axes, the legend and the text stay
//! vector and the figure stays one self-contained file (an SVG shown by `<img>` loads nothing
//! else). The PNG is written here: zlib from `miniz_oxide`, the chunk CRCs from `crc32fast`,
//! both pure Rust.

use base64::Engine as _;

/// Cells above which a mesh or deformed-body picture is drawn as a raster.
pub(super) const RASTER_MIN_CELLS: usize = 20_000;

/// Bytes of vector paths above which a field picture's cells are drawn as a raster (fewer
/// cells, but each of many colours: a raster of the same picture is a fraction of that).
pub(super) const RASTER_MIN_BYTES: usize = 100_000;

/// An RGBA image; pixel `(0, 0)` is the top left corner. What is painted is opaque; the
/// background may be transparent, so that what the SVG drew under the image shows through.
pub(super) struct Raster {
    width: usize,
    height: usize,
    pixels: Vec<[u8; 4]>,
}

/// `#rrggbb` as bytes (black if malformed).
pub(super) fn rgb(hex: &str) -> [u8; 3] {
    let byte = |i: usize| {
        hex.get(i..i + 2)
            .and_then(|s| u8::from_str_radix(s, 16).ok())
            .unwrap_or(0)
    };
    [byte(1), byte(3), byte(5)]
}

/// The colour `t` of the way from `a` to `b`.
pub(super) fn mix(a: [u8; 3], b: [u8; 3], t: f64) -> [u8; 3] {
    let m = |p: u8, q: u8| (f64::from(p) + t * (f64::from(q) - f64::from(p))).round() as u8;
    [m(a[0], b[0]), m(a[1], b[1]), m(a[2], b[2])]
}

impl Raster {
    /// A `width × height` raster (at least one pixel each way) filled with `background`
    /// (`None`: transparent).
    pub(super) fn new(width: f64, height: f64, background: Option<[u8; 3]>) -> Raster {
        let background = background.map_or([0; 4], |[r, g, b]| [r, g, b, 255]);
        let w = (width.ceil().max(1.0) as usize).min(1 << 14);
        let h = (height.ceil().max(1.0) as usize).min(1 << 14);
        Raster {
            width: w,
            height: h,
            pixels: vec![background; w * h],
        }
    }

    /// The colour of pixel `(x, y)`, if inside.
    #[cfg(test)]
    pub(super) fn get(&self, x: usize, y: usize) -> Option<[u8; 4]> {
        (x < self.width && y < self.height).then(|| self.pixels[y * self.width + x])
    }

    fn put(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.pixels[y as usize * self.width + x as usize] = [c[0], c[1], c[2], 255];
        }
    }

    /// Fill the axis-aligned box `[x0, x1] × [y0, y1]` (pixels): every pixel whose centre is
    /// inside, and at least the pixel of its centre, so that a cell narrower than a pixel still
    /// shows (as the vector pictures snap such a cell to one pixel).
    pub(super) fn fill_box(&mut self, x0: f64, x1: f64, y0: f64, y1: f64, c: [u8; 3]) {
        let (a, b) = ((x0 - 0.5).ceil() as i64, (x1 - 0.5).floor() as i64);
        let (p, q) = ((y0 - 0.5).ceil() as i64, (y1 - 0.5).floor() as i64);
        if a > b || p > q {
            self.put(
                (0.5 * (x0 + x1)).floor() as i64,
                (0.5 * (y0 + y1)).floor() as i64,
                c,
            );
            return;
        }
        for y in p.max(0)..=q.min(self.height as i64 - 1) {
            for x in a.max(0)..=b.min(self.width as i64 - 1) {
                self.put(x, y, c);
            }
        }
    }

    /// Fill the convex quadrilateral `q` (pixels): every pixel whose centre is inside, scan line
    /// by scan line, and at least the pixel of its first corner.
    pub(super) fn fill_quad(&mut self, q: &[(f64, f64); 4], c: [u8; 3]) {
        self.put(q[0].0.floor() as i64, q[0].1.floor() as i64, c);
        let top = q.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let bottom = q.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        let (first, last) = ((top - 0.5).ceil() as i64, (bottom - 0.5).floor() as i64);
        for y in first.max(0)..=last.min(self.height as i64 - 1) {
            let yc = y as f64 + 0.5;
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..4 {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                if (a.1 <= yc && yc <= b.1) || (b.1 <= yc && yc <= a.1) {
                    let x = if a.1 == b.1 {
                        lo = lo.min(a.0.min(b.0));
                        a.0.max(b.0)
                    } else {
                        a.0 + (yc - a.1) / (b.1 - a.1) * (b.0 - a.0)
                    };
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
            let (a, b) = ((lo - 0.5).ceil() as i64, (hi - 0.5).floor() as i64);
            for x in a.max(0)..=b.min(self.width as i64 - 1) {
                self.put(x, y, c);
            }
        }
    }

    /// A one-pixel line from `a` to `b` (pixels), one pixel per step along its longer axis.
    pub(super) fn line(&mut self, a: (f64, f64), b: (f64, f64), c: [u8; 3]) {
        let steps = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil().max(1.0);
        if !steps.is_finite() || steps > 1e5 {
            return;
        }
        for i in 0..=steps as i64 {
            let t = i as f64 / steps;
            let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            self.put(x.floor() as i64, y.floor() as i64, c);
        }
    }

    /// The raster as a PNG file: 8-bit RGBA, no interlace, every row with the `Up` filter (rows
    /// of a picture of cells repeat the row above in most places, which deflate then compresses
    /// to almost nothing).
    pub(super) fn png(&self) -> Vec<u8> {
        let mut raw = Vec::with_capacity(self.height * (1 + 4 * self.width));
        for y in 0..self.height {
            raw.push(2); // filter type Up
            for x in 0..self.width {
                let c = self.pixels[y * self.width + x];
                let above = if y == 0 {
                    [0; 4]
                } else {
                    self.pixels[(y - 1) * self.width + x]
                };
                for k in 0..4 {
                    raw.push(c[k].wrapping_sub(above[k]));
                }
            }
        }
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut header = Vec::with_capacity(13);
        header.extend_from_slice(&(self.width as u32).to_be_bytes());
        header.extend_from_slice(&(self.height as u32).to_be_bytes());
        header.extend_from_slice(&[8, 6, 0, 0, 0]);
        chunk(&mut png, b"IHDR", &header);
        chunk(
            &mut png,
            b"IDAT",
            &miniz_oxide::deflate::compress_to_vec_zlib(&raw, 9),
        );
        chunk(&mut png, b"IEND", &[]);
        png
    }

    /// An SVG `<image>` of the raster with its top left corner at `(x, y)`, `scale` SVG units
    /// per raster pixel.
    pub(super) fn svg_image(&self, x: f64, y: f64, scale: f64) -> String {
        format!(
            "<image x=\"{x:.1}\" y=\"{y:.1}\" width=\"{:.1}\" height=\"{:.1}\" \
             preserveAspectRatio=\"none\" href=\"data:image/png;base64,{}\"/>",
            self.width as f64 * scale,
            self.height as f64 * scale,
            base64::engine::general_purpose::STANDARD.encode(self.png())
        )
    }
}

/// Append the PNG chunk `kind` with `data`: length, type, data, CRC-32 of type and data.
fn chunk(png: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    png.extend_from_slice(&(data.len() as u32).to_be_bytes());
    png.extend_from_slice(kind);
    png.extend_from_slice(data);
    let mut crc = crc32fast::Hasher::new();
    crc.update(kind);
    crc.update(data);
    png.extend_from_slice(&crc.finalize().to_be_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_has_signature_header_and_valid_crcs() {
        let mut r = Raster::new(3.0, 2.0, None);
        r.fill_box(0.0, 1.0, 0.0, 2.0, [10, 20, 30]);
        let png = r.png();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(&png[12..16], b"IHDR");
        assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 3);
        assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), 2);
        // Walk the chunks: each CRC matches, and the image data inflates to the filtered rows.
        let mut at = 8;
        let mut kinds = Vec::new();
        while at < png.len() {
            let n = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
            let body = &png[at + 4..at + 8 + n];
            let crc = u32::from_be_bytes(png[at + 8 + n..at + 12 + n].try_into().unwrap());
            assert_eq!(crc32fast::hash(body), crc);
            if &body[..4] == b"IDAT" {
                let raw = miniz_oxide::inflate::decompress_to_vec_zlib(&body[4..]).unwrap();
                assert_eq!(raw.len(), 2 * (1 + 4 * 3));
                assert_eq!(&raw[..5], &[2, 10, 20, 30, 255]);
                // The unpainted pixel is transparent.
                assert_eq!(&raw[9..13], &[0, 0, 0, 0]);
                // Second row, first pixel: the same colour as above, so the Up filter gives 0.
                assert_eq!(&raw[13..18], &[2, 0, 0, 0, 0]);
            }
            kinds.push(body[..4].to_vec());
            at += 12 + n;
        }
        assert_eq!(
            kinds,
            [b"IHDR".to_vec(), b"IDAT".to_vec(), b"IEND".to_vec()]
        );
    }

    #[test]
    fn a_quad_fills_the_pixels_whose_centres_it_holds() {
        let mut r = Raster::new(10.0, 10.0, Some([0; 3]));
        r.fill_quad(&[(2.0, 2.0), (6.0, 2.0), (6.0, 5.0), (2.0, 5.0)], [9; 3]);
        let filled: usize = (0..10)
            .flat_map(|y| (0..10).map(move |x| (x, y)))
            .filter(|&(x, y)| r.get(x, y) == Some([9, 9, 9, 255]))
            .count();
        assert_eq!(filled, 4 * 3);
        assert_eq!(r.get(2, 2), Some([9, 9, 9, 255]));
        assert_eq!(r.get(6, 2), Some([0, 0, 0, 255]));
        // A quad inside one pixel still colours that pixel.
        r.fill_quad(&[(8.2, 8.2), (8.4, 8.2), (8.4, 8.4), (8.2, 8.4)], [7; 3]);
        assert_eq!(r.get(8, 8), Some([7, 7, 7, 255]));
    }

    #[test]
    fn colours_parse_and_mix() {
        assert_eq!(rgb("#d6e4f2"), [214, 228, 242]);
        assert_eq!(mix([0, 0, 0], [200, 100, 50], 0.5), [100, 50, 25]);
    }
}
