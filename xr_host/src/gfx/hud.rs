//! Messages in the headset: a stroke font drawn with the renderer's line
//! pipeline, placed in front of the head. Used for what the user must know
//! and cannot otherwise see: "no input device", "this tool needs hands",
//! "autosave failed: ...".
//!
//! Why our own: the renderer has a line pipeline and no texture path, and a
//! font crate plus glyph atlas would be a second pipeline for a few short
//! messages. Glyphs are polylines on a 4 x 6 grid (uppercase, digits and
//! common punctuation; lowercase is drawn as uppercase, anything else as
//! `?`), in the spirit of the Hershey simplex font.

use glam::{Quat, Vec3};

use super::LineVertex;

/// Grid cell advance per character (4 wide + 2 gap) and line height.
const ADVANCE: f32 = 6.0;
const LINE: f32 = 9.0;
/// Grid units per glyph height.
const GLYPH_H: f32 = 6.0;

/// The polylines of `c` on the 4 x 6 grid: point lists separated by `;`.
fn glyph(c: char) -> &'static str {
    match c.to_ascii_uppercase() {
        'A' => "0,0 0,4 2,6 4,4 4,0;0,3 4,3",
        'B' => "0,0 0,6 3,6 4,5 4,4 3,3 0,3;3,3 4,2 4,1 3,0 0,0",
        'C' => "4,5 3,6 1,6 0,5 0,1 1,0 3,0 4,1",
        'D' => "0,0 0,6 2,6 4,4 4,2 2,0 0,0",
        'E' => "4,6 0,6 0,0 4,0;0,3 3,3",
        'F' => "4,6 0,6 0,0;0,3 3,3",
        'G' => "4,5 3,6 1,6 0,5 0,1 1,0 3,0 4,1 4,3 2,3",
        'H' => "0,0 0,6;4,0 4,6;0,3 4,3",
        'I' => "1,6 3,6;2,6 2,0;1,0 3,0",
        'J' => "4,6 4,1 3,0 1,0 0,1",
        'K' => "0,0 0,6;4,6 0,2;1,3 4,0",
        'L' => "0,6 0,0 4,0",
        'M' => "0,0 0,6 2,3 4,6 4,0",
        'N' => "0,0 0,6 4,0 4,6",
        'O' => "1,0 0,1 0,5 1,6 3,6 4,5 4,1 3,0 1,0",
        'P' => "0,0 0,6 3,6 4,5 4,4 3,3 0,3",
        'Q' => "1,0 0,1 0,5 1,6 3,6 4,5 4,1 3,0 1,0;2,2 4,0",
        'R' => "0,0 0,6 3,6 4,5 4,4 3,3 0,3;2,3 4,0",
        'S' => "4,5 3,6 1,6 0,5 0,4 1,3 3,3 4,2 4,1 3,0 1,0 0,1",
        'T' => "0,6 4,6;2,6 2,0",
        'U' => "0,6 0,1 1,0 3,0 4,1 4,6",
        'V' => "0,6 2,0 4,6",
        'W' => "0,6 1,0 2,3 3,0 4,6",
        'X' => "0,0 4,6;0,6 4,0",
        'Y' => "0,6 2,3 4,6;2,3 2,0",
        'Z' => "0,6 4,6 0,0 4,0",
        '0' => "1,0 0,1 0,5 1,6 3,6 4,5 4,1 3,0 1,0;0,1 4,5",
        '1' => "1,5 2,6 2,0;1,0 3,0",
        '2' => "0,5 1,6 3,6 4,5 4,4 0,0 4,0",
        '3' => "0,5 1,6 3,6 4,5 4,4 3,3 1,3;3,3 4,2 4,1 3,0 1,0 0,1",
        '4' => "3,0 3,6 0,2 4,2",
        '5' => "4,6 0,6 0,3 3,3 4,2 4,1 3,0 0,0",
        '6' => "4,5 3,6 1,6 0,5 0,1 1,0 3,0 4,1 4,2 3,3 0,3",
        '7' => "0,6 4,6 1,0",
        '8' => "1,3 0,4 0,5 1,6 3,6 4,5 4,4 3,3 1,3 0,2 0,1 1,0 3,0 4,1 4,2 3,3",
        '9' => "4,3 1,3 0,4 0,5 1,6 3,6 4,5 4,1 3,0 1,0",
        '.' => "2,0 2,1",
        ',' => "2,1 1,-1",
        ':' => "2,1 2,2;2,4 2,5",
        ';' => "2,4 2,5;2,1 1,-1",
        '-' => "1,3 3,3",
        '+' => "2,1 2,5;0,3 4,3",
        '=' => "0,2 4,2;0,4 4,4",
        '/' => "0,0 4,6",
        '(' => "3,6 2,5 2,1 3,0",
        ')' => "1,6 2,5 2,1 1,0",
        '!' => "2,6 2,2;2,1 2,0",
        '\'' => "2,6 2,5",
        '"' => "1,6 1,5;3,6 3,5",
        '#' => "1,0 1,6;3,0 3,6;0,2 4,2;0,4 4,4",
        '_' => "0,0 4,0",
        '<' => "4,5 0,3 4,1",
        '>' => "0,5 4,3 0,1",
        '%' => "0,0 4,6;0,6 0,5;4,1 4,0",
        ' ' => "",
        _ => "0,5 1,6 3,6 4,5 4,4 2,3 2,2;2,1 2,0",
    }
}

