//! Text in the headset: palette labels, the active tool next to the hand,
//! drag readouts and refused-edit messages, as filled triangles in the
//! world (drawn by the renderer's flat pipeline, depth-tested like any
//! surface, so labels sit on their buttons).
//!
//! Glyph outlines come from the bundled DejaVu Sans Condensed
//! (`assets/fonts`, free licence in `DejaVu-LICENSE.txt`; wide Unicode
//! coverage, legible at small sizes) read with `ttf-parser`; `lyon`'s fill
//! tessellator turns each outline (quadratic curves, holes by the non-zero
//! rule) into triangles once, cached per character. No glyph atlas: the
//! renderer has no texture path, and triangles stay sharp at any distance
//! and in both eyes. A missing character draws the font's `.notdef` box.

use std::collections::HashMap;

use glam::Vec3;
use lyon_tessellation::geom::point;
use lyon_tessellation::path::Path;
use lyon_tessellation::{BuffersBuilder, FillOptions, FillRule, FillTessellator, VertexBuffers};

use super::LineVertex;

static DEJAVU: &[u8] = include_bytes!("../../assets/fonts/DejaVuSansCondensed.ttf");

/// One glyph, in em units (1.0 = the font's em), baseline at y = 0.
#[derive(Clone, Debug, Default)]
struct Glyph {
    /// Triangle corners, three per triangle.
    tris: Vec<[f32; 2]>,
    advance: f32,
}

/// The bundled font with its tessellated glyphs.
pub struct Font {
    face: ttf_parser::Face<'static>,
    em: f32,
    cap: f32,
    cache: HashMap<char, Glyph>,
}

impl Default for Font {
    fn default() -> Self {
        Self::bundled()
    }
}

/// ttf-parser's outline calls into a lyon path, one closed subpath per
/// contour.
struct Outline {
    b: lyon_tessellation::path::path::Builder,
    open: bool,
    scale: f32,
}

impl ttf_parser::OutlineBuilder for Outline {
    fn move_to(&mut self, x: f32, y: f32) {
        if self.open {
            self.b.end(true);
        }
        self.b.begin(point(x * self.scale, y * self.scale));
        self.open = true;
    }
    fn line_to(&mut self, x: f32, y: f32) {
        self.b.line_to(point(x * self.scale, y * self.scale));
    }
    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let s = self.scale;
        self.b
            .quadratic_bezier_to(point(x1 * s, y1 * s), point(x * s, y * s));
    }
    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let s = self.scale;
        self.b.cubic_bezier_to(
            point(x1 * s, y1 * s),
            point(x2 * s, y2 * s),
            point(x * s, y * s),
        );
    }
    fn close(&mut self) {
        if self.open {
            self.b.end(true);
            self.open = false;
        }
    }
}

impl Font {
    /// The bundled DejaVu Sans Condensed.
    pub fn bundled() -> Font {
        // The font is part of the binary and parsed by a test; a failure
        // here is a broken build, not bad input.
        let face = ttf_parser::Face::parse(DEJAVU, 0).expect("the bundled font parses");
        let em = face.units_per_em() as f32;
        let cap = face.capital_height().map_or(0.73, |h| h as f32 / em);
        Font {
            face,
            em,
            cap,
            cache: HashMap::new(),
        }
    }

    fn glyph(&mut self, c: char) -> &Glyph {
        let (face, em) = (&self.face, self.em);
        self.cache.entry(c).or_insert_with(|| {
            let id = face.glyph_index(c).unwrap_or(ttf_parser::GlyphId(0));
            let advance = face.glyph_hor_advance(id).unwrap_or(0) as f32 / em;
            let mut o = Outline {
                b: Path::builder(),
                open: false,
                scale: 1.0 / em,
            };
            if face.outline_glyph(id, &mut o).is_none() {
                return Glyph {
                    tris: Vec::new(),
                    advance,
                };
            }
            if o.open {
                o.b.end(true);
            }
            let path = o.b.build();
            let mut buf: VertexBuffers<[f32; 2], u32> = VertexBuffers::new();
            let opts = FillOptions::tolerance(0.004).with_fill_rule(FillRule::NonZero);
            let ok = FillTessellator::new()
                .tessellate_path(
                    &path,
                    &opts,
                    &mut BuffersBuilder::new(&mut buf, |v: lyon_tessellation::FillVertex| {
                        v.position().to_array()
                    }),
                )
                .is_ok();
            let tris = if ok {
                buf.indices
                    .iter()
                    .map(|&i| buf.vertices[i as usize])
                    .collect()
            } else {
                Vec::new()
            };
            Glyph { tris, advance }
        })
    }