/// The segments of `c` in grid units, as point pairs.
fn glyph_segments(c: char) -> Vec<([f32; 2], [f32; 2])> {
    let mut out = Vec::new();
    for poly in glyph(c).split(';').filter(|p| !p.is_empty()) {
        let pts: Vec<[f32; 2]> = poly
            .split(' ')
            .filter_map(|xy| {
                let (x, y) = xy.split_once(',')?;
                Some([x.parse().ok()?, y.parse().ok()?])
            })
            .collect();
        out.extend(pts.windows(2).map(|w| (w[0], w[1])));
    }
    out
}

/// `text` as line segments: the first line's baseline starts at `origin`,
/// characters advance along `right`, lines go down along `-up`; `height`
/// is the capital height in metres. `\n` starts a new line.
pub fn text_lines(
    text: &str,
    origin: Vec3,
    right: Vec3,
    up: Vec3,
    height: f32,
    color: [f32; 3],
) -> Vec<LineVertex> {
    let unit = height / GLYPH_H;
    let mut v = Vec::new();
    for (row, line) in text.lines().enumerate() {
        for (col, c) in line.chars().enumerate() {
            let base =
                origin + right * (col as f32 * ADVANCE * unit) - up * (row as f32 * LINE * unit);
            for (a, b) in glyph_segments(c) {
                for p in [a, b] {
                    v.push(LineVertex {
                        pos: (base + right * (p[0] * unit) + up * (p[1] * unit)).to_array(),
                        color,
                    });
                }
            }
        }
    }
    v
}

/// Width in metres of the longest line of `text` at capital `height`.
pub fn text_width(text: &str, height: f32) -> f32 {
    let cols = text.lines().map(|l| l.chars().count()).max().unwrap_or(0);
    (cols as f32 * ADVANCE - 2.0).max(0.0) * height / GLYPH_H
}

/// Colors of ordinary and warning messages.
pub const INFO_COLOR: [f32; 3] = [0.9, 0.92, 0.95];
/// Red for problems.
pub const WARN_COLOR: [f32; 3] = [1.0, 0.25, 0.2];

/// Messages (text, warning?) stacked 1 m in front of the head, centred,
/// a little below the line of sight, turned to face it (yaw only, so text
/// stays upright); 2.5 cm capitals.
pub fn notice_lines(messages: &[(String, bool)], head: (Vec3, Quat)) -> Vec<LineVertex> {
    let (pos, rot) = head;
    let fwd = rot * Vec3::NEG_Z;
    let flat = Vec3::new(fwd.x, 0.0, fwd.z);
    let fwd = if flat.length() > 1e-3 {
        flat.normalize()
    } else {
        Vec3::NEG_Z
    };
    let up = Vec3::Y;
    let right = fwd.cross(up).normalize();
    let height = 0.025;
    let mut v = Vec::new();
    let mut y = -0.15;
    for (text, warning) in messages {
        let w = text_width(text, height);
        let origin = pos + fwd * 1.0 + up * y - right * (w * 0.5);
        let color = if *warning { WARN_COLOR } else { INFO_COLOR };
        v.extend(text_lines(text, origin, right, up, height, color));
        y -= height * (LINE / GLYPH_H) * text.lines().count().max(1) as f32;
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_letter_and_digit_has_strokes_inside_its_cell() {
        for c in ('A'..='Z').chain('0'..='9').chain(".,:-/()!?".chars()) {
            let segs = glyph_segments(c);
            assert!(!segs.is_empty(), "{c}");
            for (a, b) in segs {
                for p in [a, b] {
                    assert!((0.0..=4.0).contains(&p[0]), "{c} {p:?}");
                    assert!((-1.0..=6.0).contains(&p[1]), "{c} {p:?}");
                }
            }
        }
        // Lowercase draws as uppercase; unknown characters as '?'.
        assert_eq!(glyph_segments('a'), glyph_segments('A'));
        assert_eq!(glyph_segments('~'), glyph_segments('?'));
        assert!(glyph_segments(' ').is_empty());
    }

    #[test]
    fn text_is_laid_out_left_to_right_and_top_down() {
        let v = text_lines("I\nI", Vec3::ZERO, Vec3::X, Vec3::Y, 0.06, INFO_COLOR);
        // 'I' has three segments: 6 vertices per line of text.
        assert_eq!(v.len(), 12);
        let top = v[..6].iter().map(|p| p.pos[1]).fold(f32::MIN, f32::max);
        let second = v[6..].iter().map(|p| p.pos[1]).fold(f32::MIN, f32::max);
        assert!((top - 0.06).abs() < 1e-6 && second < 0.0, "{top} {second}");
        assert!((text_width("AB", 0.06) - 0.10).abs() < 1e-6);
    }

    #[test]
    fn notices_face_the_head_a_metre_ahead() {
        let head = (Vec3::new(0.0, 1.6, 0.0), Quat::from_rotation_y(0.5));
        let v = notice_lines(&[("NO INPUT".into(), true)], head);
        assert!(!v.is_empty());
        let fwd = Quat::from_rotation_y(0.5) * Vec3::NEG_Z;
        for p in &v {
            let d = (Vec3::from_array(p.pos) - head.0).dot(fwd);
            assert!((d - 1.0).abs() < 1e-4, "{d}");
            assert_eq!(p.color, WARN_COLOR);
        }
    }
}