    /// Height of capitals per unit of text height (the em).
    pub fn cap_height(&self) -> f32 {
        self.cap
    }

    /// Width of `text` at em height `height`.
    pub fn width(&mut self, text: &str, height: f32) -> f32 {
        text.chars().map(|c| self.glyph(c).advance).sum::<f32>() * height
    }

    /// Appends `text` as triangles on `line` at em height `height` metres.
    pub fn push(
        &mut self,
        out: &mut Vec<LineVertex>,
        text: &str,
        line: Baseline,
        height: f32,
        color: [f32; 3],
    ) {
        let Baseline { origin, right, up } = line;
        let mut x = 0.0;
        for c in text.chars() {
            let g = self.glyph(c);
            for p in &g.tris {
                let w = origin + right * ((x + p[0]) * height) + up * (p[1] * height);
                out.push(LineVertex {
                    pos: w.to_array(),
                    color,
                });
            }
            x += g.advance;
        }
    }
}

/// Where a line of text goes: its baseline starts at `origin` and runs
/// along `right`; glyphs rise along `up` (unit vectors).
#[derive(Clone, Copy, Debug)]
pub struct Baseline {
    /// Start of the baseline.
    pub origin: Vec3,
    /// Writing direction.
    pub right: Vec3,
    /// Glyph up.
    pub up: Vec3,
}

/// Two triangles filling the quad with corners `a` (bottom left), `a +
/// right * w`, `a + up * h`.
pub fn quad(out: &mut Vec<LineVertex>, a: Vec3, right: Vec3, up: Vec3, color: [f32; 3]) {
    let (b, c, d) = (a + right, a + right + up, a + up);
    for p in [a, b, c, a, c, d] {
        out.push(LineVertex {
            pos: p.to_array(),
            color,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(tris: &[[f32; 2]]) -> f32 {
        tris.chunks(3)
            .map(|t| {
                let (a, b, c) = (t[0], t[1], t[2]);
                ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs() / 2.0
            })
            .sum()
    }

    #[test]
    fn glyphs_fill_their_outlines_with_holes() {
        let mut f = Font::bundled();
        let l = f.glyph('l').clone();
        let o = f.glyph('O').clone();
        let dot = f.glyph('.').clone();
        // 'l' is a bar about 0.1 em wide and 0.76 em tall.
        let a = area(&l.tris);
        assert!(a > 0.05 && a < 0.11, "l area {a}");
        // 'O' is a ring: much less than its bounding ellipse (the hole is
        // not filled).
        let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
        for p in &o.tris {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let ellipse = std::f32::consts::PI / 4.0 * (hi[0] - lo[0]) * (hi[1] - lo[1]);
        let ring = area(&o.tris);
        assert!(
            ring > 0.2 * ellipse && ring < 0.6 * ellipse,
            "{ring} of {ellipse}"
        );
        assert!(area(&dot.tris) > 0.0 && dot.advance > 0.2);
        // Spaces advance and draw nothing; unknown characters still draw.
        assert!(f.glyph(' ').tris.is_empty() && f.glyph(' ').advance > 0.2);
        assert!(!f.glyph('\u{E000}').tris.is_empty());
        assert!(!f.glyph('°').tris.is_empty());
    }

    #[test]
    fn text_is_laid_out_along_its_axes() {
        let mut f = Font::bundled();
        let mut out = Vec::new();
        let h = 0.01;
        let line = Baseline {
            origin: Vec3::ZERO,
            right: Vec3::X,
            up: Vec3::Y,
        };
        f.push(&mut out, "Undo", line, h, [1.0; 3]);
        let w = f.width("Undo", h);
        assert!(w > 2.0 * h && w < 3.0 * h, "{w}");
        for v in &out {
            let [x, y, z] = v.pos;
            assert!(x > -1e-4 && x < w + 1e-4 && y > -0.3 * h && y < 1.0 * h && z == 0.0);
        }
        assert_eq!(out.len() % 3, 0);
    }
}
